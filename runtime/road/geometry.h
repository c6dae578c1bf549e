// Small 2-D geometry types shared by the road model, the reference line and the simulator.
#pragma once

#include <cmath>

namespace sdv::road {

struct Vec2 {
    double x = 0.0;
    double y = 0.0;

    friend Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
    friend Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
    friend Vec2 operator*(double k, Vec2 a) { return {k * a.x, k * a.y}; }
    friend Vec2 operator*(Vec2 a, double k) { return {k * a.x, k * a.y}; }
    friend bool operator==(Vec2 a, Vec2 b) = default;
};

inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
inline double norm(Vec2 a) { return std::hypot(a.x, a.y); }
inline double distance(Vec2 a, Vec2 b) { return norm(a - b); }

}  // namespace sdv::road
