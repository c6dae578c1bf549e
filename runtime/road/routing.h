// Routing over lanes: the shortest lane path (Dijkstra) over successor edges (cost: lane
// length) and lane-change edges to same-direction neighbours (cost: kLaneChangeCost plus the
// distance still to drive in the new lane, so changes happen where they are needed), with
// deterministic tie-breaking by lane id.
#pragma once

#include <string>
#include <vector>

#include "runtime/road/road_network.h"

namespace sdv::road {

inline constexpr double kLaneChangeCost = 50.0;  // m-equivalent of one lane change

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

}  // namespace sdv::road
