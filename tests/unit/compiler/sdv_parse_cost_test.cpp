// The .sdv parser's work is bounded by the input's size: no prediction of the grammar looks
// further ahead as a value, a list or a file grows. Before the fix of fuzz finding 37 the
// waypoints of a trajectory, which follow one another without a separator, let a waypoint's time
// begin with a name or a sign: after `1 m` the parser could not tell a unit or a `+` from the
// start of the next waypoint without reading to its ':', and it did so at every term of every
// value of the file (a sum of 6,400 terms, 51 KB: 3.4 s). Counted with the parser's profiler
// (syntax::ParseStats), never with a clock: each shape below at sizes 8, 128 and 512, the largest
// prediction no longer at 512 than at 8 (and within a small constant), and the tokens examined
// per byte the same at 512 as at 128; every .sdv of the project.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/source_manager.h"
#include "compiler/syntax/parser.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace sdv_parse_cost_test {

namespace {

namespace fs = std::filesystem;
using namespace sdv;
using compiler::syntax::ParseStats;

// The most tokens one prediction examines on any input. The deepest decisions of grammar/Sdv.g4
// tell an expectation's comparison from a call and a setting from a statement; none depends on
// how long a value or a block is.
constexpr long long kMaxLookahead = 24;

struct Parsed {
    bool ok = false;
    size_t bytes = 0;
    ParseStats stats;
};

Parsed parse(const std::string& text) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    Parsed p;
    p.bytes = text.size();
    p.ok = compiler::syntax::parse(sm.add_file("t.sdv", text), sm, diags, &p.stats) != nullptr;
    return p;
}

std::string repeat(const std::string& first, const std::string& more, int n) {
    std::string out = first;
    for (int i = 1; i < n; ++i) out += more;
    return out;
}

const std::string kRoad = "road r {\n lanes 2 forward\n straight 300 m\n}\n";

std::string vehicle(const std::string& stmts) {
    return kRoad + "scenario s {\n road r\n vehicle v: sdv {\n start lane 1 at 10 m\n" + stmts + "\n }\n}\n";
}

struct Shape {
    const char* name;
    std::function<std::string(int)> text;  // the input at size n
};

std::vector<Shape> shapes() {
    return {
        {"a sum of quantities", [](int n) { return vehicle(" speed " + repeat("1 m/s", " + 1 m/s", n)); }},
        {"a difference of quantities", [](int n) { return vehicle(" speed " + repeat("30 m/s", " - 0.01 m/s", n)); }},
        {"a product of names and quantities", [](int n) { return vehicle(" length " + repeat("1 m", " * k", n)); }},
        {"a sum in parentheses with a unit", [](int n) { return vehicle(" speed (" + repeat("1", " + 1", n) + ") m/s"); }},
        {"a sum in a road's length", [](int n) { return "road r {\n lanes 1 forward\n straight (" + repeat("1 m", " + 1 m", n) + ")\n}\n"; }},
        {"an interval of sums", [](int n) {
             return vehicle(" speed " + repeat("1 m/s", " + 1 m/s", n) + " .. " + repeat("2 m/s", " + 1 m/s", n));
         }},
        {"a spread of a sum", [](int n) { return vehicle(" speed 10 m/s ±" + repeat("1 m/s", " + 1 m/s", n)); }},
        {"a trajectory's waypoints", [](int n) {
             std::string w;
             for (int i = 0; i < n; ++i) w += "  " + std::to_string(i) + " s: lane 1 at " + std::to_string(10 * i) + " m speed 10 m/s\n";
             return kRoad + "scenario s {\n road r\n vehicle v: trajectory {\n trajectory {\n" + w + " }\n }\n}\n";
         }},
        {"waypoints whose times and positions are sums", [](int n) {
             std::string w;
             for (int i = 0; i < n; ++i)
                 w += "  " + std::to_string(i) + " s + 500 ms: lane 1 at " + repeat("1 m", " + 1 m", 8) + " offset 0.5 m - 0.5 m\n";
             return kRoad + "scenario s {\n road r\n vehicle v: trajectory {\n trajectory {\n" + w + " }\n }\n}\n";
         }},
        {"a waypoint's speed a long sum", [](int n) {
             return kRoad + "scenario s {\n road r\n vehicle v: trajectory {\n trajectory {\n  0 s: lane 1 at 0 m speed " +
                    repeat("1 m/s", " + 1 m/s", n) + "\n  (2) s: lane 1 at 30 m\n }\n }\n}\n";
         }},
        {"tree arguments", [](int n) {
             std::string args;
             for (int i = 0; i < n; ++i) args += (i ? ", " : "") + std::string("a") + std::to_string(i) + " = " + std::to_string(i) + " m";
             return vehicle(" tree t(" + args + ")");
         }},
        {"a list of values", [](int n) { return vehicle(" speed [" + repeat("1 m/s", ", 1 m/s + 1 m/s", n) + "]"); }},
        {"a chain of 'and'", [](int n) {
             return kRoad + "scenario s {\n road r\n expect " + repeat("collision(a, b)", " and not collision(a, b)", std::min(n, 200)) + "\n}\n";
         }},
        {"a sum cut short", [](int n) { return vehicle(" speed " + repeat("1 m/s", " + 1 m/s", n) + " +"); }},
    };
}

