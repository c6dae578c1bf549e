// Reads the lanelet network of a CommonRoad scenario (XML, formats 2018b and 2020a) into the
// one RoadNetwork: each lanelet a lane named by its id (bounds as given, which CommonRoad orders
// in the driving direction), successors, left/right neighbours with their driving direction,
// speed limits (2018b `speedLimit`; 2020a speed-limit signs: MUTCD R2-1, German 274), traffic
// lights (named "tl<id>", at their position, controlling the lanelets that refer to them), stop
// lines (a stopLine's points, or the lanelet's end when it has none) and intersections (the
// lanelets an incoming leads into are in the junction, with their turn). The recorded agents
// of the file are read by runtime/realism. Errors name the element and its line.
#pragma once

#include <string>

#include "runtime/road/lanelet2_reader.h"

namespace sdv::road {

// The network of a CommonRoad file (LoadResult::origin stays 0: CommonRoad is in local metres).
LoadResult load_commonroad(const std::string& path);
LoadResult parse_commonroad(const std::string& xml);

// Whether the text is a CommonRoad document (its root element is <commonRoad>): how a `map`
// declaration's file is told apart from a Lanelet2 map.
bool is_commonroad(const std::string& xml);

// A map file of either format, by its content.
LoadResult load_map(const std::string& path, std::optional<GeoOrigin> origin = std::nullopt);

// The name of a CommonRoad traffic light in the network.
std::string commonroad_light_name(const std::string& id);

}  // namespace sdv::road
