// Vehicles that start on top of each other (E0502), found in O(n log n) for n vehicles whatever
// their places: a sweep along each lane with a max segment tree across it. The checker calls it
// (scenarios.cpp); tests/unit/compiler/overlaps_test.cpp checks it against every pair.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sdv::compiler::sema {

// An agent's footprint at the start, along its lane: [s_lo, s_hi] x [lat_lo, lat_hi] in metres
// (the position along the lane and the lateral offset, each +- half the agent's size). Footprints
// of different groups (lanes) never overlap; a negative group takes no part.
struct Footprint {
    int32_t group = -1;
    double s_lo = 0, s_hi = 0, lat_lo = 0, lat_hi = 0;
};

// Two footprints overlap when they share an area: each interval opens on the other on both axes
// (touching is no overlap). Footprints of sizes that are not positive and finite overlap nothing.
bool footprints_overlap(const Footprint& a, const Footprint& b);

// One footprint that overlaps another behind it: `ahead`'s back (s_lo) is further along the lane
// than `behind`'s, or at the same place with `ahead` later in the list.
struct Overlap {
    size_t ahead;
    size_t behind;
};

// The work done, for tests that bound it by the input's size (never by a clock).
struct OverlapWork {
    size_t tree_steps = 0;  // nodes of the segment tree visited
};

// One Overlap for each footprint that overlaps a footprint behind it, naming one of those, in
// the order of `ahead`. A footprint that overlaps no footprint behind it (the first of a group
// on top of each other, or one alone) is in none as `ahead`. So there are none exactly when no
// two footprints overlap, and at most n - 1.
std::vector<Overlap> find_overlaps(const std::vector<Footprint>& footprints, OverlapWork* work = nullptr);

}  // namespace sdv::compiler::sema
