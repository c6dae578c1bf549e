// `sdv run --gss-outputs`: the GeoScenario Server's own output files, so that its users'
// regression scripts keep working (SPEC §8):
//   violations.json        {vid: {tick: {Class: {payload}}}}, every SDV a key ({} when it has
//                          no violation); the reference's classes and payloads
//                          (CollisionWithVehicle, CollisionWithPedestrian, GoalOvershot,
//                          ScenarioTimeout; RequirementViolationEvents.py); the tick is the
//                          reference's planner tick in progress;
//   trajectory_v<vid>.csv  the reference's 19 columns per tick.
// Vehicle ids are taken from names of the form v<id> (pedestrians p<id>, as `sdv convert` writes
// them), else the agent's position in the scenario, from 1.
#pragma once

#include <functional>
#include <istream>
#include <string>

#include "runtime/ir/ir.h"
#include "runtime/sim/simulation.h"

namespace sdv::io {

// Where agent i (an index into the scenario's vehicles) is at time t.
struct Pose {
    double x = 0, y = 0, yaw = 0;
};
using PoseAt = std::function<Pose(int, double)>;

std::string violations_json(const ir::Program& p, int scenario, const sim::RunResult& r, const PoseAt& pose);
// Returns an error message, or "" on success.
// `trajectories_csv` reads the run's trajectories.csv.
std::string write_gss_outputs(const std::string& dir, const ir::Program& p, int scenario, const sim::RunResult& r,
                              std::istream& trajectories_csv);

}  // namespace sdv::io
