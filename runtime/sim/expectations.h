// The scenario's `expect` statements, evaluated on a finished run's events and metrics.
#pragma once

#include "runtime/ir/ir.h"
#include "runtime/sim/simulation.h"

namespace sdv::sim {

// Fills out.expectations, one per expectation root of the scenario.
void evaluate_expectations(const ir::Scenario& scenario, RunResult& out);

}  // namespace sdv::sim
