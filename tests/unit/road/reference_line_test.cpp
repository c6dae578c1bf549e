// Frenet frames: round trips on straight, arc and spline lines, and analytic values.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "runtime/road/reference_line.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace reference_line_test {

using namespace sdv::road;

namespace {

std::vector<Vec2> arc_points(double r, double angle, int n) {
    std::vector<Vec2> pts;
    for (int i = 0; i <= n; ++i) {
        const double a = angle * i / n;
        pts.push_back({r * std::sin(a), r - r * std::cos(a)});  // starts at 0 heading east, turns left
    }
    return pts;
}

void round_trips(const ReferenceLine& line) {
    double max_pos = 0, max_vel = 0, max_acc = 0;
    for (double s = 1; s < line.length() - 1; s += line.length() / 37) {
        for (double d : {-3.0, -0.5, 0.0, 1.2, 3.5}) {
            const FrenetState f{s, 11.0, 0.7, d, 0.4, -0.2};
            const CartesianState c = line.to_cartesian(f);
            const FrenetState g = line.to_frenet(c, s);
            const CartesianState c2 = line.to_cartesian(g);
            max_pos = std::max({max_pos, std::hypot(c2.x - c.x, c2.y - c.y), std::fabs(g.s - s), std::fabs(g.d - d)});
            max_vel = std::max({max_vel, std::fabs(g.s_d - f.s_d) / 11.0, std::fabs(g.d_d - f.d_d) / 11.0});
            max_acc = std::max({max_acc, std::fabs(g.s_dd - f.s_dd), std::fabs(g.d_dd - f.d_dd)});
        }
    }
    CHECK(max_pos < 1e-3);
    CHECK(max_vel < 1e-6);
    CHECK(max_acc < 1e-6);
}

}  // namespace

TEST_CASE("straight line: Frenet coordinates are rotated Cartesian ones") {
    const std::vector<Vec2> pts = {{0, 0}, {30, 40}};  // heading atan2(4, 3)
    auto line = ReferenceLine::build(pts);
    REQUIRE(line);
    CHECK(line->length() == doctest::Approx(50));
    const FrenetState f = line->project({3 + -4, 4 + 3});  // s = 5, d = 5
    CHECK(f.s == doctest::Approx(5).epsilon(1e-9));
    CHECK(f.d == doctest::Approx(5).epsilon(1e-9));
    CHECK(line->curvature(20) == doctest::Approx(0).epsilon(1e-12));
    round_trips(*line);
}

TEST_CASE("arc of radius 50 m: length, curvature and the speed of an offset vehicle") {
    const double r = 50, angle = std::numbers::pi / 2;
    auto line = ReferenceLine::build(arc_points(r, angle, 400));
    REQUIRE(line);
    CHECK(line->length() == doctest::Approx(r * angle).epsilon(1e-3));
    CHECK(line->curvature(line->length() / 2) == doctest::Approx(1 / r).epsilon(1e-3));
    // A vehicle 2 m to the left (inside of the left turn) at ṡ = 10 m/s moves at 10·(1 − κd).
    const FrenetState f{30, 10, 0, 2, 0, 0};
    const CartesianState c = line->to_cartesian(f);
    CHECK(std::hypot(c.vx, c.vy) == doctest::Approx(10 * (1 - 2 / r)).epsilon(1e-3));
    // Its centripetal acceleration is v²/(r − d).
    const double v = 10 * (1 - 2 / r);
    CHECK(std::hypot(c.ax, c.ay) == doctest::Approx(v * v / (r - 2)).epsilon(1e-2));
    round_trips(*line);
}

TEST_CASE("S-curve spline through irregular points and a map-like polyline") {
    std::vector<Vec2> s_curve;
    for (int i = 0; i <= 20; ++i) s_curve.push_back({i * 5.0 + (i % 3) * 0.7, 8 * std::sin(i * 0.35)});
    auto line = ReferenceLine::build(s_curve);
    REQUIRE(line);
    round_trips(*line);
    const std::vector<Vec2> map = {{0, 0}, {0.4, 0.01}, {7.9, 0.3}, {8.3, 0.35}, {25, 2.5}, {26, 2.7}, {60, 12}};
    auto m = ReferenceLine::build(map);
    REQUIRE(m);
    round_trips(*m);
}

TEST_CASE("points beyond the ends extrapolate along the end tangents") {
    const std::vector<Vec2> pts = {{0, 0}, {10, 0}};
    auto line = ReferenceLine::build(pts);
    REQUIRE(line);
    const FrenetState before = line->project({-5, 1});
    CHECK(before.s == doctest::Approx(-5));
    CHECK(before.d == doctest::Approx(1));
    const FrenetState after = line->project({14, -2});
    CHECK(after.s == doctest::Approx(14));
    CHECK(after.d == doctest::Approx(-2));
}

TEST_CASE("bad input gives an error, not a crash") {
    std::string why;
    const std::vector<Vec2> one = {{1, 1}};
    CHECK(!ReferenceLine::build(one, &why));
    CHECK(why == "fewer than two distinct points");
    const std::vector<Vec2> same = {{1, 1}, {1, 1}, {1, 1}};
    CHECK(!ReferenceLine::build(same, &why));
    const std::vector<Vec2> nan = {{0, 0}, {NAN, 1}};
    CHECK(!ReferenceLine::build(nan, &why));
    CHECK(why == "non-finite coordinate");
}

}  // namespace reference_line_test
