// Pedestrians (issue 18, "Numbers"): what a simulated pedestrian costs per tick, and how fast a
// crossing scene with 100 of them and 20 SDVs runs on one core (target: >= 100x real time).
//
// The scene (generated here, seeded): a straight 1 km road, 2 lanes each way of 3.5 m, 50 km/h,
// three crosswalks 4 m wide at s = 350 m (signalised, vehicles green 12 s / yellow 3 s / red 20 s),
// 500 m (unsignalised: pedestrians wait for a gap, vehicles yield) and 650 m (signalised, the same
// cycle 17.5 s later). N pedestrians (std.walk, 1.1..1.6 m/s) start on both kerbs within 12 m of a
// crosswalk (so they choose it) and walk to a goal on the other kerb, 4..12 m to either side of
// the crosswalk (--goals-near-ends: 0..12 m, see below); M SDVs (std.drive, 12 m/s) start in all
// four lanes, 25 m apart per lane, half each way, and drive to goals 110..150 m past the last
// crosswalk. 120 simulated seconds.
//
// Reports, on one thread (RunOptions::threads = 1), over --repeat runs of each:
//  - the scene's real-time factor (simulated s / wall s) median, p10 and p90, the same by the
//    process's CPU time (on a loaded machine the wall clock counts others' time slices too), and
//    the per-tick wall time percentiles of sim::RunResult::timing (the median over runs of each
//    percentile); the same for the scene without pedestrians (SDVs only) and without SDVs
//    (pedestrians only); the CPU time with minus without pedestrians, per pedestrian and tick, is
//    their whole marginal cost (motion, trees, ground-truth pairs, and what the SDVs spend
//    perceiving and yielding to them);
//  - micro-benchmarks of the parts, per pedestrian per call:
//    (a) social_force::force + step alone, for crowds of K pedestrians in a disc 20 m across (every
//        one's neighbours: the others within 12 m, as the walker model gathers them) and 2 cars;
//    (b) the walker model's advance on the live scene (grid query, gathering neighbours, force,
//        step, locating its lane), at checkpoints every 5 s, each pedestrian's state restored, and
//        the part of it that locates the pedestrian on the road (RoadNetwork::locate) alone;
//    (c) walk_cycle (one tick of its std.walk tree) on the live scene at the same checkpoints
//        (a tree runs at the planning rate: every 10th tick at 30 / 3 Hz);
//  - whether the scene is sane: goal_reached events, what the other pedestrians are doing at the
//    end, pedestrians at their goal still moving, SDVs at their goal (the others on stderr: where,
//    in which maneuver), collisions by kind (each listed on stderr: an SDV hitting a pedestrian is
//    a finding, never hidden). With --goals-near-ends some pedestrians stand at their goals within
//    2 m of a crosswalk's end: std.drive yields to a pedestrian standing there facing the
//    crosswalk, and one whose facing drifts while it stands holds the traffic (docs/performance.md).
// The clocks (steady_clock, the CPU clock) are read here only: the simulation never reads a clock
// for its states.
//   build/bench/bench/pedestrian_bench [--repeat R] [--duration S] [--pedestrians N] [--sdvs M]
//                                      [--seed S] [--emit-sdv] [--scene-only] [--goals-near-ends]
// --emit-sdv prints the scenario instead (to run it with `sdv run --trace --view`); --scene-only
// runs only the scene with pedestrians and SDVs (for a profiler: `perf record -g --call-graph dwarf`).
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "compiler/diag/render.h"
#include "compiler/sema/compile.h"
#include "runtime/planner/sampling.h"
#include "runtime/sim/agents.h"
#include "runtime/sim/pedestrian.h"
#include "runtime/sim/simulation.h"
#include "runtime/sim/social_force.h"
#include "runtime/sim/world.h"

