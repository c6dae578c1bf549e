// `sdv diff --runs`: where two runs first differ, read from their run directories (the outputs
// of `sdv run -o`, which users pass around as CI artifacts: read as untrusted input).
#pragma once

#include <string>
#include <vector>

namespace sdv::io {

// Where two runs (run directories of sdv run) first differ: the first tick at which an agent is
// in one run only or its position or speed differs by more than the tolerance, and the first
// planning decision (decisions.jsonl, both runs traced) whose maneuver, winning candidate or cost
// differs or that one run has and the other not.
struct RunDiff {
    bool equal = true;
    std::string error;  // a run directory could not be read: the file, the line and why
    long first_tick = -1;
    double first_time = 0;
    std::vector<std::string> vehicles;  // those that differ at first_tick
    std::string detail;                 // e.g. "v2: position differs by 0.52 m, speed 18 → 18.3 m/s"
    // From the decision traces, when both runs have them.
    bool has_decisions = false;
    double decision_time = 0;
    std::string decision_vehicle, decision_detail;  // detail empty: no decision differs
};

// Reads both run directories as sdv view does (TrajectoryReader of run_dir.h, at any tick; JSON
// lines nested at most kMaxRunJsonDepth levels): a file that is not what sdv run writes is an
// error naming the file and the line, never a crash.
RunDiff diff_runs(const std::string& dir_a, const std::string& dir_b, double tolerance = 1e-3);

std::string render_text(const RunDiff& d);
// The JSON of `sdv diff --runs --format json` as text: text from the runs that is not UTF-8 is
// written with U+FFFD in place of its bad bytes.
std::string render_json(const RunDiff& d);

}  // namespace sdv::io
