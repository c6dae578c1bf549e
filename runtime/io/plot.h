// `sdv plot`: a static SVG figure of a run for papers and CI logs, no browser needed: the
// vehicles' paths over the road (top) and their speed profiles over time (bottom).
#pragma once

#include <string>

namespace sdv::io {

// Reads RUN_DIR/road.json and RUN_DIR/trajectories.csv; returns the SVG text, or an error
// message in `error` (and an empty string).
std::string plot_run(const std::string& run_dir, std::string& error);

}  // namespace sdv::io
