// The time_to_arrival condition (issue "drivers that behave like drivers"): for the driver itself
// and for another vehicle, to the junction and to a stop line, it turns true when distance over
// speed falls to its bound: the branch it guards takes over within one planning period of that
// moment, for several speeds and bounds.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/unit/io/compile_text.h"
#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace time_to_arrival_test {

using namespace sdv;

namespace {

// The first tick at which vehicle 0 runs its `near` branch, and the observed vehicle's distance
// from its front bumper to the end of its approach lane and its speed then.
struct Watch : sim::RunObserver {
    int observed = 0;
    double dist = NAN, speed = NAN, time = NAN;
    bool to_stop_line = false;
    void tick(const sim::World& w, int, double t) override {
        const sim::Agent& a = w.agents[0];
        if (!std::isnan(time) || a.driver->maneuver_name != "near") return;
        const sim::Agent& o = w.agents[static_cast<size_t>(observed)];
        const auto& ln = w.net.lane(o.lane);
        const double end = to_stop_line && !ln.stop_lines.empty() ? ln.stop_lines.front().s : ln.length;
        dist = end - o.lane_s - 0.5 * o.v->length;
        speed = o.speed;
        time = t;
    }
};

std::string scenario(const std::string& control, const std::string& condition, double v_self, double v_other) {
    return R"(junction crossing {
    lanes 1
    speed_limit 50 km/h
    arm_length 150 m
    control )" + control + R"(
}
tree watcher() {
    fallback {
        sequence {
            condition )" + condition + R"(
            near: maneuver keep_velocity(speed = )" + std::to_string(v_self) + R"( m/s)
        }
        far: maneuver keep_velocity(speed = )" + std::to_string(v_self) + R"( m/s)
    }
}
tree cruise() {
    keep: maneuver keep_velocity(speed = )" + std::to_string(v_other) + R"( m/s)
}
scenario s {
    road crossing
    timeout 14 s
    rate sensor_range 400 m
    ego watcher: sdv {
        start lane south.in at 10 m
        speed )" + std::to_string(v_self) + R"( m/s
        tree watcher()
    }
    vehicle crosser: sdv {
        start lane east.in at 10 m
        speed )" + std::to_string(v_other) + R"( m/s
        tree cruise()
    }
}
)";
}

}  // namespace

TEST_CASE("time_to_arrival turns true when distance over speed reaches its bound") {
    struct Case {
        const char* control;
        const char* condition;
        int observed;
        bool stop_line;
        double v_self, v_other, bound;
    };
    const Case cases[] = {
        {"none", "time_to_arrival(max = 5 s)", 0, false, 10, 8, 5},
        {"none", "time_to_arrival(max = 3 s)", 0, false, 14, 8, 3},
        {"none", "time_to_arrival(vehicle = crosser, max = 6 s)", 1, false, 9, 12, 6},
        {"none", "time_to_arrival(vehicle = crosser, max = 9 s)", 1, false, 9, 11, 9},
        {"stop_signs", "time_to_arrival(at = stop_line, max = 4 s)", 0, true, 12, 8, 4},
    };
    for (const Case& c : cases) {
        CAPTURE(c.condition);
        CAPTURE(c.v_self);
        auto program = test::compile_text(scenario(c.control, c.condition, c.v_self, c.v_other));
        REQUIRE(program);
        Watch watch;
        watch.observed = c.observed;
        watch.to_stop_line = c.stop_line;
        const auto result = sim::simulate(*program, 0, {}, &watch);
        REQUIRE(result.error.empty());
        REQUIRE(!std::isnan(watch.time));
        CAPTURE(watch.time);
        CAPTURE(watch.dist);
        // The condition sees the state one latency (1/3 s) after the tick it is planned at, and
        // is checked once per planning period (1/3 s).
        const double t_arrive = watch.dist / watch.speed;
        CHECK(t_arrive <= c.bound + 0.34 + 0.05);
        CHECK(t_arrive >= c.bound - 0.34 - 0.05);
    }
}

TEST_CASE("a vehicle standing still never arrives: it passes a min bound, never a max bound") {
    for (const char* cond : {"time_to_arrival(vehicle = crosser, min = 4 s)", "time_to_arrival(vehicle = crosser, max = 1000 s)"}) {
        CAPTURE(cond);
        auto program = test::compile_text(scenario("none", cond, 8, 0));
        REQUIRE(program);
        Watch watch;
        watch.observed = 1;
        sim::simulate(*program, 0, {}, &watch);
        const bool min_bound = std::string(cond).find("min") != std::string::npos;
        CHECK(std::isnan(watch.time) != min_bound);
    }
}

// Which branch vehicle 0 runs at the last tick.
struct Last : sim::RunObserver {
    std::string maneuver;
    void tick(const sim::World& w, int, double) override { maneuver = w.agents[0].driver->maneuver_name; }
};

TEST_CASE("latch keeps a condition true once it was: past the junction, time_to_arrival is false again") {
    for (const bool latched : {false, true}) {
        CAPTURE(latched);
        std::string text = scenario("none", std::string(latched ? "latch condition " : "") + "time_to_arrival(max = 5 s)", 12, 8);
        // scenario() writes `condition <text>`: make the decorator wrap the condition.
        const auto at = text.find("condition latch condition");
        if (latched) {
            REQUIRE(at != std::string::npos);
            text.replace(at, std::string("condition latch condition").size(), "latch condition");
        }
        auto program = test::compile_text(text);
        REQUIRE(program);
        Last last;
        sim::simulate(*program, 0, {}, &last);
        CHECK(last.maneuver == (latched ? "near" : "far"));
    }
}

}  // namespace time_to_arrival_test
