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

std::string render_text(const std::vector<Change>& changes);
nlohmann::ordered_json to_json(const std::vector<Change>& changes);
// The JSON of `sdv diff --format json` as text.
std::string render_json(const std::vector<Change>& changes);

}  // namespace sdv::diff
