#include "runtime/realism/metrics.h"

#include <algorithm>
#include <cmath>

namespace sdv::realism {

std::optional<Comparison> compare(const std::vector<State>& sim, const std::vector<State>& rec) {
    if (sim.empty() || rec.empty()) return std::nullopt;
    const double t0 = std::max(sim.front().t, rec.front().t);
    const double t1 = std::min(sim.back().t, rec.back().t);
    if (t1 < t0) return std::nullopt;
    Comparison c;
    c.span = t1 - t0;
    double sum = 0, sq = 0;
    size_t k = 0;
    const double eps = 1e-9;
    for (const State& r : rec) {
        if (r.t < t0 - eps || r.t > t1 + eps) continue;
        while (k + 1 < sim.size() && sim[k + 1].t <= r.t) ++k;
        State s = sim[k];
        if (k + 1 < sim.size() && sim[k + 1].t > sim[k].t) {
            const double f = std::clamp((r.t - sim[k].t) / (sim[k + 1].t - sim[k].t), 0.0, 1.0);
            s.x += f * (sim[k + 1].x - sim[k].x);
            s.y += f * (sim[k + 1].y - sim[k].y);
            s.speed += f * (sim[k + 1].speed - sim[k].speed);
        }
        const double d = std::hypot(s.x - r.x, s.y - r.y);
        sum += d;
        c.max_distance = std::max(c.max_distance, d);
        c.final_displacement = d;
        sq += (s.speed - r.speed) * (s.speed - r.speed);
        ++c.samples;
    }
    if (c.samples == 0) return std::nullopt;
    c.sted = sum / c.samples;
    c.speed_rmse = std::sqrt(sq / c.samples);
    return c;
}

Distribution distribution(std::vector<double> v) {
    Distribution d;
    d.n = v.size();
    if (v.empty()) return d;
    std::sort(v.begin(), v.end());
    auto q = [&](double p) {
        const double i = p * static_cast<double>(v.size() - 1);
        const size_t lo = static_cast<size_t>(std::floor(i));
        const size_t hi = std::min(lo + 1, v.size() - 1);
        return v[lo] + (i - static_cast<double>(lo)) * (v[hi] - v[lo]);
    };
    double sum = 0;
    for (double x : v) sum += x;
    d.mean = sum / static_cast<double>(v.size());
    d.p10 = q(0.1);
    d.median = q(0.5);
    d.p90 = q(0.9);
    d.max = v.back();
    return d;
}

}  // namespace sdv::realism
