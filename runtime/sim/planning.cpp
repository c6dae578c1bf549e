#include "runtime/sim/planning.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "runtime/sim/leaves.h"
#include "runtime/sim/path.h"
#include "runtime/sim/plan_request.h"

namespace sdv::sim {
namespace {

// Every candidate as a world-frame polyline (6 points), with its outcome, for viewers.
std::vector<PlanTrace::Path> candidate_paths(const planner::PlanWorkspace& ws, const planner::PlanResult& result,
                                             const road::ReferenceLine& ref) {
    std::vector<PlanTrace::Path> out;
    out.reserve(ws.candidates.size());
    for (size_t c = 0; c < ws.candidates.size(); ++c) {
        const planner::Candidate& cand = ws.candidates[c];
        PlanTrace::Path p;
        p.status = static_cast<int>(c) == result.record.winner ? "winner"
                   : cand.feasible                              ? "feasible"
                                                                : planner::to_string(cand.cause);
        constexpr int kPoints = 6;
        for (int k = 0; k < kPoints; ++k) {
            const double t = cand.duration * k / (kPoints - 1);
            const auto q = ref.to_cartesian({cand.s.x(t), cand.s.v(t), 0, cand.d.x(t), 0, 0});
            p.xy[static_cast<size_t>(2 * k)] = q.x;
            p.xy[static_cast<size_t>(2 * k + 1)] = q.y;
        }
        out.push_back(p);
    }
    return out;
}

}  // namespace

void plan_cycle(const World& w, Agent& a, double t0) {
    const auto started = std::chrono::steady_clock::now();
    Driver& d = *a.driver;
    const double t_start = t0 + w.latency;
    const bool trace = w.options.trace;
    Leaves leaves(w, a, t0, t_start);
    // Rebuild the frame when the vehicle nears the end of its reference line.
    if (d.ref && a.lane != kNoLane) {
        const auto probe = d.ref->project({a.x, a.y}, d.ref_s);
        if (probe.s > d.ref->length() - 120 || std::fabs(probe.d) > 6) {
            if (auto r = build_path(w.net, a.route, d, a.lane, a.lane_s)) {
                d.ref = r;
                d.ref_s = -1;
            }
        }
    }
    leaves.perceive();
    std::vector<bt::Visit> visits;
    d.tree->tick(leaves, trace ? &visits : nullptr);
    if (leaves.switched && d.target_lane != kNoLane) {
        // A lane change / cut-in completed: switch to the new lane's frame, tick once more.
        // A change off the route re-plans the route from the new lane (when the goal is still
        // reachable from it; out_of_route reports when it is not).
        const bool on_route = std::any_of(a.route.begin(), a.route.end(), [&](const road::RouteStep& r) { return r.lane == d.target_lane; });
        if (a.goal_lane != kNoLane && !on_route) {
            auto route = road::shortest_route(w.net, d.target_lane, a.goal_lane);
            if (!route.steps.empty()) a.route = route.steps;
        }
        if (auto r = build_path(w.net, a.route, d, d.target_lane, a.lane_s)) {
            d.ref = r;
            d.ref_s = -1;
            a.lane = d.target_lane;
        }
        d.target_lane = kNoLane;
        leaves.switched = false;
        leaves.perceive();
        d.tree->tick(leaves, trace ? &visits : nullptr);
    }
    const int32_t sel = d.tree->selected();
    if (sel >= 0) {
        d.maneuver = sel;
        d.maneuver_name = d.tree->instance().nodes[static_cast<size_t>(sel)].name;
    }
    PlanInputs in;
    make_request(leaves, sel, in);
    ++d.plan_count;
    thread_local planner::PlanWorkspace ws;
    ws.keep_candidates = trace;
    planner::PlanResult result = planner::plan(in.request, ws);
    d.pending = ActivePlan{result.trajectory, t_start, d.ref};
    d.fallback = result.record.fallback;
    d.candidates = result.record.candidates;
    d.plan_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - started).count();
    d.trace.reset();
    if (trace) {
        PlanTrace& tr = d.trace.emplace();
        tr.time = t0;
        tr.plan_number = in.request.plan_number;
        tr.visits = std::move(visits);
        tr.maneuver = d.maneuver_name;
        tr.kind = in.config.kind;
        tr.record = result.record;
        tr.start = in.request.start;
        tr.paths = candidate_paths(ws, result, *d.ref);
    }
}

}  // namespace sdv::sim
