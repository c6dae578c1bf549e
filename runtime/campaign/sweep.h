// A sweep: every variant of a campaign run headless, in parallel, one results row each.
//
// DIR/rows/slice-I-of-K.csv    rows as they finish (appended, one write per row), per slice
// DIR/rows/manifest.json       the campaign (IR hash, variant count, columns) they belong to
// DIR/results.csv              every row, sorted by variant (written once all are in)
// DIR/summary.json             counts and worst cases, from the rows only
// DIR/timing.json              wall-clock figures of this process (the one output that varies)
// DIR/runs/<variant>/          the outputs of `sdv run` and view.html, for kept variants
//
// A row is a pure function of (IR, variant index): results.csv and summary.json are the same
// bytes for any number of jobs, after a resume, and when the slices ran as Slurm array tasks.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "runtime/campaign/variants.h"
#include "runtime/ir/ir.h"
#include "runtime/sim/simulation.h"

namespace sdv::campaign {

enum class Keep { none, failed, runs };

struct SweepOptions {
    std::string dir;
    std::string file;  // the scenario file as given (summary.json, messages)
    int jobs = 1;
    bool resume = false;  // keep the rows already in DIR (else start afresh)
    Keep keep = Keep::none;
    int slice = 0, slices = 1;  // run the variants [slice * n / slices, (slice + 1) * n / slices)
    // Called on the calling thread after each finished variant.
    std::function<void(int64_t done, int64_t total, int64_t failed)> progress;
};

struct SweepOutcome {
    std::string error;    // the sweep could not run (a row that failed is not an error)
    int64_t variants = 0; // in the whole campaign
    int64_t ran = 0;      // by this call
    int64_t skipped = 0;  // already in DIR (resume)
    int64_t damaged = 0;  // lines of DIR/rows that are not rows sdv wrote (their variants ran again)
    std::string damage;   // the first of them: "FILE:LINE: why"
    double wall_s = 0;
};

// The results columns of a campaign's scenario (see docs/campaigns.md).
std::vector<std::string> columns(const ir::Scenario& scenario);

// The row of one variant's run (row_text of run_row).
std::string row(const ir::Scenario& scenario, int64_t index, const std::vector<double>& values,
                const sim::RunResult& result);

// Runs the variants of this slice that DIR does not hold yet.
SweepOutcome run_sweep(const ir::Program& program, int scenario, const SweepOptions& options);

// Runs one variant (already applied to `variant`) with the outputs of `sdv run` and its
// view.html in DIR/runs/<index>; `error` says what could not be written.
sim::RunResult run_kept(const ir::Program& variant, int scenario, const std::string& dir, int64_t index,
                        std::string& error, const sim::RunOptions& options = {});

// Clears what a previous sweep left in DIR (rows, runs, results), for a fresh start.
std::string clear_sweep(const std::string& dir);

// A results row. A run that did not run (`error` set) has no measures: its collisions,
// fallback_share and duration are 0 and its optional values empty.
struct Row {
    int64_t variant = 0;
    std::vector<double> values;  // parameters
    bool passed = false;
    std::string error;
    int collisions = 0;
    std::optional<double> min_ttc, min_gap, min_clearance;
    double fallback_share = 0, duration = 0;
    std::vector<std::optional<double>> expect_values;
    std::vector<bool> expect_passed;
};

// The row of one variant's run, and its text (the CSV line without its '\n'; numbers to 6
// significant digits, the error quoted).
Row run_row(const ir::Scenario& scenario, int64_t index, const std::vector<double>& values,
            const sim::RunResult& result);
std::string row_text(const ir::Scenario& scenario, const Row& row);

// Reads a line of DIR/rows back: true only for the very text row_text writes for a variant of
// `space` with that variant's parameter values; otherwise `why` says what is wrong with it
// (which cell, what it holds). row_text(read) == line for every row read.
bool read_row(const ir::Scenario& scenario, const VariantSpace& space, const std::string& line, Row& out,
              std::string& why);

// What DIR/rows holds: the rows read back (read_row), the first of each variant, with their
// text; and the lines that are not rows (a torn last line of a file, from a kill during its
// write, is neither).
struct StoredRow {
    Row row;
    std::string line;
};
struct RowFiles {
    std::map<int64_t, StoredRow> rows;
    int64_t damaged = 0;
    std::string damage;  // the first line that is not a row: "FILE:LINE: why"
};
RowFiles read_row_files(const ir::Scenario& scenario, const std::string& dir);

struct Results {
    std::vector<std::string> header;
    std::vector<std::string> lines;  // row text, sorted by variant
    std::vector<Row> rows;
};

// Gathers the rows of every slice in DIR; an error names what is missing or inconsistent.
std::string gather(const ir::Program& program, int scenario, const std::string& dir, Results& out);
// gather without the check that DIR's manifest is this campaign's.
std::string gather_rows(const ir::Scenario& scenario, const std::string& dir, Results& out);

// Writes DIR/results.csv and DIR/summary.json from the gathered rows.
std::string write_results(const ir::Program& program, int scenario, const SweepOptions& options,
                          const Results& results);

// JUnit XML of a sweep: one test suite per variant, one test case per expectation.
std::string sweep_junit(const ir::Program& program, int scenario, const Results& results);

// The summary printed on stdout.
std::string sweep_report_text(const ir::Program& program, int scenario, const Results& results);

}  // namespace sdv::campaign
