// Oriented rectangles (vehicle footprints) for ground truth: overlap by the separating axis
// theorem and the smallest distance between two of them.
#pragma once

#include <array>

#include "runtime/road/geometry.h"

namespace sdv::sim {

using road::Vec2;

struct Box {
    Vec2 centre;
    double yaw = 0, length = 4.5, width = 1.8;
    std::array<Vec2, 4> corners() const;
};

bool overlap(const Box& a, const Box& b);
// 0 when overlapping.
double gap(const Box& a, const Box& b);
// Where b touches a, seen from a: "front", "rear", "left" or "right".
const char* impact_zone(const Box& a, const Box& b);

}  // namespace sdv::sim
