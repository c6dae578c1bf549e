// Fuzz target of the Lanelet2 map reader: the input as the map of a scenario through what
// `sdv run` does with it (runtime/road/lanelet2_reader.h: the reader of load_lanelet2, then
// RoadNetwork::prepare), then what placing vehicles and routing them asks of the network: locate
// (with and without a heading), each located lane's reference line (project, to_cartesian,
// heading) and a shortest route. Properties: a map that loads has no error and a network, and one
// that fails names its errors; on every probed lane's reference line a point placed at (s, d) for
// d on the line and half a metre either side of it, where the line bends gently enough for such a
// point to have a foot (|d| κ < 1/2 within two metres), comes back from Cartesian → Frenet →
// Cartesian to the same place (reference_line.h promises it to the solver's tolerance), with and
// without a hint, and every Frenet and Cartesian value on the way is finite.
#include <algorithm>
#include <cmath>
#include <string>

#include "runtime/road/lanelet2_reader.h"
#include "runtime/road/routing.h"
#include "tests/fuzz/targets/scratch.h"
#include "tests/fuzz/targets/targets.h"

using namespace sdv;

namespace {

constexpr const char* kTarget = "lanelet2";
// Lanes probed per map: enough to reach every kind of lane of a small map, bounded for big ones.
constexpr size_t kProbes = 8;

// Stations along a line where the round trip is checked.
constexpr int kStations = 5;

bool finite(const road::FrenetState& f) {
    return std::isfinite(f.s) && std::isfinite(f.d) && std::isfinite(f.s_d) && std::isfinite(f.d_d);
}

// The largest |κ| of the line within two metres of s (it is sampled every 0.25 m or closer).
double max_curvature(const road::ReferenceLine& ref, double s) {
    double k = 0;
    for (int j = -16; j <= 16; ++j) k = std::max(k, std::fabs(ref.curvature(std::clamp(s + 0.125 * j, 0.0, ref.length()))));
    return k;
}

// Cartesian → Frenet → Cartesian of points placed off the line at its stations.
void round_trips(const road::ReferenceLine& ref) {
    const double length = ref.length();
    if (!std::isfinite(length) || length <= 0) fuzz::fail(kTarget, "a reference line of length " + std::to_string(length));
    for (int i = 0; i <= kStations; ++i) {
        const double s = length * i / kStations;
        const double bend = max_curvature(ref, s);
        for (double d : {0.0, 0.5, -0.5}) {
            if (std::fabs(d) * bend >= 0.5) continue;  // beyond the centre of curvature: no foot
            road::FrenetState placed;
            placed.s = s;
            placed.d = d;
            const road::CartesianState c = ref.to_cartesian(placed);
            const road::Vec2 p{c.x, c.y};
            if (!std::isfinite(p.x) || !std::isfinite(p.y)) fuzz::fail(kTarget, "to_cartesian gives a non-finite point");
            // The solver stops at 1e-10 m of s; coordinates carry 1e-16 of their size.
            const double tolerance = 1e-6 + 1e-12 * std::max(std::fabs(p.x), std::fabs(p.y));
            for (double hint : {-1.0, s}) {
                const road::FrenetState f = ref.project(p, hint);
                if (!finite(f)) fuzz::fail(kTarget, "project gives a non-finite Frenet state");
                const road::CartesianState back = ref.to_cartesian(f);
                const double err = std::hypot(back.x - p.x, back.y - p.y);
                if (!(err <= tolerance))
                    fuzz::fail(kTarget, "a point at s=" + std::to_string(s) + " d=" + std::to_string(d) +
                                            " comes back " + std::to_string(err) + " m away (hint " +
                                            std::to_string(hint) + ", projected to s=" + std::to_string(f.s) +
                                            " d=" + std::to_string(f.d) + ")");
            }
        }
    }
}

void probe(const road::RoadNetwork& net, road::Vec2 p, std::optional<double> heading) {
    const auto loc = net.locate(p, heading);
    if (loc.lane == road::kNoLane) return;
    const road::ReferenceLine& ref = net.reference(loc.lane);
    road::FrenetState f = ref.project(p);
    (void)ref.to_cartesian(f);
    (void)ref.heading(std::clamp(f.s, 0.0, ref.length()));
    (void)ref.curvature(std::clamp(f.s, 0.0, ref.length()));
    round_trips(ref);
}

}  // namespace

int sdv_fuzz_lanelet2(const uint8_t* data, size_t size) {
    auto r = road::parse_lanelet2(std::string(reinterpret_cast<const char*>(data), size));
    if (!r.network) {
        if (r.errors.empty()) fuzz::fail(kTarget, "no network and no error");
        return 0;
    }
    if (!r.errors.empty()) fuzz::fail(kTarget, "a network although there were errors: " + r.errors.front());
    road::RoadNetwork net = std::move(*r.network);
    net.prepare();
    const auto& lanes = net.lanes();
    probe(net, {0, 0}, std::nullopt);
    const size_t step = std::max<size_t>(1, lanes.size() / kProbes);
    for (size_t i = 0; i < lanes.size(); i += step) {
        const road::Lane& l = lanes[i];
        if (l.centre.size() < 2) continue;
        const road::Vec2 a = l.centre.front(), b = l.centre[1];
        probe(net, {a.x + 0.5, a.y - 0.5}, std::atan2(b.y - a.y, b.x - a.x));
        probe(net, l.centre.back(), std::nullopt);
    }
    if (!lanes.empty()) (void)road::shortest_route(net, 0, static_cast<road::LaneId>(lanes.size() - 1));
    return 0;
}
