// Crosswalks and walkways: built-in roads and junctions checked as properties over shapes, lane
// counts and positions (every lane crossed once, crossings on the crosswalk, stop lines 1 m
// before it, the lights), the invalid specs, and the Lanelet2 maps with pedestrian lanelets.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "runtime/road/builtin_road.h"
#include "runtime/road/lanelet2_reader.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace crosswalk_test {

using namespace sdv::road;

namespace {

const std::string kMaps = std::string(SDV_SHARED_DIR) + "/data/geoscenario/maps/";

double distance_to(const std::vector<Vec2>& line, Vec2 p) {
    double best = INFINITY;
    for (size_t i = 0; i + 1 < line.size(); ++i) {
        const Vec2 d = line[i + 1] - line[i];
        const double t = std::clamp(dot(p - line[i], d) / dot(d, d), 0.0, 1.0);
        best = std::min(best, distance(p, line[i] + t * d));
    }
    return best;
}

bool finite(const std::vector<Vec2>& pts) {
    return std::all_of(pts.begin(), pts.end(), [](Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); });
}

// Everything a crosswalk holds is a number, and each crossing's s lies on its lane.
void check_finite(const RoadNetwork& net, const Crosswalk& cw) {
    CHECK(finite(cw.centre));
    CHECK(finite(cw.left_bound));
    CHECK(finite(cw.right_bound));
    CHECK(std::isfinite(cw.width));
    CHECK(std::isfinite(cw.length));
    for (const auto& x : cw.crossings) {
        CHECK(std::isfinite(x.s));
        CHECK(std::isfinite(x.half_extent));
        CHECK(x.half_extent > 0);
        CHECK(x.s >= 0);
        CHECK(x.s <= net.reference(x.lane).length() + 1e-9);
    }
}

int times_crossed(const Crosswalk& cw, LaneId lane) {
    return static_cast<int>(std::count_if(cw.crossings.begin(), cw.crossings.end(), [&](const auto& x) { return x.lane == lane; }));
}

const Crosswalk::Crossing& crossing(const Crosswalk& cw, LaneId lane) {
    auto it = std::find_if(cw.crossings.begin(), cw.crossings.end(), [&](const auto& x) { return x.lane == lane; });
    REQUIRE(it != cw.crossings.end());
    return *it;
}

// The crossing's s on the lane's reference line is a point of the crosswalk's centre line.
void check_on_centre(const RoadNetwork& net, const Crosswalk& cw, const Crosswalk::Crossing& x) {
    const Vec2 p = net.reference(x.lane).point(x.s);
    CHECK(distance_to(cw.centre, p) < 0.05);
}

// The lane has a stop line 1 m before the strip, in the lane's direction: 1 m further on is the
// edge (half a width from the centre line) on the near side of the crossing. Returns it.
const StopLine& check_stop_line(const RoadNetwork& net, const Crosswalk& cw, LaneId lane) {
    const Lane& l = net.lane(lane);
    const auto& x = crossing(cw, lane);
    const StopLine* line = l.stop_line_from(x.s - cw.width - 1.0);
    REQUIRE_MESSAGE(line != nullptr, "lane " << l.name);
    const double edge = line->s + 1.0;
    CHECK(edge < x.s);
    CHECK(edge > x.s - cw.width);
    CHECK(distance_to(cw.centre, net.reference(lane).point(edge)) == doctest::Approx(0.5 * cw.width).epsilon(0.01));
    return *line;
}

RoadSpec road(std::vector<Segment> segments, int forward, int backward) {
    RoadSpec s;
    s.name = "r";
    s.lanes_forward = forward;
    s.lanes_backward = backward;
    s.segments = std::move(segments);
    s.origin = {10, -20};
    s.heading_rad = 0.3;
    return s;
}

bool has_error(const BuildResult& r, const std::string& name, const std::string& words) {
    return std::any_of(r.errors.begin(), r.errors.end(), [&](const std::string& e) {
        return e.find("'" + name + "'") != std::string::npos && e.find(words) != std::string::npos;
    });
}

}  // namespace

