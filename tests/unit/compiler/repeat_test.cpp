// Agent templates and arithmetic: a compact declaration (`vehicle v[1..N]: ...`) must lower to
// exactly the IR of the same agents written out by hand (source locations aside), for every
// count and every place the index can appear; errors in a template are reported once.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>
#include <functional>
#include <string>

#include "compiler/sema/compile.h"
#include "runtime/ir/ir_io.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace repeat_test {

namespace {

using nlohmann::json;
using sdv::compiler::compile_source;

struct Result {
    std::optional<json> ir;
    std::vector<sdv::diag::Diagnostic> diags;
};

Result compile(const std::string& text) {
    sdv::diag::SourceManager sm;
    sdv::diag::DiagnosticEngine diags;
    auto c = compile_source("test.sdv", text, sm, diags);
    Result r;
    r.diags = diags.sorted();
    if (c.program) r.ir = json::parse(sdv::ir::write_ir(*c.program));
    return r;
}

// The IR without source locations (and the hash over them): what the two forms share.
json strip(json j) {
    std::function<void(json&)> walk = [&](json& x) {
        if (x.is_object()) {
            x.erase("loc");
            x.erase("hash");
            for (auto& [k, v] : x.items()) walk(v);
        } else if (x.is_array()) {
            for (auto& v : x) walk(v);
        }
    };
    walk(j);
    return j;
}

const char* kHead = R"(import "std/drive.sdv"
import "std/pedestrian.sdv"
road r {
    lanes 3 forward
    straight 3000 m
}
scenario s {
    road r
    ego ego: sdv { start lane 3 at 10 m speed 10 m/s tree std.drive(speed = 12 m/s) }
)";

// One agent of a template: `body` with every `{i}` replaced by the index, as a user writing
// the agents out would.
std::string instance(const std::string& body, int64_t i) {
    std::string out = body;
    const std::string key = "{i}";
    for (size_t p = out.find(key); p != std::string::npos; p = out.find(key, p)) {
        out.replace(p, key.size(), std::to_string(i));
    }
    return out;
}

struct Case {
    const char* name;
    std::string compact;                              // the template declaration(s)
    std::function<std::string(int64_t)> written_one;  // one agent written out
    int64_t lo, hi;
    std::string tail;  // statements after the agents (expectations, vary)
};

void check_same_ir(const Case& c) {
    CAPTURE(c.name);
    std::string written;
    for (int64_t i = c.lo; i <= c.hi; ++i) written += c.written_one(i);
    const Result a = compile(kHead + c.compact + c.tail + "}\n");
    const Result b = compile(kHead + written + c.tail + "}\n");
    for (const auto& d : a.diags) MESSAGE("compact: " << d.code << " " << d.message);
    for (const auto& d : b.diags) MESSAGE("written: " << d.code << " " << d.message);
    REQUIRE(a.ir.has_value());
    REQUIRE(b.ir.has_value());
    const json ja = strip(a.ir->at("program"));
    const json jb = strip(b.ir->at("program"));
    CHECK(ja == jb);
    if (ja != jb) MESSAGE(json::diff(jb, ja).dump(1));
}

}  // namespace

