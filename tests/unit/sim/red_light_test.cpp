// Queues at red lights. A line of drivers on std.drive, at random speeds and gaps, meets two
// signalised crosswalks that are red from the start and turn green one after the other. At every
// tick no front bumper crosses a red stop line; nobody runs into anybody (the queue forms behind
// the first driver at each line, however the others were in their stop when the one ahead began
// to slow); while a light is red, a stopped driver waits near the one ahead of it or the line,
// not far short of it; once both are green every driver reaches its goal. Before, a driver
// stopping for the line planned to the line through a slower driver ahead of it (the pedestrian
// bench: a rear-end collision at 2.5 m/s at the second red).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"
#include "tests/unit/io/compile_text.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace red_light_test {

using namespace sdv;

namespace {

std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    return buf;
}

struct Family {
    std::string text;
    double green1 = 0, green2 = 0;  // when each light turns green
    int n = 0;
};

// Crosswalks at 150 m and 300 m (stop lines 2.5 m before each), red from the start.
Family family(std::mt19937& rng) {
    std::uniform_int_distribution<int> count(3, 7);
    std::uniform_real_distribution<double> gap(8, 40), start_speed(4, 16), cruise(9, 16), red1(12, 30), red2(10, 30);
    Family f;
    const int n = count(rng);
    f.green1 = red1(rng);
    f.green2 = f.green1 + red2(rng);
    std::string vehicles;
    double front = 90;  // the first driver's centre: 57.5 m short of the first stop line
    for (int i = 0; i < n; ++i) {
        if (i > 0) front -= 4.5 + gap(rng);
        if (front < 5) break;
        const double v = start_speed(rng), cruise_v = cruise(rng);
        vehicles += "    vehicle v" + std::to_string(i) + ": sdv { start lane 1 at " + fmt(front) + " m  speed " + fmt(v) +
                    " m/s  goal lane 1 at " + fmt(440 - 12 * i) + " m  tree std.drive(speed = " + fmt(cruise_v) + " m/s) }\n";
        f.n = i + 1;
    }
    f.text = R"(
import "std/drive.sdv"
road main {
    lanes 1 forward, 1 backward
    straight 460 m
    crosswalk first at 150 m signalised
    crosswalk second at 300 m signalised
}
scenario s {
    road main
    timeout )" + fmt(f.green2 + 60) + R"( s
    light main.first { red )" + fmt(f.green1) + R"( s  green 200 s }
    light main.second { red )" + fmt(f.green2) + R"( s  green 200 s }
)" + vehicles + "}\n";
    return f;
}

}  // namespace

TEST_CASE("drivers queue at red lights: nobody runs a red or into the driver ahead, all get through") {
    std::mt19937 rng(20261124);
    for (int k = 0; k < 24; ++k) {
        const Family f = family(rng);
        CAPTURE(k);
        CAPTURE(f.text);
        auto p = test::compile_text(f.text);
        REQUIRE(p);
        sim::Simulation s(*p, 0, {});
        REQUIRE(s.start().empty());
        const sim::World& w = s.world();
        std::vector<double> front_before(w.agents.size(), -1);
        int red_crossings = 0;
        double worst_short = 0;  // the largest gap a driver at rest left before the one ahead / the line
        while (s.step()) {
            const double t = s.time();
            for (size_t i = 0; i < w.agents.size(); ++i) {
                const auto& a = w.agents[i];
                if (a.lane == road::kNoLane) continue;
                const double front = a.x + 0.5 * a.v->length;
                for (const double line : {147.5, 297.5}) {
                    const double past = line + 0.5;
                    const bool red = t < (line < 200 ? f.green1 : f.green2);
                    if (red && front_before[i] >= 0 && front_before[i] < past && front >= past) ++red_crossings;
                }
                front_before[i] = front;
                // At rest while its light is red (after the first 5 s, not in the last second of
                // red): the gap to what it waits behind.
                if (a.speed > 0.05 || t < 5) continue;
                const double line = front < 148.5 ? 147.5 : front < 298.5 ? 297.5 : INFINITY;
                if (!std::isfinite(line) || t > (line < 200 ? f.green1 : f.green2) - 1) continue;
                double ahead = line;
                for (size_t j = 0; j < w.agents.size(); ++j) {
                    const double rear = w.agents[j].x - 0.5 * w.agents[j].v->length;
                    if (j != i && rear > a.x && rear < ahead) ahead = rear;
                }
                worst_short = std::max(worst_short, ahead - front);
            }
        }
        const auto r = s.finish();
        CHECK(red_crossings == 0);
        for (const auto& e : r.events) {
            CAPTURE(e.time);
            CHECK(e.kind != "collision");
        }
        CHECK(worst_short < 8.0);
        for (int i = 0; i < f.n; ++i) {
            CAPTURE(i);
            CHECK(r.vehicles.at(static_cast<size_t>(i)).reached_goal);
        }
    }
}

