// One planning cycle of a driver (SPEC §3.3): refresh its reference line when needed, perceive,
// tick its tree (again after a completed lane change, in the new lane's frame), turn the
// selection into a planner request, plan, and keep the plan to take effect at t0 + latency.
// Reads the world and the snapshot only; writes only the agent's driver, so the drivers due at
// a tick plan in parallel.
#pragma once

#include "runtime/sim/world.h"

namespace sdv::sim {

void plan_cycle(const World& w, Agent& a, double t0);

}  // namespace sdv::sim
