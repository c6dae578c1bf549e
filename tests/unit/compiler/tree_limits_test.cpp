// Trees whose size doubles at every level of subtree references (finding 40 of
// docs/reliability.md): a chain of trees each referencing the next twice. Inlined, a chain of
// depth d has 2^(d+1) - 1 nodes; the checks of a tree's shape (can it select a maneuver, does a
// fallback child always succeed) walked it once per path. Such chains of depth 60 (a few KB)
// hung the compiler or exhausted memory; each is now refused or checked in work linear in the
// chain (memoised per tree), so these tests end at all only if that holds.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "compiler/sema/compile.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace tree_limits_test {

namespace {

struct Result {
    bool compiled = false;
    std::vector<std::string> errors;  // "CODE message"
};

Result compile(const std::string& text, const sdv::compiler::CompileOptions& options = {}) {
    sdv::diag::SourceManager sm;
    sdv::diag::DiagnosticEngine diags;
    auto c = sdv::compiler::compile_source("test.sdv", text, sm, diags, options);
    Result r;
    r.compiled = c.program.has_value();
    for (const auto& d : diags.sorted()) {
        if (d.severity == sdv::diag::Severity::error) r.errors.push_back(d.code + " " + d.message);
    }
    return r;
}

// Trees t0 .. t<depth>: each t<k> is `node { subtree t<k+1>() subtree t<k+1>() }`, the last `leaf`.
std::string chain(int depth, const std::string& node, const std::string& leaf) {
    std::string out;
    for (int k = 0; k < depth; ++k) {
        const std::string next = "t" + std::to_string(k + 1) + "()";
        out += "tree t" + std::to_string(k) + "() { " + node + " { subtree " + next + "  subtree " + next + " } }\n";
    }
    return out + "tree t" + std::to_string(depth) + "() { " + leaf + " }\n";
}

const char* kRoad = "road r {\n    lanes 1 forward\n    straight 2000 m\n}\n";

std::string scenario(const std::string& vehicles) {
    return "scenario s {\n    road r\n" + vehicles + "    expect no_collision()\n}\n";
}

}  // namespace

TEST_CASE("a tree of 8,191 nodes inlined compiles; of 16,383 or 2^61 - 1 it is refused (E0306)") {
    const std::string car = "    vehicle a: sdv { start lane 1 at 10 m  tree t0() }\n";
    const Result ok = compile(kRoad + chain(12, "sequence", "maneuver keep_velocity()") + scenario(car));
    CHECK(ok.compiled);
    CHECK(ok.errors.empty());
    for (const int depth : {13, 60}) {
        CAPTURE(depth);
        const Result big = compile(kRoad + chain(depth, "sequence", "maneuver keep_velocity()") + scenario(car));
        CHECK_FALSE(big.compiled);
        CHECK(big.errors == std::vector<std::string>{"E0306 tree 't0' expands to more than 10000 nodes with its subtrees inlined"});
    }
}

TEST_CASE("the agents' trees of a scenario together are limited (E0306), at the agent that passes the limit") {
    sdv::compiler::CompileOptions options;
    options.max_scenario_tree_nodes = 20000;  // two trees of 8,191 nodes, not three
    const std::string trees = chain(12, "sequence", "maneuver keep_velocity()");
    const Result two = compile(kRoad + trees +
                                   scenario("    vehicle a: sdv { start lane 1 at 10 m  tree t0() }\n"
                                            "    vehicle b: sdv { start lane 1 at 30 m  tree t0() }\n"),
                               options);
    CHECK(two.compiled);
    const Result three = compile(kRoad + trees +
                                     scenario("    vehicle a: sdv { start lane 1 at 10 m  tree t0() }\n"
                                              "    vehicle b: sdv { start lane 1 at 30 m  tree t0() }\n"
                                              "    vehicle c: sdv { start lane 1 at 50 m  tree t0() }\n"),
                                 options);
    CHECK_FALSE(three.compiled);
    CHECK(three.errors == std::vector<std::string>{"E0306 the agents' trees of scenario 's' expand to more than 20000 nodes"});
    // The same through a template: its tree expanded once, copied for each agent, counted each time.
    const Result many = compile(kRoad + trees + scenario("    vehicle v[1..3]: sdv { start lane 1 at (20 * i) m  tree t0() }\n"), options);
    CHECK_FALSE(many.compiled);
    CHECK(many.errors == three.errors);
}

TEST_CASE("the paths naming a scenario's tree nodes are limited in characters (E0306)") {
    // 40 trees of 400-character names, each referencing the next once, above a tree of 2,047
    // nodes: each node's path names the 40 (16 KB), 33 MB in all from 35 KB of text.
    const std::string name(400, 'x');
    std::string trees;
    for (int k = 0; k < 40; ++k) trees += "tree " + name + std::to_string(k) + "() { subtree " + name + std::to_string(k + 1) + "() }\n";
    trees += "tree " + name + "40() { subtree t0() }\n" + chain(10, "sequence", "maneuver keep_velocity()");
    const std::string car = "    vehicle a: sdv { start lane 1 at 10 m  tree " + name + "0() }\n";
    sdv::compiler::CompileOptions options;
    options.max_scenario_tree_path_chars = 1000000;
    const Result r = compile(kRoad + trees + scenario(car), options);
    CHECK_FALSE(r.compiled);
    CHECK(r.errors == std::vector<std::string>{"E0306 the agents' trees of scenario 's' name their nodes with more than 1000000 characters of paths"});
    // Short names: the same shape is within the limit.
    std::string short_trees;
    for (int k = 0; k < 40; ++k) short_trees += "tree u" + std::to_string(k) + "() { subtree u" + std::to_string(k + 1) + "() }\n";
    short_trees += "tree u40() { subtree t0() }\n" + chain(10, "sequence", "maneuver keep_velocity()");
    CHECK(compile(kRoad + short_trees + scenario("    vehicle a: sdv { start lane 1 at 10 m  tree u0() }\n"), options).compiled);
}

TEST_CASE("a tree's shape is checked once per tree, not once per path through its subtrees") {
    // Never selects a maneuver: every path ends in a condition (E0404 for each of the 61 trees).
    const Result never = compile(kRoad + chain(60, "fallback", "condition sim_time(after = 1 s)") + scenario(""));
    CHECK(never.errors.size() == 61);
    for (const auto& e : never.errors) CHECK(e.rfind("E0404 ", 0) == 0);
    // Always succeeds: a fallback's child after it is unreachable (E0403), found through 60
    // levels of sequences of trees that never fail.
    const Result always = compile(kRoad + chain(60, "sequence", "maneuver keep_velocity()") +
                                  "tree top() { fallback { subtree t0()  maneuver stop() } }\n" + scenario(""));
    REQUIRE(always.errors.size() == 1);
    CHECK(always.errors[0].rfind("E0403 unreachable", 0) == 0);
}

}  // namespace tree_limits_test
