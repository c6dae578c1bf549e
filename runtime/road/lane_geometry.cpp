#include "runtime/road/lane_geometry.h"

#include <algorithm>
#include <cmath>

#include "runtime/road/road_network.h"

namespace sdv::road {

int samples_for(double bound_length) {
    return std::max(2, static_cast<int>(std::ceil(bound_length / 0.5)) + 1);
}

std::vector<Vec2> resample(const std::vector<Vec2>& p, int n) {
    std::vector<double> acc = {0};
    acc.reserve(p.size());
    for (size_t i = 1; i < p.size(); ++i)
        acc.push_back(acc.back() + distance(p[i - 1], p[i]));
    std::vector<Vec2> out;
    out.reserve(static_cast<size_t>(n));
    size_t j = 0;
    for (int i = 0; i < n; ++i) {
        const double t = acc.back() * i / (n - 1);
        while (j + 2 < p.size() && acc[j + 1] < t) ++j;
        const double seg = acc[j + 1] - acc[j];
        const double f = seg > 0 ? std::clamp((t - acc[j]) / seg, 0.0, 1.0) : 0.0;
        out.push_back(p[j] + f * (p[j + 1] - p[j]));
    }
    return out;
}

BoundedCentre centre_between(const std::vector<Vec2>& left, const std::vector<Vec2>& right) {
    const int n = samples_for(std::max(polyline_length(left), polyline_length(right)));
    const auto ls = resample(left, n), rs = resample(right, n);
    BoundedCentre out;
    out.centre.reserve(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) out.centre.push_back(0.5 * (ls[static_cast<size_t>(i)] + rs[static_cast<size_t>(i)]));
    out.width = distance(ls[static_cast<size_t>(n / 2)], rs[static_cast<size_t>(n / 2)]);
    return out;
}

}  // namespace sdv::road
