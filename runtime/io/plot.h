// `sdv plot`: a static SVG figure of a run for papers and CI logs, no browser needed: the
// vehicles' paths over the road (top) and their speed profiles over time (bottom).
// Pedestrians are in both, dashed and labelled "NAME (pedestrian)": the figure shows who went
// where when, and a pedestrian's walking and standing is part of that (a car slowing for a
// crossing reads against it). Walkways and crosswalks of road.json are drawn under the paths.
#pragma once

#include <string>

namespace sdv::io {

// Reads RUN_DIR/road.json and RUN_DIR/trajectories.csv; returns the SVG text, or an error
// message in `error` (and an empty string).
std::string plot_run(const std::string& run_dir, std::string& error);

}  // namespace sdv::io
