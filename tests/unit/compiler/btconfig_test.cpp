// A GeoScenario vehicle's `btconfig` and a .btree subtree reference's overrides, against a model
// of the reference's BTreeInterpreter on random tree families: a subtree reference's override
// replaces the whole configuration of the first node of that name among the subtree's own
// leaves (reconfigure_nodes runs before the subtree's own subtrees are linked in); a btconfig
// replaces that of the first node of that name among the leaves of the whole linked tree, in
// order, however deep (reconfigure_nodes over the built tree). Every other node keeps its own.
// A btconfig may name a node more than once: each entry reconfigures it again, a maneuver's
// replacing its configuration, a condition's (`NODE=sim_time,args=(tmax=...)`) merging its
// arguments into the node's (BCondition.reconfigure). The lowered .sdv is compiled and each
// keep-velocity and each sim_time node of the IR compared with the model.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "runtime/catalog/catalog.h"
#include "compiler/gss/lower.h"
#include "compiler/sema/compile.h"
#include "runtime/ir/ir_io.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace btconfig_test {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A keep-velocity configuration: MVelKeepConfig(vel=MP(speed,10,6)[, time=duration]).
struct Config {
    double speed = 0;
    std::optional<double> duration;
    std::string text() const {
        std::string s = "MVelKeepConfig(vel=MP(" + std::to_string(speed) + ",10,6)";
        if (duration) s += ", time=" + std::to_string(*duration);
        return s + ")";
    }
};

struct Node {
    bool subtree = false;
    bool condition = false;
    std::string name;  // a leaf's name; a subtree reference's tree
    Config config;     // a maneuver's
    std::vector<std::pair<std::string, Config>> overrides;  // a subtree reference's
};
using Tree = std::vector<Node>;  // the children of a fallback root

// The expanded leaves of tree `i`, in order, with the configuration each ends with.
struct Leaf {
    std::string name;
    bool condition = false;
    Config config;
    int depth = 0;  // 0: a node of the tree itself; n: of a subtree n references down
    double tmin = 0, tmax = 1000;  // a condition's arguments: sim_time(tmin=0, tmax=1000) in the tree
};

// A btconfig entry: NAME=MVelKeepConfig(...), or NAME=sim_time,args=(tmin=..,tmax=..) with
// either argument or both.
struct Entry {
    std::string name;
    bool condition = false;
    Config config;
    std::optional<int> tmin, tmax;
    std::string text() const {
        if (!condition) return name + "=" + config.text();
        std::string args;
        if (tmin) args += "tmin=" + std::to_string(*tmin);
        if (tmax) args += std::string(args.empty() ? "" : ",") + "tmax=" + std::to_string(*tmax);
        return name + "=sim_time,args=(" + args + ")";
    }
};

std::vector<Leaf> expand(const std::vector<Tree>& trees, size_t i, const std::vector<std::pair<std::string, Config>>& overrides) {
    // The tree's own leaves first reconfigured by the reference's overrides (first of each name),
    std::vector<Leaf> own;
    for (const Node& n : trees[i]) {
        if (!n.subtree) own.push_back({n.name, n.condition, n.config});
    }
    for (const auto& [name, c] : overrides) {
        for (Leaf& l : own) {
            if (l.name == name) {
                l.config = c;
                break;
            }
        }
    }
    // then its subtrees linked in at their places.
    std::vector<Leaf> out;
    size_t k = 0;
    for (const Node& n : trees[i]) {
        if (!n.subtree) {
            out.push_back(own[k++]);
            continue;
        }
        const size_t j = static_cast<size_t>(std::stoi(n.name.substr(1)));
        for (Leaf l : expand(trees, j, n.overrides)) {
            ++l.depth;
            out.push_back(l);
        }
    }
    return out;
}

// Each node behind a gate condition, so that every branch of the root fallback can fail and
// none is unreachable.
std::string btree_text(const Tree& t, size_t i) {
    std::string s = "behaviortree t" + std::to_string(i) + ":\n    ?\n";
    for (const Node& n : t) {
        s += "        ->\n            condition c_gate(sim_time(tmin=0, tmax=1000))\n";
        if (n.subtree) {
            s += "            subtree " + n.name + "(";
            for (size_t k = 0; k < n.overrides.size(); ++k) {
                s += (k ? ", " : "") + n.overrides[k].first + "=" + n.overrides[k].second.text();
            }
            s += ")\n";
        } else if (n.condition) {
            s += "            condition " + n.name + "(sim_time(tmin=0, tmax=1000))\n";
        } else {
            s += "            maneuver " + n.name + "(" + n.config.text() + ")\n";
        }
    }
    return s;
}

// A parameter's nominal value in the IR (a number, or an object when it has a spread).
double value(const json& p) { return p.is_number() ? p.get<double>() : p.at("value").get<double>(); }

// The diagnostics as lines of code and message, to show with a failed check.
std::string messages(const std::vector<sdv::diag::Diagnostic>& diags) {
    std::string out;
    for (const auto& d : diags) out += std::string(d.code) + ": " + d.message + "\n";
    return out;
}

