// `sdv reuse`: the paper's internal reuse level (IRL) of a set of scenarios. A node is a
// behavior-tree node as declared in the source (identified by file, line and column, so a
// standard-library node is the same node in every scenario that uses it). For each scenario,
// IRL = (its nodes that also appear in another scenario) / (its nodes); overall, the same
// ratio summed over all scenarios (weighted by node count). Computed over all the nodes of the
// vehicles' trees, and over the nodes actually ticked during each scenario's run.
#pragma once

#include <string>
#include <vector>

#include "runtime/ir/ir.h"

namespace sdv::io {

struct ReuseInput {
    std::string label;  // file name
    const ir::Program* program = nullptr;
    int scenario = 0;
};

struct ReuseRow {
    std::string label, scenario;
    int nodes = 0, reused = 0;
    int executed = 0, executed_reused = 0;
};

struct ReuseReport {
    std::vector<ReuseRow> rows;
    ReuseRow total;
    std::string error;
};

// Runs every scenario (to find the executed nodes) and computes the reuse levels.
ReuseReport reuse(const std::vector<ReuseInput>& inputs);
std::string render_reuse(const ReuseReport& r);

}  // namespace sdv::io
