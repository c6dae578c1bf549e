// The lockstep loop: every tick advances each agent by its model, takes the snapshot, observes
// ground truth, reports the tick, then runs the planning cycles due at this tick (in parallel
// over the snapshot, applied and reported in vehicle order).
#include <algorithm>
#include <chrono>
#include <thread>

#include "runtime/sim/agents.h"
#include "runtime/sim/pool.h"
#include "runtime/sim/expectations.h"
#include "runtime/sim/ground_truth.h"
#include "runtime/sim/pedestrian.h"
#include "runtime/sim/planning.h"
#include "runtime/sim/progress.h"
#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"

namespace sdv::sim {
namespace {

// How far sideways an SDV's plan in force still moves it (frame-free: end minus now).
double lateral_to_go(const Agent& a, double t) {
    if (!a.driver || !a.driver->plan) return NAN;
    const ActivePlan& p = *a.driver->plan;
    return p.traj.d.x(p.traj.duration) - p.traj.d.x(std::clamp(t - p.start, 0.0, p.traj.duration));
}

void take_snapshot(World& w, double t) {
    w.snapshot.resize(w.agents.size());
    for (size_t i = 0; i < w.agents.size(); ++i) {
        const Agent& a = w.agents[i];
        w.snapshot[i] = {a.x, a.y, a.yaw, a.vx, a.vy, a.speed, a.accel, a.v->length, a.v->width, a.lane,
                         a.v->kind == ir::VehicleKind::static_object, a.v->pedestrian, a.stopped_since, a.driver ? a.driver->maneuver : -1, a.active, a.lane_s,
                         a.driver ? a.driver->target_lane : kNoLane, a.driver ? a.driver->lane_move_since : 0,
                         lateral_to_go(a, t)};
        w.snapshot[i].stopped_line = a.stopped_line;
        w.snapshot[i].stopped_line_since = a.stopped_line_since;
        w.snapshot[i].is_object = a.v->object;
        if (a.walker) {
            w.snapshot[i].intent = true;
            w.snapshot[i].crossing_at = a.walker->phase == Walker::Phase::approaching ? a.walker->crosswalk : -1;
        }
    }
    thread_local std::vector<double> xs, ys;
    thread_local std::vector<char> on;
    xs.resize(w.snapshot.size());
    ys.resize(w.snapshot.size());
    on.resize(w.snapshot.size());
    for (size_t i = 0; i < w.snapshot.size(); ++i) {
        xs[i] = w.snapshot[i].x;
        ys[i] = w.snapshot[i].y;
        on[i] = w.snapshot[i].active ? 1 : 0;
    }
    w.grid.build(xs, ys, on, w.scenario.sensor_range);
}

}  // namespace

struct Simulation::State {
    State(const ir::Program& p, int scenario, const RunOptions& options, RunObserver* obs)
        : world(p, scenario, options), observer(obs) {}
    World world;
    RunObserver* observer;
    RunResult out;
    std::optional<GroundTruth> truth;
    std::optional<ProgressMonitor> progress;
    size_t events_reported = 0;  // events the progress callback has been given
    std::optional<Pool> pool;
    std::chrono::steady_clock::time_point wall0;
    int total_ticks = 0, period = 1, tick = 0;
    bool started = false, ended = false, finished = false;
    std::vector<Agent*> due;
};

Simulation::Simulation(const ir::Program& program, int scenario, const RunOptions& options, RunObserver* observer)
    : s_(std::make_unique<State>(program, scenario, options, observer)) {}

Simulation::~Simulation() = default;

// Moves every agent to tick `tick`, takes the snapshot, observes ground truth and reports.
void Simulation::advance_to(int tick) {
    State& st = *s_;
    World& w = st.world;
    RunResult& out = st.out;
    const double t = tick * w.dt;
    st.tick = tick;
    // 1. Advance every agent to time t (each writes only its own agent: in parallel).
    st.pool->run(w.agents.size(), [&](size_t i) {  // a few µs each: in parallel from 256 agents
        Agent& a = w.agents[i];
        if (!a.active && a.enters_at >= 0 && t >= a.enters_at - 1e-9) {
            a.active = true;  // a trajectory agent's first waypoint time: it enters the run
            a.enters_at = -1;
        }
        if (!a.active) return;
        if (a.crashed) {
            // A collision ends a vehicle's motion: it stands where it hit (SPEC §3.10).
            a.vx = a.vy = a.ax = a.ay = a.speed = a.accel = 0;
            return;
        }
        a.model->advance(w, a, t, tick);
        if (std::fabs(a.speed) < 0.1) {
            if (a.stopped_since < 0) a.stopped_since = t;
        } else {
            a.stopped_since = -1;
        }
    }, 256);
    for (Agent& a : w.agents) {
        if (a.active && !a.crashed && a.past_road_end) {
            // Off the end of the road network: the agent leaves the run here.
            a.active = false;
            out.events.push_back({t, "left_road", {a.index}, 0, ""});
        }
    }
    // 2. Snapshot; 3. ground truth; 4. report.
    take_snapshot(w, t);
    const size_t events_before = out.events.size();
    st.truth->observe(w, t, tick, &*st.pool);
    for (size_t e = events_before; e < out.events.size(); ++e) {
        if (out.events[e].kind != "collision") continue;
        for (int v : out.events[e].vehicles) {
            Agent& crashed = w.agents[static_cast<size_t>(v)];
            if (crashed.v->kind != ir::VehicleKind::static_object) crashed.crashed = true;
        }
    }
    st.progress->observe(w, t, out);
    if (st.observer) st.observer->tick(w, tick, t);
    if (tick == st.total_ticks || st.truth->ended()) st.ended = true;
}

std::string Simulation::start() {
    State& st = *s_;
    if (st.started) return "";
    st.started = true;
    World& w = st.world;
    st.out.scenario = w.scenario.name;
    if (auto e = w.init(); !e.empty()) {
        st.out.error = e;
        st.ended = true;
        return e;
    }
    st.wall0 = std::chrono::steady_clock::now();
    st.total_ticks = static_cast<int>(std::llround(w.scenario.timeout / w.dt));
    st.period = std::max(1, static_cast<int>(std::llround(w.scenario.traffic_rate / w.scenario.planning_rate)));
    st.truth.emplace(w.agents.size(), st.out);
    st.progress.emplace(w.agents.size());
    st.pool.emplace(std::max(1, w.options.threads));
    if (st.observer) st.observer->start(w);
    const auto tick0 = std::chrono::steady_clock::now();
    advance_to(0);
    st.out.timing.tick_us.add(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - tick0).count());
    return "";
}