TEST_CASE("road crosswalks cross every lane once, on the crosswalk, with stop lines before them") {
    const std::vector<std::vector<Segment>> shapes = {
        {{Segment::straight, 200, 0}},
        {{Segment::arc, 150, 60}},
        {{Segment::arc, 150, -80}},
        {{Segment::straight, 50, 0}, {Segment::arc, 80, 40}, {Segment::arc, 80, -45}, {Segment::straight, 30, 0}},
    };
    const std::vector<std::pair<int, int>> lane_counts = {{1, 0}, {0, 1}, {1, 1}, {2, 1}, {3, 3}};
    for (const auto& shape : shapes) {
        for (const auto& counts : lane_counts) {
            const int fwd = counts.first;  // not a structured binding: clang 14 cannot capture one
            const int bwd = counts.second;
            for (const bool signalised : {false, true}) {
                RoadSpec spec = road(shape, fwd, bwd);
                double length = 0;
                for (const auto& g : shape) length += g.length_m;
                spec.crosswalks = {{"a", 10, "", 1, 3, signalised},
                                   {"b", 0.5 * length, "", 1, 4.5, signalised},
                                   {"c", length - 12, "", 1, 2, signalised}};
                CAPTURE(fwd);
                CAPTURE(bwd);
                CAPTURE(signalised);
                CAPTURE(length);
                const auto r = build_road(spec);
                REQUIRE_MESSAGE(r.errors.empty(), r.errors.front());
                const auto& net = r.network;
                REQUIRE(net.crosswalks.size() == 3);
                for (size_t i = 0; i < 3; ++i) {
                    const Crosswalk& cw = net.crosswalks[i];
                    CAPTURE(cw.name);
                    CHECK(cw.id == static_cast<int32_t>(i));
                    CHECK(cw.name == "r." + spec.crosswalks[i].name);
                    CHECK(cw.width == spec.crosswalks[i].width_m);
                    CHECK(cw.length == doctest::Approx((fwd + bwd) * spec.lane_width_m + 4));
                    check_finite(net, cw);
                    CHECK(cw.crossings.size() == net.lanes().size());
                    for (const auto& l : net.lanes()) {
                        CHECK(times_crossed(cw, l.id) == 1);
                        const auto& x = crossing(cw, l.id);
                        check_on_centre(net, cw, x);
                        CHECK(x.half_extent == doctest::Approx(0.5 * cw.width).epsilon(0.01));  // perpendicular
                    }
                    if (!signalised) {
                        CHECK(cw.light == -1);
                        continue;
                    }
                    REQUIRE(cw.light >= 0);
                    const TrafficLight& tl = net.lights.at(static_cast<size_t>(cw.light));
                    CHECK(tl.name == cw.name);
                    CHECK(cw.light_inverse);
                    CHECK(tl.lanes.size() == net.lanes().size());
                    for (const auto& l : net.lanes()) {
                        CHECK(std::count(l.traffic_lights.begin(), l.traffic_lights.end(), cw.light) == 1);
                    }
                }
                if (!signalised) {
                    for (const auto& l : net.lanes()) CHECK(l.stop_lines.empty());
                    continue;
                }
                // Every lane has a stop line before each of the three, with that crosswalk's
                // light, in the order the lane meets them.
                for (const auto& l : net.lanes()) {
                    CAPTURE(l.name);
                    CHECK(l.stop_lines.size() == 3);
                    for (const auto& cw : net.crosswalks) {
                        const StopLine& line = check_stop_line(net, cw, l.id);
                        CHECK(line.traffic_lights == std::vector<int32_t>{cw.light});
                    }
                    for (size_t k = 1; k < l.stop_lines.size(); ++k) CHECK(l.stop_lines[k - 1].s < l.stop_lines[k].s);
                }
            }
        }
    }
}

TEST_CASE("a single signalised crosswalk puts stop lines before it in both directions") {
    RoadSpec spec = road({{Segment::arc, 120, 50}}, 2, 2);
    spec.crosswalks = {{"x", 60, "", 1, 3, true}};
    const auto r = build_road(spec);
    REQUIRE(r.errors.empty());
    const auto& net = r.network;
    for (const auto& l : net.lanes()) {
        CAPTURE(l.name);
        check_stop_line(net, net.crosswalks[0], l.id);
        CHECK(l.traffic_lights == std::vector<int32_t>{0});
    }
}