TEST_CASE("a compact declaration lowers to the IR of its agents written out") {
    const std::vector<int64_t> counts = {1, 2, 7, 50};
    for (int64_t n : counts) {
        check_same_ir({"start, speed and tree arguments",
                       "vehicle v[1.." + std::to_string(n) + "]: sdv {\n"
                       "  start lane 1 at (20 + 25*i) m\n"
                       "  speed (8 + i) m/s\n"
                       "  tree std.drive(speed = (10 + 2 * i) km/h, time_gap = 1 s + 0.5 s * i)\n"
                       "}\n",
                       [](int64_t i) {
                           return instance("vehicle v{i}: sdv {\n  start lane 1 at " + std::to_string(20 + 25 * i) +
                                               " m\n  speed " + std::to_string(8 + i) + " m/s\n" +
                                               "  tree std.drive(speed = " + std::to_string(10 + 2 * i) +
                                               " km/h, time_gap = " + std::to_string(1 + 0.5 * static_cast<double>(i)) + " s)\n}\n",
                                           i);
                       },
                       1, n, "  expect min_gap(v1, ego) > 1 m\n"});
        // A tree reference without the index: expanded once, each agent given a copy.
        check_same_ir({"a tree without the index",
                       "vehicle w[1.." + std::to_string(n) + "]: sdv { start lane 2 at (30 + 25 * i) m  tree std.drive(speed = 12 m/s, time_gap = 2 s) }\n",
                       [](int64_t i) {
                           return "vehicle w" + std::to_string(i) + ": sdv { start lane 2 at " + std::to_string(30 + 25 * i) +
                                  " m  tree std.drive(speed = 12 m/s, time_gap = 2 s) }\n";
                       },
                       1, n, "  expect no_collision()\n"});
    }
    // A named index starting at 0, a name ending in a digit, goals, lengths and a second lane.
    check_same_ir({"named index from 0",
                   "vehicle car2[k = 0..4]: sdv {\n"
                   "  start lane 2 at 100 m + 30 m * k offset 0.1 m * k\n"
                   "  length (4 + k / 4) m\n"
                   "  goal lane 2 at (2000 - 10 * k) m\n"
                   "  tree std.cruise(speed = 10 m/s + 1 m/s * k)\n"
                   "}\n",
                   [](int64_t k) {
                       const double len = 4 + static_cast<double>(k) / 4;
                       char buf[256];
                       std::snprintf(buf, sizeof buf,
                                     "vehicle car2_%lld: sdv {\n  start lane 2 at %lld m offset %.17g m\n  length %.17g m\n"
                                     "  goal lane 2 at %lld m\n  tree std.cruise(speed = %lld m/s)\n}\n",
                                     static_cast<long long>(k), static_cast<long long>(100 + 30 * k), 0.1 * static_cast<double>(k), len,
                                     static_cast<long long>(2000 - 10 * k), static_cast<long long>(10 + k));
                       return std::string(buf);
                   },
                   0, 4, "  expect no_collision()\n"});
    // Trajectory agents: the index in waypoint times and positions.
    check_same_ir({"trajectories",
                   "vehicle t[1..3]: trajectory {\n"
                   "  trajectory {\n"
                   "    0 s: lane 1 at (500 + 40 * i) m\n"
                   "    (10 + i) s: lane 1 at (700 + 40 * i) m\n"
                   "  }\n"
                   "}\n",
                   [](int64_t i) {
                       return "vehicle t" + std::to_string(i) + ": trajectory {\n  trajectory {\n    0 s: lane 1 at " +
                              std::to_string(500 + 40 * i) + " m\n    " + std::to_string(10 + i) + " s: lane 1 at " +
                              std::to_string(700 + 40 * i) + " m\n  }\n}\n";
                   },
                   1, 3, "  expect reached_goal(ego) or no_collision()\n"});
    // Pedestrians on paths, and a vary naming an expanded agent.
    check_same_ir({"pedestrians and vary",
                   "pedestrian p[1..4]: path {\n"
                   "  path { at ((100 + 3 * i) m, -6 m) speed 1.4 m/s  at ((100 + 3 * i) m, 20 m) }\n"
                   "}\n",
                   [](int64_t i) {
                       const std::string x = std::to_string(100 + 3 * i);
                       return "pedestrian p" + std::to_string(i) + ": path {\n  path { at (" + x +
                              " m, -6 m) speed 1.4 m/s  at (" + x + " m, 20 m) }\n}\n";
                   },
                   1, 4, "  expect no_collision()\n  vary { ego.speed in [8 m/s, 10 m/s] }\n"});
}

