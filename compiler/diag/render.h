// Renders diagnostics for people (source line and caret) and for tools (JSON).
//
//   examples/cut_in.sdv:12:17: error[E0203]: unknown parameter 'sped' ...
//      12 |         maneuver keep_velocity(sped = 14 m/s)
//         |                                ^~~~
//   note: did you mean 'speed'?
//
// The gutter is the line number right-aligned in max(4, digits) columns, then " | ".
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "compiler/diag/diagnostic.h"
#include "compiler/diag/source_manager.h"

namespace sdv::diag {

std::string render_text(const Diagnostic& d, const SourceManager& sm);
// All diagnostics, then "N errors, M warnings generated." when there are any.
std::string render_all_text(const std::vector<Diagnostic>& ds, const SourceManager& sm);

nlohmann::ordered_json to_json(const Diagnostic& d, const SourceManager& sm);
// {"diagnostics": [...], "errors": N, "warnings": M}, 2-space indent.
std::string render_all_json(const std::vector<Diagnostic>& ds, const SourceManager& sm);

}  // namespace sdv::diag