struct Lowered {
    std::optional<json> ir;
    std::vector<sdv::diag::Diagnostic> diags;
};

Lowered lower_and_compile(const fs::path& dir, const std::string& btconfig) {
    sdv::diag::SourceManager sm;
    sdv::diag::DiagnosticEngine diags;
    sdv::compiler::gss::BtreeLibrary lib({dir.string()}, sm, diags);
    Lowered r;
    auto call = lib.call_with_config("t0", btconfig, "btconfig", {}, sdv::compiler::gss::BtAgent::vehicle);
    if (!call) {
        r.diags = diags.sorted();
        return r;
    }
    const std::string text = lib.text() +
                             "road r {\n    lanes 1 forward\n    straight 300 m\n}\n"
                             "scenario s {\n    road r\n    timeout 5 s\n"
                             "    ego e: sdv {\n        start lane 1 at 10 m\n        tree " + *call +
                             "\n    }\n    expect no_collision()\n}\n";
    sdv::diag::SourceManager sm2;
    sdv::diag::DiagnosticEngine diags2;
    auto c = sdv::compiler::compile_source("lowered.sdv", text, sm2, diags2);
    r.diags = diags2.sorted();
    if (c.program) r.ir = json::parse(sdv::ir::write_ir(*c.program));
    INFO(text);
    INFO(messages(r.diags));
    CHECK(r.ir.has_value());
    return r;
}

}  // namespace

