// Candidate generation, feasibility and cost. The formulas, in one place:
//
// Targets per kind (T = sampled duration, lat = lane centre + sampled lat_offset):
//   keep_velocity  s: quartic to speed v (|v − ṡ0| capped at max_speed_change), s̈ = 0
//   follow         leader L at constant speed: s_L(T) = s_L + v_L T;
//                  s: quintic to s_L(T) − (len_L + len)/2 − max(stop_distance, time_gap·v_L),
//                  speed v_L, acc 0; if v_L < 1.5 m/s: stop behind it at stop_distance;
//                  a leader faster than `speed` (the driver's own): quartic to `speed`; one
//                  beyond comfortable reach in T: quartic to min(speed, v_L + 3 m/s) (closing in)
//   lane_change    s: quartic keeping the current speed (at least 2 m/s); d to the target lane's centre
//   cut_in         target V: s_V(T) + (len + len_V)/2 + delta_s (bumper gap; gap_from = reference:
//                  2·len + delta_s, GeoScenario's), speed v_V + delta_v, acc delta_a
//   stop           s: quintic to (stop_s − distance, 0, 0),
//                  T = factor · min(2Δs / max(ṡ0, 1 m/s), √(5.77 Δs / 2 m/s²)) (at least 1 s):
//                  from (near) rest it drives up to the point at up to 2 m/s², never crawls;
//                  `now` stops 1.875·ṡ0² / (2 · decel) ahead (peak deceleration `decel`)
//   reverse        s: quartic to −speed
//   d: always quintic to (lat, 0, 0) at T.
// Feasibility at eval_points evenly spaced times in [0, T], first failure recorded:
//   |s⃛| > max_long_jerk, |d⃛| > max_lat_jerk, |s̈| > max_long_acc, |d̈| > max_lat_acc,
//   collision (n = ⌈len/width⌉ circles per vehicle, radius √((len/2n)² + (width/2)²), plus a 0.3 m
//   margin, against every obstacle's constant-velocity prediction, except followers (vehicles
//   entirely behind in the own lane at the start) and, at points where the candidate stands
//   still, moving vehicles: avoiding those is their drivers' job), off-lane (own footprint d ± width/2 outside the
//   current lane; not for lane_change / cut_in), direction (ṡ < −0.01 m/s; not for reverse).
// Cost = Σ wᵢ · logistic(xᵢ), logistic(x) = 2 / (1 + e^−x) − 1, with
//   time        |T − T_nominal| (s)
//   efficiency  |mean speed − target speed| (m/s), mean speed = (s(T) − s(0)) / T; with
//               `efficiency = reference` GeoScenario's 2 (T_nominal − mean speed) / mean speed
//   lane offset mean |d − lat| / expected_offset
//   jerk        RMS of s⃛ (resp. d⃛) / expected_jerk
//   acc         RMS of s̈ (resp. d̈) / expected_acc
//   proximity   max over points and obstacles of 1 / max(clearance, 0.1 m), clearance = the
//               smallest circle-to-circle distance (m)
// Lowest total wins; ties go to the lower candidate index.
#include "runtime/planner/planner.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sdv::planner {
namespace {

constexpr double kStopSpeed = 1.5;     // m/s: a slower leader is stopped behind
constexpr double kMinLaneChangeSpeed = 2.0;  // m/s
// Added to the footprint circles: the circles ignore the heading, which tilts the box during
// lane changes; the margin keeps the plan clear of the true (oriented) box.
constexpr double kCollisionMargin = 0.3;  // m
// Stops from (near) rest: the duration of a rest-to-rest quintic over Δs whose peak
// acceleration is this (peak = 5.77·Δs/T²), so that a vehicle short of its stop point drives
// up to it instead of crawling.
constexpr double kStopAcc = 2.0;       // m/s²
constexpr double kCloseInSpeed = 3.0;  // m/s faster than a distant leader while closing in
constexpr double kInfSpeed = 1e9;
constexpr double kStandingSpeed = 0.1;  // m/s

// A vehicle entirely behind the planning one in its lane at the plan's start (a follower):
// keeping its distance is its driver's job, so it vetoes no plan (SPEC §3.7, issue 14).
bool is_follower(const Obstacle& o, const FrenetState& st, double length, double width) {
    return !o.is_static && o.state.s + 0.5 * o.length_m < st.s - 0.5 * length &&
           std::fabs(o.state.d - st.d) < 0.5 * (width + o.width_m);
}

double logistic(double x) { return 2.0 / (1.0 + std::exp(-x)) - 1.0; }

// A footprint as n equal circles along the length (n = ⌈length / width⌉, 1..8): each covers
// a length/n slice of the box, so long vehicles are not inflated sideways.
struct Footprint {
    double offset[8];
    int n;
    double radius;
};

Footprint footprint(double length, double width) {
    Footprint f{};
    f.n = std::clamp(static_cast<int>(std::ceil(length / std::max(width, 0.1))), 1, 8);
    const double slice = length / f.n;
    for (int i = 0; i < f.n; ++i) f.offset[i] = -0.5 * length + slice * (i + 0.5);
    f.radius = std::sqrt(slice * slice / 4.0 + width * width / 4.0);
    return f;
}

// Clearance of two footprints at Frenet positions: the closest pair of their circles, less both
// radii and the margin (negative: they overlap). One square root.
double clearance(const Footprint& a, double s, double d, const Footprint& b, double os, double od) {
    const double dd = d - od;
    double min_d2 = std::numeric_limits<double>::infinity();
    for (int ia = 0; ia < a.n; ++ia) {
        for (int ib = 0; ib < b.n; ++ib) {
            const double ds = (s + a.offset[ia]) - (os + b.offset[ib]);
            min_d2 = std::min(min_d2, ds * ds + dd * dd);
        }
    }
    return std::sqrt(min_d2) - a.radius - b.radius - kCollisionMargin;
}

// The least clearance a plan may come to, given the clearance at its start: 0, unless the start
// is within the margin only (the circles clear, the margin not): then the margin gives way and
// only the circles may not overlap. Circles that already overlap (a contact) keep 0: moving
// through the other is no way out.
double margin_floor(double start_clearance) {
    return start_clearance < 0 && start_clearance >= -kCollisionMargin ? -kCollisionMargin : 0.0;
}

}  // namespace