namespace {

using Clock = std::chrono::steady_clock;
namespace sf = sdv::sim::social_force;

constexpr double kRoadLength = 1000;
constexpr double kCrosswalkS[3] = {350, 500, 650};
const char* const kCrosswalkName[3] = {"a", "b", "c"};
constexpr double kHalfRoad = 7.0;     // 2 lanes of 3.5 m each way: the kerbs at y = ±7 m
constexpr double kKerbNear = 9.5;     // pedestrians start and stop this far from the centre line, or up to 4 m farther
constexpr double kAlong = 12.0;       // and within this of their crosswalk along the road
constexpr double kGoalAside = 4.0;    // a goal's least distance along the road from its crosswalk's centre line
constexpr double kNeighbourRadius = 12.0;  // the walker model's (pedestrian.cpp)

struct Config {
    int pedestrians = 100;
    int sdvs = 20;
    double duration = 120;
    uint64_t seed = 18;
    // Goals anywhere within kAlong of the crosswalk, also in its end zones (std.drive yields to
    // someone standing there facing it); by default at least kGoalAside from its centre line.
    bool goals_near_ends = false;
};

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.2f", v);
    std::string s = b;
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
    return s == "-0" ? "0" : s;
}

// Where the pedestrians start and go: seeded, at least 0.9 m apart at the start and 1 m at the goal.
struct Walk {
    double x0, y0, x1, y1, speed;
    int crosswalk;
};

std::vector<Walk> walks(const Config& c) {
    sdv::planner::RandomStream rng(c.seed, 0, 0);
    std::vector<Walk> out;
    for (int i = 0; i < c.pedestrians; ++i) {
        const int k = static_cast<int>(rng.next_u64() % 3);
        const double side = i % 2 == 0 ? -1.0 : 1.0;  // every other one from the other kerb
        for (int attempt = 0; attempt < 1000; ++attempt) {
            const double u = 2 * rng.uniform() - 1;  // where along the road the goal is, -1..1
            const double aside = c.goals_near_ends ? kAlong * u : (u < 0 ? -1 : 1) * (kGoalAside + (kAlong - kGoalAside) * std::fabs(u));
            Walk w{kCrosswalkS[k] + kAlong * (2 * rng.uniform() - 1), side * (kKerbNear + 4 * rng.uniform()), kCrosswalkS[k] + aside,
                   -side * (kKerbNear + 4 * rng.uniform()), 1.1 + 0.5 * rng.uniform(), k};
            // What the scenario text says (2 decimals) is what is checked.
            w.x0 = std::stod(num(w.x0)), w.y0 = std::stod(num(w.y0)), w.x1 = std::stod(num(w.x1)), w.y1 = std::stod(num(w.y1));
            w.speed = std::stod(num(w.speed));
            const bool free = std::none_of(out.begin(), out.end(), [&](const Walk& o) {
                return std::hypot(o.x0 - w.x0, o.y0 - w.y0) < 0.9 || std::hypot(o.x1 - w.x1, o.y1 - w.y1) < 1.0;
            });
            if (free) {
                out.push_back(w);
                break;
            }
        }
    }
    return out;
}

