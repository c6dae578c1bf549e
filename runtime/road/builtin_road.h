// Built-in roads, what the DSL's `road` and `junction` blocks lower to, built into the same
// RoadNetwork as maps.
//
// Road: segments (straight, arc) along a reference line that separates the directions. Forward
// lanes lie to its right and are numbered from the right: lane 1 is the right-most, lane F is
// next to the reference line; backward lanes are -1 (next to it), -2, ... and run the other
// way. Names: "<road>.<index>".
//
// Junction: two roads crossing at the origin, arms north (+y), east (+x), south, west, each of
// `arm_length`. Per arm and lane k (1 = right-most): "<j>.<arm>.in[.k]" towards the centre,
// "<j>.<arm>.out[.k]" away from it (".k" only when there are several lanes); connectors through
// the junction from each incoming to each other arm's outgoing lane, "<j>.<from>_to_<to>" (for
// lane k > 1: "<j>.<from>_to_<to>.k"). Stop lines at the end of every incoming lane. With
// traffic lights: "<j>.ns" controls the north and south incoming lanes, "<j>.ew" east and west.
// With two-way stops the north and south incoming lanes yield (a right-of-way element) to east
// and west.
#pragma once

#include <string>
#include <vector>

#include "runtime/road/road_network.h"

namespace sdv::road {

struct Segment {
    enum Kind { straight, arc } kind = straight;
    double length_m = 0;
    double radius_m = 0;  // arc: > 0 turns left, < 0 right
};

// A crosswalk of a built-in road or junction.
struct CrosswalkSpec {
    std::string name;     // local: the network names it "<road>.<name>"
    double s_m = 0;       // road: position of its centre line along the reference line
    std::string arm;      // junction: north | east | south | west
    double gap_m = 1.0;   // junction: from the junction box to its near edge
    double width_m = 3.0;
    // Road: a traffic light "<road>.<name>" controls the lanes before it (stop lines 1 m before
    // its edge, both directions); pedestrians walk while it is red (Crosswalk::light_inverse).
    // Junction: with traffic lights the crosswalk on an arm follows the light of the traffic
    // parallel to it (the north and south arms' crosswalks: "<j>.ew"); stop lines move back
    // to 1 m before it.
    bool signalised = false;
};

struct RoadSpec {
    std::string name;
    int lanes_forward = 1, lanes_backward = 0;
    double lane_width_m = 3.5;
    double speed_limit_mps = 13.89;
    Vec2 origin{0, 0};
    double heading_rad = 0;
    std::vector<Segment> segments;
    std::vector<CrosswalkSpec> crosswalks;
};

struct JunctionSpec {
    std::string name;
    double arm_length_m = 100;
    int lanes_per_direction = 1;
    double lane_width_m = 3.5;
    double speed_limit_mps = 11.11;
    // stop_signs: an all-way stop; two_way_stops: the north and south arms stop and yield to
    // the east and west arms, which have priority.
    enum Control { stop_signs, traffic_lights, two_way_stops, none } control = stop_signs;
    std::vector<CrosswalkSpec> crosswalks;
};

struct BuildResult {
    RoadNetwork network;
    std::vector<std::string> errors;  // empty on success
    double length = 0;                // road: reference-line length
};

BuildResult build_road(const RoadSpec& spec);
BuildResult build_junction(const JunctionSpec& spec);

// Samples the reference line of a built-in road (≤ 0.5 m spacing, exact arcs).
std::vector<Vec2> road_reference(const RoadSpec& spec);

}  // namespace sdv::road
