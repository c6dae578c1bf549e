#include "runtime/io/reuse.h"

#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"

namespace sdv::io {
namespace {

using NodeId = std::string;  // "file:line:col" of the node's keyword

NodeId id_of(const ir::Program& p, const ir::Node& n) {
    const std::string file = n.loc.file < p.files.size() ? p.files[n.loc.file] : "?";
    return file + ":" + std::to_string(n.loc.line) + ":" + std::to_string(n.loc.col);
}

}  // namespace

ReuseReport reuse(const std::vector<ReuseInput>& inputs) {
    ReuseReport report;
    std::vector<std::set<NodeId>> all(inputs.size()), executed(inputs.size());
    for (size_t i = 0; i < inputs.size(); ++i) {
        const ir::Program& p = *inputs[i].program;
        const ir::Scenario& sc = p.scenarios.at(static_cast<size_t>(inputs[i].scenario));
        std::map<std::string, NodeId> by_path;  // "vehicle|path" → node
        for (const auto& v : sc.vehicles) {
            if (v.tree < 0) continue;
            for (const auto& n : p.instances[static_cast<size_t>(v.tree)].nodes) {
                all[i].insert(id_of(p, n));
                by_path[v.name + "|" + n.path] = id_of(p, n);
            }
        }
        sim::RunOptions opt;
        opt.trace = true;
        // Every node a planning cycle visited counts as executed.
        struct Visited : sim::RunObserver {
            const std::map<std::string, NodeId>& by_path;
            std::set<NodeId>& executed;
            Visited(const std::map<std::string, NodeId>& b, std::set<NodeId>& e) : by_path(b), executed(e) {}
            void plan(const sim::World& w, const sim::Agent& a) override {
                (void)w;
                if (!a.driver || !a.driver->trace) return;
                const auto& nodes = a.driver->tree->instance().nodes;
                for (const bt::Visit& v : a.driver->trace->visits) {
                    auto it = by_path.find(a.v->name + "|" + nodes[static_cast<size_t>(v.node)].path);
                    if (it != by_path.end()) executed.insert(it->second);
                }
            }
        } visited(by_path, executed[i]);
        const sim::RunResult r = sim::simulate(p, inputs[i].scenario, opt, &visited);
        if (!r.error.empty()) {
            report.error = inputs[i].label + ": " + r.error;
            return report;
        }
    }
    auto count_in = [&](const std::vector<std::set<NodeId>>& sets, const NodeId& n) {
        int c = 0;
        for (const auto& s : sets) c += s.count(n) > 0;
        return c;
    };
    report.total.label = "all";
    for (size_t i = 0; i < inputs.size(); ++i) {
        ReuseRow row;
        row.label = inputs[i].label;
        row.scenario = inputs[i].program->scenarios[static_cast<size_t>(inputs[i].scenario)].name;
        row.nodes = static_cast<int>(all[i].size());
        for (const auto& n : all[i]) row.reused += count_in(all, n) > 1;
        row.executed = static_cast<int>(executed[i].size());
        for (const auto& n : executed[i]) row.executed_reused += count_in(executed, n) > 1;
        report.total.nodes += row.nodes;
        report.total.reused += row.reused;
        report.total.executed += row.executed;
        report.total.executed_reused += row.executed_reused;
        report.rows.push_back(row);
    }
    return report;
}

std::string render_reuse(const ReuseReport& r) {
    if (!r.error.empty()) return r.error + "\n";
    std::ostringstream o;
    char buf[256];
    auto ratio = [](int a, int b) { return b > 0 ? static_cast<double>(a) / b : 0.0; };
    std::snprintf(buf, sizeof buf, "%-32s %6s %6s %6s %9s %6s %9s\n", "scenario", "nodes", "reused", "IRL", "executed", "reused",
                  "IRL exec");
    o << buf;
    for (const auto& row : r.rows) {
        std::snprintf(buf, sizeof buf, "%-32s %6d %6d %6.2f %9d %6d %9.2f\n", row.scenario.c_str(), row.nodes, row.reused,
                      ratio(row.reused, row.nodes), row.executed, row.executed_reused, ratio(row.executed_reused, row.executed));
        o << buf;
    }
    const auto& t = r.total;
    std::snprintf(buf, sizeof buf, "%-32s %6d %6d %6.2f %9d %6d %9.2f\n", "overall (weighted)", t.nodes, t.reused,
                  ratio(t.reused, t.nodes), t.executed, t.executed_reused, ratio(t.executed_reused, t.executed));
    o << buf;
    return o.str();
}

}  // namespace sdv::io
