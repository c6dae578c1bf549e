#include "runtime/planner/sampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sdv::planner {
namespace {

uint64_t splitmix(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

}  // namespace

Sampled Sampled::spread(double v, double pct, int n, bool magnitude) {
    const double d = std::fabs(v) * pct / 100.0;
    Sampled s{v, v - d, v + d, n, SampleMethod::linear, 0.0};
    if (magnitude) s.lo = std::max(0.0, s.lo);
    return s;
}

RandomStream::RandomStream(uint64_t seed, uint32_t vehicle, uint32_t plan)
    : key_(splitmix(splitmix(seed) ^ (static_cast<uint64_t>(vehicle) << 32 | plan))) {}

uint64_t RandomStream::next_u64() { return splitmix(key_ + 0x632BE59BD9B4E019ull * ++counter_); }

double RandomStream::uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

double RandomStream::normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

void sample(const Sampled& p, RandomStream& rng, std::vector<double>& out) {
    const int n = std::max(1, p.samples);
    if (n == 1) {
        out.push_back(p.value);
        return;
    }
    for (int i = 0; i < n; ++i) {
        switch (p.method) {
            case SampleMethod::linear:
                out.push_back(p.lo + (p.hi - p.lo) * static_cast<double>(i) / (n - 1));
                break;
            case SampleMethod::uniform: out.push_back(p.lo + (p.hi - p.lo) * rng.uniform()); break;
            case SampleMethod::normal:
                out.push_back(std::clamp(p.value + p.sigma * rng.normal(), p.lo, p.hi));
                break;
        }
    }
}

}  // namespace sdv::planner
