// `sdv view`: one self-contained HTML report of a run directory (the viewer of
// runtime/io/viewer/viewer.html with the run's data inlined as JSON, format "sdv-view/1"):
// the road, vehicles over time, per-vehicle charts, maneuver timeline with events,
// expectations and metrics, and with a decision trace the tree path and candidates of each
// planning cycle. It needs nothing at view time: no network, no files.
#pragma once

#include <string>
#include <string_view>

namespace sdv::io {

// The viewer page with its data placeholder (embedded at build time).
std::string_view viewer_template();

// The report of `run_dir` (written by `sdv run -o`), or "" with `error` set.
std::string view_report(const std::string& run_dir, std::string& error);

}  // namespace sdv::io
