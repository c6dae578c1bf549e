#include "runtime/sim/grid.h"

#include <algorithm>
#include <cmath>

namespace sdv::sim {

void Grid::build(const std::vector<double>& x, const std::vector<double>& y, const std::vector<char>& active, double cell) {
    cell_ = cell > 0 ? cell : 100;
    x_ = x;
    y_ = y;
    sorted_.clear();
    for (size_t i = 0; i < x.size(); ++i) {
        if (!active[i]) continue;
        // Clamped before the conversion: positions are bounded upstream, but a cell index must
        // never be undefined behaviour.
        const auto cx = static_cast<int64_t>(std::clamp(std::floor(x[i] / cell_), -1e15, 1e15));
        const auto cy = static_cast<int64_t>(std::clamp(std::floor(y[i] / cell_), -1e15, 1e15));
        sorted_.emplace_back(key(cx, cy), static_cast<int>(i));
    }
    std::sort(sorted_.begin(), sorted_.end());
    keys_.clear();
    starts_.clear();
    agents_.clear();
    for (size_t k = 0; k < sorted_.size(); ++k) {
        if (k == 0 || sorted_[k].first != sorted_[k - 1].first) {
            keys_.push_back(sorted_[k].first);
            starts_.push_back(static_cast<uint32_t>(k));
        }
        agents_.push_back(sorted_[k].second);
    }
    starts_.push_back(static_cast<uint32_t>(agents_.size()));
}

void Grid::query(double px, double py, double radius, std::vector<int>& out, int after) const {
    out.clear();
    const auto lo_x = static_cast<int64_t>(std::clamp(std::floor((px - radius) / cell_), -1e15, 1e15));
    const auto hi_x = static_cast<int64_t>(std::clamp(std::floor((px + radius) / cell_), -1e15, 1e15));
    const auto lo_y = static_cast<int64_t>(std::clamp(std::floor((py - radius) / cell_), -1e15, 1e15));
    const auto hi_y = static_cast<int64_t>(std::clamp(std::floor((py + radius) / cell_), -1e15, 1e15));
    const double r2 = radius * radius;
    int runs = 0;  // cells that added agents (each run is in ascending index)
    for (int64_t cx = lo_x; cx <= hi_x; ++cx) {
        for (int64_t cy = lo_y; cy <= hi_y; ++cy) {
            const auto it = std::lower_bound(keys_.begin(), keys_.end(), key(cx, cy));
            if (it == keys_.end() || *it != key(cx, cy)) continue;
            const auto c = static_cast<size_t>(it - keys_.begin());
            const size_t before = out.size();
            const auto begin = agents_.begin() + starts_[c], end = agents_.begin() + starts_[c + 1];
            const auto first = after >= 0 ? std::upper_bound(begin, end, after) : begin;
            for (auto k = static_cast<size_t>(first - agents_.begin()); k < starts_[c + 1]; ++k) {
                const auto i = static_cast<size_t>(agents_[k]);
                const double dx = x_[i] - px, dy = y_[i] - py;
                if (dx * dx + dy * dy <= r2) out.push_back(agents_[k]);
            }
            if (out.size() > before) ++runs;
        }
    }
    if (runs < 2) return;
    // Ascending index: a sort, or for a large share of the agents (a quarter or more: a sensor
    // range holding most of them) a sweep over marks, linear in their number.
    const size_t n = x_.size();
    if (out.size() * 4 < n) {
        std::sort(out.begin(), out.end());
        return;
    }
    thread_local std::vector<char> mark;
    mark.assign(n, 0);
    for (const int i : out) mark[static_cast<size_t>(i)] = 1;
    out.clear();
    for (size_t i = 0; i < n; ++i) {
        if (mark[i]) out.push_back(static_cast<int>(i));
    }
}

}  // namespace sdv::sim
