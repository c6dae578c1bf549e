// The city-like scale case of the "Scale" issue: the language's built-in junction (the largest
// road network of junctions it offers: one signalised 4-way crossing with 4 lanes per direction
// on each arm, arms up to 10 km) filled with N SDVs on routes through it, for 2 simulated minutes
// (or --duration). Every SDV drives std.drive (stops at red, at its goal, follows, keeps its
// speed) from one of the 16 entry lanes to its goal on an exit arm:
//   lane 1 (right-most) turns right, lanes 2 to 4 go straight, so that no two movements of one
//   green phase cross (the connectors of the built-in junction join lane k to lane k; a right
//   turn from lane 1 keeps to the corner, clear of the straight paths of lanes 2 to 4);
//   `--left-turns`: lane 4 turns left instead (a permissive left turn across the oncoming
//   straight traffic: std.drive has no rule to yield there).
// The lights run a 66 s cycle with two 3 s all-red clearances:
//   north-south: green 27 s, yellow 3 s, red 36 s; east-west: red 33 s, green 27 s, yellow 3 s, red 3 s.
// Vehicle i enters by lane slot i mod 16 (arm first, then lane), row i / 16 behind the first,
// `spacing` apart (25 m, less when the arms would exceed 10 km), the first 40 m before the stop
// line. Each exit lane is fed by one entry lane; the goals on it are 10 m apart, the first vehicle
// of the entry lane getting the farthest one, so that vehicles standing at their goals never
// queue back into the junction.
// Reports what platoon_bench reports (real-time factor, vehicle updates/s, plans/s, candidates/s,
// tick and plan time percentiles, TRC / TPRC, peak RSS) plus MB per vehicle and how the traffic
// fared: goals reached, vehicles through the junction, stalls, fallback share, collisions. Details
// go to stderr: braking fallbacks by place and maneuver, junction entries by light state, each
// collision (where, in which maneuver, how its vehicles entered the junction), each stall.
//   build/bench/bench/city_bench [N...] [--threads T] [--duration S] [--left-turns] [--emit-sdv]
// --emit-sdv prints the scenario of the first N instead (to run it with `sdv run --trace --view`).
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "compiler/diag/render.h"
#include "compiler/sema/compile.h"
#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"

