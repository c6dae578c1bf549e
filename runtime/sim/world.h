// The state of one run, shared by every stage of the loop: the road, the agents with their
// state, and the snapshot that planning reads. An agent is its common state (pose, lane, goal)
// plus a model that moves it (agents.h) and, for agents that plan, a driver (their behavior tree,
// reference line and plans). The stages are functions over this state: advance (agents.h),
// perceive (perception.h), tick the tree (leaves.h, conditions.cpp), plan (planning.h), ground
// truth (ground_truth.h); loop.cpp runs them in order.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "runtime/bt/behavior_tree.h"
#include "runtime/ir/ir.h"
#include "runtime/planner/planner.h"
#include "runtime/road/road_network.h"
#include "runtime/sim/road_cache.h"
#include "runtime/road/routing.h"
#include "runtime/sim/grid.h"
#include "runtime/sim/simulation.h"

namespace sdv::sim {

using road::kNoLane;
using road::LaneId;

// Bounds of the start accelerations of a plan: no vehicle accelerates beyond them (the
// catalog's default max_long_acc and max_lat_acc).
inline constexpr double kMaxStartAcc = 12.0;    // m/s²
inline constexpr double kMaxStartLatAcc = 4.9;  // m/s²
inline constexpr double kRestSpeed = 0.01;      // m/s: slower than this a vehicle is at rest

// A plan in force: a Frenet trajectory in its own frame, from its start time.
struct ActivePlan {
    planner::Trajectory traj;
    double start = 0;
    std::shared_ptr<const road::ReferenceLine> ref;
    int32_t maneuver = -1;  // the tree node whose plan it is (-1: initial or fallback)
};

// One agent in the snapshot: what every planner reads of it at t0 (immutable while planning).
struct Snap {
    double x = 0, y = 0, yaw = 0, vx = 0, vy = 0, speed = 0, accel = 0;
    double length = 4.5, width = 1.8;
    LaneId lane = kNoLane;
    bool is_static = false;
    bool pedestrian = false;
    double stopped_since = -1;
    int32_t maneuver = -1;
    bool active = true;  // false: gone from the run (left the road network)
    double lane_s = 0;             // arc length on `lane`
    LaneId target_lane = kNoLane;  // the lane a running lane change / cut-in moves into
    double lane_move_since = 0;    // when that move began
    double lateral_to_go = NAN;    // lateral motion left in its plan in force (NaN: no plan)
    // A simulated pedestrian's readable intent (its body language to a driver): the crosswalk it
    // is heading for or waiting at to cross (-1: none). `intent` is false for pedestrians that
    // follow waypoints, whose intent no one can read.
    int32_t crossing_at = -1;
    bool intent = false;
    LaneId stopped_line = kNoLane;  // the lane at whose stop line it last came to a stop
    double stopped_line_since = 0;  // when it first came to rest there
    bool is_object = false;         // an obstacle (`object`), not a parked vehicle
};

// One planning cycle as the decision trace shows it (kept only with RunOptions::trace).
struct PlanTrace {
    struct Path {
        const char* status = "";                // winner, feasible or the rejection cause
        std::array<double, 12> xy{};            // 6 world points along the candidate
    };
    double time = 0;
    uint32_t plan_number = 0;
    std::vector<bt::Visit> visits;
    std::string maneuver;       // the selected leaf's name
    catalog::ManeuverKind kind = catalog::ManeuverKind::keep_velocity;
    planner::PlanRecord record;
    planner::FrenetState start;
    std::vector<Path> paths;
    const char* fallback = nullptr;  // what the cycle did without a feasible candidate
};

// What an agent that plans owns: its tree, the reference line along its route, its plans.
struct Driver {
    std::unique_ptr<bt::BehaviorTree> tree;
    std::vector<LaneId> path;
    std::vector<double> path_start;  // s where each path lane starts on `ref`
    std::shared_ptr<const road::ReferenceLine> ref;
    double ref_s = -1;  // last projection on `ref` (search hint)
    std::optional<ActivePlan> plan, pending;
    int32_t maneuver = -1;  // selected node
    std::string maneuver_name = "none";
    LaneId target_lane = kNoLane;  // of a running lane change / cut-in
    // The lane a lane change or cut-in has been moving into since when (kNoLane: none).
    LaneId lane_move_target = kNoLane;
    double lane_move_since = 0;
    // A cut-in: its node, the plan count when last ticked, when it began, whether it reached
    // the target lane, when its end state is due (−1: not planned yet), whether it ended.
    struct CutIn {
        int32_t node = -1;
        uint32_t ticked = 0;
        double since = 0, due = -1;
        double target_v = 0;  // the target's speed its plan assumed
        bool in_lane = false, done = false;
    } cut_in;
    uint32_t plan_count = 0;
    // `wait` timers: node index → (time first ticked, plan_count of the last tick).
    std::map<int32_t, std::pair<double, uint32_t>> waits;
    // The stop line whose red or yellow light this driver decided to stop at (stop_for_light),
    // until the light is green again.
    const road::StopLine* light_stop = nullptr;
    // Results of the last cycle (written by the planning thread, applied in vehicle order).
    bool fallback = false;               // this cycle braked for want of a feasible plan
    const char* fallback_kind = nullptr;  // previous_plan, hold, comfortable_stop, emergency_stop
    int candidates = 0;
    double plan_us = 0;
    std::optional<PlanTrace> trace;
};

// What a simulated pedestrian (sdp) owns: its tree and its intent, which its maneuvers set and
// its motion model (social force, pedestrian.cpp) follows: where it walks and how fast.
struct Walker {
    std::unique_ptr<bt::BehaviorTree> tree;
    road::Vec2 goal;        // where it walks to (without one: straight ahead, far away)
    bool has_goal = false;
    double base_speed = 1.4;  // the desired speed the last walking maneuver set
    double speed = 1.4;       // desired speed now (0: it stands)
    double arrive = 0.3;      // a point of the way within this is reached
    // Its target crosswalk and where it is with it: approaching (off it, heading for the
    // entrance, where it stops), crossing (on it, to the far end), back (returning to the
    // entrance), done (left it at the far end).
    int32_t crosswalk = -1;
    int entrance = 0;  // the end it enters by: 0 the first point of the centre line, 1 the last
    double cross_offset = 0;  // across the crosswalk, from its centre line (left positive)
    enum class Phase { none, approaching, crossing, back, done } phase = Phase::none;
    int32_t maneuver = -1;
    std::string maneuver_name = "none";
    uint32_t cycles = 0;  // tree ticks so far
    double cycle_time = 0;  // of the last tick
    double located_x = NAN, located_y = NAN;  // where its lane was last searched (pedestrian.cpp)
    std::vector<bt::Visit> visits;  // of the last tick (kept only with RunOptions::trace)
    std::map<int32_t, std::pair<double, uint32_t>> waits;  // `wait` timers, as Driver's
};

class AgentModel;

struct Agent {
    const ir::Vehicle* v = nullptr;
    int index = 0;
    // Cartesian state
    double x = 0, y = 0, yaw = 0, vx = 0, vy = 0, ax = 0, ay = 0;
    double speed = 0, accel = 0, prev_accel = 0;
    // The lane the agent drives in (an SDV: the lane of its path under it) and its coordinates
    // on that lane; the lane its centre is in (kNoLane: off every lane).
    LaneId lane = kNoLane;
    double lane_s = 0, lane_d = 0;
    LaneId centre_lane = kNoLane;
    // Left the road network past the end of a lane without successor: no longer simulated.
    bool past_road_end = false;
    bool active = true;
    // A trajectory agent whose first waypoint is later than 0 s enters the run then (inactive
    // until then, as a recorded road user who enters the recorded area); < 0: none.
    double enters_at = -1;
    bool off_lanes = false;  // the centre is off every lane (an off_road episode)
    bool crashed = false;    // in a collision: stands where it hit, no longer driven
    double stopped_since = -1;
    // Route and goal
    std::vector<road::RouteStep> route;
    LaneId goal_lane = kNoLane;
    double goal_s = 0;
    bool goal_reached = false;
    double goal_dist = -1;  // along-track distance to the goal once within reach (< 0: not yet)
    LaneId stopped_line = kNoLane;  // the lane at whose stop line the agent last came to a stop
    double stopped_gap = 0;         // its front bumper's distance to that line then
    double stopped_line_since = 0;  // when it first came to rest there (its arrival at the line)
    std::shared_ptr<const AgentModel> model;
    std::unique_ptr<Driver> driver;  // agents that plan (SDVs)
    std::unique_ptr<Walker> walker;  // simulated pedestrians
    // A path agent: its points, their speeds, the distance along the path at each, and how far
    // it has gone.
    std::vector<road::Vec2> path_points;
    std::vector<double> path_speeds, path_cum;
    double path_s = 0;
    int32_t meet = -1;  // the agent it times its motion to meet (ir::Vehicle::meet), -1: none
    // An agent driven from outside (co-simulation): its state at the next tick, set before the
    // step that moves it there (box centre, heading, signed speed and acceleration).
    struct ExternalState {
        double x = 0, y = 0, yaw = 0, speed = 0, accel = 0;
        bool active = true;
    };
    std::optional<ExternalState> external;
};

struct World {
    World(const ir::Program& p, int scenario_index, const RunOptions& opt)
        : program(p), scenario(p.scenarios.at(static_cast<size_t>(scenario_index))), options(opt) {}

