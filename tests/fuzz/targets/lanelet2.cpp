// Fuzz target of the Lanelet2 map reader: the input as the map of a scenario through what
// `sdv run` does with it (runtime/road/lanelet2_reader.h: the reader of load_lanelet2, then
// RoadNetwork::prepare), then what placing vehicles and routing them asks of the network: locate
// (with and without a heading), each located lane's reference line (project, to_cartesian,
// heading) and a shortest route. Property: a map that loads has no error and a network, and one
// that fails names its errors.
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

void probe(const road::RoadNetwork& net, road::Vec2 p, std::optional<double> heading) {
    const auto loc = net.locate(p, heading);
    if (loc.lane == road::kNoLane) return;
    const road::ReferenceLine& ref = net.reference(loc.lane);
    road::FrenetState f = ref.project(p);
    (void)ref.to_cartesian(f);
    (void)ref.heading(std::clamp(f.s, 0.0, ref.length()));
    (void)ref.curvature(std::clamp(f.s, 0.0, ref.length()));
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
