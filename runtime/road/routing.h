// Routing over lanes as Lanelet2's RoutingGraph::getRoute / shortestPath does it with its default
// RoutingCostDistance(laneChangeCost = 10): the shortest lane path (Dijkstra) over successor
// edges, costing the mean of the two lanes' lengths (geometry::approximatedLength2d of the left
// bound), and lane-change edges to same-direction neighbours, costing kLaneChangeCost. A Lanelet2
// map keeps a same-direction neighbour only where the traffic rules allow the lane change (see
// lanelet2_reader.h). Ties are broken deterministically by lane id.
#pragma once

#include <string>
#include <vector>

#include "runtime/road/road_network.h"

namespace sdv::road {

inline constexpr double kLaneChangeCost =
    10.0;  // m-equivalent of one lane change (Lanelet2's default)

struct RouteStep {
    LaneId lane = kNoLane;
    bool by_lane_change = false;  // entered from the previous step by changing lanes
};

struct Route {
    std::vector<RouteStep> steps;  // empty when unreachable
    double cost = 0;
    std::string error;
};

Route shortest_route(const RoadNetwork& net, LaneId from, LaneId to);

// The length Lanelet2's RoutingCostDistance gives a lane: geometry::approximatedLength2d, the
// length of the left bound sampled at every max(1, n/10)-th of its n points (the centre line's
// length when a lane has no left bound).
double routing_length(const Lane& lane);

}  // namespace sdv::road
