#include "runtime/sim/expectations.h"

#include <algorithm>
#include <functional>

#include "runtime/catalog/catalog.h"

namespace sdv::sim {

void evaluate_expectations(const ir::Scenario& sc, RunResult& out) {
    std::function<bool(int32_t, std::optional<double>&)> eval = [&](int32_t i, std::optional<double>& value) -> bool {
        const ir::Expect& e = sc.expects[static_cast<size_t>(i)];
        std::optional<double> ignored;
        switch (e.kind) {
            case ir::Expect::Kind::not_: return !eval(e.lhs, ignored);
            case ir::Expect::Kind::and_: return eval(e.lhs, ignored) && eval(e.rhs, ignored);
            case ir::Expect::Kind::or_: return eval(e.lhs, ignored) || eval(e.rhs, ignored);
            case ir::Expect::Kind::call: break;
        }
        auto pair = [&](int a, int b) -> const PairMetrics& {
            for (const auto& m : out.pairs) {
                if ((m.a == a && m.b == b) || (m.a == b && m.b == a)) return m;
            }
            static const PairMetrics kNone;
            return kNone;
        };
        const auto kind = static_cast<catalog::ExpectKind>(e.function);
        double x = 0;
        switch (kind) {
            case catalog::ExpectKind::collision:
                for (const Event& ev : out.events) {
                    if (ev.kind != "collision") continue;
                    bool match = true;
                    for (int v : e.vehicles) match = match && std::find(ev.vehicles.begin(), ev.vehicles.end(), v) != ev.vehicles.end();
                    if (match) return true;
                }
                return false;
            case catalog::ExpectKind::no_collision:
                return std::none_of(out.events.begin(), out.events.end(), [](const Event& ev) { return ev.kind == "collision"; });
            case catalog::ExpectKind::reached_goal: return out.vehicles[static_cast<size_t>(e.vehicles[0])].reached_goal;
            case catalog::ExpectKind::fallback_used: return out.vehicles[static_cast<size_t>(e.vehicles[0])].fallback_used;
            case catalog::ExpectKind::timeout: return out.timed_out;
            case catalog::ExpectKind::min_gap: x = pair(e.vehicles[0], e.vehicles[1]).min_gap; break;
            case catalog::ExpectKind::min_ttc: x = pair(e.vehicles[0], e.vehicles[1]).min_ttc; break;
            case catalog::ExpectKind::min_headway: x = pair(e.vehicles[0], e.vehicles[1]).min_headway; break;
            case catalog::ExpectKind::max_jerk: x = out.vehicles[static_cast<size_t>(e.vehicles[0])].max_jerk; break;
            case catalog::ExpectKind::max_acc: x = out.vehicles[static_cast<size_t>(e.vehicles[0])].max_acc; break;
            case catalog::ExpectKind::max_speed: x = out.vehicles[static_cast<size_t>(e.vehicles[0])].max_speed; break;
        }
        value = x;
        if (e.cmp == "<") return x < e.bound;
        if (e.cmp == "<=") return x <= e.bound;
        if (e.cmp == ">") return x > e.bound;
        return x >= e.bound;
    };
    for (int32_t root : sc.expect_roots) {
        ExpectResult r;
        r.text = sc.expects[static_cast<size_t>(root)].text;
        r.loc = sc.expects[static_cast<size_t>(root)].loc;
        r.passed = eval(root, r.value);
        out.expectations.push_back(r);
    }
}

}  // namespace sdv::sim
