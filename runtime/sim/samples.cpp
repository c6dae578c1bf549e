#include <algorithm>
#include <cmath>

#include "runtime/sim/simulation.h"

namespace sdv::sim {
namespace {

// Bucket b holds (kLow·kRatio^(b-1), kLow·kRatio^b]; bucket 0 everything up to kLow.
constexpr double kLow = 0.01;    // µs
constexpr double kRatio = 1.01;  // 1 % wide

size_t bucket_of(double us) {
    if (!(us > kLow)) return 0;
    return static_cast<size_t>(std::ceil(std::log(us / kLow) / std::log(kRatio)));
}

double upper_of(size_t b) { return kLow * std::pow(kRatio, static_cast<double>(b)); }

}  // namespace

void Samples::add(double us) {
    if (!std::isfinite(us)) return;
    const size_t b = bucket_of(us);
    if (b >= buckets_.size()) buckets_.resize(b + 1, 0);
    ++buckets_[b];
    ++count_;
    max_ = std::max(max_, us);
}

double Samples::percentile(double p) const {
    if (count_ == 0) return 0;
    if (p >= 1) return max_;
    // The same rank as sorting and indexing at floor(p·n).
    const long long rank = std::min(count_ - 1, static_cast<long long>(p * static_cast<double>(count_)));
    long long seen = 0;
    for (size_t b = 0; b < buckets_.size(); ++b) {
        seen += buckets_[b];
        if (seen > rank) return std::min(max_, b == 0 ? kLow : std::sqrt(upper_of(b - 1) * upper_of(b)));
    }
    return max_;
}

double Samples::share_below(double limit) const {
    if (count_ == 0) return 1;
    const size_t last = bucket_of(limit);
    long long n = 0;
    for (size_t b = 0; b <= last && b < buckets_.size(); ++b) n += buckets_[b];
    return static_cast<double>(n) / static_cast<double>(count_);
}

}  // namespace sdv::sim
