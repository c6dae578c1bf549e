// A uniform grid over the agents of one snapshot: the spatial index behind every neighbour
// query of a tick (perception, ground-truth pairs). Cells are squares of side `cell`; agents are
// kept sorted by cell key, so a query visits the 3×3 (or more) cells around a point and returns
// indices in ascending order: the same neighbours in the same order as a scan of every agent,
// at O(k) per query instead of O(N). docs/design-notes.md says why a grid and not per-lane lists.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace sdv::sim {

class Grid {
public:
    // Rebuilds the index over points (x[i], y[i]) of the agents with active[i].
    void build(const std::vector<double>& x, const std::vector<double>& y, const std::vector<char>& active, double cell);
    // The active agents within `radius` of (px, py) (centre distance), ascending index, into
    // `out` (cleared first); only those with an index above `after` when it is given.
    void query(double px, double py, double radius, std::vector<int>& out, int after = -1) const;

private:
    int64_t key(int64_t cx, int64_t cy) const { return (cx << 32) ^ (cy & 0xffffffffLL); }
    double cell_ = 100;
    // The occupied cells by key, the agents of cell c at agents_[starts_[c]..starts_[c + 1])
    // in ascending index.
    std::vector<int64_t> keys_;
    std::vector<uint32_t> starts_;
    std::vector<int> agents_;
    std::vector<std::pair<int64_t, int>> sorted_;  // (cell key, agent index), build()'s scratch
    std::vector<double> x_, y_;
};

}  // namespace sdv::sim