const char* to_string(RejectCause cause) {
    switch (cause) {
        case RejectCause::long_jerk: return "long_jerk";
        case RejectCause::lat_jerk: return "lat_jerk";
        case RejectCause::long_acc: return "long_acc";
        case RejectCause::lat_acc: return "lat_acc";
        case RejectCause::collision: return "collision";
        case RejectCause::off_lane: return "off_lane";
        case RejectCause::direction: return "direction";
        case RejectCause::count_: break;
    }
    return "none";
}

FrenetState Trajectory::at(double t) const {
    FrenetState f;
    if (t <= duration) {
        f = {s.x(t), s.v(t), s.a(t), d.x(t), d.v(t), d.a(t)};
        return f;
    }
    const double sv = s.v(duration);
    f.s = s.x(duration) + sv * (t - duration);
    f.s_d = sv;
    f.d = d.x(duration);
    return f;
}

Trajectory plan_fallback(const FrenetState& start, double max_decel) {
    // A quintic stop over T = 2|v| / a covers v·T/2 = v²/a; its peak deceleration is
    // 1.875·|v|/T ≈ 0.94·a, within the limit. d comes to rest where it is.
    Trajectory tr;
    const double v = start.s_d;
    const double decel = std::max(0.1, max_decel);
    const double T = std::max(2.0 * std::fabs(v) / decel, 0.5);
    const double a0 = std::clamp(start.s_dd, -decel, decel);
    tr.s = std::fabs(v) < 1e-3 ? Poly::quadratic(start.s, 0.0, 0.0)
                               : Poly::quintic(start.s, v, a0, start.s + 0.5 * v * T, 0.0, 0.0, T);
    tr.d = Poly::quintic(start.d, start.d_d, start.d_dd, start.d + 0.5 * start.d_d * T, 0.0, 0.0, T);
    tr.duration = T;
    return tr;
}