std::string scene(const Config& c, bool with_pedestrians, bool with_sdvs) {
    std::string s = "import \"std/drive.sdv\"\nimport \"std/pedestrian.sdv\"\n";
    s += "road main {\n lanes 2 forward, 2 backward\n lane_width 3.5 m\n speed_limit 50 km/h\n straight " + num(kRoadLength) + " m\n";
    s += " crosswalk a at " + num(kCrosswalkS[0]) + " m width 4 m signalised\n";
    s += " crosswalk b at " + num(kCrosswalkS[1]) + " m width 4 m\n";
    s += " crosswalk c at " + num(kCrosswalkS[2]) + " m width 4 m signalised\n}\n";
    s += "scenario crossing {\n road main\n timeout " + num(c.duration) + " s\n";
    s += " light main.a { green 12 s yellow 3 s red 20 s }\n";
    s += " light main.c { red 2.5 s green 12 s yellow 3 s red 17.5 s }\n";
    if (with_sdvs) {
        // Half each way, alternating lanes, 12.5 m apart per direction (25 m per lane), the first 125 m
        // before the first crosswalk; goals 10 m apart per lane, 110..150 m past the last crosswalk,
        // the front vehicle's the farthest.
        const int east = (c.sdvs + 1) / 2;
        for (int i = 0; i < c.sdvs; ++i) {
            const bool fwd = i < east;
            const int j = fwd ? i : i - east, count = fwd ? east : c.sdvs - east;
            const int lane = (fwd ? 1 : -1) * (1 + j % 2);
            const double back = 12.5 * (count - 1 - j);  // the first of each direction is in front
            const double start = fwd ? 225 - back : kRoadLength - 225 + back;
            const double goal = fwd ? 800 - 10 * ((count - 1 - j) / 2) : kRoadLength - 800 + 10 * ((count - 1 - j) / 2);
            s += " vehicle " + std::string(fwd ? "e" : "w") + std::to_string(j) + ": sdv { start lane " + std::to_string(lane) + " at " +
                 num(start) + " m speed 12 m/s goal lane " + std::to_string(lane) + " at " + num(goal) + " m tree std.drive(speed = 12 m/s) }\n";
        }
    }
    if (with_pedestrians) {
        int i = 0;
        for (const Walk& w : walks(c)) {
            s += " pedestrian p" + std::to_string(i++) + ": sdp { start at (" + num(w.x0) + " m, " + num(w.y0) + " m) goal at (" + num(w.x1) +
                 " m, " + num(w.y1) + " m) speed " + num(w.speed) + " m/s tree std.walk(speed = " + num(w.speed) + " m/s) }\n";
        }
    }
    s += " expect no_collision()\n}\n";
    return s;
}

std::optional<sdv::ir::Program> compile(const std::string& text) {
    sdv::diag::SourceManager sm;
    sdv::diag::DiagnosticEngine diags;
    auto comp = sdv::compiler::compile_source("pedestrians.sdv", text, sm, diags);
    if (!comp.program) std::fprintf(stderr, "%s", sdv::diag::render_all_text(diags.sorted(), sm).c_str());
    return std::move(comp.program);
}

// The q-quantile of xs by linear interpolation between closest ranks.
double quantile(std::vector<double> xs, double q) {
    if (xs.empty()) return NAN;
    std::sort(xs.begin(), xs.end());
    const double at = q * static_cast<double>(xs.size() - 1);
    const size_t lo = static_cast<size_t>(std::floor(at)), hi = std::min(xs.size() - 1, lo + 1);
    return xs[lo] + (at - static_cast<double>(lo)) * (xs[hi] - xs[lo]);
}

// CPU time of the process: on a loaded machine the wall clock also counts the time others ran.
double cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// One run to its end, as sim::simulate runs it, keeping the world for the checks.
struct Outcome {
    sdv::sim::RunResult r;
    double cpu_s = 0;  // the process's CPU time over the run's ticks (the world built)
    int peds = 0, ped_goals = 0, ped_walking = 0, ped_waiting = 0, ped_standing = 0, ped_crashed = 0;
    int ped_drifting = 0;        // at their goal at the end, still moving faster than 0.05 m/s
    double drift_max = 0;        // the fastest of those (m/s)
    int sdvs = 0, sdv_goals = 0;
    int collisions = 0, sdv_ped = 0, sdv_sdv = 0;
    std::map<std::string, int> not_there;  // the maneuvers of the pedestrians not at their goal
    std::vector<std::string> hits;         // every collision, for stderr
    std::vector<std::string> sdvs_short;   // the SDVs not at their goal: where, doing what
};

