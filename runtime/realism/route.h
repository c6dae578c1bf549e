// The route a recorded path drives: the lanes it passes through, for the SDV that replaces it.
#pragma once

#include <string>
#include <vector>

#include "runtime/realism/recording.h"
#include "runtime/road/road_network.h"

namespace sdv::realism {

struct RecordedRoute {
    std::vector<road::LaneId> lanes;  // in order, each held for at least 3 states (or first/last)
    // The goal, unless the lanes end less than `beyond` past the last state: then the vehicle
    // drives off the network, as the recorded one left the recorded area (an SDV stops at its
    // goal, a recorded vehicle does not).
    bool has_goal = false;
    road::LaneId goal_lane = road::kNoLane;
    double goal_s = 0;  // on goal_lane
    std::string error;  // the path is on no lane
};

// Locates every state (lanes within 90° of its heading), keeps the lanes held for at least three
// consecutive states, and places the goal `beyond` metres past the last state along the lanes
// that follow (straight on where there is a choice).
RecordedRoute recorded_route(const road::RoadNetwork& net, const Track& track, double beyond);

}  // namespace sdv::realism