    const ir::Program& program;
    const ir::Scenario& scenario;
    RunOptions options;
    road::RoadNetwork net;
    std::vector<Agent> agents;
    std::vector<Snap> snapshot;
    Grid grid;  // the snapshot's agents by position (cells of the sensor range)
    double widest_reach = 0;  // m: the largest half diagonal of any agent (set by init)
    // Reference lines of the drivers' paths (runtime/sim/road_cache.h): this run's own, or
    // those shared through RunOptions::roads.
    std::shared_ptr<PathCache> paths = std::make_shared<PathCache>();
    double dt = 1.0 / 30;
    double latency = 1.0 / 3;
    uint64_t seed = 0;
    std::map<std::string, const ir::LightProgram*> programs;  // by light name

    // Builds the road and places every agent; returns a located error message, or "".
    std::string init();
    std::string light_state(int32_t light, double t) const;
    // |goal s − own s| along the agent's path (or its lane); nullopt when the goal lane is not
    // ahead on it.
    std::optional<double> goal_distance(const Agent& a) const;
    // A position of the IR as a lane and s on it; returns an error message, or "".
    std::string locate(const ir::Position& pos, LaneId& lane, double& s) const;
    std::string where(const ir::SourceLoc& loc) const;  // "file:line:col"

private:
    std::string build_road();
    std::string make_road(road::RoadNetwork& out) const;
    std::string place_agent(Agent& a);
    std::string place_walking(Agent& a);
    void enter_later(Agent& a) const;  // a trajectory that starts after 0 s: inactive until then
    // A position of the IR as a point (lane positions with their offset); an error, or "".
    std::string point(const ir::Position& pos, road::Vec2& out) const;
};

// Fixed-point text of a number as every output writes it ("-0.0000" printed as "0.0000").
std::string fmt(double v, int digits = 4);

}  // namespace sdv::sim
