#include "runtime/sim/planning.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string_view>

#include "runtime/sim/leaves.h"
#include "runtime/sim/path.h"
#include "runtime/sim/plan_request.h"

namespace sdv::sim {
namespace {

constexpr double kComfortableStop = 3.0;  // m/s²: the deceleration of a comfortable stop
constexpr double kCreepSpeed = 1.0;       // m/s: slower, stopping is holding, not braking
constexpr double kStopSpeed = 0.05;       // m/s: the reference's "already stopped"
constexpr double kStopReplan = 1.0;       // m: a stop point nearer than this is not planned for again

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
            if (auto r = build_path(w.net, a.route, d, a.lane, a.lane_s, *w.paths)) {
                d.ref = r;
                d.ref_s = -1;
            }
        }
    }
    leaves.perceive();
    d.target_lane = kNoLane;  // set again by a lane change or cut-in that is still running
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
        if (auto r = build_path(w.net, a.route, d, d.target_lane, a.lane_s, *w.paths)) {
            d.ref = r;
            d.ref_s = -1;
            a.lane = d.target_lane;
        }
        d.target_lane = kNoLane;
        leaves.switched = false;
        leaves.perceive();
        d.tree->tick(leaves, trace ? &visits : nullptr);
    }
    if (d.target_lane == kNoLane) d.lane_move_target = kNoLane;
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
    // A cut-in in its target lane commits to its plan until the plan's end (its end state)
    // while the target keeps the speed the plan assumed (within 1 m/s) and the plan stays
    // clear: re-planning a receding end state every cycle never gets there.
    Driver::CutIn& cut = d.cut_in;
    const ActivePlan* held = d.plan ? &*d.plan : nullptr;
    const auto& obstacles = in.request.obstacles;
    const int tv = in.request.target_vehicle;
    const double target_v = tv >= 0 ? obstacles[static_cast<size_t>(tv)].state.s_d : 0;
    const bool commit = sel >= 0 && sel == cut.node && cut.in_lane && !d.pending && tv >= 0 && std::fabs(target_v - cut.target_v) <= 1.0 &&
                        held != nullptr && held->maneuver == sel && held->ref == d.ref && t_start < cut.due - 1e-9 &&
                        planner::stays_clear(held->traj, t_start - held->start, cut.due - t_start, in.request);
    // A stop point less than 1 m ahead of a vehicle still moving, or behind it, gets no new plan
    // (as the reference's plan_stop, sv/maneuvers/Models.py): it goes on with the plan in force,
    // the stop it planned before or the drive that took it there. Re-planning a stop there only
    // holds it in place: at an all-way stop, "stopped, my turn, go" then became a crawl over the
    // line, every start braked again by the next cycle's stop.
    const auto& start = in.request.start;
    const double from_held = held != nullptr ? t_start - held->start : 0;
    // (Not for a stop before a pedestrian: a plan in force that drives on would run into it.)
    const bool at_stop_point = sel >= 0 && in.config.kind == catalog::ManeuverKind::stop && in.config.stop_at != planner::StopTarget::now &&
                               in.config.stop_at != planner::StopTarget::pedestrian &&
                               std::fabs(start.s_d) > kStopSpeed && in.request.stop_s - in.config.stop_before - start.s < kStopReplan;
    const bool keep_held = at_stop_point && !commit && held != nullptr && !d.pending && held->ref == d.ref && from_held >= 0 &&
                           held->traj.duration - from_held >= 1.0 &&
                           planner::stays_clear(held->traj, from_held, std::min(3.0, held->traj.duration - from_held), in.request);
    planner::PlanResult result;
    if (keep_held) {
        result.trajectory = held->traj;
        ws.candidates.clear();
    } else if (commit) {
        result.trajectory = held->traj;
        ws.candidates.clear();
        d.pending.reset();
    } else {
        result = planner::plan(in.request, ws);
        d.pending = ActivePlan{result.trajectory, t_start, d.ref, sel};
        if (sel >= 0 && sel == cut.node && !result.record.fallback) {
            cut.due = t_start + result.trajectory.duration;
            cut.target_v = target_v;
        }
    }
    d.fallback_kind = keep_held ? "previous_plan" : nullptr;
    if (result.record.fallback && !keep_held) {
        // Nothing feasible: keep the plan in force while it stays valid (the same maneuver, at
        // least one more second of it, in the same frame) and clear of everyone; else a
        // comfortable stop (firm enough to stop at a stop maneuver's point) when that is clear;
        // else the planner's emergency stop (SPEC §3.3, docs/language.md).
        const ActivePlan* prev = d.plan ? &*d.plan : nullptr;
        const double from = prev ? t_start - prev->start : 0;
        const auto& st = in.request.start;
        double decel = kComfortableStop;
        if (in.config.kind == catalog::ManeuverKind::stop && in.config.stop_at != planner::StopTarget::now) {
            const double ds = in.request.stop_s - in.config.stop_before - st.s;
            if (ds > 0.1 && st.s_d > 0) decel = std::max(decel, st.s_d * st.s_d / (2 * ds));
        }
        decel = std::min(decel, in.config.common.max_long_acc);
        const auto comfortable = planner::plan_fallback(st, decel);
        if (prev && prev->maneuver == sel && sel >= 0 && prev->ref == d.ref && from >= 0 && prev->traj.duration - from >= 1.0 &&
            planner::stays_clear(prev->traj, from, std::min(3.0, prev->traj.duration - from), in.request)) {
            d.pending.reset();
            d.fallback_kind = "previous_plan";
        } else if (planner::stays_clear(comfortable, 0, comfortable.duration, in.request)) {
            d.pending = ActivePlan{comfortable, t_start, d.ref, -1};
            // At rest or creeping (below 1 m/s), it holds where it is: waiting, not braking.
            d.fallback_kind = std::fabs(st.s_d) < kCreepSpeed ? "hold" : "comfortable_stop";
        } else {
            d.pending->maneuver = -1;
            d.fallback_kind = "emergency_stop";
        }
    }
    d.fallback = d.fallback_kind != nullptr && d.fallback_kind != std::string_view("previous_plan") &&
                 d.fallback_kind != std::string_view("hold");
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
        tr.fallback = d.fallback_kind;
    }
}

}  // namespace sdv::sim
