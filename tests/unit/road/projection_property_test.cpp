// Properties of the Frenet projection on every shape a road can take (issue "exact roads"): a
// point placed at (s, d) on a lane's reference line projects back to (s, d) within 1 cm from any
// hint and from none, on straight roads, arcs left and right, turns beyond 180°, multi-lane
// roads in both directions, junction connectors, and every lane of every Lanelet2 map in the
// shared data.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "runtime/road/builtin_road.h"
#include "runtime/road/lanelet2_reader.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace projection_property_test {

using namespace sdv::road;

namespace {

struct Shape {
    const char* name;
    RoadSpec spec;
};

RoadSpec road(int forward, int backward, std::vector<Segment> segments) {
    RoadSpec s;
    s.name = "r";
    s.lanes_forward = forward;
    s.lanes_backward = backward;
    s.segments = std::move(segments);
    return s;
}

std::vector<Shape> shapes() {
    return {
        {"straight", road(1, 0, {{Segment::straight, 400, 0}})},
        {"arc left 150 m", road(1, 0, {{Segment::arc, 200, 150}})},
        {"arc right 80 m", road(2, 1, {{Segment::arc, 200, -80}})},
        {"turn of 270 degrees", road(1, 1, {{Segment::straight, 20, 0}, {Segment::arc, 1.5 * std::numbers::pi * 40, 40}, {Segment::straight, 20, 0}})},
        {"full circle", road(1, 0, {{Segment::arc, 2 * std::numbers::pi * 60 - 8, 60}})},
        {"S bend", road(2, 2, {{Segment::arc, 120, 60}, {Segment::arc, 120, -60}, {Segment::straight, 30, 0}})},
        {"highway with a long arc", road(3, 2, {{Segment::straight, 300, 0}, {Segment::arc, 120, 250}, {Segment::straight, 200, 0}})},
        {"tight hairpin", road(1, 0, {{Segment::straight, 30, 0}, {Segment::arc, std::numbers::pi * 15, 15}, {Segment::straight, 30, 0}})},
    };
}

// Every lane: points at (s, d) for s along the lane and |d| up to most of a lane width, with
// hints nowhere near, exact, slightly off, far off, at both ends, and none. A Frenet frame is
// defined only inside the radius of curvature: points with |d| beyond half of it near s (the
// kinks of a map's centre line) are not checked, and they must be rare.
void check_round_trips(const RoadNetwork& net, const std::string& label, double max_d) {
    int checked = 0, skipped = 0;
    double worst = 0;
    std::string worst_case;
    for (const Lane& lane : net.lanes()) {
        const ReferenceLine& ref = net.reference(lane.id);
        const double len = ref.length();
        const int steps = std::max(4, static_cast<int>(len / 3.0));
        for (int k = 0; k <= steps; ++k) {
            const double s = len * k / steps;
            double kmax = 0;
            for (double u = s - 2.0; u <= s + 2.0; u += 0.25) kmax = std::max(kmax, std::fabs(ref.curvature(std::clamp(u, 0.0, len))));
            for (double d : {-max_d, -0.6, 0.0, 0.45, max_d}) {
                if (std::fabs(d) * kmax >= 0.5) {
                    ++skipped;
                    continue;
                }
                const CartesianState c = ref.to_cartesian({s, 0, 0, d, 0, 0});
                for (double hint : {-1.0, s, s + 2.5, s - 7.0, s + 60.0, s - 150.0, 0.0, len, 0.5 * len, 1e9}) {
                    const FrenetState f = ref.project({c.x, c.y}, hint);
                    const double err = std::max(std::fabs(f.s - s), std::fabs(f.d - d));
                    ++checked;
                    if (err > worst) {
                        worst = err;
                        worst_case = lane.name + " s=" + std::to_string(s) + " d=" + std::to_string(d) + " hint=" + std::to_string(hint) +
                                     " -> s=" + std::to_string(f.s) + " d=" + std::to_string(f.d);
                    }
                }
            }
        }
    }
    INFO(label << ": worst " << worst_case << "; " << skipped << " points inside a kink skipped, " << checked << " checked");
    CHECK(checked > 0);
    CHECK(skipped * 10 < checked);
    CHECK(worst < 0.01);
}

}  // namespace

TEST_CASE("projection round-trips on every built-in road shape, from any hint and from none") {
    for (const Shape& shape : shapes()) {
        auto b = build_road(shape.spec);
        INFO(shape.name);
        REQUIRE(b.errors.empty());
        check_round_trips(b.network, shape.name, 1.6);
    }
}

TEST_CASE("projection round-trips on junction connectors and arms") {
    for (int lanes : {1, 2}) {
        JunctionSpec j;
        j.name = "j";
        j.lanes_per_direction = lanes;
        auto b = build_junction(j);
        REQUIRE(b.errors.empty());
        check_round_trips(b.network, "junction", 1.0);
    }
}

TEST_CASE("projection round-trips on every lane of every Lanelet2 map of the shared data") {
    namespace fs = std::filesystem;
    const fs::path data = fs::path(SDV_SHARED_DIR) / "data";
    std::vector<fs::path> maps = {data / "lanelet2" / "mapping_example.osm"};
    for (const auto& e : fs::directory_iterator(data / "geoscenario" / "maps")) {
        if (e.path().extension() == ".osm") maps.push_back(e.path());
    }
    std::sort(maps.begin(), maps.end());
    for (const auto& m : maps) {
        auto l = load_lanelet2(m.string(), std::nullopt);
        INFO(m.filename().string());
        REQUIRE(l.errors.empty());
        // Lanelets are narrow and their centre lines may bend sharply: 0.8 m either side.
        check_round_trips(*l.network, m.filename().string(), 0.8);
    }
}

TEST_CASE("points beyond the ends extrapolate along the end tangents") {
    auto b = build_road(road(1, 0, {{Segment::arc, 100, 80}}));
    REQUIRE(b.errors.empty());
    const ReferenceLine& ref = b.network.reference(0);
    for (double ds : {-20.0, -3.0, 3.0, 20.0}) {
        const double s = ds < 0 ? ds : ref.length() + ds;
        const CartesianState c = ref.to_cartesian({s, 0, 0, 0.5, 0, 0});
        for (double hint : {-1.0, 0.0, ref.length()}) {
            const FrenetState f = ref.project({c.x, c.y}, hint);
            CHECK(f.s == doctest::Approx(s).epsilon(1e-6));
            CHECK(f.d == doctest::Approx(0.5).epsilon(1e-6));
        }
    }
}

}  // namespace projection_property_test
