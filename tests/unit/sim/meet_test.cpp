// `meet V`: a path agent times its motion to reach the point where V's heading crosses its path
// when V does (GeoScenario's ensured collision, collision_vehicle_vid). Pinned by properties
// over vehicle speeds and crossing places: the meeting happens (a collision with a vehicle that
// cannot react, a trajectory) in every case; the same pedestrian at its own pace meets it in none; and a
// vehicle that never crosses the path leaves the pedestrian at its own pace.
#include <doctest/doctest.h>

#include <string>

#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"
#include "tests/unit/io/compile_text.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace meet_test {

using namespace sdv;

namespace {

// A car at a constant `speed` along lane 1 (forward: from 20 m to 380 m; else lane -1, from 380 m
// to 20 m): a trajectory, which does not react. The pedestrian crosses at x from 30 m beside the
// road, at 0.5 m/s on its own.
std::string scenario(double speed, double x, bool meet, bool forward = true) {
    const std::string lane = forward ? "lane 1" : "lane -1";
    const std::string end = std::to_string(360.0 / speed);
    return R"(road r {
    lanes 1 forward, 1 backward
    straight 400 m
}
scenario s {
    road r
    timeout 70 s
    vehicle car: trajectory { trajectory { 0 s: )" + lane + (forward ? " at 20 m  " : " at 380 m  ") + end + " s: " + lane +
           (forward ? " at 380 m" : " at 20 m") + R"( } }
    pedestrian p: path {
        speed 0.5 m/s
)" + (meet ? "        meet car\n" : "") +
           "        path { at (" + std::to_string(x) + " m, -30 m) speed 0.5 m/s  at (" + std::to_string(x) + R"( m, 9 m) speed 0.5 m/s }
    }
}
)";
}

bool collided(const sim::RunResult& r) {
    for (const auto& e : r.events) {
        if (e.kind == "collision") return true;
    }
    return false;
}

}  // namespace

TEST_CASE("meet: a path pedestrian reaches the crossing point when the vehicle does, at every speed and place") {
    for (double speed : {6.0, 10.0, 15.0}) {
        for (double x : {120.0, 200.0, 300.0}) {
            CAPTURE(speed);
            CAPTURE(x);
            auto timed = test::compile_text(scenario(speed, x, true));
            REQUIRE(timed);
            CHECK(collided(sim::simulate(*timed, 0, {})));
            // The conflict removed: at its own pace (30 m away, 0.5 m/s) it is far from the road when the car passes.
            auto own = test::compile_text(scenario(speed, x, false));
            REQUIRE(own);
            CHECK(!collided(sim::simulate(*own, 0, {})));
        }
    }
}

TEST_CASE("meet: a vehicle driving away from the path leaves the pedestrian at its own pace") {
    // The car starts at 380 m in the backward lane and drives away from the path at 390 m (to the
    // road's start): its heading never crosses the path ahead, so the pedestrian keeps 0.5 m/s.
    auto p = test::compile_text(scenario(10, 390, true, false));
    REQUIRE(p);
    sim::Simulation s(*p, 0, {});
    REQUIRE(s.start().empty());
    const auto& walker = s.world().agents[1];
    while (s.step()) {
        if (s.time() > 1 && s.time() < 15) CHECK(walker.speed == doctest::Approx(0.5).epsilon(1e-6));
    }
}

TEST_CASE("walk(meet = V): timed to the crosswalk by the vehicle heading for it, standing while none does") {
    // A pedestrian 10 m beside a crosswalk at 200 m walks to it timed by a car: the nearer the
    // car (the same speed), the faster it must walk; a car that has passed the crosswalk heads
    // for no point of it, and the pedestrian stands (GeoScenario's plan_keep_in_lane).
    auto desired = [](double car_at, double car_to) {
        const std::string text = R"(import "std/pedestrian.sdv"
road r {
    lanes 1 forward, 1 backward
    straight 400 m
    crosswalk x at 200 m width 4 m
}
scenario s {
    road r
    timeout 2 s
    vehicle car: trajectory { trajectory { 0 s: lane 1 at )" + std::to_string(car_at) + " m  20 s: lane 1 at " +
                                 std::to_string(car_to) + R"( m } }
    pedestrian p: sdp {
        start lane 1 at 200 m offset -12 m
        goal lane -1 at 200 m offset -8 m
        tree timed()
    }
}
tree timed() {
    sequence {
        maneuver select_crosswalk(by = nearest)
        maneuver walk(meet = car)
    }
}
)";
        auto p = test::compile_text(text);
        REQUIRE(p);
        sim::Simulation s(*p, 0, {});
        REQUIRE(s.start().empty());
        for (int i = 0; i < 20; ++i) s.step();
        const auto& w = s.world().agents[1];
        REQUIRE(w.walker);
        return w.walker->speed;
    };
    const double far = desired(0, 200), near = desired(100, 300), away = desired(250, 390);
    CHECK(far > 0);
    CHECK(near > 1.5 * far);  // half as far to go for the car: about twice the speed
    CHECK(away == 0);
}

}  // namespace meet_test
