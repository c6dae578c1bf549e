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
                         a.v->kind == ir::VehicleKind::static_object, a.stopped_since, a.driver ? a.driver->maneuver : -1, a.active, a.lane_s,
                         a.driver ? a.driver->target_lane : kNoLane, a.driver ? a.driver->lane_move_since : 0,
                         lateral_to_go(a, t)};
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

RunResult run(World& w, RunObserver* observer) {
    RunResult out;
    const ir::Scenario& sc = w.scenario;
    out.scenario = sc.name;
    const auto wall0 = std::chrono::steady_clock::now();
    const int total_ticks = static_cast<int>(std::llround(sc.timeout / w.dt));
    const int period = std::max(1, static_cast<int>(std::llround(sc.traffic_rate / sc.planning_rate)));
    GroundTruth truth(w.agents.size(), out);
    ProgressMonitor progress(w.agents.size());
    const int threads = std::max(1, w.options.threads);
    Pool pool(threads);
    if (observer) observer->start(w);
    int last_tick = 0;
    std::vector<Agent*> due;
    for (int tick = 0; tick <= total_ticks; ++tick) {
        const auto tick0 = std::chrono::steady_clock::now();
        const double t = tick * w.dt;
        // 1. Advance every agent to time t (each writes only its own agent: in parallel).
        pool.run(w.agents.size(), [&](size_t i) {  // a few µs each: in parallel from 256 agents
            Agent& a = w.agents[i];
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
        truth.observe(w, t, tick, &pool);
        for (size_t e = events_before; e < out.events.size(); ++e) {
            if (out.events[e].kind != "collision") continue;
            for (int v : out.events[e].vehicles) {
                Agent& crashed = w.agents[static_cast<size_t>(v)];
                if (crashed.v->kind != ir::VehicleKind::static_object) crashed.crashed = true;
            }
        }
        progress.observe(w, t, out);
        if (observer) observer->tick(w, tick, t);
        last_tick = tick;
        if (tick == total_ticks || truth.ended()) break;
        // 5. Planning of the drivers due at this tick, applied in vehicle order.
        due.clear();
        for (Agent& a : w.agents) {
            if (a.driver && a.active && !a.crashed && (tick + a.index) % period == 0) due.push_back(&a);
        }
        pool.run(due.size(), [&](size_t i) { plan_cycle(w, *due[i], t); }, 4);  // tens of µs each
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
            if (observer) observer->plan(w, *a);
        }
        out.timing.tick_us.add(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - tick0).count());
        if (w.options.realtime) std::this_thread::sleep_until(wall0 + std::chrono::duration<double>((tick + 1) * w.dt));
        if (w.options.progress && tick % 30 == 0) w.options.progress(static_cast<double>(tick) / total_ticks);
    }
    truth.finish();
    out.ticks = last_tick;
    out.duration = last_tick * w.dt;
    out.timed_out = !truth.ended();
    if (out.timed_out) out.events.push_back({out.duration, "timeout", {}, 0, ""});
    std::stable_sort(out.events.begin(), out.events.end(), [](const Event& a, const Event& b) { return a.time < b.time; });
    out.timing.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    evaluate_expectations(sc, out);
    return out;
}

}  // namespace

bool RunResult::passed() const {
    return error.empty() && std::all_of(expectations.begin(), expectations.end(), [](const ExpectResult& e) { return e.passed; });
}

RunResult simulate(const ir::Program& program, int scenario, const RunOptions& options, RunObserver* observer) {
    RunResult out;
    if (scenario < 0 || static_cast<size_t>(scenario) >= program.scenarios.size()) {
        out.error = "no such scenario";
        return out;
    }
    World world(program, scenario, options);
    if (auto e = world.init(); !e.empty()) {
        out.error = e;
        out.scenario = program.scenarios[static_cast<size_t>(scenario)].name;
        return out;
    }
    return run(world, observer);
}

}  // namespace sdv::sim
