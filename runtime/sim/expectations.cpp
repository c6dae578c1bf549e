#include "runtime/sim/expectations.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>

#include "runtime/catalog/catalog.h"

namespace sdv::sim {
namespace {

using catalog::ExpectKind;

// The metrics and events one expectation reads: the whole run, or one window of it.
struct Scope {
    const RunResult& run;
    const std::vector<PairMetrics>& pairs;
    const std::vector<VehicleMetrics>& vehicles;
    double after = -INFINITY, before = INFINITY;

    bool holds(const Event& ev) const { return ev.time >= after - 1e-9 && ev.time <= before + 1e-9; }
    const PairMetrics& pair(int a, int b) const {
        for (const auto& m : pairs) {
            if ((m.a == a && m.b == b) || (m.a == b && m.b == a)) return m;
        }
        static const PairMetrics kNone;
        return kNone;
    }
    // The first event of `kinds` in scope that involves every vehicle of `vs`.
    std::optional<double> first(std::initializer_list<const char*> kinds, const std::vector<int32_t>& vs) const {
        for (const Event& ev : run.events) {
            if (!holds(ev) || std::none_of(kinds.begin(), kinds.end(), [&](const char* k) { return ev.kind == k; })) continue;
            const bool all = std::all_of(vs.begin(), vs.end(), [&](int32_t v) {
                return std::find(ev.vehicles.begin(), ev.vehicles.end(), v) != ev.vehicles.end();
            });
            if (all) return ev.time;
        }
        return std::nullopt;
    }
};

Scope scope_of(const ir::Expect& root, const RunResult& out) {
    if (!root.after && !root.before) return {out, out.pairs, out.vehicles};
    const double after = root.after.value_or(-INFINITY), before = root.before.value_or(INFINITY);
    for (const auto& m : out.windows) {
        if (m.after == after && m.before == before) return {out, m.pairs, m.vehicles, after, before};
    }
    // Not observed (a run that failed before its first tick): nothing was measured.
    static const std::vector<PairMetrics> kNoPairs;
    static const std::vector<VehicleMetrics> kNoVehicles;
    return {out, kNoPairs, kNoVehicles, after, before};
}

// One call: its truth, and its value or event time in `part`.
bool evaluate_call(const ir::Expect& e, const Scope& sc, ExpectPart& part) {
    const auto kind = static_cast<ExpectKind>(e.function);
    const auto vehicle = [&]() -> const VehicleMetrics& {
        const auto v = static_cast<size_t>(e.vehicles[0]);
        static const VehicleMetrics kNone;
        return v < sc.vehicles.size() ? sc.vehicles[v] : kNone;
    };
    const auto pair = [&]() -> const PairMetrics& { return sc.pair(e.vehicles[0], e.vehicles[1]); };
    double x = 0;
    switch (kind) {
        case ExpectKind::collision: part.time = sc.first({"collision"}, e.vehicles); return part.time.has_value();
        case ExpectKind::no_collision: part.time = sc.first({"collision"}, {}); return !part.time;
        case ExpectKind::reached_goal:
            part.time = sc.first({"goal_reached", "goal_overshot"}, e.vehicles);
            return part.time.has_value();
        case ExpectKind::fallback_used:
            part.time = sc.first({"fallback"}, e.vehicles);
            return sc.run.vehicles[static_cast<size_t>(e.vehicles[0])].fallback_used;
        case ExpectKind::timeout:
            if (sc.run.timed_out) part.time = sc.run.duration;
            return sc.run.timed_out;
        case ExpectKind::min_clearance: x = pair().min_clearance; break;
        case ExpectKind::min_gap: x = pair().min_gap; break;
        case ExpectKind::min_lateral: x = pair().min_lateral; break;
        case ExpectKind::min_ttc: x = pair().min_ttc; break;
        case ExpectKind::min_headway: x = pair().min_headway; break;
        case ExpectKind::max_jerk: x = vehicle().max_jerk; break;
        case ExpectKind::min_acc: x = vehicle().min_acc; break;
        case ExpectKind::max_acc: x = vehicle().max_acc; break;
        case ExpectKind::min_speed: x = vehicle().min_speed; break;
        case ExpectKind::max_speed: x = vehicle().max_speed; break;
        case ExpectKind::fallback_share: x = sc.run.vehicles[static_cast<size_t>(e.vehicles[0])].fallback_share(); break;
    }
    // Never measured: a minimum is +infinity, a maximum -infinity (no value is reported).
    if (std::isfinite(x)) part.value = x;
    if (e.cmp == "<") return x < e.bound;
    if (e.cmp == "<=") return x <= e.bound;
    if (e.cmp == ">") return x > e.bound;
    return x >= e.bound;
}

}  // namespace

void evaluate_expectations(const ir::Scenario& sc, RunResult& out) {
    for (int32_t root : sc.expect_roots) {
        const ir::Expect& r = sc.expects[static_cast<size_t>(root)];
        const Scope scope = scope_of(r, out);
        ExpectResult result;
        result.text = r.text;
        result.loc = r.loc;
        // Every part is evaluated (no short circuit), so that each one reports its value.
        std::function<bool(int32_t)> eval = [&](int32_t i) -> bool {
            const ir::Expect& e = sc.expects[static_cast<size_t>(i)];
            switch (e.kind) {
                case ir::Expect::Kind::not_: return !eval(e.lhs);
                case ir::Expect::Kind::and_: {
                    const bool a = eval(e.lhs);
                    const bool b = eval(e.rhs);
                    return a && b;
                }
                case ir::Expect::Kind::or_: {
                    const bool a = eval(e.lhs);
                    const bool b = eval(e.rhs);
                    return a || b;
                }
                case ir::Expect::Kind::call: break;
            }
            ExpectPart part;
            part.text = e.text;
            if (!e.window.empty()) {
                // The root call of a windowed statement: the call without its window.
                part.text.resize(part.text.size() - e.window.size());
                while (!part.text.empty() && std::isspace(static_cast<unsigned char>(part.text.back()))) part.text.pop_back();
            }
            part.function = e.function;
            part.holds = evaluate_call(e, scope, part);
            result.parts.push_back(part);
            return part.holds;
        };
        result.passed = eval(root);
        if (r.kind == ir::Expect::Kind::call) result.value = result.parts.front().value;
        out.expectations.push_back(std::move(result));
    }
}

}  // namespace sdv::sim
