// Two drivers changing into the same lane at the same time (issue "drivers that behave like
// drivers", finding 6): the one farther from the target lane (the later one; on a tie the
// higher vehicle index) aborts back to its own lane; the other completes; nobody collides,
// brakes for want of a plan or stalls, whichever starts first, at whatever speeds, on straight
// and curved roads.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/unit/io/compile_text.h"
#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace lane_change_conflict_test {

using namespace sdv;

namespace {

struct Lanes : sim::RunObserver {
    std::vector<std::string> final_lane{"", ""};
    std::vector<double> first_in_middle{INFINITY, INFINITY};
    void tick(const sim::World& w, int, double t) override {
        for (size_t i = 0; i < 2; ++i) {
            final_lane[i] = w.net.lane(w.agents[i].lane).name;
            if (final_lane[i] == "r.2" && std::isinf(first_in_middle[i])) first_in_middle[i] = t;
        }
    }
};

std::string scenario(const std::string& shape, double t_a, double t_b, double v_a, double v_b, double s_b) {
    auto num = [](double x) { return std::to_string(x); };
    return R"(import "std/drive.sdv"
road r {
    lanes 3 forward
    lane_width 3.5 m
    speed_limit 110 km/h
    )" + shape + R"(
}
# Once, after `t`, change lanes when the target lane looks free; cruise otherwise.
tree change_at(t: time = 3 s, side: lane = left, speed: speed = 20 m/s) {
    fallback {
        once sequence {
            condition sim_time(after = t)
            condition can_lane_change(lane = side, gap = 5 m)
            change: maneuver lane_change(lane = side)
        }
        subtree std.cruise(speed = speed)
    }
}
scenario s {
    road r
    timeout 20 s
    vehicle a: sdv {
        start lane 1 at 50 m
        speed )" + num(v_a) + R"( m/s
        tree change_at(t = )" + num(t_a) + R"( s, side = left, speed = )" + num(v_a) + R"( m/s)
    }
    vehicle b: sdv {
        start lane 3 at )" + num(s_b) + R"( m
        speed )" + num(v_b) + R"( m/s
        tree change_at(t = )" + num(t_b) + R"( s, side = right, speed = )" + num(v_b) + R"( m/s)
    }
    expect no_collision()
}
)";
}

}  // namespace

TEST_CASE("simultaneous lane changes into one lane: one completes, the other aborts back") {
    struct Case {
        double t_a, t_b, v_a, v_b, s_b;
        int winner;  // 0: a, 1: b
    };
    const Case cases[] = {
        {3.0, 3.0, 20, 20, 50, 0},  // a tie: the lower index goes
        {3.0, 3.4, 20, 20, 50, 0},  // b starts later
        {3.4, 3.0, 20, 20, 50, 1},  // a starts later
        {3.0, 3.2, 20, 21, 46, 0},  // b slightly faster, just behind
        {3.3, 3.0, 22, 20, 54, 1},  // a faster, just behind
    };
    // On a straight and on arcs either way (the lanes then differ in length).
    for (const char* shape : {"straight 900 m", "arc 700 m radius 250 m left", "arc 700 m radius 300 m right"}) {
        for (const Case& c : cases) {
            CAPTURE(shape);
            CAPTURE(c.t_a);
            CAPTURE(c.t_b);
            CAPTURE(c.v_b);
            auto program = test::compile_text(scenario(shape, c.t_a, c.t_b, c.v_a, c.v_b, c.s_b));
            REQUIRE(program);
            Lanes lanes;
            const auto result = sim::simulate(*program, 0, {}, &lanes);
            REQUIRE(result.error.empty());
            CHECK(result.passed());  // no collision
            const auto w = static_cast<size_t>(c.winner), l = 1 - w;
            // The winner is in the middle lane first; the other was not in it while they were beside.
            CHECK(std::isfinite(lanes.first_in_middle[w]));
            CHECK(lanes.first_in_middle[w] < lanes.first_in_middle[l]);
            for (size_t i = 0; i < 2; ++i) {
                CHECK(result.vehicles[i].fallback_plans == 0);
                CHECK(result.vehicles[i].min_speed > 15);
            }
        }
    }
}

}  // namespace lane_change_conflict_test
