// The realism subcommands of `sdv` (docs/realism.md): `replay` replaces recorded vehicles by
// SDVs one at a time and measures how far each drives from its recording (STED); `calibrate`
// fits driving-style parameters to a recording with a derivative-free optimiser (NLopt).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cli/common.h"

namespace sdv::cli {

struct ReplayArgs {
    std::string recording, map, out;
    std::string sdv = "all";  // a track id, a comma-separated list, or "all"
    std::string tree;         // the SDV's tree call; empty: std.drive at the lane's speed limit
    std::vector<std::string> imports;
    int jobs = 0;  // 0: every core
};

int cmd_replay(const ReplayArgs& args, const Common& c);

struct CalibrateArgs {
    std::string recording, map, out;
    std::string params;       // "time_gap,speed" or "time_gap=0.5..3,speed"
    std::string sdv = "all";  // the vehicles used (split into training and held-out)
    std::string tree;         // the tree whose parameters are fitted (default std.drive)
    std::vector<std::string> imports;
    double split = 0.7;
    uint64_t seed = 1;
    int budget = 60;  // objective evaluations
    int jobs = 0;
};

int cmd_calibrate(const CalibrateArgs& args, const Common& c);

// `sdv convert RECORDING`: the .sdv text replaying a recording (optionally with one SDV).
int cmd_convert_recording(const std::string& recording, const std::string& map, const std::string& sdv,
                          const std::string& out, const Common& c);

// Whether a file is recorded traffic (a CommonRoad scenario with dynamic obstacles, or an
// INTERACTION track file) rather than a map or a scenario.
bool is_recording_path(const std::string& file);

}  // namespace sdv::cli
