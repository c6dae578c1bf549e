// A trajectory vehicle is under way from its first waypoint: at t = 0 it already has the
// velocity of its first segment (it used to stand still for the first tick, and every driver
// that planned from that snapshot braked for a vehicle it took for stopped). Pinned by
// properties over speeds, road shapes and waypoint kinds: the speed seen at t = 0 is the first
// segment's, and a driver behind it at its own speed does not slow down.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"
#include "tests/unit/io/compile_text.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace trajectory_start_test {

using namespace sdv;

namespace {

// Speeds of every agent at t = 0 (the snapshot drivers plan their first cycle from) and at 2 s.
class Speeds final : public sim::RunObserver {
public:
    void start(const sim::World& w) override {
        for (const auto& a : w.agents) at0.push_back(a.speed);
    }
    void tick(const sim::World& w, int, double time) override {
        if (std::fabs(time - 2.0) < 1e-9)
            for (const auto& a : w.agents) at2.push_back(a.speed);
    }
    std::vector<double> at0, at2;
};

std::string scenario(const std::string& segment, double speed, bool xy) {
    const double t1 = 100.0 / speed;
    const std::string wp = xy ? "0 s: at (20 m, -1.75 m) heading 0 deg  " + std::to_string(t1) + " s: at (120 m, -1.75 m) heading 0 deg"
                              : "0 s: lane 1 at 20 m  " + std::to_string(t1) + " s: lane 1 at 120 m";
    return R"(import "std/drive.sdv"
road r {
    lanes 1 forward
    )" + segment + R"(
}
scenario s {
    road r
    timeout 3 s
    vehicle lead: trajectory { trajectory { )" + wp + R"( } }
    vehicle follower: sdv {
        start lane 1 at 2 m
        speed )" + std::to_string(speed) + R"( m/s
        tree std.drive(speed = )" + std::to_string(speed) + R"( m/s, time_gap = 1 s)
    }
}
)";
}

}  // namespace

TEST_CASE("a trajectory vehicle has its first segment's speed at t = 0, and a driver behind it keeps its speed") {
    for (double speed : {4.0, 8.0, 14.0}) {
        for (const bool xy : {false, true}) {
            for (const char* segment : {"straight 400 m", "arc 300 m radius 400 m"}) {
                if (xy && std::string(segment) != "straight 400 m") continue;  // xy points lie on the straight road
                CAPTURE(speed);
                CAPTURE(xy);
                CAPTURE(segment);
                auto p = test::compile_text(scenario(segment, speed, xy));
                REQUIRE(p);
                Speeds s;
                const auto r = sim::simulate(*p, 0, {}, &s);
                REQUIRE(r.error.empty());
                REQUIRE(s.at0.size() == 2);
                // Lane waypoints on an arc: the chord is shorter than the arc length.
                CHECK(s.at0[0] == doctest::Approx(speed).epsilon(0.01));
                REQUIRE(s.at2.size() == 2);
                // 18 m behind at its own speed and a 1 s time gap: nothing to brake for.
                CHECK(s.at2[1] >= 0.97 * speed);
            }
        }
    }
}

TEST_CASE("a trajectory whose first waypoint is later than 0 s enters the run then, under way") {
    for (double entry : {0.5, 2.0, 3.3}) {
        CAPTURE(entry);
        const std::string text = R"(road r {
    lanes 1 forward
    straight 400 m
}
scenario s {
    road r
    timeout 6 s
    vehicle parked: static { start lane 1 at 52 m }
    vehicle late: trajectory { trajectory { )" + std::to_string(entry) + " s: lane 1 at 50 m  " + std::to_string(entry + 10) +
                                 R"( s: lane 1 at 150 m } }
}
)";
        auto p = test::compile_text(text);
        REQUIRE(p);
        // Where the late vehicle is, tick by tick, while it is in the run.
        class Watch final : public sim::RunObserver {
        public:
            void tick(const sim::World& w, int, double t) override {
                const auto& a = w.agents[1];
                if (a.active) seen.push_back({t, a.x, a.speed});
            }
            struct Seen {
                double t, x, speed;
            };
            std::vector<Seen> seen;
        } watch;
        const auto r = sim::simulate(*p, 0, {}, &watch);
        REQUIRE(r.error.empty());
        REQUIRE(!watch.seen.empty());
        CHECK(watch.seen.front().t >= entry - 1e-9);
        CHECK(watch.seen.front().t <= entry + 1.0 / 30 + 1e-9);
        CHECK(watch.seen.front().speed == doctest::Approx(10).epsilon(0.01));
        // Its first waypoint overlaps the parked car (2 m apart): before it entered it was
        // nowhere, so the collision happens when it enters, not at 0 s.
        double first_collision = -1;
        for (const auto& e : r.events)
            if (e.kind == "collision" && first_collision < 0) first_collision = e.time;
        CHECK(first_collision >= entry - 1e-9);
        CHECK(first_collision <= entry + 1.0 / 30 + 1e-9);
    }
}

}  // namespace trajectory_start_test