TEST_CASE("junction crosswalks cross their arm's lanes, move its stop lines back and follow the parallel light") {
    const char* arms[] = {"north", "east", "south", "west"};
    for (int n = 1; n <= 2; ++n) {
        for (const auto control : {JunctionSpec::traffic_lights, JunctionSpec::stop_signs, JunctionSpec::none}) {
            for (int a = 0; a < 4; ++a) {
                JunctionSpec spec;
                spec.name = "j";
                spec.lanes_per_direction = n;
                spec.arm_length_m = 60;
                spec.control = control;
                const double gap = 1.0 + a, width = 3.0 + 0.5 * a;
                spec.crosswalks = {{"z", 0, arms[a], gap, width, false}};
                CAPTURE(n);
                CAPTURE(static_cast<int>(control));
                CAPTURE(arms[a]);
                const auto r = build_junction(spec);
                REQUIRE_MESSAGE(r.errors.empty(), r.errors.front());
                const auto& net = r.network;
                REQUIRE(net.crosswalks.size() == 1);
                const Crosswalk& cw = net.crosswalks[0];
                CHECK(cw.name == "j.z");
                CHECK(cw.length == doctest::Approx(2 * n * spec.lane_width_m + 4));
                check_finite(net, cw);
                // Exactly the arm's lanes, both ways, each once.
                CHECK(cw.crossings.size() == static_cast<size_t>(2 * n));
                for (int k = 1; k <= n; ++k) {
                    const std::string suffix = n > 1 ? "." + std::to_string(k) : "";
                    const LaneId in = *net.find(std::string("j.") + arms[a] + ".in" + suffix);
                    const LaneId out = *net.find(std::string("j.") + arms[a] + ".out" + suffix);
                    CHECK(times_crossed(cw, in) == 1);
                    CHECK(times_crossed(cw, out) == 1);
                    check_on_centre(net, cw, crossing(cw, in));
                    check_on_centre(net, cw, crossing(cw, out));
                    // Incoming: the stop line moved back to 1 m before the strip; outgoing: none.
                    check_stop_line(net, cw, in);
                    REQUIRE(net.lane(in).stop_lines.size() == 1);
                    CHECK(net.lane(in).stop_lines[0].s == doctest::Approx(spec.arm_length_m - gap - width - 1).epsilon(1e-4));
                    CHECK(net.lane(out).stop_lines.empty());
                }
                // The other arms keep their stop lines at the junction box.
                for (int b = 0; b < 4; ++b) {
                    if (b == a) continue;
                    const Lane& in = net.lane(*net.find(std::string("j.") + arms[b] + ".in" + (n > 1 ? ".1" : "")));
                    REQUIRE(in.stop_lines.size() == 1);
                    CHECK(in.stop_lines[0].s == doctest::Approx(in.length));
                }
                CHECK(!cw.light_inverse);
                if (control == JunctionSpec::traffic_lights) {
                    REQUIRE(cw.light >= 0);
                    CHECK(net.lights.at(static_cast<size_t>(cw.light)).name == (a % 2 == 0 ? "j.ew" : "j.ns"));
                } else {
                    CHECK(cw.light == -1);
                }
            }
        }
    }
}

TEST_CASE("crosswalks on every arm of a junction at once") {
    JunctionSpec spec;
    spec.name = "j";
    spec.lanes_per_direction = 2;
    spec.control = JunctionSpec::traffic_lights;
    spec.crosswalks = {{"n", 0, "north", 0, 3, false},
                       {"e", 0, "east", 1, 3, false},
                       {"s", 0, "south", 2, 3, false},
                       {"w", 0, "west", 3, 3, false},
                       {"n2", 0, "north", 20, 4, false}};
    const auto r = build_junction(spec);
    REQUIRE(r.errors.empty());
    const auto& net = r.network;
    REQUIRE(net.crosswalks.size() == 5);
    for (const auto& cw : net.crosswalks) CHECK(cw.crossings.size() == 4);
    // Two crosswalks on the north arm: its lanes stop before the outer one, met first.
    const LaneId in = *net.find("j.north.in.1");
    check_stop_line(net, net.crosswalks[4], in);
}