TEST_CASE("template errors are reported once, with the instances they failed for") {
    const Result r = compile(std::string(kHead) +
                             "vehicle v[1..50]: sdv { start lane 1 at (20 + 100 * i) m tree std.drive(speed = 10 m/s) }\n"
                             "expect no_collision()\n}\n");
    REQUIRE(r.diags.size() == 1);
    CHECK(r.diags[0].code == "E0503");
    REQUIRE(!r.diags[0].notes.empty());
    CHECK(r.diags[0].notes.back().message == "for v30 (i = 30), v31 (i = 31), v32 (i = 32) and 18 more of 'v[1..50]'");
    // An error in a tree expanded once for all the agents (its reference does not use the index)
    // names every agent all the same.
    const Result t = compile(std::string(kHead) +
                             "vehicle v[1..50]: sdv { start lane 1 at (20 + 20 * i) m tree std.drive(speed = 500 m/s) }\n"
                             "expect no_collision()\n}\n");
    REQUIRE(t.diags.size() == 1);
    CHECK(t.diags[0].code == "E0301");
    REQUIRE(!t.diags[0].notes.empty());
    CHECK(t.diags[0].notes.back().message == "for v1 (i = 1), v2 (i = 2), v3 (i = 3) and 47 more of 'v[1..50]'");
}

TEST_CASE("agent templates: names, limits and arithmetic errors") {
    auto codes = [](const std::string& scenario_body) {
        const Result r = compile(std::string(kHead) + scenario_body + "expect no_collision()\n}\n");
        std::vector<std::string> out;
        for (const auto& d : r.diags) {
            if (d.severity == sdv::diag::Severity::error) out.push_back(d.code);
        }
        return out;
    };
    using V = std::vector<std::string>;
    CHECK(codes("vehicle v[3..1]: sdv { start lane 1 at 50 m tree std.drive(speed = 10 m/s) }\n") == V{"E0511"});
    CHECK(codes("vehicle v[1..10001]: sdv { start lane 1 at 50 m tree std.drive(speed = 10 m/s) }\n") == V{"E0511"});
    CHECK(codes("vehicle v[1..1.5]: sdv { start lane 1 at 50 m tree std.drive(speed = 10 m/s) }\n") == V{"E0511"});
    CHECK(codes("vehicle v[-1..3]: sdv { start lane 1 at (50 + 10 * i) m tree std.drive(speed = 10 m/s) }\n") == V{"E0511"});
    CHECK(codes("ego e2[1..2]: sdv { start lane 2 at 50 m tree std.drive(speed = 10 m/s) }\n") == V{"E0512", "E0507"});
    CHECK(codes("vehicle v[1..3]: sdv { start lane 1 at (50 + 10 * i) m tree std.drive(speed = 10 m/s) }\n"
                "vehicle v2: sdv { start lane 2 at 50 m tree std.drive(speed = 10 m/s) }\n") == V{"E0108"});
    // The 10,000 agents a declaration may have are accepted (and checked quickly).
    CHECK(codes("vehicle v[1..10000]: static { start lane 1 at (20 + 0.25 * i) m length 0.2 m width 0.2 m }\n").empty());
    // Arithmetic outside templates: folded the same way, dimension-checked.
    CHECK(codes("vehicle a: sdv { start lane 1 at 2 * 50 m + 1 km speed 36 km/h / 2 tree std.drive(speed = 10 m/s) }\n").empty());
    CHECK(codes("vehicle a: sdv { start lane 1 at 50 m * 2 m tree std.drive(speed = 10 m/s) }\n") == V{"E0207"});
    CHECK(codes("vehicle a: sdv { start lane 1 at (50 m + 2) m tree std.drive(speed = 10 m/s) }\n") == V{"E0207"});
    CHECK(codes("vehicle a: sdv { start lane 1 at (50 + 2) s tree std.drive(speed = 10 m/s) }\n") == V{"E0201"});
    CHECK(codes("vehicle a: sdv { start lane 1 at 50 + i tree std.drive(speed = 10 m/s) }\n") == V{"E0207"});
    CHECK(codes("vehicle a: sdv { start lane 1 at 100 m / (4 - 4) tree std.drive(speed = 10 m/s) }\n") == V{"E0207"});
    // Speeds from a length over a time.
    CHECK(codes("vehicle a: sdv { start lane 1 at 50 m speed 100 m / 10 s tree std.drive(speed = 10 m/s) }\n").empty());
}

}  // namespace repeat_test
