// Reads a Lanelet2 map (OSM XML) into the RoadNetwork: drivable lanelets with centre lines
// from their bounds, successors (a lanelet's bounds end where another's begin), neighbours
// (shared bound ways; a way shared as both left bounds means opposite directions), traffic
// lights, right-of-way and all-way-stop regulatory elements, stop lines and speed limits.
// Geographic coordinates are projected with GeographicLib's LocalCartesian about the origin
// (default: the first node of the file). Malformed maps give errors naming the element.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "runtime/road/road_network.h"

namespace sdv::road {

struct GeoOrigin {
    double lat = 0, lon = 0, alt = 0;
};

struct LoadResult {
    std::optional<RoadNetwork> network;  // empty when there are errors
    std::vector<std::string> errors;     // "lanelet 44970: ..." — element kind and id first
    std::vector<std::string> warnings;
    GeoOrigin origin;                    // the origin used
    int lanelets = 0;                    // all lanelet relations
    int drivable = 0;                    // of which became lanes
};

LoadResult load_lanelet2(const std::string& path, std::optional<GeoOrigin> origin = std::nullopt);
// A geographic position in the map frame of `origin`: the projection the reader applies to
// every map node (GeoScenario files place vehicles and goals with it).
Vec2 project(const GeoOrigin& origin, double lat, double lon);

LoadResult parse_lanelet2(const std::string& xml, std::optional<GeoOrigin> origin = std::nullopt);

}  // namespace sdv::road
