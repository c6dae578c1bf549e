// Tick semantics of SPEC §3.4 on hand-built trees with a scripted world.
#include <doctest/doctest.h>

#include <algorithm>

#include <functional>
#include <map>

#include "runtime/bt/behavior_tree.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace behavior_tree_test {

using namespace sdv;
using bt::Status;

namespace {

// Builds a TreeInstance from a compact description.
struct Builder {
    ir::TreeInstance inst;
    int32_t add(ir::NodeKind kind, const std::string& name, std::vector<int32_t> children = {},
                int32_t threshold = 0) {
        ir::Node n;
        n.kind = kind;
        n.name = name;
        n.children = std::move(children);
        n.success_threshold = threshold;
        inst.nodes.push_back(n);
        return static_cast<int32_t>(inst.nodes.size() - 1);
    }
};

// Leaves answer from a script keyed by name; every call is logged.
struct World : bt::TickContext {
    std::map<std::string, bool> conditions;
    std::map<std::string, Status> maneuvers;
    std::vector<std::string> log;
    bool condition(const ir::Node& n, int32_t) override {
        log.push_back(n.name);
        return conditions[n.name];
    }
    Status maneuver(const ir::Node& n, int32_t) override {
        log.push_back(n.name);
        auto it = maneuvers.find(n.name);
        return it == maneuvers.end() ? Status::success : it->second;
    }
};

// Root must be node 0: reserve it, then fill it in.
ir::TreeInstance make(std::function<void(Builder&)> body) {
    Builder b;
    b.inst.nodes.emplace_back();
    body(b);
    return b.inst;
}

}  // namespace

TEST_CASE("fallback re-evaluates from the first child every tick (no memory)") {
    auto inst = make([](Builder& b) {
        const auto c = b.add(ir::NodeKind::condition, "c");
        const auto m1 = b.add(ir::NodeKind::maneuver, "m1");
        const auto seq = b.add(ir::NodeKind::sequence, "seq", {c, m1});
        const auto m2 = b.add(ir::NodeKind::maneuver, "m2");
        b.inst.nodes[0] = {ir::NodeKind::fallback, {seq, m2}, -1, {}, 0, "root", "", -1, {}};
    });
    bt::BehaviorTree tree(&inst);
    World w;
    w.conditions["c"] = false;
    CHECK(tree.tick(w) == Status::success);
    CHECK(inst.nodes[static_cast<size_t>(tree.selected())].name == "m2");
    w.conditions["c"] = true;
    CHECK(tree.tick(w) == Status::success);
    CHECK(inst.nodes[static_cast<size_t>(tree.selected())].name == "m1");
}

TEST_CASE("sequence resumes its RUNNING child; reactive sequence re-checks") {
    for (auto kind : {ir::NodeKind::sequence, ir::NodeKind::reactive_sequence}) {
        auto inst = make([&](Builder& b) {
            const auto c = b.add(ir::NodeKind::condition, "c");
            const auto lc = b.add(ir::NodeKind::maneuver, "lc");
            b.inst.nodes[0] = {kind, {c, lc}, -1, {}, 0, "root", "", -1, {}};
        });
        bt::BehaviorTree tree(&inst);
        World w;
        w.conditions["c"] = true;
        w.maneuvers["lc"] = Status::running;
        CHECK(tree.tick(w) == Status::running);
        w.conditions["c"] = false;  // the gap closed after the lane change started
        w.log.clear();
        const Status s = tree.tick(w);
        if (kind == ir::NodeKind::sequence) {
            CHECK(s == Status::running);  // memory: the condition is not re-checked
            CHECK(w.log == std::vector<std::string>{"lc"});
        } else {
            CHECK(s == Status::failure);
            CHECK(w.log == std::vector<std::string>{"c"});
        }
    }
}

TEST_CASE("sequence memory is dropped when the sequence was not ticked in between") {
    auto inst = make([](Builder& b) {
        const auto stop = b.add(ir::NodeKind::condition, "stop");
        const auto brake = b.add(ir::NodeKind::maneuver, "brake");
        const auto first = b.add(ir::NodeKind::sequence, "first", {stop, brake});
        const auto c = b.add(ir::NodeKind::condition, "c");
        const auto lc = b.add(ir::NodeKind::maneuver, "lc");
        const auto seq = b.add(ir::NodeKind::sequence, "seq", {c, lc});
        b.inst.nodes[0] = {ir::NodeKind::fallback, {first, seq}, -1, {}, 0, "root", "", -1, {}};
    });
    bt::BehaviorTree tree(&inst);
    World w;
    w.conditions["c"] = true;
    w.maneuvers["lc"] = Status::running;
    CHECK(tree.tick(w) == Status::running);  // seq running at lc
    w.conditions["stop"] = true;
    CHECK(tree.tick(w) == Status::success);  // the first branch takes over
    w.conditions["stop"] = false;
    w.conditions["c"] = false;
    w.log.clear();
    CHECK(tree.tick(w) == Status::failure);  // seq starts over: checks c again
    CHECK(w.log == std::vector<std::string>{"stop", "c"});
}