TEST_CASE("btconfig and subtree overrides reconfigure the nodes the reference's interpreter does") {
    const auto* keep = sdv::catalog::find_maneuver("keep_velocity");
    REQUIRE(keep != nullptr);
    const double default_duration = keep->find_param("duration")->def->value;
    const std::vector<std::string> names = {"m_a", "m_b", "m_c"};
    std::mt19937 rng(20261124);
    auto pick = [&](int n) { return static_cast<int>(std::uniform_int_distribution<int>(0, n - 1)(rng)); };
    double next_speed = 1;
    auto config = [&] {
        Config c{next_speed, std::nullopt};
        next_speed += 1;
        if (pick(3) == 0) c.duration = 2 + pick(5);
        return c;
    };
    const fs::path root = fs::temp_directory_path() / ("sdv-btconfig-test-" + std::to_string(::getpid()));
    int checked = 0, deep[3] = {0, 0, 0}, checked_conditions = 0;
    // Entries that reconfigure a node for the first time, and again.
    int maneuvers_again[2] = {0, 0}, conditions_again[2] = {0, 0};
    for (int round = 0; round < 100; ++round) {
        // A family of trees t0..tN; ti refers only to tj with j > i (no cycle).
        next_speed = 1;  // distinct speeds name the configurations
        const size_t count = 2 + static_cast<size_t>(pick(3));
        std::vector<Tree> trees(count);
        for (size_t i = 0; i < count; ++i) {
            const int leaves = 1 + pick(3);
            for (int k = 0; k < leaves; ++k) {
                Node n;
                n.condition = pick(4) == 0;
                n.name = names[static_cast<size_t>(pick(3))];  // a condition may share a maneuver's name
                if (!n.condition) n.config = config();
                trees[i].push_back(n);
            }
            if (trees[i].front().condition) {  // a tree selects a maneuver (E0404)
                trees[i].front().condition = false;
                trees[i].front().config = config();
            }
            if (i + 1 < count) {
                const int subs = 1 + pick(2);
                for (int k = 0; k < subs; ++k) {
                    Node s;
                    s.subtree = true;
                    s.name = "t" + std::to_string(i + 1 + static_cast<size_t>(pick(static_cast<int>(count - i - 1))));
                    trees[i].insert(trees[i].begin() + pick(static_cast<int>(trees[i].size()) + 1), s);
                }
            }
        }
        // Subtree overrides, now that every tree's own leaves are known.
        for (size_t i = 0; i < count; ++i) {
            for (Node& s : trees[i]) {
                if (!s.subtree || pick(2) == 0) continue;
                const size_t j = static_cast<size_t>(std::stoi(s.name.substr(1)));
                for (const Node& m : trees[j]) {
                    // A name whose first leaf in the tree is a maneuver (else E0908).
                    const auto first = std::find_if(trees[j].begin(), trees[j].end(),
                                                    [&](const Node& o) { return !o.subtree && o.name == m.name; });
                    if (!m.subtree && !first->condition && pick(2) == 0) {
                        bool dup = false;
                        for (const auto& o : s.overrides) dup = dup || o.first == m.name;
                        if (!dup) s.overrides.push_back({m.name, config()});
                    }
                }
            }
        }
        fs::remove_all(root);
        fs::create_directories(root);
        for (size_t i = 0; i < count; ++i) std::ofstream(root / ("t" + std::to_string(i) + ".btree")) << btree_text(trees[i], i);

        // The btconfig: one to four entries, a name again in some (each entry reconfigures the
        // node once more), maneuvers' and conditions'.
        // Most name a node of the linked tree by its first node of that name (as it has to be), a
        // third of them the node of the entry before; one in eight of the others takes any name
        // and kind, which may name none (E0908).
        const std::vector<Leaf> linked = expand(trees, 0, {});
        std::vector<Entry> btconfig;
        const int items = 1 + pick(4);
        for (int k = 0; k < items; ++k) {
            Entry e;
            if (k > 0 && pick(3) == 0) {  // the node of the entry before, again
                e.name = btconfig.back().name;
                e.condition = btconfig.back().condition;
            } else if (pick(8) == 0) {
                e.name = names[static_cast<size_t>(pick(3))];
                e.condition = pick(2) == 0;
            } else {
                e.name = linked[static_cast<size_t>(pick(static_cast<int>(linked.size())))].name;
                e.condition = std::find_if(linked.begin(), linked.end(), [&](const Leaf& l) { return l.name == e.name; })->condition;
            }
            if (e.condition) {
                const int which = pick(3);  // tmin, tmax or both
                if (which != 1) e.tmin = 1 + pick(50);
                if (which != 0) e.tmax = 100 + pick(800);
            } else {
                e.config = config();
            }
            btconfig.push_back(e);
        }
        std::string text;
        for (const Entry& e : btconfig) text += e.text() + ";";

        std::vector<Leaf> expected = linked;
        bool refused = false;
        std::set<std::string> named;
        for (const Entry& e : btconfig) {
            auto it = std::find_if(expected.begin(), expected.end(), [&](const Leaf& l) { return l.name == e.name; });
            if (it == expected.end() || it->condition != e.condition) {
                refused = true;  // no node of that name and kind: E0908
            } else if (e.condition) {
                if (e.tmin) it->tmin = *e.tmin;
                if (e.tmax) it->tmax = *e.tmax;
                ++conditions_again[named.insert(e.name).second ? 0 : 1];
            } else {
                it->config = e.config;
                ++deep[std::min(it->depth, 2)];
                ++maneuvers_again[named.insert(e.name).second ? 0 : 1];
            }
        }
        INFO("round " << round << ", btconfig " << text);
        std::string files;
        for (size_t i = 0; i < count; ++i) files += btree_text(trees[i], i);
        INFO(files);
        const Lowered got = lower_and_compile(root, text);
        if (refused) {
            bool e0908 = false;
            for (const auto& d : got.diags) e0908 = e0908 || d.code == "E0908";
            CHECK(e0908);
            continue;
        }
        INFO(messages(got.diags));
        REQUIRE(got.ir.has_value());
        std::vector<json> maneuvers;
        for (const auto& n : (*got.ir)["program"]["instances"][0]["nodes"]) {
            if (n["kind"] == "maneuver") maneuvers.push_back(n);
        }
        std::vector<Leaf> expected_maneuvers;
        for (const Leaf& l : expected) {
            if (!l.condition) expected_maneuvers.push_back(l);
        }
        REQUIRE(maneuvers.size() == expected_maneuvers.size());
        for (size_t k = 0; k < maneuvers.size(); ++k) {
            INFO("maneuver " << k << " " << maneuvers[k]["path"].get<std::string>());
            CHECK(value(maneuvers[k]["params"]["speed"]) == doctest::Approx(expected_maneuvers[k].config.speed));
            CHECK(value(maneuvers[k]["params"]["duration"]) ==
                  doctest::Approx(expected_maneuvers[k].config.duration.value_or(default_duration)));
            ++checked;
        }
        // The conditions named like the maneuvers (not the gates, c_gate, c_gate_2, ...), in order.
        std::vector<json> conditions;
        for (const auto& n : (*got.ir)["program"]["instances"][0]["nodes"]) {
            if (n["kind"] == "condition" && n["name"].get<std::string>().rfind("c_gate", 0) != 0) conditions.push_back(n);
        }
        std::vector<Leaf> expected_conditions;
        for (const Leaf& l : expected) {
            if (l.condition) expected_conditions.push_back(l);
        }
        REQUIRE(conditions.size() == expected_conditions.size());
        for (size_t k = 0; k < conditions.size(); ++k) {
            INFO("condition " << k << " " << conditions[k].dump());
            CHECK(value(conditions[k]["params"]["after"]) == doctest::Approx(expected_conditions[k].tmin));
            CHECK(value(conditions[k]["params"]["before"]) == doctest::Approx(expected_conditions[k].tmax));
            ++checked_conditions;
        }
    }
    fs::remove_all(root);
    CHECK(checked > 200);
    CHECK(checked_conditions > 20);
    // Nodes reconfigured once and again, maneuvers and conditions.
    CHECK(maneuvers_again[0] > 10);
    CHECK(maneuvers_again[1] > 5);
    CHECK(conditions_again[0] > 5);
    CHECK(conditions_again[1] > 2);
    // The random families reach nodes of the tree itself, of its subtrees, and deeper.
    CHECK(deep[0] > 5);
    CHECK(deep[1] > 5);
    CHECK(deep[2] > 5);
}

}  // namespace btconfig_test
