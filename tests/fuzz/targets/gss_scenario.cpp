// Fuzz target of the GeoScenario scenario reader: the input as a .gs.osm file through what
// `sdv lint x.gs.osm` and `sdv convert` do with it (compiler/gss/scenario.h convert_geoscenario,
// then the converted text compiled and formatted), the diagnostics rendered as text and as
// JSON. The map the scenario names is found beside it: a small Lanelet2 map written under that
// name (the map is read only for routes with intermediate nodes). Trees resolve in the
// reference's .btree library (../shared/data) when it is there.
//
// Property: nothing in the scenario adds statements to the converted .sdv (names pasted
// unescaped could): the compiled scenario has one agent per GeoScenario vehicle, pedestrian and object,
// one light per traffic light, and the expectations of the reference's success criterion
// (no collision when `collision` is on, each goal-ending SDV, else every SDV, reaches its goal,
// and no time-out when some goal ends the run), as convert_geoscenario writes them. And a
// scenario the converter accepts compiles: every value it writes is one the .sdv checker
// accepts, so no error is located in the converted text, a file the user does not have (the
// converter reports it at the GeoScenario tag instead).
#include <pugixml.hpp>

#include <filesystem>
#include <string>

#include "compiler/diag/render.h"
#include "compiler/gss/scenario.h"
#include "compiler/sema/compile.h"
#include "compiler/syntax/format.h"
#include "tests/fuzz/targets/scratch.h"
#include "tests/fuzz/targets/targets.h"

using namespace sdv;
namespace fs = std::filesystem;

namespace {

constexpr const char* kTarget = "gss_scenario";

// Two lanelets in a row near the reference's scenarios (Karlsruhe), 60 m each.
constexpr const char* kMap = R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6">
  <node id="1" lat="49.00800" lon="8.45700"/>
  <node id="2" lat="49.00854" lon="8.45700"/>
  <node id="3" lat="49.00908" lon="8.45700"/>
  <node id="4" lat="49.00800" lon="8.45705"/>
  <node id="5" lat="49.00854" lon="8.45705"/>
  <node id="6" lat="49.00908" lon="8.45705"/>
  <way id="10"><nd ref="1"/><nd ref="2"/><tag k="type" v="line_thin"/><tag k="subtype" v="solid"/></way>
  <way id="11"><nd ref="4"/><nd ref="5"/><tag k="type" v="line_thin"/><tag k="subtype" v="solid"/></way>
  <way id="12"><nd ref="2"/><nd ref="3"/><tag k="type" v="line_thin"/><tag k="subtype" v="solid"/></way>
  <way id="13"><nd ref="5"/><nd ref="6"/><tag k="type" v="line_thin"/><tag k="subtype" v="solid"/></way>
  <relation id="20"><member type="way" ref="10" role="left"/><member type="way" ref="11" role="right"/>
    <tag k="type" v="lanelet"/><tag k="subtype" v="road"/><tag k="location" v="urban"/><tag k="one_way" v="yes"/></relation>
  <relation id="21"><member type="way" ref="12" role="left"/><member type="way" ref="13" role="right"/>
    <tag k="type" v="lanelet"/><tag k="subtype" v="road"/><tag k="location" v="urban"/><tag k="one_way" v="yes"/></relation>
</osm>
)";

// The file name of the map the globalconfig names, when it is one a file can have here.
std::string map_name(const std::string& text) {
    pugi::xml_document doc;
    if (!doc.load_buffer(text.data(), text.size())) return "";
    for (auto node : doc.child("osm").children("node")) {
        bool config = false;
        std::string lanelet;
        for (auto tag : node.children("tag")) {
            const std::string k = tag.attribute("k").value();
            if (k == "gs") config = std::string(tag.attribute("v").value()) == "globalconfig";
            if (k == "lanelet") lanelet = tag.attribute("v").value();
        }
        if (!config) continue;
        const std::string name = fs::path(lanelet).filename().string();
        if (name.empty() || name == "." || name == ".." || name.size() > 200) return "";
        if (name.find('\0') != std::string::npos) return "";
        return name;
    }
    return "";
}

void check_no_injection(const std::string& path, const std::string& text, const ir::Program& program) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    auto sc = compiler::gss::read_geoscenario(sm.add_file(path, text), sm, diags);
    if (!sc) fuzz::fail(kTarget, "converted, but the scenario does not read again");
    if (program.scenarios.size() != 1) fuzz::fail(kTarget, "the converted text has " + std::to_string(program.scenarios.size()) + " scenarios");
    const ir::Scenario& s = program.scenarios[0];
    size_t sdv = 0, goal_enders = 0;
    for (const auto& v : sc->vehicles) {
        sdv += v.btype == "SDV";
        goal_enders += v.btype == "SDV" && v.goal_ends_simulation;
    }
    const size_t expects = (sc->collision ? 1 : 0) + (goal_enders ? goal_enders + 1 : sdv);
    // Every agent: vehicles, objects, pedestrians, and the ego an egostart adds (vehicle 99).
    const size_t vehicles = sc->vehicles.size() + sc->objects.size() + sc->pedestrians.size() + (sc->egostart ? 1 : 0);
    if (s.vehicles.size() != vehicles || s.lights.size() != sc->lights.size() || s.expect_roots.size() != expects) {
        fuzz::fail(kTarget, "the converted scenario has " + std::to_string(s.vehicles.size()) + " vehicles, " +
                                std::to_string(s.lights.size()) + " lights, " + std::to_string(s.expect_roots.size()) +
                                " expectations; the GeoScenario one " + std::to_string(vehicles) + ", " +
                                std::to_string(sc->lights.size()) + ", " + std::to_string(expects) +
                                ": something in it was pasted into the .sdv as statements");
    }
}

}  // namespace

int sdv_fuzz_gss_scenario(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::string dir = fuzz::fresh_dir("gss_scenario");
    const std::string path = dir + "/input.gs.osm";
    fuzz::write_file(path, text);
    if (const std::string map = map_name(text); !map.empty() && map != "input.gs.osm") fuzz::write_file(dir + "/" + map, kMap);

    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    const compiler::gss::ConvertOptions options{fuzz::btree_library(), {}, dir};
    auto converted = compiler::gss::convert_geoscenario(path, options, sm, diags);
    if (converted && !diags.has_errors()) {
        // sdv lint and sdv run compile the converted text; sdv convert writes it formatted.
        const std::string display = path + ".sdv";
        auto result = compiler::compile_source(display, converted->text, sm, diags, fuzz::compile_options());
        fuzz::require_converted_text_compiles(kTarget, display, sm, diags);
        if (result.program && !diags.has_errors()) check_no_injection(path, text, *result.program);
        (void)compiler::syntax::format(sm.add_file(display, converted->text), sm, diags);
    }
    fuzz::require_located_diagnostics(kTarget, sm, diags);
    (void)diag::render_all_text(diags, sm);
    (void)diag::render_all_json(diags, sm);
    return 0;
}
