// One planning cycle of an SDV (SPEC §3.6–3.7): from a maneuver configuration and a traffic
// snapshot already projected into the driver's Frenet frame, generate every candidate
// trajectory (Cartesian product of the sampled targets), reject infeasible ones in a fixed
// order of causes, score the rest with logistic-normalised costs and return the cheapest
// (ties by candidate index), or an emergency-brake fallback when nothing is feasible.
#pragma once

#include <limits>

#include <algorithm>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "runtime/planner/maneuver.h"
#include "runtime/planner/polynomial.h"

namespace sdv::planner {

struct FrenetState {
    double s = 0, s_d = 0, s_dd = 0;  // along the reference line: m, m/s, m/s²
    double d = 0, d_d = 0, d_dd = 0;  // to the left of it
};

// Another vehicle or obstacle, predicted at constant Frenet velocity from the plan start.
struct Obstacle {
    int id = 0;
    FrenetState state;
    double length_m = 4.5, width_m = 1.8;
    bool is_static = false;
    // Where its lateral motion stops (a driver moving to its lane's or its target lane's
    // centre): the constant-velocity prediction of d is clamped to [d_min, d_max].
    double d_min = -std::numeric_limits<double>::infinity(), d_max = std::numeric_limits<double>::infinity();
    // Its predicted lateral offset t seconds ahead.
    double d_at(double t) const { return std::clamp(state.d + state.d_d * t, d_min, d_max); }
};

// A lane's lateral extent in the reference frame (left_d > right_d).
struct LaneBand {
    double center_d = 0, left_d = 1.75, right_d = -1.75;
};

struct PlanRequest {
    FrenetState start;
    double length_m = 4.5, width_m = 1.8;
    const ManeuverConfig* config = nullptr;
    LaneBand current_lane;
    LaneBand target_lane;  // lane_change / cut_in; others use current_lane
    std::span<const Obstacle> obstacles;
    int leader = -1;          // follow: index into obstacles
    int target_vehicle = -1;  // cut_in: index into obstacles
    double stop_s = 0;        // stop: resolved stop point (goal, stop line or position)
    double speed_limit_mps = 0;  // > 0: efficiency targets are capped at it
    uint64_t seed = 0;
    uint32_t vehicle = 0;
    uint32_t plan_number = 0;
};

enum class RejectCause { long_jerk, lat_jerk, long_acc, lat_acc, collision, off_lane, direction, count_ };
inline constexpr size_t kCauseCount = static_cast<size_t>(RejectCause::count_);
const char* to_string(RejectCause cause);

struct CostTerms {
    double time = 0, efficiency = 0, lane_offset = 0, long_jerk = 0, lat_jerk = 0, long_acc = 0,
           lat_acc = 0, proximity = 0, total = 0;
};

struct Trajectory {
    Poly s, d;
    double duration = 0;  // after it: constant velocity in s, constant d
    FrenetState at(double t) const;
};

// One candidate, for decision traces.
struct Candidate {
    double duration = 0;
    double target_s = 0, target_v = 0, target_d = 0;
    bool feasible = false;
    RejectCause cause = RejectCause::count_;
    CostTerms cost;
    Poly s, d;  // the trajectory in the Frenet frame (kept only when tracing)
};

struct PlanRecord {
    int candidates = 0;
    int feasible = 0;
    std::array<int, kCauseCount> rejections{};
    int winner = -1;
    CostTerms winner_cost;
    bool fallback = false;
};

struct PlanResult {
    Trajectory trajectory;
    PlanRecord record;
};

// Reusable buffers: no allocation per cycle once warmed up.
struct PlanWorkspace {
    std::vector<double> a, b, c;
    std::vector<Candidate> candidates;
    bool keep_candidates = false;  // fill `candidates` (tracing)
};

PlanResult plan(const PlanRequest& request, PlanWorkspace& workspace);

// Emergency brake within max_long_acc, straight in d (used when nothing is feasible).
Trajectory plan_fallback(const FrenetState& start, double max_decel);

// Whether `trajectory`, from its time `from` for `horizon` seconds, stays clear of the
// request's obstacles (their constant-velocity predictions from the request's start), with the
// planner's footprints and margin. Followers, and every point at which it stands still, are
// never in conflict.
bool stays_clear(const Trajectory& trajectory, double from, double horizon, const PlanRequest& request);

}  // namespace sdv::planner
