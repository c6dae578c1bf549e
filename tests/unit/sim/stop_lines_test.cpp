// Several stop lines on one lane: a road with two signalised crosswalks gives every lane a stop
// line before each, with that crosswalk's light. Drivers on std.drive obey each in turn. Over
// phasings of the second light (the second crosswalk the eastbound driver meets, the first of the
// westbound) that are red when a driver comes within sight of it, at every tick no front bumper
// crosses a stop line whose light is red, and every driver reaches its goal; with the second light
// always green nobody stops at it (the stop is the light's doing). std.drive does not stop on
// yellow, so a light turning red just before a driver reaches it is left out. Before, a lane kept
// only its first stop line and drivers ran the second red.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"
#include "tests/unit/io/compile_text.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace stop_lines_test {

using namespace sdv;

namespace {

std::string scenario(const std::string& second_light) {
    return R"(
import "std/drive.sdv"
road main {
    lanes 1 forward, 1 backward
    straight 400 m
    crosswalk first at 100 m signalised
    crosswalk second at 250 m signalised
}
scenario s {
    road main
    timeout 90 s
    light main.first { green 80 s  yellow 3 s  red 20 s }
    light main.second { )" + second_light + R"( }
    vehicle east: sdv { start lane 1 at 10 m  speed 12 m/s  goal lane 1 at 380 m  tree std.drive(speed = 12 m/s) }
    vehicle west: sdv { start lane -1 at 390 m  speed 12 m/s  goal lane -1 at 20 m  tree std.drive(speed = 12 m/s) }
}
)";
}

}  // namespace

TEST_CASE("a driver stops at each red stop line of its lane, not only the first") {
    struct Case {
        std::string light;
        bool stops;  // at the second crosswalk
    };
    const Case cases[] = {
        {"red 40 s  green 40 s  yellow 3 s", true},
        {"green 3 s  yellow 3 s  red 40 s  green 60 s", true},  // red while both are far away
        {"red 60 s  green 30 s  yellow 3 s", true},
        {"green 90 s  yellow 3 s  red 5 s", false},
    };
    for (const auto& c : cases) {
        CAPTURE(c.light);
        auto p = test::compile_text(scenario(c.light));
        REQUIRE(p);
        sim::Simulation s(*p, 0, {});
        REQUIRE(s.start().empty());
        const sim::World& w = s.world();
        REQUIRE(w.net.crosswalks.size() == 2);
        std::vector<double> front_before(w.agents.size(), -1);
        std::vector<double> slowest_near_second(w.agents.size(), INFINITY);
        int red_crossings = 0, lines_crossed = 0;
        while (s.step()) {
            for (size_t i = 0; i < w.agents.size(); ++i) {
                const auto& a = w.agents[i];
                if (a.lane == road::kNoLane) continue;
                const double front = a.lane_s + 0.5 * a.v->length;
                for (const auto& line : w.net.lane(a.lane).stop_lines) {
                    // Crossed: the front bumper half a metre past it (a stop puts it on the line).
                    const double past = line.s + 0.5;
                    if (front_before[i] >= 0 && front_before[i] < past && front >= past) {
                        ++lines_crossed;
                        for (const int32_t l : line.traffic_lights) red_crossings += w.light_state(l, s.time()) == "red";
                    }
                }
                // On the approach to the second crosswalk (x = 250 m; its stop lines 2.5 m before it).
                const double to_second = i == 0 ? 250 - a.x : a.x - 250;
                if (to_second > 2 && to_second < 50) slowest_near_second[i] = std::min(slowest_near_second[i], a.speed);
                front_before[i] = front;
            }
        }
        const auto r = s.finish();
        CHECK(red_crossings == 0);
        CHECK(lines_crossed == 4);  // two lines each
        for (size_t i = 0; i < w.agents.size(); ++i) {
            CAPTURE(i);
            CHECK(r.vehicles.at(i).reached_goal);
            if (c.stops) {
                CHECK(slowest_near_second[i] < 0.5);
            } else {
                CHECK(slowest_near_second[i] > 8);
            }
        }
    }
}

}  // namespace stop_lines_test
