// One planning cycle per maneuver in the reference's timing scene (SPEC §9): a straight road
// with 3 lanes of 3.5 m; the planner at s = 0, d = 0, 12 m/s; K other vehicles (4.5 × 1.8 m) at
// lane centres and constant speed: vehicle 1 leads in the own lane at s = 30 m, 10 m/s (the
// follow target), vehicle 2 in the left lane at s = 10 m, 8 m/s (the cut-in target), the rest
// seeded uniform in s 10..80 m and speed 8..14 m/s, at least 7 m apart in a lane.
//   build/bench/bench/planner_bench --benchmark_repetitions=10 --benchmark_report_aggregates_only
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "runtime/planner/planner.h"

using namespace sdv::planner;

namespace {

std::vector<Obstacle> scene(int k) {
    std::vector<Obstacle> obs;
    if (k >= 1) obs.push_back({1, {30, 10, 0, 0, 0, 0}, 4.5, 1.8, false});
    if (k >= 2) obs.push_back({2, {10, 8, 0, 3.5, 0, 0}, 4.5, 1.8, false});
    RandomStream rng(2024, 0, 0);
    int id = 3;
    int attempts = 0;
    while (static_cast<int>(obs.size()) < k && attempts++ < 100000) {
        const double lane = -3.5 + 3.5 * static_cast<double>(rng.next_u64() % 3);
        const double s = 10 + 70 * rng.uniform();
        const double v = 8 + 6 * rng.uniform();
        bool ok = std::fabs(s) > 7 || lane != 0;  // keep clear of the planner itself
        for (const auto& o : obs) ok = ok && (o.state.d != lane || std::fabs(o.state.s - s) >= 7);
        if (ok) obs.push_back({id++, {s, v, 0, lane, 0, 0}, 4.5, 1.8, false});
    }
    return obs;
}

void plan_cycle(benchmark::State& state) {
    const auto kind = static_cast<ManeuverKind>(state.range(0));
    const int k = static_cast<int>(state.range(1));
    const std::vector<Obstacle> obs = scene(k);
    ManeuverConfig cfg = default_config(kind);
    cfg.stop_at = StopTarget::stop_line;
    PlanRequest req;
    req.start = {0, 12, 0, 0, 0, 0};
    req.config = &cfg;
    req.obstacles = obs;
    req.current_lane = {0, 1.75, -1.75};
    req.target_lane = {3.5, 5.25, 1.75};
    req.leader = k >= 1 ? 0 : -1;
    req.target_vehicle = k >= 2 ? 1 : -1;
    req.stop_s = 40;
    PlanWorkspace ws;
    int64_t candidates = 0;
    uint32_t n = 0;
    for (auto _ : state) {
        req.plan_number = n++;
        PlanResult r = plan(req, ws);
        candidates += r.record.candidates;
        benchmark::DoNotOptimize(r);
    }
    state.counters["candidates/s"] = benchmark::Counter(static_cast<double>(candidates), benchmark::Counter::kIsRate);
    state.SetLabel(sdv::catalog::maneuver(kind).name + " K=" + std::to_string(k));
}

double percentile(const std::vector<double>& v, double p) {
    std::vector<double> s = v;
    std::sort(s.begin(), s.end());
    return s[static_cast<size_t>(std::min<double>(static_cast<double>(s.size() - 1), p * static_cast<double>(s.size())))];
}

}  // namespace

BENCHMARK(plan_cycle)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5}, {0, 5, 10, 20}})
    ->Unit(benchmark::kMicrosecond)
    ->ComputeStatistics("p90", [](const std::vector<double>& v) { return percentile(v, 0.9); })
    ->ComputeStatistics("p99", [](const std::vector<double>& v) { return percentile(v, 0.99); });

BENCHMARK_MAIN();
