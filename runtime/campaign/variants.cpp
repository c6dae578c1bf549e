// Variant values of a campaign (see variants.h).
#include "runtime/campaign/variants.h"

#include <algorithm>
#include <cmath>

#include "runtime/catalog/catalog.h"

namespace sdv::campaign {
namespace {

uint64_t mix(uint64_t x) {  // SplitMix64's finaliser
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

// A uniform number in [0, 1) for (seed, a, b, c), independent of every other key.
double uniform(uint64_t seed, uint64_t a, uint64_t b, uint64_t c) {
    const uint64_t h = mix(mix(mix(mix(seed) ^ a) ^ (b * 0x632be59bd9b4e019ULL)) ^ (c + 0x2545f4914f6cdd1dULL));
    return static_cast<double>(h >> 11) * 0x1.0p-53;
}

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

}  // namespace

double normal_quantile(double p) {
    // Acklam's rational approximation, then one Halley step on erfc: ~1e-15 relative.
    static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                               1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                               6.680131188771972e+01, -1.328068155288572e+01};
    static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                               -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
    static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                               3.754408661907416e+00};
    p = std::clamp(p, 1e-300, 1 - 1e-16);
    double x;
    if (p < 0.02425) {
        const double q = std::sqrt(-2 * std::log(p));
        x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    } else if (p > 1 - 0.02425) {
        const double q = std::sqrt(-2 * std::log(1 - p));
        x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    } else {
        const double q = p - 0.5, r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
    }
    const double e = normal_cdf(x) - p;
    const double u = e * std::sqrt(2 * M_PI) * std::exp(x * x / 2);
    return x - u / (1 + x * u / 2);
}

VariantSpace::VariantSpace(const ir::Vary& vary) : vary_(vary) {
    if (vary.params.empty()) return;
    if (vary.sample == ir::Vary::Sample::grid) {
        size_ = 1;
        for (size_t k = 0; k < vary.params.size(); ++k) size_ *= static_cast<int64_t>(std::max<size_t>(1, levels(k).size()));
        return;
    }
    size_ = vary.count;
    if (vary.sample == ir::Vary::Sample::latin) {
        // Per parameter, a permutation of the N bins (Fisher-Yates on its own stream).
        strata_.resize(vary.params.size());
        for (size_t k = 0; k < vary.params.size(); ++k) {
            auto& perm = strata_[k];
            perm.resize(static_cast<size_t>(size_));
            for (int64_t i = 0; i < size_; ++i) perm[static_cast<size_t>(i)] = i;
            for (int64_t i = size_ - 1; i > 0; --i) {
                const double u = uniform(vary.seed, 0xfeedULL, k, static_cast<uint64_t>(i));
                const auto j = static_cast<int64_t>(u * static_cast<double>(i + 1));
                std::swap(perm[static_cast<size_t>(i)], perm[static_cast<size_t>(std::min(j, i))]);
            }
        }
    }
}

std::vector<double> VariantSpace::levels(size_t k) const {
    const ir::VaryParam& p = vary_.params[k];
    if (p.kind == ir::VaryParam::Kind::set) return p.values;
    if (p.kind != ir::VaryParam::Kind::range || p.count < 1) return {};
    std::vector<double> out;
    for (int32_t j = 0; j < p.count; ++j) {
        out.push_back(p.count == 1 ? p.lo : p.lo + (p.hi - p.lo) * j / (p.count - 1));
    }
    if (p.integer) {
        for (auto& v : out) v = std::round(v);
    }
    return out;
}

double VariantSpace::at(size_t k, double u) const {
    const ir::VaryParam& p = vary_.params[k];
    u = std::clamp(u, 0.0, 1.0);
    const auto lv = levels(k);
    if (!lv.empty()) {
        const auto j = std::min(lv.size() - 1, static_cast<size_t>(u * static_cast<double>(lv.size())));
        return lv[j];
    }
    switch (p.kind) {
        case ir::VaryParam::Kind::normal: {
            const double lo = normal_cdf(-3), hi = normal_cdf(3);
            return p.mean + p.sd * normal_quantile(lo + u * (hi - lo));
        }
        default:
            if (p.integer) {
                const double span = p.hi - p.lo + 1;
                return std::min(p.hi, p.lo + std::floor(u * span));
            }
            return p.lo + u * (p.hi - p.lo);
    }
}

std::vector<double> VariantSpace::values(int64_t index) const {
    std::vector<double> out(vary_.params.size());
    if (vary_.sample == ir::Vary::Sample::grid) {
        int64_t rest = index;
        for (size_t k = vary_.params.size(); k-- > 0;) {
            const auto lv = levels(k);
            const auto n = static_cast<int64_t>(lv.size());
            out[k] = lv[static_cast<size_t>(rest % n)];
            rest /= n;
        }
        return out;
    }
    const auto i = static_cast<uint64_t>(index);
    for (size_t k = 0; k < vary_.params.size(); ++k) {
        double u = uniform(vary_.seed, i, k, 1);
        if (vary_.sample == ir::Vary::Sample::latin) {
            u = (static_cast<double>(strata_[k][static_cast<size_t>(index)]) + u) / static_cast<double>(size_);
        }
        out[k] = at(k, u);
    }
    return out;
}

std::string describe(const ir::Vary& vary, const std::vector<double>& values) {
    std::string out;
    for (size_t k = 0; k < vary.params.size() && k < values.size(); ++k) {
        const auto& p = vary.params[k];
        out += (k ? ", " : "") + p.name + " = " + catalog::format_number(values[k]) + (p.unit.empty() ? "" : " " + p.unit);
    }
    return out;
}

}  // namespace sdv::campaign
