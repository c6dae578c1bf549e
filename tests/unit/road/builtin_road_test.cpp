// Built-in roads and junctions, and routing over them.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "runtime/road/builtin_road.h"
#include "runtime/road/routing.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace builtin_road_test {

using namespace sdv::road;

namespace {

RoadSpec highway() {
    RoadSpec s;
    s.name = "highway";
    s.lanes_forward = 2;
    s.lanes_backward = 1;
    s.lane_width_m = 3.5;
    s.segments = {{Segment::straight, 300, 0}, {Segment::arc, 120, 250}, {Segment::straight, 200, 0}};
    return s;
}

}  // namespace

TEST_CASE("lanes are numbered from the right, with neighbours both ways") {
    auto r = build_road(highway());
    REQUIRE(r.errors.empty());
    const auto& net = r.network;
    REQUIRE(net.lanes().size() == 3);
    const LaneId l1 = *net.find("highway.1"), l2 = *net.find("highway.2"), b1 = *net.find("highway.-1");
    CHECK(net.lane(l1).left == l2);
    CHECK(net.lane(l2).right == l1);
    CHECK(net.lane(l2).left == b1);
    CHECK(!net.lane(l2).left_same_direction);
    CHECK(net.lane(b1).left == l2);
    // Lane 1 starts 1.5 lane widths right of the reference line, lane 2 half a width.
    CHECK(net.lane(l1).centre.front().y == doctest::Approx(-5.25));
    CHECK(net.lane(l2).centre.front().y == doctest::Approx(-1.75));
    CHECK(net.lane(b1).centre.front().x == doctest::Approx(net.lane(l1).centre.back().x).epsilon(0.05));
}

TEST_CASE("lengths follow the offsets on the arc; the arc ends where geometry says") {
    auto r = build_road(highway());
    REQUIRE(r.errors.empty());
    CHECK(r.length == doctest::Approx(620));
    const auto& net = r.network;
    // A lane at offset d on an arc of radius R (left turn) has radius R − d.
    const double ref_arc = 120, R = 250, angle = ref_arc / R;
    const double d1 = -5.25;
    CHECK(net.lane(*net.find("highway.1")).length == doctest::Approx(500 + angle * (R - d1)).epsilon(1e-4));
    const auto ref = road_reference(highway());
    // End of the arc: (300 + R sin a, R − R cos a), then 200 m straight at heading a.
    const Vec2 arc_end{300 + R * std::sin(angle), R - R * std::cos(angle)};
    const Vec2 end = arc_end + 200.0 * Vec2{std::cos(angle), std::sin(angle)};
    CHECK(ref.back().x == doctest::Approx(end.x).epsilon(1e-9));
    CHECK(ref.back().y == doctest::Approx(end.y).epsilon(1e-9));
}

TEST_CASE("invalid built-in roads give errors") {
    RoadSpec s = highway();
    s.segments[0].length_m = -3;
    CHECK(!build_road(s).errors.empty());
    s = highway();
    s.segments[1].radius_m = 2;  // tighter than half the road
    CHECK(!build_road(s).errors.empty());
    s = highway();
    s.segments[1].radius_m = -4;  // a right arc with two 3.5 m lanes on its inside
    CHECK(!build_road(s).errors.empty());
    s.segments[1].radius_m = 5;  // a left arc has only the backward lane (3.5 m) inside: fine
    CHECK(build_road(s).errors.empty());
    s = highway();
    s.lanes_forward = 0;
    s.lanes_backward = 0;
    CHECK(!build_road(s).errors.empty());
    s = highway();
    s.segments[0].length_m = 1e308;
    CHECK(!build_road(s).errors.empty());
    s = highway();
    s.segments[0].length_m = NAN;
    CHECK(!build_road(s).errors.empty());
}

TEST_CASE("junction: lanes, connectors, stop lines, lights") {
    JunctionSpec j;
    j.name = "x";
    j.control = JunctionSpec::traffic_lights;
    auto r = build_junction(j);
    REQUIRE(r.errors.empty());
    const auto& net = r.network;
    CHECK(net.lanes().size() == 4 * 2 + 4 * 3);
    const LaneId south_in = *net.find("x.south.in");
    const Lane& si = net.lane(south_in);
    REQUIRE(si.stop_lines.size() == 1);
    CHECK(si.stop_lines[0].s == doctest::Approx(si.length));
    CHECK(si.stop_lines[0].traffic_lights == std::vector<int32_t>{0});
    CHECK(si.successors.size() == 3);
    CHECK(si.centre.front().x == doctest::Approx(1.75));  // right-hand traffic: east side
    const Lane& left = net.lane(*net.find("x.south_to_west"));
    CHECK(left.turn == Turn::left);
    CHECK(net.lane(*net.find("x.south_to_east")).turn == Turn::right);
    CHECK(net.lane(*net.find("x.south_to_north")).turn == Turn::straight);
    REQUIRE(net.lights.size() == 2);
    CHECK(net.lights[0].name == "x.ns");
    CHECK(si.traffic_lights == std::vector<int32_t>{0});
    CHECK(net.lane(*net.find("x.east.in")).traffic_lights == std::vector<int32_t>{1});
}

TEST_CASE("routing: a left turn through the junction, and a lane change") {
    JunctionSpec j;
    j.name = "x";
    auto jr = build_junction(j);
    const auto& jn = jr.network;
    Route route = shortest_route(jn, *jn.find("x.south.in"), *jn.find("x.west.out"));
    REQUIRE(route.steps.size() == 3);
    CHECK(jn.lane(route.steps[1].lane).name == "x.south_to_west");
    auto rr = build_road(highway());
    const auto& net = rr.network;
    Route lc = shortest_route(net, *net.find("highway.1"), *net.find("highway.2"));
    REQUIRE(lc.steps.size() == 2);
    CHECK(lc.steps[1].by_lane_change);
    // Backward lanes are not reachable from forward ones.
    Route none = shortest_route(net, *net.find("highway.1"), *net.find("highway.-1"));
    CHECK(none.steps.empty());
    CHECK(!none.error.empty());
}

TEST_CASE("locating points on lanes") {
    auto r = build_road(highway());
    const auto& net = r.network;
    const auto loc = net.locate({100, -5.0});
    CHECK(net.lane(loc.lane).name == "highway.1");
    CHECK(loc.s == doctest::Approx(100).epsilon(1e-6));
    CHECK(loc.d == doctest::Approx(0.25).epsilon(1e-6));
}

}  // namespace builtin_road_test
