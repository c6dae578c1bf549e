// How close a simulated path is to its recording (the paper's RQ2, docs/realism.md): STED, the
// spatio-temporal Euclidean distance (mean distance between the two positions at equal times,
// over the span both exist), the final displacement, and the speed RMSE over the same span.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "runtime/realism/recording.h"

namespace sdv::realism {

struct Comparison {
    double sted = 0;                // m
    double max_distance = 0;        // m
    double final_displacement = 0;  // m, at the end of the common span
    double speed_rmse = 0;          // m/s
    double span = 0;                // s, the common span compared
    int samples = 0;                // recorded states within it
};

// The simulated path (states in time order, any rate) against the recorded one, at the recorded
// time stamps within the common span (the simulated state linearly interpolated between its
// samples). nullopt when the spans do not overlap.
std::optional<Comparison> compare(const std::vector<State>& simulated, const std::vector<State>& recorded);

// Mean, median and percentiles of a sample (empty sample: all 0).
struct Distribution {
    size_t n = 0;
    double mean = 0, p10 = 0, median = 0, p90 = 0, max = 0;
};
Distribution distribution(std::vector<double> values);

}  // namespace sdv::realism