namespace {

constexpr int kArms = 4, kLanes = 4, kSlots = kArms * kLanes;
constexpr double kMaxArm = 10000;    // the language's largest arm_length
constexpr double kHead = 40;         // the first vehicle of an entry lane: its distance to the stop line
constexpr double kGoalBase = 50;     // the nearest goal on an exit lane
constexpr double kMinSpacing = 12;   // closer than this a queue of 4.5 m cars is not a sane start
const char* const kArmName[kArms] = {"north", "east", "south", "west"};

// Where a vehicle entering from arm a ends up: its right, straight ahead, its left.
int right_of(int a) { return (a + 3) % 4; }  // from north (driving south) the right is west
int left_of(int a) { return (a + 1) % 4; }
int opposite(int a) { return (a + 2) % 4; }

struct Layout {
    int n = 0;
    int rows = 0;              // vehicles per entry lane (the fullest)
    double spacing = 25;       // m between consecutive vehicles of an entry lane
    double goal_spacing = 10;  // m between consecutive goals of an exit lane
    double arm = 200;          // arm_length
    double speed = 10;         // start and cruising speed
    bool ok = true;
};

Layout layout(int n) {
    Layout l;
    l.n = n;
    l.rows = (n + kSlots - 1) / kSlots;
    const double need = std::max(kHead + l.spacing * (l.rows - 1), kGoalBase + l.goal_spacing * (l.rows - 1)) + 20;
    l.arm = std::max(200.0, std::ceil(need / 10) * 10);
    if (l.arm > kMaxArm) {
        // Closer together, and slower so that the 2 s time gap of std.drive still (nearly) holds.
        l.arm = kMaxArm;
        l.spacing = std::floor((kMaxArm - 20 - kHead) / std::max(1, l.rows - 1) * 10) / 10;
        l.goal_spacing = std::min(l.goal_spacing, std::floor((kMaxArm - 20 - kGoalBase) / std::max(1, l.rows - 1) * 10) / 10);
        l.speed = std::min(10.0, std::max(3.0, std::floor((l.spacing - 4.5) / 2)));
        l.ok = l.spacing >= kMinSpacing && l.goal_spacing >= 7;
    }
    return l;
}

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

std::string city(const Layout& l, double duration, bool left_turns) {
    std::string s = "import \"std/drive.sdv\"\n";
    s += "junction city {\n lanes 4\n lane_width 3.5 m\n speed_limit 40 km/h\n arm_length " + num(l.arm) +
         " m\n control traffic_lights\n}\n";
    s += "scenario city {\n road city\n timeout " + num(duration) + " s\n";
    s += " light city.ns { green 27 s yellow 3 s red 36 s }\n";
    s += " light city.ew { red 33 s green 27 s yellow 3 s red 3 s }\n";
    int count[kSlots] = {};
    for (int i = 0; i < l.n; ++i) ++count[i % kSlots];
    for (int i = 0; i < l.n; ++i) {
        const int slot = i % kSlots, row = i / kSlots;
        const int arm = slot % kArms, lane = 1 + slot / kArms;
        const int to = lane == 1 ? right_of(arm) : (lane == 4 && left_turns) ? left_of(arm) : opposite(arm);
        const double at = l.arm - kHead - l.spacing * row;
        const double goal = kGoalBase + l.goal_spacing * (count[slot] - 1 - row);
        s += " vehicle v" + std::to_string(i) + ": sdv { start lane \"" + kArmName[arm] + ".in." + std::to_string(lane) +
             "\" at " + num(at) + " m speed " + num(l.speed) + " m/s goal lane \"" + kArmName[to] + ".out." +
             std::to_string(lane) + "\" at " + num(goal) + " m tree std.drive(speed = " + num(l.speed) + " m/s) }\n";
    }
    s += " expect no_collision()\n}\n";
    return s;
}

// Watches the run: distance driven, whether a vehicle got through the junction (onto an exit
// lane), when it entered the junction and what its light showed then, where and in which
// maneuver it crashed, fallbacks by kind and by where they happened.
class Watch : public sdv::sim::RunObserver {
public:
    struct Crash {
        std::string lane, maneuver;
        double speed = 0;  // at the tick before the crash
    };
    std::vector<double> dist;
    std::vector<char> through;
    std::vector<double> entered;            // when it entered the junction (< 0: never)
    std::vector<std::string> entered_light; // its light's state then
    std::map<int, Crash> crashes;
    std::map<std::string, long long> fallback_kinds;
    std::map<std::string, long long> fallback_where;  // braking fallbacks by kind, place, maneuver
    long long entries[3] = {0, 0, 0};                 // entries into the junction on green, yellow, red

    void start(const sdv::sim::World& w) override {
        const size_t n = w.agents.size();
        dist.assign(n, 0);
        through.assign(n, 0);
        entered.assign(n, -1);
        entered_light.assign(n, "");
        prev_lane_.clear();
        for (const auto& a : w.agents) prev_lane_.push_back(a.lane);
        speed_.assign(n, 0);
    }
    void tick(const sdv::sim::World& w, int, double t) override {
        for (size_t i = 0; i < w.agents.size(); ++i) {
            const auto& a = w.agents[i];
            if (!a.active) continue;
            dist[i] += std::fabs(a.speed) * w.dt;
            if (a.lane != prev_lane_[i] && a.lane != sdv::sim::kNoLane) {
                const auto& l = w.net.lane(a.lane);
                if (l.name.find(".out") != std::string::npos) through[i] = 1;
                if (l.in_junction && entered[i] < 0 && prev_lane_[i] != sdv::sim::kNoLane) {
                    const auto& from = w.net.lane(prev_lane_[i]);
                    const std::string st = from.traffic_lights.empty() ? "green" : w.light_state(from.traffic_lights.front(), t);
                    entered[i] = t;
                    entered_light[i] = st;
                    ++entries[st == "red" ? 2 : st == "yellow" ? 1 : 0];
                }
                prev_lane_[i] = a.lane;
            }
            if (a.crashed && !crashes.count(static_cast<int>(i))) {
                crashes[static_cast<int>(i)] = {a.lane == sdv::sim::kNoLane ? "-" : w.net.lane(a.lane).name,
                                                a.driver ? a.driver->maneuver_name : "-", speed_[i]};
            }
            speed_[i] = a.speed;
        }
    }
    void plan(const sdv::sim::World& w, const sdv::sim::Agent& a) override {
        if (!a.driver || !a.driver->fallback_kind) return;
        ++fallback_kinds[a.driver->fallback_kind];
        if (a.driver->fallback) {
            ++fallback_where[std::string(a.driver->fallback_kind) + " on " + where(w, a.lane) + " in " + a.driver->maneuver_name];
        }
    }

