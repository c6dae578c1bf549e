// Lanes between two bounds, as both map readers (Lanelet2, CommonRoad) build them: the bounds
// resampled at the same arc-length fractions every 0.5 m and averaged into the centre line.
#pragma once

#include <vector>

#include "runtime/road/geometry.h"

namespace sdv::road {

// The number of samples for a bound of this length (one every 0.5 m, at least two).
int samples_for(double bound_length);

// n points at equal arc-length fractions of a polyline (of at least two points).
std::vector<Vec2> resample(const std::vector<Vec2>& p, int n);

struct BoundedCentre {
    std::vector<Vec2> centre;
    double width = 0;  // between the bounds at the middle sample
};

// The centre line between a left and a right bound (each of at least two points, both in the
// driving direction).
BoundedCentre centre_between(const std::vector<Vec2>& left, const std::vector<Vec2>& right);

}  // namespace sdv::road
