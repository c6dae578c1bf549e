// The property of the btree fuzz target, over the whole space a fuzzer samples: whatever
// `sdv convert` accepts compiles, or the converter refuses it with a located error in the .btree
// file. First every condition of the reference's trees the converter maps, called with random
// subsets of its parameters and random values (right, wrong and out of range); then random tree
// shapes of fallbacks, sequences and parallels over leaves that never fail (keep velocity, stop),
// can fail (follow, a condition) or always hold (set_target_lane, which the maneuver after it
// implies). The CI fuzz run of 2026-11-28 found traffic_light_state(threshold=20), without a
// colour, converted to text that did not compile; the first test found vehicle ids converted to
// names that are not identifiers, the second fallbacks whose children after a never-failing one
// the checker refuses as unreachable.
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
namespace gss_conditions_test {

namespace {

namespace fs = std::filesystem;
using namespace sdv;
using compiler::gss::BtAgent;

// Values of every shape the reference's conditions take, and some no condition takes.
const std::vector<std::string> kValues = {
    "1",     "2",     "20",    "0",     "-3",   "0.5",  "1e9",        "RED",       "YELLOW",       "GREEN",
    "True",  "False", "LEFT",  "RIGHT", "main", "zone", "ALL_WAY_STOP", "TRAFFIC_LIGHT", "MP(10,10,3)", "(1,2)",
};

// A tree of `agent` with one condition node calling `call`, guarding a maneuver the agent has.
std::string tree_with(BtAgent agent, const std::string& call) {
    const std::string maneuver =
        agent == BtAgent::pedestrian ? "MEnterCrosswalkConfig()" : "MVelKeepConfig(vel=MP(14.0,10,6))";
    const std::string fallback = agent == BtAgent::pedestrian ? "MWaitAtCrosswalkConfig()" : "MStopConfig()";
    return "behaviortree t:\n    ?\n        ->\n            condition c(" + call + ")\n            maneuver m(" +
           maneuver + ")\n        maneuver m_else(" + fallback + ")\n";
}

struct Outcome {
    bool accepted = false;
    bool compiled = false;
    std::string messages;
};

// `dir` is also the search path of subtrees.
Outcome convert_and_compile(const std::string& dir, const std::string& text, int* unreachable = nullptr) {
    const std::string path = dir + "/t.btree";
    std::ofstream(path) << text;
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    Outcome o;
    auto converted = compiler::gss::convert_btrees({path}, {{dir}, {}, ""}, sm, diags);
    o.accepted = converted && !diags.has_errors();
    for (const auto& d : diags.sorted()) {
        if (unreachable != nullptr && d.code == "W0906") ++*unreachable;
    }
    if (o.accepted) {
        diag::DiagnosticEngine compile_diags;
        (void)compiler::compile_source(path + ".sdv", converted->text, sm, compile_diags);
        o.compiled = !compile_diags.has_errors();
        for (const auto& d : compile_diags.sorted()) o.messages += d.code + " " + d.message + "\n";
        if (!o.compiled) o.messages += converted->text;
    }
    return o;
}

}  // namespace

TEST_CASE("every mapped condition, with any of its parameters, converts to text that compiles or is refused") {
    const std::string dir = (fs::temp_directory_path() / ("sdv_gss_conditions_" + std::to_string(getpid()))).string();
    fs::create_directories(dir);
    std::mt19937 rng(20261128);
    int accepted = 0, refused = 0, conditions_accepted = 0, conditions = 0;
    for (BtAgent agent : {BtAgent::vehicle, BtAgent::pedestrian}) {
        const auto mapped = compiler::gss::reference_conditions(agent);
        REQUIRE(mapped.size() >= 5);
        for (const auto& c : mapped) {
            ++conditions;
            bool any = false;
            // No arguments; each parameter alone with each value; then random subsets.
            std::vector<std::string> calls = {c.name + "()"};
            for (const auto& p : c.reads) {
                for (const auto& v : kValues) calls.push_back(c.name + "(" + p + "=" + v + ")");
            }
            for (int i = 0; i < 40 && c.reads.size() > 1; ++i) {
                std::string args;
                for (const auto& p : c.reads) {
                    if (rng() % 2) args += (args.empty() ? "" : ", ") + p + "=" + kValues[rng() % kValues.size()];
                }
                calls.push_back(c.name + "(" + args + ")");
            }
            for (const auto& call : calls) {
                const Outcome o = convert_and_compile(dir, tree_with(agent, call));
                INFO("condition ", call, " of a ", std::string(agent == BtAgent::pedestrian ? "pedestrian" : "vehicle"),
                     "'s tree\n", o.messages);
                if (o.accepted) CHECK(o.compiled);
                (o.accepted ? accepted : refused) += 1;
                any = any || o.accepted;
            }
            conditions_accepted += any;
        }
    }
    fs::remove_all(dir);
    // The calls are not all refused: the property is tested on accepted conversions.
    MESSAGE(accepted, " calls accepted, ", refused, " refused; ", conditions_accepted, " of ", conditions,
            " conditions accepted with some arguments");
    CHECK(accepted > refused / 4);
    CHECK(conditions_accepted >= conditions - 4);
}

namespace {

// A random node of a vehicle's tree, `depth` levels below the root, its leaves labelled from `n`.
std::string random_node(std::mt19937& rng, int depth, int& n) {
    const std::string ind(static_cast<size_t>(depth + 1) * 4, ' ');
    const auto pick = rng() % (depth >= 3 ? 7 : 10);
    const std::string label = std::to_string(n++);
    switch (pick) {
        case 0: return ind + "maneuver m_keep" + label + "(MVelKeepConfig(vel=MP(14.0,10,6)))\n";
        case 1: return ind + "maneuver m_stop" + label + "(MStopConfig())\n";
        case 2: return ind + "maneuver m_follow" + label + "(MFollowConfig(time_gap=2.0))\n";
        case 3: return ind + "condition c_lane" + label + "(set_target_lane(lid=1))\n";
        case 4: return ind + "condition c_time" + label + "(sim_time(tmin=3))\n";
        case 5: return ind + "subtree cruise()\n";  // never fails
        case 6: return ind + "subtree guarded()\n";
        default: {
            std::string s = ind + (pick == 7 ? "?" : pick == 8 ? "->" : "||") + "\n";
            const auto children = 1 + rng() % 3;
            for (decltype(rng()) i = 0; i < children; ++i) s += random_node(rng, depth + 1, n);
            return s;
        }
    }
}

}  // namespace

TEST_CASE("random .btree tree shapes convert to text that compiles or are refused") {
    const std::string dir = (fs::temp_directory_path() / ("sdv_gss_shapes_" + std::to_string(getpid()))).string();
    fs::create_directories(dir);
    std::mt19937 rng(1128);
    // Subtrees: one whose root never fails (a sequence of an implied condition and keep
    // velocity), one that can fail.
    std::ofstream(dir + "/cruise.btree") << "behaviortree cruise:\n    ->\n        condition c_l(set_target_lane(lid=1))\n"
                                            "        maneuver m_k(MVelKeepConfig(vel=MP(14.0,10,6)))\n";
    std::ofstream(dir + "/guarded.btree") << "behaviortree guarded:\n    ->\n        condition c_t(sim_time(tmin=3))\n"
                                             "        maneuver m_f(MFollowConfig(time_gap=2.0))\n";
    int accepted = 0, unreachable = 0;
    for (int i = 0; i < 1000; ++i) {
        int n = 0;
        const std::string text = "behaviortree t:\n" + random_node(rng, 0, n);
        const Outcome o = convert_and_compile(dir, text, &unreachable);
        INFO("tree:\n", text, o.messages);
        if (o.accepted) CHECK(o.compiled);
        accepted += o.accepted;
    }
    fs::remove_all(dir);
    MESSAGE(accepted, " of 1000 trees accepted, ", unreachable, " unreachable children left out (W0906)");
    // Both kinds of tree occur: the property is tested where it matters.
    CHECK(accepted > 500);
    CHECK(unreachable > 20);
}

}  // namespace gss_conditions_test
