// The checker's lowering, seen through the IR: units normalised to SI, defaults resolved,
// arguments and overrides bound, imports resolved; and the diagnostics it reports.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "compiler/diag/render.h"
#include "runtime/ir/ir_io.h"
#include "compiler/sema/compile.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace compile_test {

using namespace sdv;

namespace {

struct Result {
    diag::SourceManager sm;
    std::unique_ptr<diag::DiagnosticEngine> diags;
    compiler::Compilation comp;
    std::string text;  // rendered diagnostics
};

std::unique_ptr<Result> compile(const std::string& src, const std::string& path = "test.sdv") {
    auto r = std::make_unique<Result>();
    r->diags = std::make_unique<diag::DiagnosticEngine>();
    r->comp = compiler::compile_source(path, src, r->sm, *r->diags);
    r->text = diag::render_all_text(*r->diags, r->sm);
    return r;
}

const std::string kRoad = "road r {\n lanes 2 forward, 1 backward\n straight 300 m\n}\n";

std::string scenario(const std::string& tree, const std::string& use) {
    return kRoad + tree + "scenario s {\n road r\n vehicle a: sdv { start lane 1 at 10 m tree " + use +
           " }\n expect no_collision()\n}\n";
}

const ir::Node& first_leaf(const ir::Program& p, ir::NodeKind kind, int skip = 0) {
    for (const auto& n : p.instances.at(0).nodes) {
        if (n.kind == kind && skip-- == 0) return n;
    }
    FAIL("no such leaf");
    static ir::Node none;
    return none;
}

const ir::ParamValue& param(const ir::Node& n, const std::string& name) {
    const auto& defs = n.kind == ir::NodeKind::maneuver
                           ? catalog::maneuvers()[static_cast<size_t>(n.leaf)].params
                           : catalog::conditions()[static_cast<size_t>(n.leaf)].params;
    for (size_t i = 0; i < defs.size(); ++i) {
        if (defs[i].name == name) return n.params.at(i);
    }
    FAIL("no parameter " << name);
    static ir::ParamValue none;
    return none;
}

}  // namespace

TEST_CASE("units are normalised to SI") {
    auto r = compile(scenario("tree t() {\n maneuver keep_velocity(speed = 36 km/h, duration = 1500 ms, "
                              "max_long_acc = 3 m/s², max_lat_acc = 2 m/s2, max_long_jerk = 5 m/s^3)\n}\n",
                              "t()"));
    REQUIRE_MESSAGE(r->comp.program, r->text);
    const auto& n = first_leaf(*r->comp.program, ir::NodeKind::maneuver);
    CHECK(param(n, "speed").number.value == doctest::Approx(10.0));
    CHECK(param(n, "duration").number.value == doctest::Approx(1.5));
    CHECK(param(n, "max_long_acc").number.value == doctest::Approx(3.0));
    CHECK(param(n, "max_lat_acc").number.value == doctest::Approx(2.0));
    CHECK(param(n, "max_long_jerk").number.value == doctest::Approx(5.0));
}

TEST_CASE("defaults come from the catalog, ranges keep their samples") {
    auto r = compile(scenario("tree t() {\n maneuver keep_velocity(duration = 2 s .. 4 s samples 5)\n}\n", "t()"));
    REQUIRE_MESSAGE(r->comp.program, r->text);
    const auto& n = first_leaf(*r->comp.program, ir::NodeKind::maneuver);
    const auto& speed = param(n, "speed").number;
    CHECK(speed.value == 14);
    CHECK(speed.lo == doctest::Approx(12.6));
    CHECK(speed.hi == doctest::Approx(15.4));
    CHECK(speed.samples == 3);
    const auto& dur = param(n, "duration").number;
    CHECK(dur.lo == 2);
    CHECK(dur.hi == 4);
    CHECK(dur.value == 3);
    CHECK(dur.samples == 5);
    CHECK(param(n, "collision").number.value == 1);
}

TEST_CASE("magnitudes clip their lower bound at zero") {
    auto r = compile(scenario("tree t() {\n maneuver keep_velocity(speed = 1 m/s +- 3 m/s samples 3)\n}\n", "t()"));
    REQUIRE_MESSAGE(r->comp.program, r->text);
    CHECK(param(first_leaf(*r->comp.program, ir::NodeKind::maneuver), "speed").number.lo == 0.0);
}

TEST_CASE("subtree arguments bind by name; overrides change only the named field") {
    auto r = compile(scenario(
        "tree inner(v: speed = 10 m/s) {\n keep: maneuver keep_velocity(speed = v, duration = 2 s)\n}\n"
        "tree outer() {\n subtree inner(v = 20 m/s, keep.max_speed_change = 3 m/s)\n}\n",
        "outer()"));
    REQUIRE_MESSAGE(r->comp.program, r->text);
    const auto& n = first_leaf(*r->comp.program, ir::NodeKind::maneuver);
    CHECK(param(n, "speed").number.value == 20);
    CHECK(param(n, "duration").number.value == 2);
    CHECK(param(n, "max_speed_change").number.value == 3);
    CHECK(n.path == "outer/inner/keep");
}

