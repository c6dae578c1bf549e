// The snapshot's grid: a query returns what a scan of every agent with the same test returns,
// in ascending index, whether it sorts its cells' runs or sweeps marks over all agents, and with
// only the indices above a given one.
#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "runtime/sim/grid.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace grid_test {

using namespace sdv::sim;

namespace {

// The reference: every active agent within `radius` (the grid's own test) with an index above
// `after`, ascending.
std::vector<int> scan(const std::vector<double>& x, const std::vector<double>& y, const std::vector<char>& on,
                      double px, double py, double radius, int after = -1) {
    std::vector<int> out;
    for (size_t i = static_cast<size_t>(after + 1); i < x.size(); ++i) {
        const double dx = x[i] - px, dy = y[i] - py;
        if (on[i] && dx * dx + dy * dy <= radius * radius) out.push_back(static_cast<int>(i));
    }
    return out;
}

}  // namespace

TEST_CASE("a grid query is a scan of every agent, in ascending index") {
    // Agents spread over 5 × 3 cells of 100 m and over negative coordinates, some inactive;
    // radii from one cell's share (sorted runs) to nearly all agents (the sweep).
    uint64_t state = 18;
    auto uniform = [&](double lo, double hi) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.0;
    };
    std::vector<double> x, y;
    std::vector<char> on;
    for (int i = 0; i < 300; ++i) {
        x.push_back(uniform(-250, 250));
        y.push_back(uniform(-150, 150));
        on.push_back(i % 7 == 3 ? 0 : 1);
    }
    Grid grid;
    grid.build(x, y, on, 100);
    std::vector<int> got;
    for (const double radius : {5.0, 12.0, 60.0, 100.0, 400.0}) {
        for (int q = 0; q < 50; ++q) {
            const double px = uniform(-300, 300), py = uniform(-200, 200);
            grid.query(px, py, radius, got);
            CHECK(got == scan(x, y, on, px, py, radius));
            const int after = q * 6;
            grid.query(px, py, radius, got, after);
            CHECK(got == scan(x, y, on, px, py, radius, after));
        }
    }
    // An agent exactly at the radius counts, as in the scan.
    grid.query(x[0] + 30, y[0], 30, got);
    CHECK(got == scan(x, y, on, x[0] + 30, y[0], 30));
}

}  // namespace grid_test
