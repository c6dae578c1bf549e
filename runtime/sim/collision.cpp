#include "runtime/sim/collision.h"

#include <algorithm>
#include <cmath>

namespace sdv::sim {

namespace {

// A box's heading and corners, each computed once (std::cos and std::sin were most of a gap).
struct Outline {
    Vec2 f;
    std::array<Vec2, 4> c;
};

Outline outline(const Box& b) {
    const Vec2 f{std::cos(b.yaw), std::sin(b.yaw)}, l{-f.y, f.x};
    const Vec2 hf = 0.5 * b.length * f, hl = 0.5 * b.width * l;
    return {f, {b.centre + hf + hl, b.centre + hf - hl, b.centre - hf - hl, b.centre - hf + hl}};
}

bool overlap(const Outline& a, const Outline& b) {
    for (const Outline* box : {&a, &b}) {
        const Vec2 f = box->f;
        for (const Vec2 axis : {f, Vec2{-f.y, f.x}}) {
            double amin = INFINITY, amax = -INFINITY, bmin = INFINITY, bmax = -INFINITY;
            for (const Vec2& p : a.c) {
                amin = std::min(amin, road::dot(p, axis));
                amax = std::max(amax, road::dot(p, axis));
            }
            for (const Vec2& p : b.c) {
                bmin = std::min(bmin, road::dot(p, axis));
                bmax = std::max(bmax, road::dot(p, axis));
            }
            if (amax < bmin || bmax < amin) return false;
        }
    }
    return true;
}

}  // namespace

std::array<Vec2, 4> Box::corners() const { return outline(*this).c; }

bool overlap(const Box& a, const Box& b) { return overlap(outline(a), outline(b)); }

namespace {

// Squared distance from p to the segment [a, b] (one square root for the whole box pair).
double point_segment2(Vec2 p, Vec2 a, Vec2 b) {
    const Vec2 ab = b - a;
    const double len2 = road::dot(ab, ab);
    const double t = len2 > 0 ? std::clamp(road::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    const Vec2 d = p - (a + t * ab);
    return road::dot(d, d);
}

}  // namespace

double gap(const Box& a, const Box& b) {
    const Outline oa = outline(a), ob = outline(b);
    if (overlap(oa, ob)) return 0.0;
    const auto& ca = oa.c;
    const auto& cb = ob.c;
    double best = INFINITY;
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            best = std::min(best, point_segment2(ca[static_cast<size_t>(i)], cb[static_cast<size_t>(j)], cb[static_cast<size_t>((j + 1) % 4)]));
            best = std::min(best, point_segment2(cb[static_cast<size_t>(i)], ca[static_cast<size_t>(j)], ca[static_cast<size_t>((j + 1) % 4)]));
        }
    }
    return std::sqrt(best);
}

const char* impact_zone(const Box& a, const Box& b) {
    const Vec2 f{std::cos(a.yaw), std::sin(a.yaw)};
    const Vec2 rel = b.centre - a.centre;
    const double lon = road::dot(rel, f) / std::max(a.length, 1e-9);
    const double lat = road::cross(f, rel) / std::max(a.width, 1e-9);
    if (std::fabs(lon) >= std::fabs(lat)) return lon >= 0 ? "front" : "rear";
    return lat >= 0 ? "left" : "right";
}

}  // namespace sdv::sim