TEST_CASE("invalid crosswalks give errors naming them") {
    RoadSpec spec = road({{Segment::straight, 100, 0}}, 1, 1);
    spec.crosswalks = {{"neg", -5, "", 1, 3, false}, {"beyond", 101, "", 1, 3, false},
                       {"edge", 99, "", 1, 3, false}, {"narrow", 20, "", 1, 0.5, false},
                       {"wide", 60, "", 1, 25, false}, {"p", 40, "", 1, 3, false},
                       {"q", 42, "", 1, 3, false},     {"p", 90, "", 1, 3, false}};
    auto r = build_road(spec);
    CHECK(has_error(r, "neg", "outside the road"));
    CHECK(has_error(r, "beyond", "outside the road"));
    CHECK(has_error(r, "edge", "outside the road"));
    CHECK(has_error(r, "narrow", "width"));
    CHECK(has_error(r, "wide", "width"));
    CHECK(has_error(r, "q", "overlaps crosswalk 'p'"));
    CHECK(has_error(r, "p", "defined twice"));
    // Strips that just touch are fine; one near the start has no room for its stop line.
    spec.crosswalks = {{"p", 40, "", 1, 3, false}, {"q", 43, "", 1, 3, false}};
    CHECK(build_road(spec).errors.empty());
    spec.crosswalks = {{"start", 1.8, "", 1, 3, true}};
    CHECK(has_error(build_road(spec), "start", "no room for the stop line"));
    // A hairpin brings the lane back through the strip: crossed twice.
    RoadSpec hairpin = road({{Segment::straight, 20, 0}, {Segment::arc, M_PI * 1.6, -1.6}, {Segment::straight, 20, 0}}, 1, 0);
    hairpin.lane_width_m = 1;
    hairpin.crosswalks = {{"h", 10, "", 1, 3, false}};
    CHECK(has_error(build_road(hairpin), "h", "2 times"));

    JunctionSpec j;
    j.name = "j";
    j.arm_length_m = 50;
    j.crosswalks = {{"up", 0, "up", 1, 3, false},        {"far", 0, "east", 47, 3, false},
                    {"back", 0, "west", -1, 3, false},   {"thin", 0, "south", 1, 0.9, false},
                    {"n1", 0, "north", 1, 3, false},     {"n2", 0, "north", 3, 3, false},
                    {"n1", 0, "south", 10, 3, false}};
    auto jr = build_junction(j);
    CHECK(has_error(jr, "up", "unknown arm 'up'"));
    CHECK(has_error(jr, "far", "gap"));
    CHECK(has_error(jr, "back", "gap"));
    CHECK(has_error(jr, "thin", "width"));
    CHECK(has_error(jr, "n2", "overlaps crosswalk 'n1'"));
    CHECK(has_error(jr, "n1", "defined twice"));
    CHECK(jr.network.crosswalks.empty());
}