TEST_CASE("parallel success policies") {
    for (int threshold : {1, 2, 3}) {
        auto inst = make([&](Builder& b) {
            const auto a = b.add(ir::NodeKind::condition, "a");
            const auto bb = b.add(ir::NodeKind::condition, "b");
            const auto m = b.add(ir::NodeKind::maneuver, "m");
            b.inst.nodes[0] = {ir::NodeKind::parallel, {a, bb, m}, -1, {}, threshold, "root", "", -1, {}};
        });
        bt::BehaviorTree tree(&inst);
        World w;
        w.conditions["a"] = true;
        w.conditions["b"] = false;
        w.maneuvers["m"] = Status::running;
        const Status s = tree.tick(w);
        // 1 success, 1 failure, 1 running.
        if (threshold == 1) CHECK(s == Status::success);
        if (threshold == 2) CHECK(s == Status::running);
        if (threshold == 3) CHECK(s == Status::failure);
        CHECK(w.log.size() == 3);  // every child ticked
    }
}

TEST_CASE("not inverts, once fires once") {
    auto inst = make([](Builder& b) {
        const auto c = b.add(ir::NodeKind::condition, "c");
        const auto o = b.add(ir::NodeKind::once, "once", {c});
        const auto d = b.add(ir::NodeKind::condition, "d");
        const auto n = b.add(ir::NodeKind::not_, "not", {d});
        const auto m = b.add(ir::NodeKind::maneuver, "m");
        const auto seq1 = b.add(ir::NodeKind::sequence, "s1", {o, m});
        const auto m2 = b.add(ir::NodeKind::maneuver, "m2");
        const auto seq2 = b.add(ir::NodeKind::sequence, "s2", {n, m2});
        b.inst.nodes[0] = {ir::NodeKind::fallback, {seq1, seq2}, -1, {}, 0, "root", "", -1, {}};
    });
    bt::BehaviorTree tree(&inst);
    World w;
    w.conditions["c"] = true;
    w.conditions["d"] = false;
    tree.tick(w);
    CHECK(inst.nodes[static_cast<size_t>(tree.selected())].name == "m");
    tree.tick(w);  // once already fired: falls through to not(d) → m2
    CHECK(inst.nodes[static_cast<size_t>(tree.selected())].name == "m2");
    w.conditions["d"] = true;
    CHECK(tree.tick(w) == Status::failure);
}

TEST_CASE("latch: FAILURE until its child succeeds, then SUCCESS for good without ticking the child") {
    auto inst = make([](Builder& b) {
        const auto c = b.add(ir::NodeKind::condition, "c");
        const auto l = b.add(ir::NodeKind::latch, "latch", {c});
        const auto go = b.add(ir::NodeKind::maneuver, "go");
        const auto seq = b.add(ir::NodeKind::sequence, "seq", {l, go});
        const auto wait = b.add(ir::NodeKind::maneuver, "wait");
        b.inst.nodes[0] = {ir::NodeKind::fallback, {seq, wait}, -1, {}, 0, "root", "", -1, {}};
    });
    bt::BehaviorTree tree(&inst);
    World w;
    for (int i = 0; i < 3; ++i) {
        tree.tick(w);
        CHECK(inst.nodes[static_cast<size_t>(tree.selected())].name == "wait");
    }
    w.conditions["c"] = true;
    tree.tick(w);
    CHECK(inst.nodes[static_cast<size_t>(tree.selected())].name == "go");
    w.conditions["c"] = false;  // no longer true: the latch holds
    for (int i = 0; i < 3; ++i) {
        w.log.clear();
        tree.tick(w);
        CHECK(inst.nodes[static_cast<size_t>(tree.selected())].name == "go");
        CHECK(std::find(w.log.begin(), w.log.end(), "c") == w.log.end());
    }
}

TEST_CASE("the selected maneuver is sticky; a failing maneuver leaf is not selected") {
    auto inst = make([](Builder& b) {
        const auto c = b.add(ir::NodeKind::condition, "c");
        const auto m = b.add(ir::NodeKind::maneuver, "keep");
        const auto f = b.add(ir::NodeKind::maneuver, "follow");
        const auto seq = b.add(ir::NodeKind::sequence, "seq", {c, m});
        b.inst.nodes[0] = {ir::NodeKind::fallback, {f, seq}, -1, {}, 0, "root", "", -1, {}};
    });
    bt::BehaviorTree tree(&inst);
    World w;
    w.maneuvers["follow"] = Status::failure;  // no leader
    w.conditions["c"] = true;
    tree.tick(w);
    CHECK(inst.nodes[static_cast<size_t>(tree.selected())].name == "keep");
    CHECK(tree.selected_this_tick());
    w.conditions["c"] = false;
    CHECK(tree.tick(w) == Status::failure);
    CHECK(!tree.selected_this_tick());
    CHECK(inst.nodes[static_cast<size_t>(tree.selected())].name == "keep");  // sticky
}

TEST_CASE("trace lists visited nodes with their status, children first") {
    auto inst = make([](Builder& b) {
        const auto c = b.add(ir::NodeKind::condition, "c");
        const auto m = b.add(ir::NodeKind::maneuver, "m");
        b.inst.nodes[0] = {ir::NodeKind::sequence, {c, m}, -1, {}, 0, "root", "", -1, {}};
    });
    bt::BehaviorTree tree(&inst);
    World w;
    w.conditions["c"] = true;
    std::vector<bt::Visit> trace;
    tree.tick(w, &trace);
    REQUIRE(trace.size() == 3);
    CHECK(trace[0].node == 1);
    CHECK(trace[1].node == 2);
    CHECK(trace[2].node == 0);
    CHECK(trace[2].status == Status::success);
}

}  // namespace behavior_tree_test