Outcome run(const sdv::ir::Program& p) {
    sdv::sim::RunOptions opt;
    opt.threads = 1;
    sdv::sim::Simulation sim(p, 0, opt);
    Outcome o;
    if (auto e = sim.start(); !e.empty()) {
        o.r = sim.finish();
        return o;
    }
    const double cpu0 = cpu_seconds();  // after building the world, as RunResult::timing.wall_s
    while (sim.step()) {
    }
    o.r = sim.finish();
    o.cpu_s = cpu_seconds() - cpu0;
    const auto& w = sim.world();
    std::vector<char> reached(w.agents.size(), 0);
    for (const auto& e : o.r.events) {
        if (e.kind == "goal_reached" && !e.vehicles.empty()) reached[static_cast<size_t>(e.vehicles.front())] = 1;
        if (e.kind != "collision") continue;
        ++o.collisions;
        int peds = 0;
        std::string who;
        for (int v : e.vehicles) {
            const auto& a = w.agents[static_cast<size_t>(v)];
            peds += a.v->pedestrian;
            who += " " + a.v->name + (a.v->pedestrian ? " (pedestrian)" : "");
        }
        if (e.vehicles.size() == 2 && peds == 1) ++o.sdv_ped;
        if (e.vehicles.size() == 2 && peds == 0) ++o.sdv_sdv;
        char b[96];
        std::snprintf(b, sizeof b, "collision t=%.2f s, %.1f m/s, zone %s:", e.time, e.relative_speed, e.zone.c_str());
        o.hits.push_back(b + who);
    }
    for (const auto& a : w.agents) {
        const bool got = reached[static_cast<size_t>(a.index)] != 0;
        if (a.walker) {
            ++o.peds;
            o.ped_goals += got;
            if (got && a.speed > 0.05) {
                ++o.ped_drifting;
                o.drift_max = std::max(o.drift_max, a.speed);
            }
            if (got) continue;
            if (a.crashed) ++o.ped_crashed;
            else if (a.speed > 0.1) ++o.ped_walking;
            else if (a.walker->maneuver_name.find("wait") != std::string::npos) ++o.ped_waiting;
            else ++o.ped_standing;
            ++o.not_there[a.walker->maneuver_name];
        } else if (a.driver) {
            ++o.sdvs;
            o.sdv_goals += got;
            if (got) continue;
            const auto& m = o.r.vehicles[static_cast<size_t>(a.index)];
            char b[200];
            std::snprintf(b, sizeof b, "%s on %s at s = %.1f m, %.1f m/s, in %s, longest stall %.1f s, fallback plans %d / %d",
                          a.v->name.c_str(), a.lane == sdv::sim::kNoLane ? "-" : w.net.lane(a.lane).name.c_str(), a.lane_s, a.speed,
                          a.driver->maneuver_name.c_str(), m.longest_stall_s, m.fallback_plans, m.plans);
            o.sdvs_short.push_back(b);
        }
    }
    return o;
}

struct Series {
    std::vector<double> rtf, cpu_rtf, p50, p90, p99, cpu;
    int ticks = 0;
    double simulated = 0;
};

// Runs `p` `repeat` times; the outcome of the last run (every run is the same: checked).
Series series(const sdv::ir::Program& p, int repeat, Outcome& last, bool& same) {
    Series s;
    same = true;
    std::optional<std::pair<size_t, int>> first;
    for (int i = 0; i < repeat; ++i) {
        last = run(p);
        if (!last.r.error.empty()) {
            std::fprintf(stderr, "%s\n", last.r.error.c_str());
            std::exit(1);
        }
        const auto& t = last.r.timing;
        s.rtf.push_back(last.r.duration / t.wall_s);
        s.cpu_rtf.push_back(last.r.duration / last.cpu_s);
        s.cpu.push_back(last.cpu_s);
        s.p50.push_back(t.tick_us.percentile(0.5));
        s.p90.push_back(t.tick_us.percentile(0.9));
        s.p99.push_back(t.tick_us.percentile(0.99));
        s.ticks = last.r.ticks;
        s.simulated = last.r.duration;
        const std::pair<size_t, int> sig{last.r.events.size(), last.ped_goals * 1000 + last.collisions};
        if (first && *first != sig) same = false;
        first = sig;
    }
    return s;
}

