// The variants of a campaign (ir::Vary): how many there are and the parameter values of each,
// as a pure function of (vary block, index). A grid enumerates the levels (the last parameter
// fastest); `random N` draws each value independently; `latin N` stratifies every parameter
// into N equal-probability bins and visits each bin once (a Latin hypercube). Draws come from
// a counter-based generator keyed by (seed, variant, parameter), so any variant can be made
// alone, in any order, on any machine: what lets a sweep run in parallel, resume, and split
// into Slurm array tasks with identical results.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/ir/ir.h"

namespace sdv::campaign {

class VariantSpace {
public:
    explicit VariantSpace(const ir::Vary& vary);

    int64_t size() const { return size_; }
    // The value of every parameter (SI, in ir::Vary::params order) of variant `index`.
    std::vector<double> values(int64_t index) const;
    // The value of parameter `k` at the position `u` in [0, 1] of its domain (quantile of a
    // distribution, fraction of a range, level of a set): what the search optimises over.
    double at(size_t k, double u) const;
    // The grid levels of parameter `k` (set elements, or a range's count levels); empty when
    // the parameter is continuous.
    std::vector<double> levels(size_t k) const;

private:
    ir::Vary vary_;  // a copy: a space outlives the program it came from
    int64_t size_ = 0;
    std::vector<std::vector<int64_t>> strata_;  // latin: per parameter, the bin of each variant
};

// A variant's values as text for messages and file names: "v2.speed = 14 m/s, seed = 3".
std::string describe(const ir::Vary& vary, const std::vector<double>& values);

// Standard normal quantile (inverse CDF), for p in (0, 1).
double normal_quantile(double p);

}  // namespace sdv::campaign
