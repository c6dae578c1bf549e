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
#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/source_manager.h"

namespace sdv::diag {

std::string render_text(const Diagnostic& d, const SourceManager& sm);
// A compilation's diagnostics (DiagnosticEngine::sorted), then "N errors, M warnings
// generated." when there are any. N and M are the engine's counts: they include the warnings
// past its limit, which are not listed (W0001 gives their number), so "103 warnings" may follow
// 100 listed ones.
std::string render_all_text(const DiagnosticEngine& diags, const SourceManager& sm);
// Diagnostics from elsewhere: N and M count the ones given.
std::string render_all_text(const std::vector<Diagnostic>& ds, const SourceManager& sm);

nlohmann::ordered_json to_json(const Diagnostic& d, const SourceManager& sm);
// {"diagnostics": [...], "errors": N, "warnings": M}, 2-space indent; N and M as for
// render_all_text (a tool reads the total from "warnings", the listed ones from the array).
std::string render_all_json(const DiagnosticEngine& diags, const SourceManager& sm);
std::string render_all_json(const std::vector<Diagnostic>& ds, const SourceManager& sm);

}  // namespace sdv::diag
