// `sdv diff`: what changed in behavior between two scenarios (compared on their IR, so .sdv and
// .sdvir mix freely and formatting never shows), and where two runs first diverge.
//
// Trees are compared per vehicle on the expanded instances, matching nodes by their path of
// names (tree / label or leaf name), not by text: a node is added, removed, moved (same tree
// and name, another place) or has parameters changed (old → new, in units).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "runtime/ir/ir.h"

namespace sdv::diff {

struct Change {
    std::string where;  // "scenario s", "vehicle v2", "vehicle v2: node cut_in/.../gap"
    std::string what;   // "min 5 m → 2 m", "added", "removed", "moved from A to B"
};

std::vector<Change> diff_programs(const ir::Program& a, const ir::Program& b);

struct RunDiff {
    bool equal = true;
    std::string error;  // a run directory could not be read
    int first_tick = -1;
    double first_time = 0;
    std::vector<std::string> vehicles;  // those that differ at first_tick
    std::string detail;                 // e.g. "v2: x 12.5 → 13.1"
    // From the decision traces, when both runs have them.
    bool has_decisions = false;
    double decision_time = -1;
    std::string decision_vehicle, decision_detail;
};

RunDiff diff_runs(const std::string& dir_a, const std::string& dir_b, double tolerance = 1e-3);

std::string render_text(const std::vector<Change>& changes);
nlohmann::ordered_json to_json(const std::vector<Change>& changes);
std::string render_text(const RunDiff& d);
nlohmann::ordered_json to_json(const RunDiff& d);

}  // namespace sdv::diff
