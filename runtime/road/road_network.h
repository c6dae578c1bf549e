// The one road-network model that both built-in roads and Lanelet2 maps feed: lanes with
// centre lines and bounds, direction (a lane's centre line runs in its driving direction),
// speed limits, successors and predecessors, left/right neighbours (same or opposite
// direction), stop lines, traffic lights and intersection rules.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "runtime/road/geometry.h"
#include "runtime/road/reference_line.h"

namespace sdv::road {

using LaneId = int32_t;
inline constexpr LaneId kNoLane = -1;

enum class Turn { none, straight, left, right };

// A line across a lane where vehicles stop: before a junction, a crosswalk, a stop sign. A lane
// may have several (two signalised crosswalks on one road); each has the lights that control it.
struct StopLine {
    double s = 0.0;                      // along the lane's centre line
    std::vector<int32_t> traffic_lights;  // the first is the one drivers read
};

struct Lane {
    LaneId id = kNoLane;
    std::string name;               // built-in: "<road>.<index>"; Lanelet2: the lanelet id
    std::vector<Vec2> centre;       // in driving direction
    std::vector<Vec2> left_bound, right_bound;
    double length = 0.0;            // of the centre line
    double width = 3.5;             // nominal
    double speed_limit = 13.89;     // m/s
    std::vector<LaneId> successors, predecessors;
    LaneId left = kNoLane, right = kNoLane;
    bool left_same_direction = true, right_same_direction = true;
    std::vector<StopLine> stop_lines;   // by s
    // Every light that controls the lane: those of its stop lines, and (Lanelet2) those its
    // regulatory elements name, with or without a stop line.
    std::vector<int32_t> traffic_lights;
    bool all_way_stop = false;
    int32_t right_of_way = -1;      // index into RoadNetwork::rights_of_way
    bool in_junction = false;
    Turn turn = Turn::none;

    // Adds a stop line at `s` controlled by `lights` (appended to those of a stop line within
    // 1 cm of it), keeping the lines ordered by s.
    void add_stop_line(double s, const std::vector<int32_t>& lights = {});
    // The first stop line at or after `s`; nullptr if none.
    const StopLine* stop_line_from(double s) const;
};

struct TrafficLight {
    int32_t id = 0;
    std::string name;
    Vec2 position;
    std::vector<LaneId> lanes;  // lanes whose stop line it controls
};

struct RightOfWay {
    std::vector<LaneId> yield, priority;
};

// A pedestrian crossing: a strip across vehicle lanes. Pedestrians enter it at either end and
// walk along `centre` (or against it); vehicles whose lanes it crosses yield to them there.
struct Crosswalk {
    int32_t id = 0;
    std::string name;          // built-in: "<road>.<name>"; Lanelet2: the lanelet id
    std::vector<Vec2> centre;  // from one end (an entrance) to the other, over the lanes
    std::vector<Vec2> left_bound, right_bound;
    double width = 3.0;
    double length = 0.0;       // of the centre line
    // The pedestrians' signal (index into RoadNetwork::lights; -1: none). With `light_inverse`
    // the light is the vehicles' one and pedestrians may walk while it is red (a signalised
    // mid-block crossing whose pedestrian signal is derived from the vehicles').
    int32_t light = -1;
    bool light_inverse = false;
    // Where it crosses vehicle lanes: the lane, the s of the crossing on the lane's centre line,
    // and the half-extent along the lane (its half width there).
    struct Crossing {
        LaneId lane = kNoLane;
        double s = 0.0;
        double half_extent = 1.5;
    };
    std::vector<Crossing> crossings;
};

// A footpath (Lanelet2 walkway lanelet or area): where pedestrians walk beside the road.
struct Walkway {
    std::string name;
    std::vector<Vec2> centre, left_bound, right_bound;
    double width = 2.0;
};

class RoadNetwork {
public:
    LaneId add_lane(Lane lane);  // assigns the id; computes the length
    void connect(LaneId from, LaneId to);
    void set_neighbours(LaneId right, LaneId left, bool same_direction);

    const std::vector<Lane>& lanes() const { return lanes_; }
    const Lane& lane(LaneId id) const { return lanes_.at(static_cast<size_t>(id)); }
    Lane& lane_mut(LaneId id) { return lanes_.at(static_cast<size_t>(id)); }
    std::optional<LaneId> find(const std::string& name) const;

    std::vector<TrafficLight> lights;
    std::vector<RightOfWay> rights_of_way;
    std::vector<Crosswalk> crosswalks;
    std::vector<Walkway> walkways;

    // The lane whose centre line is nearest to p (among lanes whose direction is within 90° of
    // `heading`, when given), with the position along it.
    struct Location {
        LaneId lane = kNoLane;
        double s = 0, d = 0;
    };
    Location locate(Vec2 p, std::optional<double> heading = std::nullopt) const;

    // The reference line of one lane (built on first use and kept).
    const ReferenceLine& reference(LaneId id) const;

    // Builds every reference line and the index that makes locate() fast (boxes around runs of
    // centre points): call once the network is complete, before threads read it. locate()
    // gives the same answer with or without the index.
    void prepare();

private:
    struct Box {
        double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
        void add(Vec2 p);
        double distance2(Vec2 p) const;  // squared; 0 inside
    };
    static constexpr size_t kChunk = 16;  // centre points per box
    struct LaneBoxes {
        Box all;
        std::vector<Box> chunks;  // points [k·kChunk, (k+1)·kChunk)
    };
    // The distance from p to the nearest centre point of lane l (exactly the minimum over its
    // points), skipping runs of points whose box is farther than the nearest so far.
    double nearest_point(const Lane& l, Vec2 p) const;

    std::vector<Lane> lanes_;
    mutable std::vector<std::optional<ReferenceLine>> refs_;
    std::vector<LaneBoxes> boxes_;  // empty until prepare()
};

// A located error when more than 16 lanes and crosswalks, or more than 96 segments of their
// centre lines, pass through one place (a 2 m square for sampled lanes): the limits that keep
// find_crossings and mark_junctions linear in the map.
std::optional<std::string> crowded_place(const RoadNetwork& net);

// Fills every crosswalk's `length` and `crossings` from its centre line and the lanes (call
// once lanes and crosswalks are complete, before prepare()). A crosswalk that lies on a lane
// (parallel within 1e-6 and a few µm away) does not cross it there. Returns the pairs of segments
// it examined: its work, which tests bound by the map's size.
size_t find_crossings(RoadNetwork& net);

// Marks the lanes of junctions in a network that does not say where its junctions are (a
// Lanelet2 map): a lane is in a junction when its centre line crosses or touches another's that
// is neither its successor, its predecessor nor its neighbour, as the lanes of an intersection
// cross, merge and diverge (Lanelet2's conflicting lanelets). Lanes that lie on each other
// (parallel within 1e-6 and a few µm apart) touch along a line, which is no meeting. Returns the
// pairs of segments it examined: its work, which tests bound by the map's size.
size_t mark_junctions(RoadNetwork& net);

// Polyline helpers.
double polyline_length(const std::vector<Vec2>& pts);
std::vector<Vec2> offset_polyline(const std::vector<Vec2>& pts, double d);  // left positive

}  // namespace sdv::road