bool Simulation::step() {
    State& st = *s_;
    if (!st.started || st.ended || st.finished) return false;
    World& w = st.world;
    RunResult& out = st.out;
    const auto tick0 = std::chrono::steady_clock::now();
    const int tick = st.tick;
    const double t = tick * w.dt;
    // 5. Planning of the drivers due at this tick (from its snapshot), applied in vehicle order.
    auto& due = st.due;
    due.clear();
    for (Agent& a : w.agents) {
        if (a.driver && a.active && !a.crashed && (tick + a.index) % st.period == 0) due.push_back(&a);
    }
    st.pool->run(due.size(), [&](size_t i) { plan_cycle(w, *due[i], t); }, 4);  // tens of µs each
    for (Agent* a : due) {
        const Driver& d = *a->driver;
        VehicleMetrics& vm = out.vehicles[static_cast<size_t>(a->index)];
        ++vm.plans;
        out.timing.plan_us.add(d.plan_us);
        out.timing.candidates += d.candidates;
        if (d.fallback) {
            ++vm.fallback_plans;
            if (!vm.fallback_used) out.events.push_back({t, "fallback", {a->index}, 0, ""});
            vm.fallback_used = true;
        }
        if (st.observer) st.observer->plan(w, *a);
    }
    // The pedestrians' trees due at this tick, over the same snapshot (a few µs each, in order).
    for (Agent& a : w.agents) {
        if (a.walker && a.active && !a.crashed && (tick + a.index) % st.period == 0) {
            walk_cycle(w, a, t);
            if (st.observer) st.observer->plan(w, a);
        }
    }
    // Then the next tick.
    advance_to(tick + 1);
    out.timing.tick_us.add(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - tick0).count());
    if (w.options.realtime) std::this_thread::sleep_until(st.wall0 + std::chrono::duration<double>((tick + 1) * w.dt));
    if (w.options.progress && ((tick + 1) % 30 == 0 || out.events.size() != st.events_reported)) {
        st.events_reported = out.events.size();
        w.options.progress((tick + 1) * w.dt, static_cast<double>(tick + 1) / st.total_ticks, out.events);
    }
    return true;
}

bool Simulation::ended() const { return s_->ended; }
int Simulation::tick() const { return s_->tick; }
double Simulation::time() const { return s_->tick * s_->world.dt; }
World& Simulation::world() { return s_->world; }
const World& Simulation::world() const { return s_->world; }
const RunResult& Simulation::result() const { return s_->out; }

RunResult Simulation::finish() {
    State& st = *s_;
    if (!st.started) start();
    if (st.finished || !st.out.error.empty()) {
        st.finished = true;
        return st.out;
    }
    st.finished = true;
    RunResult& out = st.out;
    st.truth->finish();
    out.ticks = st.tick;
    out.duration = st.tick * st.world.dt;
    out.timed_out = !st.truth->ended() && st.tick == st.total_ticks;
    if (out.timed_out) out.events.push_back({out.duration, "timeout", {}, 0, ""});
    std::stable_sort(out.events.begin(), out.events.end(), [](const Event& a, const Event& b) { return a.time < b.time; });
    out.timing.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - st.wall0).count();
    evaluate_expectations(st.world.scenario, out);
    return out;
}


bool RunResult::passed() const {
    return error.empty() && std::all_of(expectations.begin(), expectations.end(), [](const ExpectResult& e) { return e.passed; });
}

RunResult simulate(const ir::Program& program, int scenario, const RunOptions& options, RunObserver* observer) {
    RunResult out;
    if (scenario < 0 || static_cast<size_t>(scenario) >= program.scenarios.size()) {
        out.error = "no such scenario";
        return out;
    }
    Simulation sim(program, scenario, options, observer);
    if (auto e = sim.start(); !e.empty()) return sim.finish();
    while (sim.step()) {
    }
    return sim.finish();
}

}  // namespace sdv::sim
