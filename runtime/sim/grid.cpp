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
}

void Grid::query(double px, double py, double radius, std::vector<int>& out) const {
    out.clear();
    const auto lo_x = static_cast<int64_t>(std::clamp(std::floor((px - radius) / cell_), -1e15, 1e15));
    const auto hi_x = static_cast<int64_t>(std::clamp(std::floor((px + radius) / cell_), -1e15, 1e15));
    const auto lo_y = static_cast<int64_t>(std::clamp(std::floor((py - radius) / cell_), -1e15, 1e15));
    const auto hi_y = static_cast<int64_t>(std::clamp(std::floor((py + radius) / cell_), -1e15, 1e15));
    const double r2 = radius * radius;
    for (int64_t cx = lo_x; cx <= hi_x; ++cx) {
        for (int64_t cy = lo_y; cy <= hi_y; ++cy) {
            const int64_t k = key(cx, cy);
            auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::make_pair(k, -1));
            for (; it != sorted_.end() && it->first == k; ++it) {
                const auto i = static_cast<size_t>(it->second);
                const double dx = x_[i] - px, dy = y_[i] - py;
                if (dx * dx + dy * dy <= r2) out.push_back(it->second);
            }
        }
    }
    std::sort(out.begin(), out.end());
}

}  // namespace sdv::sim
