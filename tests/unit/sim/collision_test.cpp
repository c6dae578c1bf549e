// Oriented-box ground truth: overlap (SAT), distance and impact zones.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <numbers>

#include "runtime/sim/collision.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace collision_test {

using namespace sdv::sim;

TEST_CASE("axis-aligned boxes overlap exactly when they touch") {
    const Box a{{0, 0}, 0, 4.5, 1.8};
    CHECK(overlap(a, Box{{4.4, 0}, 0, 4.5, 1.8}));
    CHECK(!overlap(a, Box{{4.6, 0}, 0, 4.5, 1.8}));
    CHECK(gap(a, Box{{6.5, 0}, 0, 4.5, 1.8}) == doctest::Approx(2.0));
    CHECK(gap(a, Box{{0, 3.8}, 0, 4.5, 1.8}) == doctest::Approx(2.0));
    CHECK(gap(a, Box{{1, 0.5}, 0, 4.5, 1.8}) == 0.0);
}

TEST_CASE("rotation matters: a rotated box clears where its bounding circle would not") {
    const Box a{{0, 0}, 0, 4.5, 1.8};
    // A box turned 90° just beyond a's front: its width now lies along x.
    const Box b{{2.25 + 0.9 + 0.05, 0}, std::numbers::pi / 2, 4.5, 1.8};
    CHECK(!overlap(a, b));
    CHECK(gap(a, b) == doctest::Approx(0.05).epsilon(1e-6));
    const Box c{{2.25 + 0.9 - 0.05, 0}, std::numbers::pi / 2, 4.5, 1.8};
    CHECK(overlap(a, c));
    // Separated only along a diagonal axis (SAT needs both boxes' axes).
    const Box d{{3.4, 1.5}, std::numbers::pi / 4, 4.5, 1.8};
    CHECK(overlap(a, d) == (gap(a, d) == 0.0));
}

TEST_CASE("impact zones are seen from the first box") {
    const Box a{{0, 0}, 0, 4.5, 1.8};
    CHECK(std::string(impact_zone(a, Box{{4, 0}, 0, 4.5, 1.8})) == "front");
    CHECK(std::string(impact_zone(a, Box{{-4, 0}, 0, 4.5, 1.8})) == "rear");
    CHECK(std::string(impact_zone(a, Box{{0.5, 1.7}, 0, 4.5, 1.8})) == "left");
    CHECK(std::string(impact_zone(a, Box{{0.5, -1.7}, 0, 4.5, 1.8})) == "right");
}

}  // namespace collision_test
