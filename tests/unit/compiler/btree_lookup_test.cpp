// Where a GeoScenario scenario's behavior trees are found (docs/geoscenario.md): each
// --btree-path directory, the scenario's directory, then every btrees/ directory in the
// scenario's directory and its parents, as the reference keeps its trees (btrees/sdv for
// vehicles, btrees/sp for pedestrians, under the collection's root); in each directory NAME.btree,
// then the agent type's folder. The reference's scenarios convert as they are, to the text that
// naming the folders explicitly gives; explicit directories come first; a vehicle never takes a
// pedestrian's tree folder; E0905 names the directories it tried.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/render.h"
#include "compiler/diag/source_manager.h"
#include "compiler/gss/scenario.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace btree_lookup_test {

namespace {

namespace fs = std::filesystem;
using namespace sdv;

const fs::path kData = fs::path(SDV_SHARED_DIR) / "data" / "geoscenario";

struct Result {
    std::optional<compiler::gss::Converted> converted;
    std::string diagnostics;
};

Result convert(const fs::path& scenario, std::vector<std::string> btree_path = {}) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    const compiler::gss::ConvertOptions options{std::move(btree_path), {}, ""};
    Result r;
    r.converted = compiler::gss::convert_geoscenario(scenario.string(), options, sm, diags);
    r.diagnostics = diag::render_all_text(diags, sm);
    if (diags.has_errors()) r.converted.reset();
    return r;
}

// A scratch copy of the reference's layout: maps/, scenarios/ (one scenario, at `at` below it)
// and, unless `trees` is empty, the tree folders copied to `trees` (relative to the root).
struct Layout {
    fs::path root;
    fs::path scenario;

    Layout(const std::string& name, const fs::path& scenario_in_data, const fs::path& at, const fs::path& trees) {
        root = fs::temp_directory_path() / ("sdv_btree_lookup_" + std::to_string(getpid()) + "_" + name);
        fs::remove_all(root);
        fs::create_directories(root / "scenarios" / at);
        fs::copy(kData / "maps", root / "maps", fs::copy_options::recursive);
        scenario = root / "scenarios" / at / scenario_in_data.filename();
        fs::copy_file(kData / scenario_in_data, scenario);
        if (!trees.empty()) {
            fs::create_directories(root / trees);
            fs::copy(kData / "btrees", root / trees, fs::copy_options::recursive);
        }
    }
    ~Layout() { fs::remove_all(root); }
};

std::vector<fs::path> reference_scenarios() {
    std::vector<fs::path> out;
    for (const char* group : {"scenarios", "scenarios/test"}) {
        for (const auto& e : fs::directory_iterator(kData / group)) {
            if (e.path().extension() == ".osm") out.push_back(e.path());
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST_CASE("the reference's scenarios find their trees where the reference keeps them") {
    if (!fs::is_directory(kData)) return;  // ../shared/data is not there
    const auto scenarios = reference_scenarios();
    REQUIRE(scenarios.size() >= 14);
    const std::vector<std::string> explicit_dirs = {(kData / "btrees" / "sdv").string(),
                                                    (kData / "btrees" / "sp").string()};
    for (const auto& s : scenarios) {
        CAPTURE(s);
        const Result found = convert(s);
        const Result named = convert(s, explicit_dirs);
        REQUIRE(named.converted);
        REQUIRE_MESSAGE(found.converted, found.diagnostics);
        CHECK(found.converted->text == named.converted->text);
        CHECK(found.converted->btree_files == named.converted->btree_files);
        // The reference's own form of a search location: the folder holding sdv/ and sp/.
        const Result located = convert(s, {(kData / "btrees").string()});
        REQUIRE(located.converted);
        CHECK(located.converted->btree_files == named.converted->btree_files);
    }
}

TEST_CASE("btrees/ is looked for in the scenario's directory and each of its parents") {
    if (!fs::is_directory(kData)) return;
    const fs::path follow = "scenarios/follow.gs.osm";
    // Trees at the root, the scenario two levels below it.
    {
        Layout l("root", follow, "a/b", "btrees");
        const Result r = convert(l.scenario);
        REQUIRE_MESSAGE(r.converted, r.diagnostics);
        for (const auto& f : r.converted->btree_files) {
            CHECK(fs::path(f).parent_path() == (l.root / "btrees" / "sdv").lexically_normal());
        }
    }
    // Trees beside the scenario.
    {
        Layout l("beside", follow, "a", "scenarios/a/btrees");
        const Result r = convert(l.scenario);
        REQUIRE_MESSAGE(r.converted, r.diagnostics);
        CHECK(fs::path(r.converted->btree_files.at(0)).parent_path() ==
              (l.root / "scenarios" / "a" / "btrees" / "sdv").lexically_normal());
    }
    // No trees anywhere up the path: E0905 at the vehicle's btree tag, naming the directories.
    {
        Layout l("none", follow, "a", "");
        const Result r = convert(l.scenario);
        CHECK(!r.converted);
        CHECK(r.diagnostics.find("error[E0905]") != std::string::npos);
        CHECK(r.diagnostics.find("in each directory and its sdv/: " + (l.root / "scenarios" / "a").string()) !=
              std::string::npos);
        CHECK(r.diagnostics.find("--btree-path") != std::string::npos);
        // Given with --btree-path, in either form, they are found.
        CHECK(convert(l.scenario, {(kData / "btrees").string()}).converted);
        CHECK(convert(l.scenario, {(kData / "btrees" / "sdv").string()}).converted);
    }
}

TEST_CASE("--btree-path comes first, and a vehicle's tree is never taken from sp/") {
    if (!fs::is_directory(kData)) return;
    Layout l("order", "scenarios/follow.gs.osm", "", "btrees");
    const Result base = convert(l.scenario);
    REQUIRE_MESSAGE(base.converted, base.diagnostics);
    const std::string name = "st_standard_driver.btree";  // follow's vehicle's tree, read first
    CHECK(fs::path(base.converted->btree_files.at(0)).filename() == name);

    // An explicit directory with a tree of that name (one that stops at once) is used instead.
    const fs::path mine = l.root / "mine";
    fs::create_directories(mine);
    {
        std::ofstream(mine / name) << "behaviortree mine:\n    maneuver m_stop ( MStopConfig() )\n";
    }
    const Result chosen = convert(l.scenario, {mine.string()});
    REQUIRE_MESSAGE(chosen.converted, chosen.diagnostics);
    CHECK(chosen.converted->btree_files == std::vector<std::string>{(mine / name).lexically_normal().string()});
    CHECK(chosen.converted->text != base.converted->text);

    // The vehicle's trees moved to sp/: not found for a vehicle.
    fs::remove_all(l.root / "btrees" / "sp");
    fs::rename(l.root / "btrees" / "sdv", l.root / "btrees" / "sp");
    const Result moved = convert(l.scenario);
    CHECK(!moved.converted);
    CHECK(moved.diagnostics.find("error[E0905]") != std::string::npos);
    CHECK(moved.diagnostics.find((l.root / "btrees").string()) != std::string::npos);
}

}  // namespace btree_lookup_test
