// Reads a Lanelet2 map (OSM XML) into the RoadNetwork with Lanelet2's own rules for a vehicle
// under the German traffic rules (docs/design-notes.md, "Lanelet2 topology"): the lanelets a
// vehicle may drive (subtype and participant tags), each oriented as Lanelet2's loader aligns
// its bounds, plus an inverted copy of each lanelet drivable both ways (one_way=no), named
// "<id>:inv"; successors (a lanelet's bounds end where another's begin, by node identity);
// same-direction neighbours where the shared bound lets a vehicle change lanes, opposite ones
// where a bound is shared inverted; traffic lights, right-of-way and all-way-stop regulatory
// elements, stop lines and speed limits; crosswalk lanelets, walkway lanelets and simple walkway
// areas become the network's crosswalks and walkways. Geographic coordinates are projected with
// GeographicLib's LocalCartesian about the origin (default: the first node of the file).
// Malformed maps give errors naming the element.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "runtime/road/road_network.h"

namespace sdv::road {

// Name suffix of the lane that drives a two-way lanelet against its orientation.
inline constexpr const char* kInvertedSuffix = ":inv";

struct GeoOrigin {
    double lat = 0, lon = 0, alt = 0;
};

struct LoadResult {
    std::optional<RoadNetwork> network;  // empty when there are errors
    std::vector<std::string> errors;     // "lanelet 44970: ..." — element kind and id first
    std::vector<std::string> warnings;
    GeoOrigin origin;   // the origin used
    int lanelets = 0;   // all lanelet relations
    int drivable = 0;   // of which a vehicle may drive: each became a lane
    int both_ways = 0;  // of which drivable both ways: each also became "<id>:inv"
};

LoadResult load_lanelet2(const std::string& path, std::optional<GeoOrigin> origin = std::nullopt);
// A geographic position in the map frame of `origin`: the projection the reader applies to
// every map node (GeoScenario files place vehicles and goals with it).
Vec2 project(const GeoOrigin& origin, double lat, double lon);

LoadResult parse_lanelet2(const std::string& xml, std::optional<GeoOrigin> origin = std::nullopt);

}  // namespace sdv::road
