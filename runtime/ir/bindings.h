// The numbers of a scenario in one fixed order, and a variant of a campaign applied to them.
// The order is what `VaryBinding::number` indexes: the checker records bindings in it and the
// runtime applies them in it, so it must not change without a new IR format version.
#pragma once

#include <string>
#include <vector>

#include "runtime/ir/ir.h"

namespace sdv::ir {

// Every number of scenario `index` that a value written in the source can reach: the
// scenario's settings, its vehicles (sizes, speeds, positions, trajectories), its light
// programs, its expectations' bounds and windows, then the leaf parameters of its vehicles'
// tree instances (in vehicle order). Seeds are not numbers here (see VaryParam::seed).
std::vector<double*> scenario_numbers(Program& program, int index);
std::vector<double> scenario_number_values(const Program& program, int index);

// The values of one variant (one per VaryParam, SI) written into `program`, whose numbers
// must still be those of `base` (the compiled program) for the bound ones. Checks nothing
// beyond the bindings' indices; returns "" or what is wrong.
std::string apply_variant(Program& program, int index, const std::vector<double>& base_numbers,
                          const std::vector<double>& values);

// Restores the numbers and the seed that apply_variant may have changed.
void reset_variant(Program& program, int index, const Program& base);

}  // namespace sdv::ir
