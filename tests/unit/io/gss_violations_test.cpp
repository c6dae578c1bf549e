// violations.json as the reference writes it (RequirementViolationEvents.py, HardRequirements.py):
// the classes, payloads and messages of each violation, at the reference's tick keys; pinned on
// synthetic runs where the answer is known by construction: a pedestrian hit at every bearing
// round the car gets the side the reference's geometry gives; static objects are not the
// reference's collisions; only SDVs are keys.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

#include "runtime/io/gss_outputs.h"
#include "tests/unit/io/compile_text.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace gss_violations_test {

using namespace sdv;

namespace {

const char* kScenario = R"(import "std/drive.sdv"
road r {
    lanes 1 forward
    straight 300 m
}
scenario s {
    road r
    timeout 20 s
    rate planning 5 Hz
    vehicle v1: sdv { start lane 1 at 20 m  goal lane 1 at 280 m  tree std.drive() }
    vehicle v2: sdv { start lane 1 at 60 m  goal lane 1 at 280 m  tree std.drive() }
    vehicle v3: trajectory { trajectory { 0 s: lane 1 at 100 m  10 s: lane 1 at 200 m } }
    object cone { start lane 1 at 150 m }
    pedestrian p1: path { speed 1 m/s  path { at (40 m, 5 m) speed 1 m/s  at (40 m, -5 m) speed 1 m/s } }
}
)";

constexpr double kPi = 3.14159265358979323846;

}  // namespace

TEST_CASE("violations.json: the reference's classes, payloads and tick keys") {
    auto p = test::compile_text(kScenario);
    REQUIRE(p);
    const auto& vs = p->scenarios[0].vehicles;
    REQUIRE(vs.size() == 5);
    REQUIRE(vs[3].object);
    REQUIRE(vs[4].pedestrian);
    sim::RunResult r;
    r.vehicles.resize(vs.size());
    r.events.push_back({2.1, "collision", {0, 1}, 0, ""});  // two SDVs: an entry on each
    r.events.push_back({3.0, "collision", {1, 2}, 0, ""});  // an SDV and a TV: on the SDV only
    r.events.push_back({4.0, "collision", {0, 3}, 0, ""});  // an object: not the reference's
    r.events.push_back({6.0, "goal_overshot", {1}, 0, ""});
    r.vehicles[1].reached_goal = true;
    r.events.push_back({20.0, "timeout", {}, 0, ""});
    const auto pose = [](int, double) { return io::Pose{}; };
    const auto j = nlohmann::json::parse(io::violations_json(*p, 0, r, pose));
    // Keys: the SDVs only (v1, v2); the TV, object and pedestrian are not.
    CHECK(j.size() == 2);
    // 2.1 s at 5 Hz: the planner tick in progress is 10 (ticks at 0, 0.2, ..., 2.0 s).
    CHECK(j["1"]["10"]["CollisionWithVehicle"]["message"] == "v_1 bounding box overlapped with the vehicle agent v_2");
    CHECK(j["1"]["10"]["CollisionWithVehicle"]["collections"]["vehicles"]["alias"] == "v_2");
    CHECK(j["1"]["10"]["CollisionWithVehicle"]["collections"]["vehicles"]["id"] == 2);
    CHECK(j["2"]["10"]["CollisionWithVehicle"]["message"] == "v_2 bounding box overlapped with the vehicle agent v_1");
    CHECK(j["2"]["14"]["CollisionWithVehicle"]["message"] == "v_2 bounding box overlapped with the vehicle agent v_3");
    CHECK(!j["1"].contains("19"));  // the cone
    CHECK(j["2"]["29"]["GoalOvershot"]["message"] == "v2 drove past its target location");
    // The timeout: the SDVs short of their goal, at the last tick that ran (99 of 0..100).
    CHECK(j["1"]["99"]["ScenarioTimeout"]["message"] ==
          "v1 did not reach its target location during the 20.0 seconds allowed by this scenario.");
    CHECK(!j["2"].contains("99"));
}

TEST_CASE("a pedestrian hit: its side and bearing as the reference's geometry gives them, all round the car") {
    auto p = test::compile_text(kScenario);
    REQUIRE(p);
    const auto& car = p->scenarios[0].vehicles[0];
    // The corners of a 4.5 m x 1.8 m car are 23.58 degrees off its axis (asin(width / length)).
    const double corner = std::asin(car.width / car.length) * 180 / kPi;
    for (double heading : {0.0, 1.0, -2.5}) {
        for (double bearing = -179; bearing <= 179; bearing += 7) {
            CAPTURE(heading);
            CAPTURE(bearing);
            sim::RunResult r;
            r.vehicles.resize(5);
            r.events.push_back({5.0, "collision", {0, 4}, 0, ""});
            const double b = heading + bearing * kPi / 180;
            const auto pose = [&](int i, double) { return i == 0 ? io::Pose{10, 20, heading} : io::Pose{10 + 2 * std::cos(b), 20 + 2 * std::sin(b), 0}; };
            const auto j = nlohmann::json::parse(io::violations_json(*p, 0, r, pose));
            const auto& v = j["1"]["24"]["CollisionWithPedestrian"];
            REQUIRE(v.is_object());
            const std::string zone = std::fabs(bearing) <= corner ? "front" : std::fabs(bearing) >= 180 - corner ? "rear" : bearing > 0 ? "left" : "right";
            CHECK(v["zone"] == zone);
            CHECK(v["angle"].get<double>() == doctest::Approx(bearing).epsilon(1e-6));
            CHECK(v["collections"]["pedestrians"]["alias"] == "p_1");
            const std::string msg = v["message"];
            CHECK(msg.rfind("v_1 bounding box overlapped with the pedestrian agent p_1 on the vehicle " + zone + " side at ", 0) == 0);
            CHECK(msg.size() > 8);
            CHECK(msg.substr(msg.size() - 8) == " degrees");
        }
    }
}

}  // namespace gss_violations_test
