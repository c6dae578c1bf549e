// The reference line of a Frenet frame: a lane centre line (or a route's concatenated centre
// lines) smoothed by an interpolating cubic spline and resampled densely, with heading and
// curvature per sample. Positions and headings are interpolated linearly between samples, and
// the projection solves the orthogonality condition on that same interpolation, so that
// Cartesian → Frenet → Cartesian round trips are exact to the solver tolerance.
//
// Kinematics (T tangent, N normal to the left, κ curvature, κ' = dκ/ds, dT/ds = κN,
// dN/ds = −κT):
//   ṙ = ṡ(1 − κd) T + ḋ N
//   r̈ = [s̈(1 − κd) − κ'ṡ²d − 2κṡḋ] T + [κṡ²(1 − κd) + d̈] N
#pragma once

#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "runtime/road/geometry.h"

namespace sdv::road {

struct FrenetState {
    double s = 0, s_d = 0, s_dd = 0;
    double d = 0, d_d = 0, d_dd = 0;
};

struct CartesianState {
    double x = 0, vx = 0, ax = 0;
    double y = 0, vy = 0, ay = 0;
};

class ReferenceLine {
public:
    // Fits and resamples the points (duplicates removed). Fails (nullopt, with a reason) for
    // fewer than two distinct points or non-finite coordinates.
    static std::optional<ReferenceLine> build(std::span<const Vec2> points, std::string* error = nullptr,
                                              double spacing = 0.25);

    double length() const { return s_.back(); }
    Vec2 point(double s) const;
    double heading(double s) const;
    double curvature(double s) const;

    // Position only: the s whose normal passes through p, nearest to p. `hint`: an s near the
    // answer (continuity along routes that come back near themselves): the answer near the hint
    // when p is within `reach` (8 m) of the line there and its nearest point lies inside a ±12 m
    // window around the hint; otherwise (and for a negative hint) the nearest point over the
    // whole line. Only points beyond the ends extrapolate, along the end tangents.
    FrenetState project(Vec2 p, double hint = -1, double reach = 8.0) const;
    FrenetState to_frenet(const CartesianState& c, double hint = -1, double reach = 8.0) const;
    CartesianState to_cartesian(const FrenetState& f) const;

private:
    struct Interp {
        Vec2 p;
        double theta, kappa, dkappa;
    };
    // The nearest point of the sampled polyline: its segment, the foot's parameter on it and the
    // squared distance.
    struct Foot {
        size_t segment = 0;
        double t = 0, d2 = INFINITY;
    };
    // Samples in chunks with bounding boxes, for the global search; chunks in groups with the
    // box round theirs (a kilometre of line is 250 chunks, 16 groups), whose first..last-1 are
    // chunk indices.
    struct Chunk {
        size_t first = 0, last = 0;  // sample indices (segments first..last-1)
        Vec2 min, max;
    };
    static constexpr size_t kChunk = 16;
    static constexpr size_t kGroup = 16;  // chunks

    Interp at(double s) const;
    size_t segment(double s) const;
    Foot nearest_in(Vec2 p, size_t first_segment, size_t end_segment) const;
    // nearest_in's answer, skipping the chunks whose box is farther than the best point so far.
    Foot nearest_window(Vec2 p, size_t first_segment, size_t end_segment) const;
    Foot nearest_global(Vec2 p) const;

    std::vector<double> s_, x_, y_, theta_, kappa_, dkappa_;
    std::vector<Chunk> chunks_, groups_;
    double slack_ = 0;  // far beyond the rounding of a coordinate of the line (nearest_window)
    double per_metre_ = 0;  // samples per metre of s on average (segment()'s first guess)
};

}  // namespace sdv::road
