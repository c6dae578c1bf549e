// The lockstep simulation of one scenario (SPEC §3.1–3.3, §3.9–3.10). Traffic advances in fixed
// steps (traffic rate, default 30 Hz). Each SDV plans at the planning rate, staggered by
// vehicle: from the snapshot at t0 it predicts its own state at t0 + latency along its current
// plan, projects every perceived vehicle into its Frenet frame (constant velocity), ticks its
// behavior tree, plans the selected maneuver and publishes the plan to start at t0 + latency.
// All SDVs due at a tick read the same immutable snapshot, so their planning runs in parallel
// threads; results are applied in vehicle order. Nothing reads the wall clock: a run is a pure
// function of (IR, seed). The simulation writes no output itself: a RunObserver (runtime/io)
// sees the world at the start, after every tick and after every plan, and writes what it needs.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "runtime/ir/ir.h"

namespace sdv::sim {

class RoadCache;

struct Event {
    double time = 0;
    std::string kind;  // collision, goal_reached, goal_overshot, fallback, timeout
    std::vector<int> vehicles;
    double relative_speed = 0;
    std::string zone;
};

struct RunOptions {
    std::optional<uint64_t> seed;  // overrides the scenario's
    // Roads shared with other runs of this process (runtime/sim/road_cache.h); null: built here.
    std::shared_ptr<RoadCache> roads;
    int threads = 1;
    bool trace = false;             // decisions.jsonl
    bool realtime = false;          // pace to the wall clock (never changes the states)
    // Called every 30 ticks and at every tick that adds events: the simulated time, the
    // fraction of the run done, and the events so far (a terminal's progress line).
    std::function<void(double time, double fraction, const std::vector<Event>& events)> progress;
};

// Metrics of a pair over the run or a window (SPEC §3.10). A minimum never measured stays
// INFINITY (summary.json: null; an expectation compares it as +infinity).
struct PairMetrics {
    int a = 0, b = 0;
    double min_clearance = INFINITY;  // outline clearance: footprint to footprint, any direction
    double min_gap = INFINITY;        // same-lane bumper gap along the lane
    double min_lateral = INFINITY;    // across the heading of either, while side by side
    double min_ttc = INFINITY;        // same lane: bumper gap / closing speed along the lane
    double min_headway = INFINITY;    // same lane: bumper gap / speed of the one behind
};

// Metrics of a vehicle. Accelerations and speeds are signed (along the heading): braking and
// reversing are negative. Extremes never measured stay ±INFINITY (summary.json: null).
struct VehicleMetrics {
    double max_jerk = 0;                             // largest |jerk|
    double min_acc = INFINITY, max_acc = -INFINITY;  // longitudinal
    double min_speed = INFINITY, max_speed = -INFINITY;
    bool reached_goal = false;
    bool fallback_used = false;
    int plans = 0;
    int fallback_plans = 0;     // plans that found no feasible candidate
    double longest_stall_s = 0; // longest time below 0.5 m/s while its tree was not waiting
    double fallback_share() const { return plans > 0 ? static_cast<double>(fallback_plans) / plans : 0.0; }
};

// The metrics of the ticks inside one expectation window (after <= t <= before).
struct WindowMetrics {
    double after = -INFINITY, before = INFINITY;
    std::vector<PairMetrics> pairs;
    std::vector<VehicleMetrics> vehicles;
    bool contains(double t) const { return t >= after - 1e-9 && t <= before + 1e-9; }
};

// One function call of an expectation, with the value it measured.
struct ExpectPart {
    std::string text;              // as written: "min_gap(ego, v2) < 5 m"
    int32_t function = -1;         // catalog::ExpectKind: the metric it checks
    std::optional<double> value;   // a quantity's value (none: never measured, e.g. never closing)
    std::optional<double> time;    // a boolean's first matching event, when there is one
    bool holds = false;            // the call (with its comparison) is true
};

struct ExpectResult {
    std::string text;
    bool passed = false;
    std::optional<double> value;     // the measured quantity of a single comparison
    std::vector<ExpectPart> parts;   // every call of the expression, in source order
    ir::SourceLoc loc;
};

// Durations (µs) kept as a log-spaced histogram: percentiles to within 1 %, in constant memory
// whatever the run's length or vehicle count (a run of 10,000 SDVs makes 10^7 plans).
class Samples {
public:
    void add(double us);
    long long count() const { return count_; }
    double max() const { return max_; }
    // The p-quantile (0 <= p <= 1; 1 is the maximum); 0 when empty.
    double percentile(double p) const;
    // The share of samples <= limit (to the histogram's resolution); 1 when empty.
    double share_below(double limit) const;

private:
    std::vector<long long> buckets_;
    long long count_ = 0;
    double max_ = 0;
};

struct Timing {
    double wall_s = 0;
    Samples tick_us, plan_us;
    long long candidates = 0;
};

struct RunResult {
    std::string error;  // a runtime error (vehicle off the road, unreachable goal), with location
    std::string scenario;
    int ticks = 0;
    double duration = 0;
    bool timed_out = false;
    std::vector<Event> events;
    std::vector<PairMetrics> pairs;
    std::vector<VehicleMetrics> vehicles;
    std::vector<WindowMetrics> windows;  // one per distinct window of the expectations
    std::vector<ExpectResult> expectations;
    Timing timing;
    bool passed() const;
};

struct World;
struct Agent;
struct PlanTrace;

// What watches a run, called on the simulation's thread in a deterministic order: `start` once
// the world is built, `tick` after every tick's ground truth, `plan` for every planning cycle in
// vehicle order (its trace is set only with RunOptions::trace).
class RunObserver {
public:
    virtual ~RunObserver() = default;
    virtual void start(const World& world) { (void)world; }
    virtual void tick(const World& world, int tick, double time) {
        (void)world;
        (void)tick;
        (void)time;
    }
    virtual void plan(const World& world, const Agent& agent) {
        (void)world;
        (void)agent;
    }
};

// A run taken one tick at a time (co-simulation drives it; simulate() runs one to its end).
// Tick k's step plans every SDV due at k from the snapshot at k, then moves every agent to
// k+1 (agents driven from outside take the state set on them for k+1), takes the snapshot at
// k+1 and its ground truth: a Jacobi step, independent of who sets what when.
class Simulation {
public:
    Simulation(const ir::Program& program, int scenario, const RunOptions& options, RunObserver* observer = nullptr);
    ~Simulation();
    Simulation(const Simulation&) = delete;
    Simulation& operator=(const Simulation&) = delete;
    // Builds the world and takes tick 0; a located error message, or "".
    std::string start();
    // One step k → k+1; false (and nothing done) once the run has ended.
    bool step();
    // The run has ended: its timeout, or an end condition (a goal that ends it, a collision...).
    bool ended() const;
    int tick() const;
    double time() const;
    World& world();
    const World& world() const;
    // The result so far: events as they happen (in time order), metrics of the ticks so far.
    const RunResult& result() const;
    // Ends the run (at any tick): final metrics and the expectations' verdicts.
    RunResult finish();

private:
    struct State;
    void advance_to(int tick);
    std::unique_ptr<State> s_;
};

// Builds the world (roads, vehicles, trees) of one scenario and runs it, reporting to
// `observer` when given.
RunResult simulate(const ir::Program& program, int scenario, const RunOptions& options, RunObserver* observer = nullptr);

}  // namespace sdv::sim
