// Target sampling: a parameter given as a range becomes a small set of values, spaced
// linearly (default, both ends included) or drawn uniformly or normally from a counter-based
// random stream keyed by (seed, vehicle, plan number), so every draw is reproducible and
// independent of thread scheduling.
#pragma once

#include <cstdint>
#include <vector>

namespace sdv::planner {

enum class SampleMethod { linear, uniform, normal };

struct Sampled {
    double value = 0.0;
    double lo = 0.0;
    double hi = 0.0;
    int samples = 1;
    SampleMethod method = SampleMethod::linear;
    double sigma = 0.0;

    static Sampled single(double v) { return {v, v, v, 1, SampleMethod::linear, 0.0}; }
    // value ± pct % with n samples; with `magnitude` the lower end is clipped at 0.
    static Sampled spread(double v, double pct, int n, bool magnitude = true);
};

// SplitMix64 over a counter: the i-th number of the stream is a pure function of (key, i).
class RandomStream {
public:
    RandomStream(uint64_t seed, uint32_t vehicle, uint32_t plan);
    uint64_t next_u64();
    double uniform();  // in [0, 1)
    double normal();   // standard normal (Box–Muller, our own transform: stable across libraries)

private:
    uint64_t key_;
    uint64_t counter_ = 0;
};

// The values of a sampled parameter (one value when samples == 1). Appends to `out`.
void sample(const Sampled& p, RandomStream& rng, std::vector<double>& out);

}  // namespace sdv::planner
