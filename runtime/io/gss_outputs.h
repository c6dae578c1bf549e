// `sdv run --gss-outputs`: the GeoScenario Server's own output files, so that its users'
// regression scripts keep working (SPEC §8):
//   violations.json        {vid: {tick: {Class: {"message": ...}}}}, every SDV a key ({} when
//                          it has no violation); classes CollisionWithVehicle, GoalOvershot,
//                          ScenarioTimeout; the tick is the SDV's planning-cycle count;
//   trajectory_v<vid>.csv  the reference's 19 columns per tick.
// Vehicle ids are taken from names of the form v<id> (as `sdv convert` writes them), else the
// vehicle's position in the scenario, from 1.
#pragma once

#include <istream>
#include <string>

#include "runtime/ir/ir.h"
#include "runtime/sim/simulation.h"

namespace sdv::io {

std::string violations_json(const ir::Program& p, int scenario, const sim::RunResult& r);
// Returns an error message, or "" on success.
// `trajectories_csv` reads the run's trajectories.csv.
std::string write_gss_outputs(const std::string& dir, const ir::Program& p, int scenario, const sim::RunResult& r,
                              std::istream& trajectories_csv);

}  // namespace sdv::io
