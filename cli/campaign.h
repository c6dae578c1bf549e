// The campaign subcommands of `sdv` (docs/campaigns.md): `sweep` runs every variant of a
// scenario's vary block, `search` looks for the worst one with a derivative-free optimiser.
#pragma once

#include <string>

#include "cli/common.h"

namespace sdv::cli {

struct SweepArgs {
    std::string file, out, scenario;
    int jobs = 0;  // 0: every core
    bool resume = false;
    std::string keep = "none";  // none | failed | runs
    bool report = false;
    std::string junit;
    std::string slice;  // I/K: one slice (what a Slurm array task runs)
    bool slurm = false, slurm_script_only = false;
    int array_tasks = 4;
    std::string partition;
};

int cmd_sweep(const SweepArgs& args, const Common& c, const WarningFlags& w);

struct SearchArgs {
    std::string file, out, scenario;
    std::string minimize, maximize;  // a metric as an expectation names it: "min_ttc(ego, v2)"
    int budget = 200;
    uint64_t seed = 1;
    std::string write;  // the worst case as a concrete .sdv (default OUT/worst.sdv)
};

int cmd_search(const SearchArgs& args, const Common& c, const WarningFlags& w);

}  // namespace sdv::cli