// Counts read off the files with an XML parser: lanelet relations with subtype crosswalk, and
// walkway lanelets plus walkway multipolygons (each a single closed outline of outer ways).
TEST_CASE("Lanelet2 maps: crosswalks, walkways, lights, crossings") {
    struct Case {
        const char* file;
        size_t crosswalks, walkways;
        std::vector<std::string> crossing_roads;  // the crosswalks that cross vehicle lanes
        int with_light;
    };
    const std::vector<Case> cases = {
        // One unsignalised crosswalk over both lanes of the ring road.
        {"lanelet2_ringroad_pedestrians.osm", 1, 8, {"-5001877"}, 0},
        // Four signalised crosswalks over the junction's arms; -5001982 and -5001985 lie between
        // walkways, away from the lanes.
        {"lanelet2_university_weber_alt_walkways.osm", 6, 24, {"-5001980", "-5001981", "-5001983", "-5001984"}, 4},
        // 3 walkway lanelets and 19 walkway areas. Of the 8 crosswalk lanelets, 44986, 45170 and
        // 45174 cross roads; 45172 is the part on a traffic island between 45170 and 45174; the
        // other four lie between a kerb and a wall, along the road.
        {"ll2_mapping_example.osm", 8, 22, {"44986", "45170", "45174"}, 0},
    };
    for (const auto& c : cases) {
        CAPTURE(c.file);
        const auto r = load_lanelet2(kMaps + c.file);
        REQUIRE_MESSAGE(r.errors.empty(), r.errors.front());
        const auto& net = *r.network;
        CHECK(net.crosswalks.size() == c.crosswalks);
        CHECK(net.walkways.size() == c.walkways);
        int lights = 0;
        for (const auto& cw : net.crosswalks) {
            CAPTURE(cw.name);
            check_finite(net, cw);
            CHECK(cw.width > 0.5);
            CHECK(cw.length == doctest::Approx(polyline_length(cw.centre)));
            CHECK(!cw.light_inverse);
            const bool crosses = std::find(c.crossing_roads.begin(), c.crossing_roads.end(), cw.name) != c.crossing_roads.end();
            CHECK(cw.crossings.empty() == !crosses);
            for (const auto& x : cw.crossings) {
                check_on_centre(net, cw, x);
                CHECK(!net.lane(x.lane).name.empty());
            }
            if (cw.light >= 0) {
                ++lights;
                CHECK(static_cast<size_t>(cw.light) < net.lights.size());
            }
            // Crosswalk lanelets are no lanes.
            CHECK(!net.find(cw.name));
        }
        CHECK(lights == c.with_light);
        for (const auto& w : net.walkways) {
            CAPTURE(w.name);
            CHECK(finite(w.centre));
            CHECK(finite(w.left_bound));
            CHECK(finite(w.right_bound));
            CHECK(w.centre.size() >= 2);
            CHECK(std::isfinite(w.width));
            CHECK(w.width > 0);
            CHECK(!net.find(w.name));
        }
    }
}

TEST_CASE("a crosswalk lanelet's traffic light is its pedestrians' signal") {
    const auto r = load_lanelet2(kMaps + "lanelet2_university_weber_alt_walkways.osm");
    REQUIRE(r.network);
    const auto& net = *r.network;
    // Read off the file: crosswalk lanelet -5001980 refers to traffic_light element -5002056,
    // whose light way (-1952643) is named ped_tl_e_w_south.
    for (const auto& cw : net.crosswalks) {
        if (cw.name != "-5001980") continue;
        REQUIRE(cw.light >= 0);
        CHECK(net.lights[static_cast<size_t>(cw.light)].name == "ped_tl_e_w_south");  // its light way's name
    }
}

TEST_CASE("find_crossings: a crossing through a shared vertex counts once; the half extent grows with the angle") {
    RoadNetwork net;
    Lane l;
    l.name = "l";
    l.centre = {{0, 0}, {5, 0}, {10, 0}};
    net.add_lane(l);
    Crosswalk straight;
    straight.centre = {{5, -3}, {5, 3}};
    straight.width = 3;
    Crosswalk slanted;
    slanted.centre = {{-3, -3}, {3, 3}};  // at 45° through the lane
    slanted.width = 2;
    Crosswalk along;
    along.centre = {{0, 0.0}, {10, 0.0}};  // collinear: no crossing
    net.crosswalks = {straight, slanted, along};
    find_crossings(net);
    REQUIRE(net.crosswalks[0].crossings.size() == 1);
    CHECK(net.crosswalks[0].crossings[0].s == doctest::Approx(5));
    CHECK(net.crosswalks[0].crossings[0].half_extent == doctest::Approx(1.5));
    CHECK(net.crosswalks[0].length == doctest::Approx(6));
    REQUIRE(net.crosswalks[1].crossings.size() == 1);
    CHECK(net.crosswalks[1].crossings[0].s == doctest::Approx(0).epsilon(1e-6));
    CHECK(net.crosswalks[1].crossings[0].half_extent == doctest::Approx(std::sqrt(2.0)));
    CHECK(net.crosswalks[1].id == 1);
    CHECK(net.crosswalks[2].crossings.empty());
}

}  // namespace crosswalk_test