bool stays_clear(const Trajectory& tr, double from, double horizon, const PlanRequest& req) {
    const Footprint own = footprint(req.length_m, req.width_m);
    constexpr int kPoints = 13;
    // As in plan(): an obstacle within the margin already at the start counts by its circles only.
    const FrenetState f0 = tr.at(from);
    thread_local std::vector<double> floors;
    floors.clear();
    for (const Obstacle& o : req.obstacles) {
        floors.push_back(margin_floor(clearance(own, f0.s, f0.d, footprint(o.length_m, o.width_m), o.state.s, o.d_at(0))));
    }
    for (int e = 0; e < kPoints; ++e) {
        const double t = horizon * e / (kPoints - 1);
        const FrenetState f = tr.at(from + t);
        const bool standing = std::fabs(f.s_d) < kStandingSpeed && std::fabs(f.d_d) < kStandingSpeed;
        for (size_t oi = 0; oi < req.obstacles.size(); ++oi) {
            const Obstacle& o = req.obstacles[oi];
            if (is_follower(o, req.start, req.length_m, req.width_m)) continue;
            // Standing still can be no one's fault: only moving can conflict.
            if (standing) continue;
            const double os = o.state.s + o.state.s_d * t, od = o.d_at(t);
            if (std::fabs(os - f.s) > 0.5 * (req.length_m + o.length_m) + 6.0 || std::fabs(od - f.d) > 6.0) continue;
            if (clearance(own, f.s, f.d, footprint(o.length_m, o.width_m), os, od) < floors[oi]) return false;
        }
    }
    return true;
}