    // "an entry lane", "an exit lane", "the junction (right turn / straight / left turn)".
    static std::string where(const sdv::sim::World& w, sdv::sim::LaneId id) {
        if (id == sdv::sim::kNoLane) return "no lane";
        const auto& l = w.net.lane(id);
        if (l.in_junction) {
            return l.turn == sdv::road::Turn::right  ? "the junction (right turn)"
                   : l.turn == sdv::road::Turn::left ? "the junction (left turn)"
                                                     : "the junction (straight)";
        }
        return l.name.find(".in") != std::string::npos ? "an entry lane" : "an exit lane";
    }

private:
    std::vector<sdv::sim::LaneId> prev_lane_;
    std::vector<double> speed_;
};

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> sizes;
    int threads = 1;
    double duration = 120;
    bool left_turns = false, emit = false;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
        else if (a == "--duration" && i + 1 < argc) duration = std::atof(argv[++i]);
        else if (a == "--left-turns") left_turns = true;
        else if (a == "--emit-sdv") emit = true;
        else if (std::atoi(a.c_str()) > 0) sizes.push_back(std::atoi(a.c_str()));
        else {
            std::fprintf(stderr, "usage: city_bench [N...] [--threads T] [--duration S] [--left-turns] [--emit-sdv]\n");
            return 2;
        }
    }
    if (sizes.empty()) sizes = {20, 100, 1000};
    if (emit) {
        std::fputs(city(layout(sizes.front()), duration, left_turns).c_str(), stdout);
        return 0;
    }
    // How the vehicles are placed, per N, before the table.
    for (int n : sizes) {
        const Layout l = layout(n);
        std::printf("placement N=%d: junction, 4 lanes per direction, arms %g m, traffic lights; %d entry lanes x up to %d "
                    "vehicles, %g m apart at %g m/s, the first %g m before the stop line; goals %g m apart from %g m on the "
                    "exit lanes; movements: lane 1 right, lanes 2-3 straight, lane 4 %s; %g s simulated%s\n",
                    n, l.arm, kSlots, l.rows, l.spacing, l.speed, kHead, l.goal_spacing, kGoalBase,
                    left_turns ? "left" : "straight", duration, l.ok ? "" : " — DOES NOT FIT (spacing below 12 m)");
        if (!l.ok) return 2;
    }
    std::printf("\n| N | threads | simulated (s) | RTF | vehicle-updates/s | plans/s | candidates/s | tick p50 / p99 (µs) | "
                "plan p50 / p99 (µs) | TRC | TPRC | peak RSS (MB) | MB per vehicle | collisions | reached goal | "
                "through junction | driven (m, mean) | stalled > 5 s | fallback share |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    std::fflush(stdout);
    for (int n : sizes) {
        const Layout l = layout(n);
        sdv::diag::SourceManager sm;
        sdv::diag::DiagnosticEngine diags;
        auto comp = sdv::compiler::compile_source("city.sdv", city(l, duration, left_turns), sm, diags);
        if (!comp.program) {
            std::fprintf(stderr, "%s", sdv::diag::render_all_text(diags.sorted(), sm).c_str());
            return 1;
        }
        sdv::sim::RunOptions opt;
        opt.threads = threads;
        Watch watch;
        const auto r = sdv::sim::simulate(*comp.program, 0, opt, &watch);
        if (!r.error.empty()) {
            std::fprintf(stderr, "%s\n", r.error.c_str());
            return 1;
        }
        int collisions = 0;
        for (const auto& e : r.events) collisions += e.kind == "collision";
        int goals = 0, through = 0, stalled = 0;
        long long plans = 0, fallbacks = 0;
        for (size_t i = 0; i < r.vehicles.size(); ++i) {
            const auto& v = r.vehicles[i];
            goals += v.reached_goal;
            through += watch.through[i] != 0 || v.reached_goal;
            plans += v.plans;
            fallbacks += v.fallback_plans;
            if (v.longest_stall_s > 5) ++stalled;
        }
        double driven = 0;
        for (double d : watch.dist) driven += d;
        rusage ru{};
        getrusage(RUSAGE_SELF, &ru);
        const double wall = r.timing.wall_s;
        const double mb = static_cast<double>(ru.ru_maxrss) / 1024.0;
        const double updates = static_cast<double>(r.ticks + 1) * n;
        std::printf("| %d | %d | %g | %.3g× | %.3g | %.3g | %.3g | %.0f / %.0f | %.0f / %.0f | %.4f | %.4f | %.0f | %.3f | %d | "
                    "%d / %d | %d / %d | %.0f | %d | %.2f %% |\n",
                    n, threads, r.duration, r.duration / wall, updates / wall, static_cast<double>(r.timing.plan_us.count()) / wall,
                    static_cast<double>(r.timing.candidates) / wall, r.timing.tick_us.percentile(0.5),
                    r.timing.tick_us.percentile(0.99), r.timing.plan_us.percentile(0.5), r.timing.plan_us.percentile(0.99),
                    r.timing.tick_us.share_below(33333), r.timing.plan_us.share_below(333333), mb, mb / n, collisions, goals, n,
                    through, n, driven / std::max(1, n), stalled, plans > 0 ? 100.0 * static_cast<double>(fallbacks) / static_cast<double>(plans) : 0.0);
        std::fflush(stdout);
        // Findings: where the traffic went wrong.
        std::fprintf(stderr, "N=%d: planning cycles by fallback kind:", n);
        for (const auto& [k, c] : watch.fallback_kinds) std::fprintf(stderr, " %s %lld", k.c_str(), c);
        std::fprintf(stderr, "\n");
        for (const auto& [k, c] : watch.fallback_where) std::fprintf(stderr, "N=%d:   %lld %s\n", n, c, k.c_str());
        std::fprintf(stderr, "N=%d: junction entries on green %lld, yellow %lld, red %lld\n", n, watch.entries[0], watch.entries[1],
                     watch.entries[2]);
        int shown = 0;
        for (const auto& e : r.events) {
            if (e.kind != "collision" || e.vehicles.size() != 2) continue;
            if (++shown > 20) break;
            std::fprintf(stderr, "N=%d: collision t=%.2f s (%.1f m/s, zone %s):", n, e.time, e.relative_speed, e.zone.c_str());
            for (int v : e.vehicles) {
                const auto it = watch.crashes.find(v);
                const auto& c = it != watch.crashes.end() ? it->second : Watch::Crash{};
                std::fprintf(stderr, " v%d in %s (%s, %.1f m/s; entered the junction %s%s%s)", v, c.lane.c_str(), c.maneuver.c_str(),
                             c.speed, watch.entered[static_cast<size_t>(v)] < 0 ? "never" : "at ",
                             watch.entered[static_cast<size_t>(v)] < 0 ? "" : (num(watch.entered[static_cast<size_t>(v)]) + " s").c_str(),
                             watch.entered[static_cast<size_t>(v)] < 0 ? "" : (" on " + watch.entered_light[static_cast<size_t>(v)]).c_str());
            }
            std::fprintf(stderr, "\n");
        }
        for (size_t i = 0; i < r.vehicles.size(); ++i) {
            if (r.vehicles[i].longest_stall_s > 5) {
                std::fprintf(stderr, "N=%d: v%zu stalled %.1f s (drove %.0f m, %s)\n", n, i, r.vehicles[i].longest_stall_s,
                             watch.dist[i], watch.through[i] ? "through the junction" : "not through");
            }
        }
    }
    return 0;
}