// (a) force + step for a crowd of `k` in a disc 20 m across, with two cars beside it: ns per
// pedestrian step, one sample per repetition; `mean_neighbours` is set.
std::vector<double> force_step_bench(int k, int repeat, double& mean_neighbours) {
    const sf::Params params;
    sdv::planner::RandomStream rng(7, static_cast<uint32_t>(k), 0);
    std::vector<sf::State> st;
    std::vector<sdv::road::Vec2> target;
    std::vector<double> speed;
    while (static_cast<int>(st.size()) < k) {
        const double r = 10 * std::sqrt(rng.uniform()), phi = 2 * std::numbers::pi * rng.uniform();
        const sdv::road::Vec2 p{r * std::cos(phi), r * std::sin(phi)};
        if (std::any_of(st.begin(), st.end(), [&](const sf::State& o) { return sdv::road::distance(o.p, p) < 0.6; })) continue;
        const double v = 1.1 + 0.5 * rng.uniform(), head = 2 * std::numbers::pi * rng.uniform();
        st.push_back({p, {v * std::cos(head), v * std::sin(head)}});
        target.push_back({p.x + 15 * std::cos(head), p.y + 15 * std::sin(head)});
        speed.push_back(v);
    }
    const std::vector<sf::Obstacle> cars = {{{0, 12}, 0, 4.5, 1.8, {10, 0}}, {{-6, -12}, std::numbers::pi, 4.5, 1.8, {0, 0}}};
    std::vector<std::vector<sf::Neighbour>> near(static_cast<size_t>(k));
    std::vector<std::vector<sf::Obstacle>> boxes(static_cast<size_t>(k));
    double total = 0;
    for (int i = 0; i < k; ++i) {
        for (int j = 0; j < k; ++j) {
            if (j != i && sdv::road::distance(st[static_cast<size_t>(i)].p, st[static_cast<size_t>(j)].p) <= kNeighbourRadius) {
                near[static_cast<size_t>(i)].push_back({st[static_cast<size_t>(j)].p, st[static_cast<size_t>(j)].v, 0.27});
            }
        }
        for (const auto& c : cars) {
            if (sdv::road::distance(st[static_cast<size_t>(i)].p, c.centre) <= kNeighbourRadius) boxes[static_cast<size_t>(i)].push_back(c);
        }
        total += static_cast<double>(near[static_cast<size_t>(i)].size());
    }
    mean_neighbours = total / k;
    const int iters = std::max(20, 200000 / (k * k));
    std::vector<double> out;
    volatile double sink = 0;
    for (int r = 0; r < repeat; ++r) {
        double acc = 0;
        const auto t0 = Clock::now();
        for (int it = 0; it < iters; ++it) {
            for (size_t i = 0; i < st.size(); ++i) {
                const auto f = sf::force(params, st[i], 0.27, target[i], speed[i], near[i], boxes[i]);
                const auto n = sf::step(params, st[i], f, speed[i], 1.0 / 30);
                acc += n.p.x + n.v.y;
            }
        }
        const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
        sink = sink + acc;
        out.push_back(ns / (static_cast<double>(iters) * k));
    }
    (void)sink;
    return out;
}

// The state of a pedestrian that its model's advance writes.
struct Kinematics {
    double x, y, yaw, vx, vy, ax, ay, speed, accel, lane_s, lane_d;
    sdv::sim::LaneId lane, centre_lane;
    sdv::sim::Walker::Phase phase;
};
Kinematics save(const sdv::sim::Agent& a) {
    return {a.x, a.y, a.yaw, a.vx, a.vy, a.ax, a.ay, a.speed, a.accel, a.lane_s, a.lane_d, a.lane, a.centre_lane, a.walker->phase};
}
void restore(sdv::sim::Agent& a, const Kinematics& k) {
    a.x = k.x, a.y = k.y, a.yaw = k.yaw, a.vx = k.vx, a.vy = k.vy, a.ax = k.ax, a.ay = k.ay, a.speed = k.speed, a.accel = k.accel;
    a.lane_s = k.lane_s, a.lane_d = k.lane_d, a.lane = k.lane, a.centre_lane = k.centre_lane, a.walker->phase = k.phase;
}

