#include "runtime/road/routing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace sdv::road {

double routing_length(const Lane& lane) {
    const auto& line = lane.left_bound;
    if (line.size() < 2) return lane.length;
    // lanelet2_core geometry/impl/Lanelet.h, approximatedLength2d.
    double length = 0;
    const size_t step = std::max<size_t>(1, line.size() / 10);
    for (size_t i1 = 0, i2 = step; i2 < line.size(); i1 += step, i2 += step) {
        length += distance(line[i1], line[i2]);
        if (i2 + step >= line.size()) length += distance(line[i2], line.back());
    }
    return length;
}

Route shortest_route(const RoadNetwork& net, LaneId from, LaneId to) {
    Route route;
    const size_t n = net.lanes().size();
    if (from < 0 || to < 0 || static_cast<size_t>(from) >= n || static_cast<size_t>(to) >= n) {
        route.error = "unknown lane";
        return route;
    }
    std::vector<double> length(n);
    for (size_t i = 0; i < n; ++i) length[i] = routing_length(net.lanes()[i]);
    std::vector<double> dist(n, std::numeric_limits<double>::infinity());
    std::vector<LaneId> prev(n, kNoLane);
    std::vector<bool> change(n, false);
    using Item = std::pair<double, LaneId>;  // ties: smaller lane id first
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    dist[static_cast<size_t>(from)] = 0;
    queue.push({0, from});
    while (!queue.empty()) {
        const double d = queue.top().first;  // not a structured binding: clang 14 cannot capture those
        const LaneId u = queue.top().second;
        queue.pop();
        if (d > dist[static_cast<size_t>(u)]) continue;
        if (u == to) break;
        const Lane& lane = net.lane(u);
        auto relax = [&](LaneId v, double w, bool lc) {
            const double nd = d + w;
            if (nd < dist[static_cast<size_t>(v)]) {
                dist[static_cast<size_t>(v)] = nd;
                prev[static_cast<size_t>(v)] = u;
                change[static_cast<size_t>(v)] = lc;
                queue.push({nd, v});
            }
        };
        // RoutingCostDistance::getCostSucceeding: the mean of both lengths.
        for (LaneId v : lane.successors)
            relax(v, 0.5 * (length[static_cast<size_t>(u)] + length[static_cast<size_t>(v)]),
                  false);
        if (lane.left != kNoLane && lane.left_same_direction)
            relax(lane.left, kLaneChangeCost, true);
        if (lane.right != kNoLane && lane.right_same_direction)
            relax(lane.right, kLaneChangeCost, true);
    }
    if (!std::isfinite(dist[static_cast<size_t>(to)])) {
        route.error =
            "no route from lane '" + net.lane(from).name + "' to lane '" + net.lane(to).name + "'";
        return route;
    }
    for (LaneId v = to; v != kNoLane; v = prev[static_cast<size_t>(v)]) {
        route.steps.insert(route.steps.begin(), {v, change[static_cast<size_t>(v)]});
        if (v == from) break;
    }
    route.cost = dist[static_cast<size_t>(to)];
    return route;
}

}  // namespace sdv::road
