// The property of the btree fuzz target over the maneuvers, as gss_conditions_test.cpp pins it
// over the conditions: whatever `sdv convert` accepts compiles, or the converter refuses it with a
// located error in the .btree file. Every MConfig class the converter maps, each field it knows
// alone with values of every shape the reference's trees write (numbers, MP(...) and LT(...)
// with every count, method and σ, tuples, names), then random sets of fields. The campaign
// without sanitizers of 2026-12-02 found LT(71.0) converted to `lat_offset = 71 m`, which the
// checker refuses (finding 33); this test found the rest of that finding at once: MP and LT
// counts over 100 and normal sampling with σ ≤ 0 went into the text as written.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "compiler/gss/lower.h"
#include "compiler/gss/scenario.h"
#include "compiler/sema/compile.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace gss_maneuvers_test {

namespace {

namespace fs = std::filesystem;
using namespace sdv;
using compiler::gss::BtAgent;

// Values of every shape the reference's MConfig fields take, in range and out of it, and some no
// field takes.
const std::vector<std::string> kValues = {
    "0", "1", "-1", "2.5", "14", "-3", "71", "1e9", "-1e9", "1e-7", "True", "False", "LEFT", "RIGHT", "GOAL_POINT",
    "STOP_LINE", "main", "(1,2)", "(5,0,0)", "(1e9,0,0)", "(0,0)",
    // MP(value, bound %, samples, method, sigma)
    "MP(14)", "MP(14,10)", "MP(14,10,3)", "MP(14,10,6,1)", "MP(14,10,6,2)", "MP(14,10,6,3,2)", "MP(14,10,6,3,0)",
    "MP(14,10,6,3,-1)", "MP(14,10,6,3,1e-300)", "MP(14,10,100)", "MP(14,10,101)", "MP(14,10,200)", "MP(14,10,1e300)",
    "MP(14,10,3,4)", "MP(14,10,3,0)", "MP(14,10,3,2.6)", "MP(860,10,6)", "MP(-5,10,3)", "MP(14,-10,3)",
    "MP(14,300,3)", "MP(0.5,100,3)", "MP(14,10,0)", "MP(14,10,-5)", "MP(14,10,3.4)",
    // LT(target, samples, method, sigma, limit_lane_width, limit_vehicle_size)
    "LT(0)", "LT(71.0)", "LT(-71)", "LT(9.5,3)", "LT(9.5,3,1)", "LT(-9.9,3,3,1,1,0)", "LT(9.2,3,3,1,1,1)",
    "LT(1.0,3,1)", "LT(0,3,3,0)", "LT(0,3,3,-2)", "LT(0,200)", "LT(0,101,2)", "LT(0,100,2)", "LT(2,4,2,1,1,1)",
    "LT(0,3,7)", "LT(0,1e300)",
};

struct Outcome {
    bool accepted = false;
    bool compiled = false;
    bool spread = false;  // the converted text samples a value
    std::string messages;
};

Outcome convert_and_compile(const std::string& dir, const std::string& text) {
    const std::string path = dir + "/t.btree";
    std::ofstream(path) << text;
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    Outcome o;
    auto converted = compiler::gss::convert_btrees({path}, {{dir}, {}, ""}, sm, diags);
    o.accepted = converted && !diags.has_errors();
    if (!o.accepted) {
        // A refusal is located in the .btree file.
        for (const auto& d : diags.sorted()) {
            if (d.severity == diag::Severity::error && !d.range.valid()) o.messages += "unlocated: " + d.code + " " + d.message + "\n";
        }
        return o;
    }
    diag::DiagnosticEngine compile_diags;
    (void)compiler::compile_source(path + ".sdv", converted->text, sm, compile_diags);
    o.compiled = !compile_diags.has_errors();
    o.spread = converted->text.find(" samples ") != std::string::npos;
    for (const auto& d : compile_diags.sorted()) o.messages += d.code + " " + d.message + "\n";
    if (!o.compiled) o.messages += converted->text;
    return o;
}

// A tree of `agent` whose first choice is a node calling `call`.
std::string tree_with(BtAgent agent, const std::string& call) {
    const std::string fallback = agent == BtAgent::pedestrian ? "MWaitAtCrosswalkConfig()" : "MStopConfig()";
    return "behaviortree t:\n    ?\n        maneuver m(" + call + ")\n        maneuver m_else(" + fallback + ")\n";
}

}  // namespace