struct Live {
    std::vector<double> advance_ns, locate_ns, tree_ns;  // per pedestrian per call, one sample per checkpoint and repetition
    double peds_near = 0, cars_near = 0;      // mean neighbours within 12 m of a pedestrian, over every tick
    int max_peds_near = 0;
};

// (b) and (c) on a run of the scene of its own: every 5 s of simulated time, each pedestrian's
// advance (its state restored) and its tree tick, `repeat` times over all pedestrians.
Live live_bench(const sdv::ir::Program& p, int repeat) {
    sdv::sim::RunOptions opt;
    opt.threads = 1;
    sdv::sim::Simulation sim(p, 0, opt);
    Live out;
    if (!sim.start().empty()) return out;
    long long samples = 0;
    double peds_near = 0, cars_near = 0;
    std::vector<int> near;
    std::vector<Kinematics> saved;
    volatile double sink = 0;
    while (sim.step()) {
        auto& w = sim.world();
        std::vector<sdv::sim::Agent*> peds;
        for (auto& a : w.agents) {
            if (a.walker && a.active && !a.crashed) peds.push_back(&a);
        }
        for (const auto* a : peds) {
            w.grid.query(a->x, a->y, kNeighbourRadius, near);
            int np = 0, nc = 0;
            for (int j : near) {
                const auto& o = w.snapshot[static_cast<size_t>(j)];
                if (j == a->index || !o.active || std::hypot(o.x - a->x, o.y - a->y) > kNeighbourRadius) continue;
                (o.pedestrian ? np : nc)++;
            }
            peds_near += np;
            cars_near += nc;
            out.max_peds_near = std::max(out.max_peds_near, np);
            ++samples;
        }
        if (sim.tick() % 150 != 0 || peds.empty()) continue;
        const int tick = sim.tick();
        const double t = sim.time();
        saved.clear();
        for (const auto* a : peds) saved.push_back(save(*a));
        for (int r = 0; r < repeat; ++r) {
            const auto t0 = Clock::now();
            for (auto* a : peds) a->model->advance(w, *a, t, tick + 1);
            const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
            for (size_t i = 0; i < peds.size(); ++i) restore(*peds[i], saved[i]);
            out.advance_ns.push_back(ns / static_cast<double>(peds.size()));
        }
        for (int r = 0; r < repeat; ++r) {
            double sum = 0;
            const auto t0 = Clock::now();
            for (const auto* a : peds) sum += w.net.locate({a->x, a->y}).s;
            const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
            sink = sink + sum;
            out.locate_ns.push_back(ns / static_cast<double>(peds.size()));
        }
        // The tree reads the snapshot and sets the intent; ticking it again at the same t changes
        // nothing std.walk depends on (no running nodes, no `wait`), but put its count back.
        std::vector<uint32_t> cycles;
        for (const auto* a : peds) cycles.push_back(a->walker->cycles);
        for (int r = 0; r < repeat; ++r) {
            const auto t0 = Clock::now();
            for (auto* a : peds) sdv::sim::walk_cycle(w, *a, t);
            const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
            out.tree_ns.push_back(ns / static_cast<double>(peds.size()));
        }
        for (size_t i = 0; i < peds.size(); ++i) peds[i]->walker->cycles = cycles[i];
    }
    sim.finish();
    out.peds_near = samples > 0 ? peds_near / static_cast<double>(samples) : 0;
    out.cars_near = samples > 0 ? cars_near / static_cast<double>(samples) : 0;
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    Config c;
    int repeat = 5;
    bool emit = false, scene_only = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--repeat" && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
        else if (a == "--duration" && i + 1 < argc) c.duration = std::atof(argv[++i]);
        else if (a == "--pedestrians" && i + 1 < argc) c.pedestrians = std::atoi(argv[++i]);
        else if (a == "--sdvs" && i + 1 < argc) c.sdvs = std::atoi(argv[++i]);
        else if (a == "--seed" && i + 1 < argc) c.seed = std::strtoull(argv[++i], nullptr, 10);
        else if (a == "--emit-sdv") emit = true;
        else if (a == "--scene-only") scene_only = true;
        else if (a == "--goals-near-ends") c.goals_near_ends = true;
        else {
            std::fprintf(stderr, "usage: pedestrian_bench [--repeat R] [--duration S] [--pedestrians N] [--sdvs M] [--seed S] [--emit-sdv] [--scene-only] [--goals-near-ends]\n");
            return 2;
        }
    }
    if (emit) {
        std::fputs(scene(c, true, true).c_str(), stdout);
        return 0;
    }
    if (scene_only) {
        // For a profiler: the scene with pedestrians and SDVs, `repeat` runs, nothing else.
        const auto p = compile(scene(c, true, true));
        if (!p) return 1;
        for (int i = 0; i < repeat; ++i) {
            const Outcome o = run(*p);
            std::printf("RTF %.0f×, collisions %d, pedestrians at their goal %d / %d, SDVs %d / %d\n", o.r.duration / o.r.timing.wall_s,
                        o.collisions, o.ped_goals, o.peds, o.sdv_goals, o.sdvs);
            for (const auto& h : o.hits) std::fprintf(stderr, "%s\n", h.c_str());
            for (const auto& v : o.sdvs_short) std::fprintf(stderr, "SDV not at its goal: %s\n", v.c_str());
        }
        return 0;
    }
    std::printf("scene: straight %g m, 2 lanes each way, crosswalks at 350 m (signalised), 500 m (zebra), 650 m (signalised); "
                "%d pedestrians (std.walk) from both kerbs, %d SDVs (std.drive, 12 m/s) both ways; %g s simulated, seed %llu, "
                "1 thread, %d runs each\n\n",
                kRoadLength, c.pedestrians, c.sdvs, c.duration, static_cast<unsigned long long>(c.seed), repeat);
    std::fflush(stdout);

    struct Case {
        const char* name;
        bool peds, sdvs;
    };
    const Case cases[] = {{"pedestrians + SDVs", true, true}, {"SDVs only", false, true}, {"pedestrians only", true, false}};
    std::printf("| scene | agents | simulated (s) | RTF median | RTF p10 / p90 | RTF by CPU time, median | tick p50 / p90 / p99 (µs) |\n"
                "|---|---|---|---|---|---|---|\n");
    std::vector<Series> results;
    std::vector<Outcome> outcomes;
    for (const Case& k : cases) {
        const auto p = compile(scene(c, k.peds, k.sdvs));
        if (!p) return 1;
        Outcome o;
        bool same = true;
        const Series s = series(*p, repeat, o, same);
        // RTF p10 is the slow end: the 10th percentile of the factor.
        std::printf("| %s | %d + %d | %g | %.0f× | %.0f× / %.0f× | %.0f× | %.0f / %.0f / %.0f |\n", k.name, k.peds ? c.pedestrians : 0,
                    k.sdvs ? c.sdvs : 0, s.simulated, quantile(s.rtf, 0.5), quantile(s.rtf, 0.1), quantile(s.rtf, 0.9),
                    quantile(s.cpu_rtf, 0.5), quantile(s.p50, 0.5), quantile(s.p90, 0.5), quantile(s.p99, 0.5));
        std::fflush(stdout);
        if (!same) std::fprintf(stderr, "%s: the runs differ (events or goals): the simulation is not deterministic\n", k.name);
        results.push_back(s);
        outcomes.push_back(std::move(o));
    }
    const Series& full = results[0];
    const Series& sdv_only = results[1];
    const Series& peds_only = results[2];
    const double ticks = full.ticks + 1;
    const double marginal_ns = (quantile(full.cpu, 0.5) - quantile(sdv_only.cpu, 0.5)) / (ticks * c.pedestrians) * 1e9;
    const double alone_ns = quantile(peds_only.cpu, 0.5) / (ticks * c.pedestrians) * 1e9;

    // Micro-benchmarks.
    std::printf("\n| part (per pedestrian per call) | neighbours within 12 m | p50 (ns) | p90 (ns) | p99 (ns) |\n|---|---|---|---|---|\n");
    for (int k : {10, 30, 100}) {
        double mean_near = 0;
        const auto ns = force_step_bench(k, 31, mean_near);
        std::printf("| (a) force + step, crowd of %d in 20 m, 2 cars | %.0f | %.0f | %.0f | %.0f |\n", k, mean_near, quantile(ns, 0.5),
                    quantile(ns, 0.9), quantile(ns, 0.99));
        std::fflush(stdout);
    }
    const auto p = compile(scene(c, true, true));
    if (!p) return 1;
    const Live live = live_bench(*p, 20);
    char near[64];
    std::snprintf(near, sizeof near, "%.1f + %.1f cars (max %d)", live.peds_near, live.cars_near, live.max_peds_near);
    std::printf("| (b) walker advance in the scene (grid, gather, force, step, locate) | %s | %.0f | %.0f | %.0f |\n", near,
                quantile(live.advance_ns, 0.5), quantile(live.advance_ns, 0.9), quantile(live.advance_ns, 0.99));
    std::printf("| (b1) of which RoadNetwork::locate of its position | | %.0f | %.0f | %.0f |\n", quantile(live.locate_ns, 0.5),
                quantile(live.locate_ns, 0.9), quantile(live.locate_ns, 0.99));
    std::printf("| (c) walk_cycle (std.walk tree tick) in the scene | | %.0f | %.0f | %.0f |\n", quantile(live.tree_ns, 0.5),
                quantile(live.tree_ns, 0.9), quantile(live.tree_ns, 0.99));
    const double per_tick_ns = quantile(live.advance_ns, 0.5) + quantile(live.tree_ns, 0.5) / 10;
    std::printf("\nper pedestrian per tick: (b) + (c) / 10 = %.0f ns (the tree ticks at the planning rate, every 10th tick); "
                "whole runs (median CPU time): %.0f ns marginal (with minus without pedestrians, over %d pedestrians x %.0f ticks), "
                "%.0f ns in the pedestrians-only scene (its whole CPU time / pedestrian-ticks)\n",
                per_tick_ns, marginal_ns, c.pedestrians, ticks, alone_ns);

    // Sanity.
    const Outcome& o = outcomes[0];
    std::printf("\nsanity (pedestrians + SDVs, every run the same): pedestrians at their goal %d / %d (goal_reached events), "
                "walking %d, waiting at a crosswalk %d, standing %d, crashed %d; at their goal and still moving (> 0.05 m/s) %d "
                "(fastest %.2f m/s); SDVs at their goal %d / %d; collisions %d (SDV-pedestrian %d, SDV-SDV %d)\n",
                o.ped_goals, o.peds, o.ped_walking, o.ped_waiting, o.ped_standing, o.ped_crashed, o.ped_drifting, o.drift_max, o.sdv_goals,
                o.sdvs, o.collisions, o.sdv_ped, o.sdv_sdv);
    const Outcome& po = outcomes[2];
    std::printf("sanity (pedestrians only): at their goal %d / %d, collisions %d; (SDVs only): SDVs at their goal %d / %d, collisions %d\n",
                po.ped_goals, po.peds, po.collisions, outcomes[1].sdv_goals, outcomes[1].sdvs, outcomes[1].collisions);
    for (const auto& [m, n] : o.not_there) std::fprintf(stderr, "not at the goal at the end: %d in maneuver %s\n", n, m.c_str());
    for (const auto& h : o.hits) std::fprintf(stderr, "%s\n", h.c_str());
    for (const auto& v : o.sdvs_short) std::fprintf(stderr, "SDV not at its goal: %s\n", v.c_str());
    const bool met = quantile(full.rtf, 0.1) >= 100;
    std::printf("\ntarget (issue 18): >= 100x real time with %d pedestrians and %d SDVs on one core: %s (median %.0f×, p10 %.0f×)\n",
                c.pedestrians, c.sdvs, met ? "met" : "NOT met", quantile(full.rtf, 0.5), quantile(full.rtf, 0.1));
    return 0;
}
