// The reference line a driver plans in: the centre lines of the lanes along its route from a
// lane (one predecessor behind it, up to a few hundred metres ahead), fitted into one line.
#pragma once

#include <memory>
#include <vector>

#include "runtime/road/reference_line.h"
#include "runtime/road/road_network.h"
#include "runtime/road/routing.h"
#include "runtime/sim/world.h"

namespace sdv::sim {

// Builds the driver's path from `from` along `route` (the first straight-ahead successor where
// the route says nothing), reaching at least 300 m beyond `from_s` (the driver's position on
// `from`) however long the lanes are: fills d.path and d.path_start and returns the fitted line,
// or null when no line can be fitted.
// Lines are shared through `cache` (World::paths) by their lanes.
std::shared_ptr<const road::ReferenceLine> build_path(const road::RoadNetwork& net, const std::vector<road::RouteStep>& route,
                                                      Driver& d, LaneId from, double from_s, PathCache& cache);

}  // namespace sdv::sim