// The dilemma zone. A light turns yellow for 1 s + v / 6 m/s² (the ITE's yellow for a reaction
// second and 3 m/s²) and then red while a driver approaches at v, from every distance: it either
// stops at the line or is over it before red, never over it on red, and never brakes beyond
// comfort to do so (no fallback); the driver behind keeps clear. Before, std.drive ignored
// yellow and, when red came within a short stop, braked hard (fallback) and crossed on red at 5 to
// 10 m/s.
TEST_CASE("at a light turning yellow a driver stops if it comfortably can, else goes on before red") {
    for (const double v : {8.0, 11.0, 14.0, 16.0}) {
        const double yellow = 1 + v / 6;
        for (double gap = 4; gap <= 80; gap += 4) {
            CAPTURE(v);
            CAPTURE(gap);
            // v0's front bumper is `gap` short of the stop line (147.5 m) when the light turns.
            const double green = (147.5 - gap - 42.25) / v;
            const std::string text = R"(
import "std/drive.sdv"
road main {
    lanes 1 forward, 1 backward
    straight 400 m
    crosswalk first at 150 m signalised
}
scenario s {
    road main
    timeout )" + fmt(green + yellow + 30 + 400 / v) + R"( s
    light main.first { green )" + fmt(green) + " s  yellow " + fmt(yellow) + R"( s  red 20 s  green 100 s }
    vehicle v0: sdv { start lane 1 at 40 m  speed )" + fmt(v) + " m/s  goal lane 1 at 380 m  tree std.drive(speed = " + fmt(v) + R"( m/s) }
    vehicle v1: sdv { start lane 1 at )" + fmt(35.5 - 2 * v) + " m  speed " + fmt(v) + " m/s  goal lane 1 at 360 m  tree std.drive(speed = " +
                                     fmt(v) + R"( m/s) }
}
)";
            auto p = test::compile_text(text);
            REQUIRE(p);
            sim::Simulation s(*p, 0, {});
            REQUIRE(s.start().empty());
            const sim::World& w = s.world();
            std::vector<double> front_before(w.agents.size(), -1);
            int red_crossings = 0;
            std::vector<double> past_light(w.agents.size(), INFINITY);  // when 50 m past the line
            while (s.step()) {
                const bool red = s.time() >= green + yellow && s.time() < green + yellow + 20;
                for (size_t i = 0; i < w.agents.size(); ++i) {
                    const double front = w.agents[i].x + 0.5 * w.agents[i].v->length;
                    if (red && front_before[i] >= 0 && front_before[i] < 148 && front >= 148) ++red_crossings;
                    if (front > 200 && past_light[i] == INFINITY) past_light[i] = s.time();
                    front_before[i] = front;
                }
            }
            const auto r = s.finish();
            CHECK(red_crossings == 0);
            for (const auto& e : r.events) {
                CAPTURE(e.time);
                CHECK(e.kind != "collision");
                // Braking for the light (the stop at the goal is not this test's business).
                if (e.kind == "fallback") CHECK((e.time < green || e.time > past_light.at(static_cast<size_t>(e.vehicles.at(0)))));
            }
            CHECK(r.vehicles.at(0).reached_goal);
            CHECK(r.vehicles.at(1).reached_goal);
        }
    }
}

}  // namespace red_light_test
