// Writes a run's outputs (SPEC §7) into a directory: trajectories.csv, summary.json (no wall-
// clock value: identical runs give identical bytes), decisions.jsonl (with --trace) and
// timing.json (the only file that varies between identical runs).
#pragma once

#include <string>

#include "runtime/io/recorder.h"
#include "runtime/ir/ir.h"
#include "runtime/sim/simulation.h"

namespace sdv::io {

struct RunInfo {
    std::string ir_hash;
    uint64_t seed = 0;
    bool trace = false;
    int threads = 1;
    // A co-simulated run: how it ended ("finished", "stopped by client at tick N",
    // "aborted: <why>"); empty for a run without a client.
    std::string cosim_ending;
};

std::string summary_json(const ir::Program& p, int scenario, const sim::RunResult& r, const RunInfo& info);
std::string timing_json(const sim::RunResult& r, int threads);
// Returns an error message, or "" on success.
std::string write_outputs(const std::string& dir, const ir::Program& p, int scenario, const sim::RunResult& r,
                          const Recording& rec, const RunInfo& info);
// The short report printed on stdout.
std::string report(const ir::Program& p, int scenario, const sim::RunResult& r);
// One event as the report lists it ("    3.40 s  collision car p1 (1.8 m/s, front)").
std::string event_line(const ir::Scenario& sc, const sim::Event& ev);

}  // namespace sdv::io