TEST_CASE("every mapped MConfig, with any of its fields and values, converts to text that compiles or is refused") {
    const std::string dir = (fs::temp_directory_path() / ("sdv_gss_maneuvers_" + std::to_string(getpid()))).string();
    fs::create_directories(dir);
    std::mt19937 rng(20261202);
    int accepted = 0, refused = 0, unlocated = 0, spreads = 0;
    for (BtAgent agent : {BtAgent::vehicle, BtAgent::pedestrian}) {
        const auto mapped = compiler::gss::reference_maneuvers(agent);
        REQUIRE(mapped.size() >= 5);
        for (const auto& c : mapped) {
            // No fields; each field alone with each value; then random sets of fields.
            std::vector<std::string> calls = {c.name + "()"};
            for (const auto& f : c.fields) {
                for (const auto& v : kValues) calls.push_back(c.name + "(" + f + "=" + v + ")");
            }
            for (int i = 0; i < 40; ++i) {
                std::string args;
                for (const auto& f : c.fields) {
                    if (rng() % 4 == 0) args += (args.empty() ? "" : ", ") + f + "=" + kValues[rng() % kValues.size()];
                }
                calls.push_back(c.name + "(" + args + ")");
            }
            for (const auto& call : calls) {
                const Outcome o = convert_and_compile(dir, tree_with(agent, call));
                INFO("maneuver ", call, " of a ", std::string(agent == BtAgent::pedestrian ? "pedestrian" : "vehicle"),
                     "'s tree\n", o.messages);
                if (o.accepted) {
                    CHECK(o.compiled);
                    spreads += o.spread;
                } else {
                    CHECK(o.messages.empty());
                    unlocated += !o.messages.empty();
                }
                (o.accepted ? accepted : refused) += 1;
            }
        }
    }
    fs::remove_all(dir);
    MESSAGE(accepted, " calls accepted, ", refused, " refused, ", spreads, " of those accepted sample a value");
    // Both outcomes occur, and spreads (the values the checks are about) are among those accepted.
    CHECK(accepted > refused / 4);
    CHECK(refused > 100);
    CHECK(spreads > 50);
    CHECK(unlocated == 0);
}

// The limits are the checker's, exactly: the last value inside each converts, the first outside
// is refused at the value with E0906.
TEST_CASE("a .btree value at the limits of sdv's parameter converts, one past it is refused") {
    const std::string dir = (fs::temp_directory_path() / ("sdv_gss_maneuver_limits_" + std::to_string(getpid()))).string();
    fs::create_directories(dir);
    struct Case {
        std::string value;
        bool accepted;
    };
    // Each case's value in the call `before` VALUE `after`.
    const auto check = [&](const std::vector<Case>& cs, const std::string& before, const std::string& after) {
        for (const auto& c : cs) {
            const std::string call = before + c.value + after;
            const Outcome o = convert_and_compile(dir, tree_with(BtAgent::vehicle, call));
            INFO(call, "\n", o.messages);
            CHECK(o.accepted == c.accepted);
            if (o.accepted) CHECK(o.compiled);
        }
    };
    // lat_offset is -10 m to 10 m; sdv spreads LT's samples ±0.75 m (with limit_vehicle_size, the
    // default) or ±1.75 m; counts go to 100; σ must be above 0.
    const std::vector<Case> cases = {
        {"LT(10)", true},           {"LT(10.001)", false},        {"LT(-10)", true},         {"LT(-10.001)", false},
        {"LT(9.25,3)", true},       {"LT(9.26,3)", false},        {"LT(-9.25,3)", true},     {"LT(-9.26,3)", false},
        {"LT(8.25,3,3,1,1,0)", true}, {"LT(8.26,3,3,1,1,0)", false}, {"LT(9.9,1)", true},    {"LT(0,100)", true},
        {"LT(0,101)", false},       {"LT(0,100.4)", true},        {"LT(0,3,3,0)", false},    {"LT(0,3,3,1e-9)", true},
        {"LT(0,3,2,0)", true},      {"LT(0,3,4)", false},
    };
    check(cases, "MVelKeepConfig(vel=MP(14,10,3), lat_target=", ")");
    const std::vector<Case> speeds = {
        {"MP(14,10,100)", true},    {"MP(14,10,101)", false},     {"MP(14,10,3,3,0.001)", true},
        {"MP(14,10,3,3,0)", false}, {"MP(14,10,3,3,-1)", false},  {"MP(14,10,3,5)", false},
        {"MP(14,10,1,3,0)", true},  // one sample: no spread, no σ written
    };
    check(speeds, "MVelKeepConfig(vel=", ")");
    fs::remove_all(dir);
}

}  // namespace gss_maneuvers_test
