// Cost of one Cartesian → Frenet projection on a 2 km road of straights and arcs (issue "exact
// roads"): global (no hint: bounding-box search over the whole line) and hinted (the previous s,
// as a vehicle's own projection each tick). Points lie up to 3 m either side of the line.
//   build/bench/bench/projection_bench --benchmark_repetitions=10 --benchmark_report_aggregates_only
#include <benchmark/benchmark.h>

#include <vector>

#include "runtime/road/builtin_road.h"

using namespace sdv::road;

namespace {

struct Scene {
    RoadNetwork net;
    std::vector<std::pair<Vec2, double>> points;  // point, its true s
};

const Scene& scene() {
    static const Scene s = [] {
        RoadSpec spec;
        spec.name = "r";
        spec.segments = {{Segment::straight, 400, 0}, {Segment::arc, 300, 150}, {Segment::straight, 300, 0},
                         {Segment::arc, 400, -200}, {Segment::straight, 300, 0}, {Segment::arc, 300, 120}};
        Scene out;
        out.net = build_road(spec).network;
        const ReferenceLine& ref = out.net.reference(0);
        for (int i = 0; i < 4096; ++i) {
            const double at = ref.length() * ((i * 2654435761u) % 4096) / 4096.0;
            const double d = -3.0 + 6.0 * ((i * 40503u) % 1000) / 1000.0;
            const auto c = ref.to_cartesian({at, 0, 0, d, 0, 0});
            out.points.push_back({{c.x, c.y}, at});
        }
        return out;
    }();
    return s;
}

void project_global(benchmark::State& state) {
    const Scene& sc = scene();
    const ReferenceLine& ref = sc.net.reference(0);
    size_t i = 0;
    for (auto _ : state) {
        const auto& p = sc.points[i++ % sc.points.size()];
        benchmark::DoNotOptimize(ref.project(p.first));
    }
    state.SetLabel("road " + std::to_string(static_cast<int>(ref.length())) + " m");
}

void project_hinted(benchmark::State& state) {
    const Scene& sc = scene();
    const ReferenceLine& ref = sc.net.reference(0);
    size_t i = 0;
    for (auto _ : state) {
        const auto& p = sc.points[i++ % sc.points.size()];
        benchmark::DoNotOptimize(ref.project(p.first, p.second + 0.4));  // last tick's s
    }
    state.SetLabel("road " + std::to_string(static_cast<int>(ref.length())) + " m");
}

}  // namespace

BENCHMARK(project_global);
BENCHMARK(project_hinted);
BENCHMARK_MAIN();
