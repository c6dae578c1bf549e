// Critical-scenario search: the variant of a campaign that minimises (or maximises) a metric,
// found with a derivative-free optimiser from NLopt within a budget of runs. The search space
// is the vary block's: each parameter is a coordinate u in [0, 1] mapped through its domain
// (a range linearly, a distribution by its quantile, a set or a count's levels by index), so
// the optimiser never proposes a value the campaign does not allow. A global phase (controlled
// random search, CRS2 with local mutation, seeded) then a local refinement (BOBYQA) from the
// best point; runs of a value already run are reused. Deterministic for a given seed.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "runtime/ir/ir.h"
#include "runtime/sim/simulation.h"

namespace sdv::campaign {

// A metric as an expectation names it: `min_ttc(ego, v2)`, `collision(ego)`, `max_jerk(v2)`.
struct Metric {
    int32_t function = -1;  // catalog::ExpectKind
    std::vector<int32_t> vehicles;
    std::string text;
    std::string unit;
    bool boolean = false;
};

// Parses `text` against the scenario's vehicles and the catalog; nullopt with `error` set.
std::optional<Metric> parse_metric(const ir::Scenario& scenario, const std::string& text, std::string& error);

// The metric's value in a finished run: booleans 1/0; a minimum never measured +infinity, a
// maximum never measured -infinity.
double metric_value(const ir::Scenario& scenario, const Metric& metric, const sim::RunResult& run);

struct SearchOptions {
    Metric metric;
    bool maximize = false;
    int budget = 200;  // runs (distinct variants simulated)
    uint64_t seed = 1;
    std::function<void(int runs, int budget, double best)> progress;
};

struct Evaluation {
    std::vector<double> values;  // one per varied parameter (SI)
    double metric = 0;
    std::string error;           // the run failed (its metric counts as the worst possible)
};

struct SearchResult {
    std::string error;
    std::vector<Evaluation> runs;  // in the order they ran
    size_t best = 0;               // index into runs
};

SearchResult search(const ir::Program& program, int scenario, const SearchOptions& options);

}  // namespace sdv::campaign
