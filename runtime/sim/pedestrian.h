// Pedestrians. A simulated pedestrian (sdp) has a tree whose maneuvers set its intent (where it
// walks, how fast: world.h `Walker`); every tick its motion model moves it by the social force
// toward that intent, repelled by the pedestrians and vehicles around it (social_force.h).
// Path and trajectory pedestrians follow their waypoints like trajectory vehicles (agents.cpp).
// Its way: to its goal, through its target crosswalk when it has chosen one (entrance, along
// the crosswalk, far end). Its tree ticks at the planning rate (pedestrian_leaves.cpp).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "runtime/sim/world.h"

namespace sdv::sim {

class AgentModel;

// The motion model of a simulated pedestrian.
std::shared_ptr<const AgentModel> make_walker_model();

// An end of a crosswalk: 0 the first point of its centre line, 1 the last.
road::Vec2 crosswalk_end(const road::Crosswalk& c, int end);
// Where a walker enters or leaves a crosswalk at an end: the end, moved across the crosswalk by
// the walker's offset (a crowd crosses side by side, not through one point).
road::Vec2 crosswalk_point(const road::Crosswalk& c, const Walker& k, int end);
// The offset across the crosswalk a pedestrian of `radius` at `p` keeps, entering by `entrance`:
// where it stands across it, within its width.
double crosswalk_offset(const road::Crosswalk& c, int entrance, road::Vec2 p, double radius);

// Where the pedestrian walks now and how fast (speed 0: it stands).
struct Intent {
    road::Vec2 target;
    double speed = 0;
};
Intent intent(const World& w, const Agent& a);

// A crosswalk on the way from `p` to `goal`: one across vehicle lanes whose far end (from the
// end nearer to p, its entrance) is nearer to the goal than its entrance, with the detour over
// walking straight.
struct WayCrosswalk {
    int32_t crosswalk = -1;
    int entrance = 0;
    double detour = 0;
    double distance = 0;  // from p to its entrance
};
// Those within `max_detour`, nearest entrance first (ties: lower index).
std::vector<WayCrosswalk> crosswalks_on_way(const World& w, road::Vec2 p, road::Vec2 goal, double max_detour);

// The state of a crosswalk's pedestrian signal at t: "red", "yellow", "green", or "" without one.
std::string pedestrian_signal(const World& w, int32_t crosswalk, double t);
// How long from t its pedestrian signal stays other than red (0 when red; +inf without a
// signal or when it never turns red).
double time_until_red(const World& w, int32_t crosswalk, double t);

class Leaves;

// For a driver: the nearest pedestrian within `distance` ahead that it yields to (on a crosswalk
// across its path near its lane or heading into it, waiting at one of its ends, or in its lane
// ahead off any crosswalk), and the s on its reference line where its centre stops for it (the
// front bumper 1 m before the crosswalk, or 2 m before the pedestrian).
struct Yield {
    int pedestrian = -1;
    double stop_s = 0;
};
std::optional<Yield> pedestrian_ahead(const Leaves& l, double distance);
// The room a driver's trajectory leaves round a pedestrian's footprint, on every side.
inline constexpr double kPedestrianMargin = 0.5;  // m
// How far ahead `stop(at = pedestrian)` looks for the pedestrian of `pedestrian_crossing`.
inline constexpr double kPedestrianLookAhead = 300.0;  // m

// One tick of a pedestrian's tree at time t over the snapshot: sets its intent.
void walk_cycle(const World& w, Agent& a, double t);

}  // namespace sdv::sim