std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace

TEST_CASE("no prediction of the .sdv grammar looks further ahead as its input grows") {
    for (const auto& shape : shapes()) {
        INFO(shape.name);
        const Parsed small = parse(shape.text(8));
        const Parsed large = parse(shape.text(512));
        CHECK(large.stats.max_lookahead <= kMaxLookahead);
        CHECK(large.stats.max_lookahead <= small.stats.max_lookahead);
        CHECK(large.stats.full_context == 0);
        // Linear: four times the size, about the same tokens examined per byte (the fixed text
        // around a shape weighs less at 128 already; quadratic work would examine four times more).
        const Parsed mid = parse(shape.text(128));
        const double per_byte_mid = static_cast<double>(mid.stats.lookahead) / static_cast<double>(mid.bytes);
        const double per_byte_large = static_cast<double>(large.stats.lookahead) / static_cast<double>(large.bytes);
        CHECK(per_byte_large <= 1.1 * per_byte_mid + 0.05);
    }
}

TEST_CASE("the shapes parse: the bound is on the parses a user writes") {
    for (const auto& shape : shapes()) {
        INFO(shape.name);
        const bool cut = std::string(shape.name).find("cut short") != std::string::npos;
        CHECK(parse(shape.text(512)).ok == !cut);
    }
}

TEST_CASE("every .sdv of the project parses within the lookahead bound") {
    size_t files = 0;
    for (const char* dir : {"examples", "stdlib-trees", "tests"}) {
        for (const auto& e : fs::recursive_directory_iterator(fs::path(SDV_SOURCE_DIR) / dir)) {
            if (!e.is_regular_file() || e.path().extension() != ".sdv") continue;
            ++files;
            INFO(e.path().string());
            const Parsed p = parse(read(e.path()));
            CHECK(p.stats.max_lookahead <= kMaxLookahead);
        }
    }
    CHECK(files > 50);
}

TEST_CASE("a waypoint's time begins with a number or a parenthesis") {
    const auto traj = [](const std::string& waypoints) {
        return kRoad + "scenario s {\n road r\n vehicle v: trajectory {\n trajectory {\n" + waypoints + " }\n }\n}\n";
    };
    CHECK(parse(traj("  0 s: lane 1 at 0 m\n  2 s + 500 ms: lane 1 at 30 m\n  (3) s: lane 1 at 40 m\n")).ok);
    CHECK(parse(traj("  0 s: lane 1 at 0 m speed 10 m/s\n  2 s: lane 1 at 30 m\n")).ok);
    CHECK_FALSE(parse(traj("  0 s: lane 1 at 0 m\n  t: lane 1 at 30 m\n")).ok);
    CHECK_FALSE(parse(traj("  0 s: lane 1 at 0 m\n  -1 s: lane 1 at 30 m\n")).ok);
}

}  // namespace sdv_parse_cost_test
