// What moves an agent from one tick to the next. An agent model is a small interface: an SDV
// follows the plan its driver published, a trajectory vehicle interpolates its time-stamped
// waypoints, a static object stays put. New kinds (a pedestrian, an externally driven vehicle)
// are new models, not branches on a kind field in the loop.
#pragma once

#include <memory>
#include <optional>

#include "runtime/sim/world.h"

namespace sdv::sim {

class AgentModel {
public:
    virtual ~AgentModel() = default;
    // The `kind` column of trajectories.csv.
    virtual const char* kind() const = 0;
    // Moves the agent to time t of tick `tick`: pose, speed, acceleration, lane and lane
    // coordinates. Reads only the agent itself and the road.
    virtual void advance(const World& w, Agent& a, double t, int tick) const = 0;
};

// The model of an IR vehicle by its kind.
std::shared_ptr<const AgentModel> make_model(const ir::Vehicle& v);

// The lane whose band holds a point at lateral offset d from the centre of `lane`: the lane
// itself, its left or right neighbour (either direction), or kNoLane (off every lane).
LaneId centre_lane(const road::RoadNetwork& net, LaneId lane, double d);

// Sets an agent's pose from a Cartesian state: heading from the velocity (kept within a
// steering angle's reach of `lane_heading` when given), signed speed (negative in reverse) and
// longitudinal acceleration.
void place(Agent& a, const road::CartesianState& c, std::optional<double> lane_heading = std::nullopt);

}  // namespace sdv::sim