TEST_CASE("vehicle references resolve to scenario indices, zones and the ego") {
    const std::string src = kRoad +
                            "tree t() {\n sequence {\n condition gap(vehicle = ego, min = 5 m)\n"
                            " condition distance(vehicle = b, max = 30 m)\n"
                            " maneuver follow(leader = front)\n }\n}\n"
                            "scenario s {\n road r\n ego e: sdv { start lane 1 at 50 m tree t() }\n"
                            " vehicle b: sdv { start lane 2 at 10 m tree t() }\n expect no_collision()\n}\n";
    auto r = compile(src);
    REQUIRE_MESSAGE(r->comp.program, r->text);
    const auto& p = *r->comp.program;
    CHECK(param(first_leaf(p, ir::NodeKind::condition, 0), "vehicle").vehicle.vehicle == 0);
    CHECK(param(first_leaf(p, ir::NodeKind::condition, 1), "vehicle").vehicle.vehicle == 1);
    const auto& leader = param(first_leaf(p, ir::NodeKind::maneuver), "leader").vehicle;
    CHECK(leader.kind == ir::VehicleRef::Kind::zone);
    CHECK(catalog::vehicle_zones()[static_cast<size_t>(leader.zone)] == "front");
}

TEST_CASE("the standard library is embedded and qualified") {
    auto r = compile("import \"std/drive.sdv\"\n" + scenario("", "std.drive(speed = 12 m/s)"));
    REQUIRE_MESSAGE(r->comp.program, r->text);
    CHECK(r->comp.program->files.size() >= 2);
    CHECK(r->comp.program->files[1] == "std/drive.sdv");
}

TEST_CASE("relative imports and aliases") {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / "sdv_import_test";
    fs::create_directories(dir / "lib");
    std::ofstream(dir / "lib" / "mine.sdv") << "tree mine() {\n maneuver keep_velocity()\n}\n";
    auto plain = compile("import \"lib/mine.sdv\"\n" + scenario("", "mine()"), (dir / "main.sdv").string());
    CHECK_MESSAGE(plain->comp.program, plain->text);
    auto alias = compile("import \"lib/mine.sdv\" as lib\n" + scenario("", "lib.mine()"), (dir / "main.sdv").string());
    CHECK_MESSAGE(alias->comp.program, alias->text);
    auto missing = compile("import \"lib/none.sdv\"\n" + scenario("", "mine()"), (dir / "main.sdv").string());
    CHECK(!missing->comp.program);
    CHECK(missing->text.find("E0107") != std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("diagnostics are sorted by position across checker phases") {
    auto r = compile("tree b() {\n maneuver keep_velocity(speed = 3 m)\n}\ntree a() {\n maneuver folow()\n}\n");
    const auto all = r->diags->sorted();
    REQUIRE(all.size() == 2);
    CHECK(all[0].code == "E0201");
    CHECK(all[1].code == "E0102");
    CHECK(all[0].range.begin.offset < all[1].range.begin.offset);
}

TEST_CASE("the IR exists only without errors, and is deterministic") {
    auto bad = compile(scenario("tree t() {\n maneuver keep_velocity(speed = 3 m)\n}\n", "t()"));
    CHECK(!bad->comp.program);
    auto a = compile(scenario("tree t() {\n maneuver keep_velocity()\n}\n", "t()"));
    auto b = compile(scenario("tree t() {\n maneuver keep_velocity()\n}\n", "t()"));
    REQUIRE(a->comp.program);
    REQUIRE(b->comp.program);
    CHECK(ir::write_ir(*a->comp.program) == ir::write_ir(*b->comp.program));
}

TEST_CASE("IR round trip through the reader") {
    auto a = compile(scenario("tree t() {\n maneuver keep_velocity(speed = 10 m/s +- 10% samples 3 normal(1 m/s))\n}\n", "t()"));
    REQUIRE(a->comp.program);
    const std::string text = ir::write_ir(*a->comp.program);
    auto back = ir::read_ir(text);
    REQUIRE_MESSAGE(back.program, back.error);
    CHECK(ir::write_ir(*back.program) == text);
    // Every prefix of the file is rejected without crashing.
    for (size_t n = 0; n < text.size(); n += 7) {
        auto cut = ir::read_ir(std::string_view(text).substr(0, n));
        CHECK(!cut.program);
    }
}

TEST_CASE("IR reader messages") {
    auto a = compile(scenario("tree t() {\n maneuver keep_velocity()\n}\n", "t()"));
    REQUIRE(a->comp.program);
    std::string text = ir::write_ir(*a->comp.program);
    CHECK(ir::read_ir("{}").error == "not an sdv IR file: missing \"format\": \"sdvir\"");
    std::string v = text;
    v.replace(v.find("\"version\": 1"), 12, "\"version\": 9");
    CHECK(ir::read_ir(v).error.find("IR format version 9 is not supported") == 0);
    std::string flipped = text;
    flipped.replace(flipped.find("\"seed\": 0"), 9, "\"seed\": 5");
    CHECK(ir::read_ir(flipped).error.find("IR file is corrupted: content hash mismatch") == 0);
}

}  // namespace compile_test
