// From the maneuver leaf a driver's tree selected to the planner's request: the configuration
// (catalog defaults, then every given parameter through the catalog's one binding,
// planner::set_field), the perceived agents as obstacles, the lanes, the leader or target, the
// stop point.
#pragma once

#include <vector>

#include "runtime/planner/planner.h"
#include "runtime/sim/leaves.h"

namespace sdv::sim {

// Applies the parameters given on a maneuver node to `config` (those left out keep the
// catalog's defaults).
void apply_params(const ir::Node& node, planner::ManeuverConfig& config);

struct PlanInputs {
    planner::ManeuverConfig config = planner::default_config(catalog::ManeuverKind::keep_velocity);
    std::vector<planner::Obstacle> obstacles;
    planner::PlanRequest request;  // points into config and obstacles
};

// Fills `out` for the selected maneuver leaf `selected` (−1: none yet, keep velocity by default).
void make_request(const Leaves& leaves, int32_t selected, PlanInputs& out);

}  // namespace sdv::sim