PlanResult plan(const PlanRequest& req, PlanWorkspace& ws) {
    PlanResult result;
    const ManeuverConfig& cfg = *req.config;
    const CommonConfig& k = cfg.common;
    const FrenetState& st = req.start;
    RandomStream rng(req.seed, req.vehicle, req.plan_number);
    PlanRecord& rec = result.record;
    if (ws.keep_candidates) ws.candidates.clear();

    const bool lateral_move = cfg.kind == ManeuverKind::lane_change || cfg.kind == ManeuverKind::cut_in;
    const LaneBand& lane = lateral_move ? req.target_lane : req.current_lane;
    const bool check_off_lane = k.off_lane && !lateral_move;
    const bool check_direction = k.direction && cfg.kind != ManeuverKind::reverse;
    // A vehicle that starts partly outside its lane (placed off-centre, or a lane narrower than
    // it) may stay as far out as it is, but not go farther.
    const double allow_left = std::max(req.current_lane.left_d, st.d + 0.5 * req.width_m);
    const double allow_right = std::min(req.current_lane.right_d, st.d - 0.5 * req.width_m);

    // Longitudinal sampled dimension (a) × second dimension (b) × lateral offsets (c).
    ws.a.clear();
    ws.b.clear();
    ws.c.clear();
    switch (cfg.kind) {
        case ManeuverKind::keep_velocity:
        case ManeuverKind::reverse:
            sample(cfg.speed, rng, ws.a);
            sample(cfg.duration, rng, ws.b);
            break;
        case ManeuverKind::cut_in:
            sample(cfg.delta_s, rng, ws.a);
            sample(cfg.duration, rng, ws.b);
            break;
        case ManeuverKind::stop:
            ws.a.push_back(0.0);
            sample(cfg.duration_factor, rng, ws.b);
            break;
        default:
            ws.a.push_back(0.0);
            sample(cfg.duration, rng, ws.b);
            break;
    }
    sample(k.lat_offset, rng, ws.c);

    const Obstacle* leader =
        req.leader >= 0 && static_cast<size_t>(req.leader) < req.obstacles.size() ? &req.obstacles[static_cast<size_t>(req.leader)] : nullptr;
    const Obstacle* target = req.target_vehicle >= 0 && static_cast<size_t>(req.target_vehicle) < req.obstacles.size()
                                 ? &req.obstacles[static_cast<size_t>(req.target_vehicle)]
                                 : nullptr;
    // Stop distance for stop(now); the resolved point otherwise.
    double stop_point = req.stop_s - cfg.stop_before;
    if (cfg.kind == ManeuverKind::stop && cfg.stop_at == StopTarget::now) {
        // A quintic stop over Δs from v peaks at 1.875·v²/(2Δs): this Δs peaks at `decel`.
        stop_point = st.s + 1.875 * std::max(0.0, st.s_d) * std::max(0.0, st.s_d) / (2 * std::max(cfg.stop_decel, 0.1));
    }
    const double nominal_T = cfg.duration.value;
    // follow: a leader beyond reach is closed in on at the driver's pace (decided once per plan,
    // at the nominal duration): its position asks for a mean speed above both speeds + 3 m/s.
    bool leader_beyond = false;
    if (cfg.kind == ManeuverKind::follow && leader != nullptr && leader->state.s_d >= kStopSpeed) {
        const double vl = leader->state.s_d;
        const double ts = leader->state.s + vl * nominal_T - 0.5 * (leader->length_m + req.length_m) -
                          std::max(cfg.stop_distance, cfg.time_gap * vl);
        leader_beyond = (ts - st.s) / nominal_T > std::max(st.s_d, vl) + kCloseInSpeed;
    }
    const Footprint own = footprint(req.length_m, req.width_m);
    // Obstacle footprints once per plan, not per candidate and point (reused buffer).
    thread_local std::vector<Footprint> footprints;
    thread_local std::vector<char> vetoes;
    // An obstacle already within the margin at the start (passing close beside it) rejects only
    // candidates whose circles touch it: else every candidate is rejected while the vehicle
    // passes, and it brakes beside the obstacle it is leaving behind.
    thread_local std::vector<double> start_clear;
    footprints.clear();
    vetoes.clear();
    start_clear.clear();
    for (const Obstacle& o : req.obstacles) {
        footprints.push_back(footprint(o.length_m, o.width_m));
        vetoes.push_back(is_follower(o, st, req.length_m, req.width_m) ? 0 : 1);
        start_clear.push_back(margin_floor(clearance(own, st.s, st.d, footprints.back(), o.state.s, o.d_at(0))));
    }
    const int n_eval = std::max(2, k.eval_points);

    double best = std::numeric_limits<double>::infinity();
    int index = -1;
    for (double a_val : ws.a) {
        for (double b_val : ws.b) {
            for (double lat : ws.c) {
                ++index;
                ++rec.candidates;
                Candidate cand;
                double T = b_val;
                double target_v = 0;
                Poly sp;
                const double target_d = lane.center_d + lat;
                switch (cfg.kind) {
                    case ManeuverKind::keep_velocity: {
                        const double dv = std::clamp(a_val - st.s_d, -cfg.max_speed_change, cfg.max_speed_change);
                        target_v = st.s_d + dv;
                        sp = Poly::quartic(st.s, st.s_d, st.s_dd, target_v, 0.0, T);
                        break;
                    }
                    case ManeuverKind::reverse:
                        target_v = -std::fabs(a_val);
                        sp = Poly::quartic(st.s, st.s_d, st.s_dd, target_v, 0.0, T);
                        break;
                    case ManeuverKind::lane_change:
                        // A car cannot move sideways standing still: change lanes at walking
                        // pace at least.
                        target_v = std::max(st.s_d, kMinLaneChangeSpeed);
                        sp = Poly::quartic(st.s, st.s_d, st.s_dd, target_v, 0.0, T);
                        break;
                    case ManeuverKind::follow: {
                        if (leader == nullptr) {
                            target_v = st.s_d;
                            sp = Poly::quartic(st.s, st.s_d, st.s_dd, target_v, 0.0, T);
                            break;
                        }
                        const double vl = leader->state.s_d;
                        const double half = 0.5 * (leader->length_m + req.length_m);
                        const double cap = cfg.follow_speed > 0 ? cfg.follow_speed : kInfSpeed;
                        double ts;
                        if (vl < kStopSpeed) {
                            ts = leader->state.s + vl * T - half - cfg.stop_distance;
                            target_v = 0;
                        } else {
                            ts = leader->state.s + vl * T - half - std::max(cfg.stop_distance, cfg.time_gap * vl);
                            target_v = vl;
                        }
                        // A leader faster than the driver wants to go, or beyond reach in T at
                        // a comfortable pace: drive at the driver's speed (closing in), not
                        // after the leader's position.
                        const double close_v = std::min(cap, std::max(vl, 0.0) + kCloseInSpeed);
                        if (vl > cap || leader_beyond) {
                            target_v = vl > cap ? cap : close_v;
                            sp = Poly::quartic(st.s, st.s_d, st.s_dd, target_v, 0.0, T);
                            break;
                        }
                        cand.target_s = ts;
                        sp = Poly::quintic(st.s, st.s_d, st.s_dd, ts, target_v, 0.0, T);
                        break;
                    }
                    case ManeuverKind::cut_in: {
                        if (target == nullptr) {
                            target_v = st.s_d;
                            sp = Poly::quartic(st.s, st.s_d, st.s_dd, target_v, 0.0, T);
                            break;
                        }
                        const double vt = target->state.s_d;
                        const double ahead = cfg.gap_from_reference ? 2 * req.length_m : 0.5 * (req.length_m + target->length_m);
                        const double ts = target->state.s + vt * T + ahead + a_val;
                        target_v = vt + cfg.delta_v;
                        cand.target_s = ts;
                        sp = Poly::quintic(st.s, st.s_d, st.s_dd, ts, target_v, cfg.delta_a, T);
                        break;
                    }
                    case ManeuverKind::stop: {
                        const double ds = std::max(0.0, stop_point - st.s);
                        const double t_rest = std::sqrt(5.77 * ds / kStopAcc);
                        T = std::max(1.0, b_val * std::min(2.0 * ds / std::max(st.s_d, 1.0), t_rest));
                        const double stop_ds = ds;
                        cand.target_s = st.s + stop_ds;
                        sp = Poly::quintic(st.s, st.s_d, st.s_dd, st.s + stop_ds, 0.0, 0.0, T);
                        break;
                    }
                    // Pedestrian maneuvers never reach the planner (the checker keeps them out
                    // of vehicles' trees); keeping the speed is the harmless answer.
                    case ManeuverKind::walk:
                    case ManeuverKind::stand:
                    case ManeuverKind::wait_at_crosswalk:
                    case ManeuverKind::enter_crosswalk:
                    case ManeuverKind::exit_crosswalk:
                    case ManeuverKind::turn_back:
                    case ManeuverKind::select_crosswalk:
                    case ManeuverKind::speed_up:
                        target_v = st.s_d;
                        sp = Poly::quartic(st.s, st.s_d, st.s_dd, target_v, 0.0, T);
                        break;
                }
                const Poly dp = Poly::quintic(st.d, st.d_d, st.d_dd, target_d, 0.0, 0.0, T);
                cand.duration = T;
                if (ws.keep_candidates) {
                    cand.s = sp;
                    cand.d = dp;
                }
                cand.target_v = target_v;
                cand.target_d = target_d;

                // Feasibility and the per-point cost accumulators in one pass over the points.
                RejectCause cause = RejectCause::count_;
                double sum_lj2 = 0, sum_dj2 = 0, sum_la2 = 0, sum_da2 = 0, sum_off = 0;
                double min_clear = std::numeric_limits<double>::infinity();
                const double dt = T / (n_eval - 1);
                for (int e = 0; e < n_eval && cause == RejectCause::count_; ++e) {
                    const double t = e * dt;
                    const double sj = sp.j(t), dj = dp.j(t), sa = sp.a(t), da = dp.a(t);
                    sum_lj2 += sj * sj;
                    sum_dj2 += dj * dj;
                    sum_la2 += sa * sa;
                    sum_da2 += da * da;
                    if (std::fabs(sj) > k.max_long_jerk) cause = RejectCause::long_jerk;
                    else if (std::fabs(dj) > k.max_lat_jerk) cause = RejectCause::lat_jerk;
                    else if (std::fabs(sa) > k.max_long_acc) cause = RejectCause::long_acc;
                    else if (std::fabs(da) > k.max_lat_acc) cause = RejectCause::lat_acc;
                    if (cause != RejectCause::count_) break;
                    const double s = sp.x(t), d = dp.x(t);
                    sum_off += std::fabs(d - target_d);
                    for (size_t oi = 0; oi < req.obstacles.size(); ++oi) {
                        const Obstacle& o = req.obstacles[oi];
                        const double os = o.state.s + o.state.s_d * t;
                        const double od = o.d_at(t);
                        const double reach = 0.5 * (req.length_m + o.length_m) + 6.0;
                        if (std::fabs(os - s) > reach || std::fabs(od - d) > 6.0) continue;
                        const double clear = clearance(own, s, d, footprints[oi], os, od);
                        min_clear = std::min(min_clear, clear);
                        // A moving vehicle predicted into one standing still is its own
                        // driver's conflict, not a reason to reject standing still.
                        auto standing_hit = [&] {
                            return std::fabs(o.state.s_d) + std::fabs(o.state.d_d) > kStandingSpeed &&
                                   std::fabs(sp.v(t)) < kStandingSpeed && std::fabs(dp.v(t)) < kStandingSpeed;
                        };
                        if (k.collision && clear < start_clear[oi] && vetoes[oi] && !standing_hit()) {
                            cause = RejectCause::collision;
                            break;
                        }
                    }
                    if (cause != RejectCause::count_) break;
                    if (check_off_lane &&
                        (d + 0.5 * req.width_m > allow_left + 1e-6 || d - 0.5 * req.width_m < allow_right - 1e-6)) {
                        cause = RejectCause::off_lane;
                    } else if (check_direction && sp.v(t) < -0.01) {
                        cause = RejectCause::direction;
                    }
                }
                if (cause != RejectCause::count_) {
                    ++rec.rejections[static_cast<size_t>(cause)];
                    cand.cause = cause;
                    if (ws.keep_candidates) ws.candidates.push_back(cand);
                    continue;
                }
                ++rec.feasible;
                cand.feasible = true;
                CostTerms& c = cand.cost;
                const double n = n_eval;
                c.time = k.w_time * logistic(cfg.kind == ManeuverKind::stop ? 0.0 : std::fabs(T - nominal_T));
                double v_goal = target_v;
                if (req.speed_limit_mps > 0 && cfg.kind == ManeuverKind::keep_velocity) v_goal = std::min(v_goal, req.speed_limit_mps);
                const double mean_v = (sp.x(T) - sp.x(0)) / T;
                if (k.efficiency_reference) {
                    // GeoScenario's effic_cost, called with the nominal duration where a target
                    // speed is meant: it falls as the mean speed rises, whatever the target.
                    c.efficiency = cfg.kind == ManeuverKind::stop || mean_v == 0 ? 0.0 : k.w_efficiency * logistic(2 * (nominal_T - mean_v) / mean_v);
                } else {
                    c.efficiency = k.w_efficiency * logistic(cfg.kind == ManeuverKind::stop ? 0.0 : std::fabs(mean_v - v_goal));
                }
                c.lane_offset = k.w_lane_offset * logistic(sum_off / n / k.expected_offset);
                c.long_jerk = k.w_long_jerk * logistic(std::sqrt(sum_lj2 / n) / k.expected_jerk);
                c.lat_jerk = k.w_lat_jerk * logistic(std::sqrt(sum_dj2 / n) / k.expected_jerk);
                c.long_acc = k.w_long_acc * logistic(std::sqrt(sum_la2 / n) / k.expected_acc);
                c.lat_acc = k.w_lat_acc * logistic(std::sqrt(sum_da2 / n) / k.expected_acc);
                c.proximity = std::isinf(min_clear) ? 0.0 : k.w_proximity * logistic(1.0 / std::max(min_clear, 0.1));
                c.total = c.time + c.efficiency + c.lane_offset + c.long_jerk + c.lat_jerk + c.long_acc + c.lat_acc + c.proximity;
                if (ws.keep_candidates) ws.candidates.push_back(cand);
                if (c.total < best) {
                    best = c.total;
                    rec.winner = index;
                    rec.winner_cost = c;
                    result.trajectory.s = sp;
                    result.trajectory.d = dp;
                    result.trajectory.duration = T;
                }
            }
        }
    }
    if (rec.winner < 0) {
        result.trajectory = plan_fallback(st, k.max_long_acc);
        rec.fallback = true;
    }
    return result;
}

}  // namespace sdv::planner
