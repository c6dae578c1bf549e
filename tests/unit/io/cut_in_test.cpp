// cut_in ends in its end state (issue "drivers that behave like drivers", finding 5): it stays
// the selected maneuver after the vehicle has entered the target lane until the bumper gap to
// the target and the relative speed are those asked for, then it succeeds; it moves exactly one
// lane (a cut-in to the right from the leftmost of three lanes ends in the middle one); and
// `gap` means the bumper gap, with no hidden vehicle lengths.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/unit/io/compile_text.h"
#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace cut_in_test {

using namespace sdv;

namespace {

// Per tick: v2's maneuver and lane, and the bumper gap and relative speed to the ego.
struct Watch : sim::RunObserver {
    struct Row {
        double t;
        std::string maneuver, lane, ego_lane;
        double gap, dv;
    };
    std::vector<Row> rows;
    void tick(const sim::World& w, int, double t) override {
        const sim::Agent& ego = w.agents[0];
        const sim::Agent& v2 = w.agents[1];
        const double gap = v2.lane_s - ego.lane_s - 0.5 * (ego.v->length + v2.v->length);
        rows.push_back({t, v2.driver->maneuver_name, w.net.lane(v2.lane).name, w.net.lane(ego.lane).name, gap, v2.speed - ego.speed});
    }
};

std::string scenario(double gap, double dv) {
    return R"(import "std/drive.sdv"
import "std/lane_change.sdv"
road r {
    lanes 3 forward
    lane_width 3.5 m
    speed_limit 90 km/h
    straight 1500 m
}
tree cutter() {
    fallback {
        subtree std.cut_in(target = ego, lane = right, accept_gap = 5 m, gap = )" +
           std::to_string(gap) + " m, dv = " + std::to_string(dv) + R"( m/s)
        subtree std.cruise(speed = 24 m/s)
    }
}
scenario s {
    road r
    timeout 40 s
    ego ego: sdv {
        start lane 2 at 60 m
        speed 18 m/s
        tree std.cruise(speed = 18 m/s)
    }
    vehicle v2: sdv {
        start lane 3 at 20 m
        speed 22 m/s
        tree cutter()
    }
}
)";
}

}  // namespace

TEST_CASE("cut_in runs until its end state: the asked bumper gap and relative speed, one lane over") {
    struct Case {
        double gap, dv;
    };
    for (const Case c : {Case{10, -3}, Case{20, 1}, Case{18, 0}, Case{15, -2}}) {
        CAPTURE(c.gap);
        CAPTURE(c.dv);
        auto program = test::compile_text(scenario(c.gap, c.dv));
        REQUIRE(program);
        Watch watch;
        const auto result = sim::simulate(*program, 0, {}, &watch);
        REQUIRE(result.error.empty());
        // The cut-in happened, into the ego's lane and no farther.
        bool entered = false, ended = false;
        std::string last;
        for (size_t i = 0; i < watch.rows.size(); ++i) {
            const auto& r = watch.rows[i];
            CHECK(r.lane != "r.1");
            if (r.maneuver == "cut" && r.lane == r.ego_lane) entered = true;
            // The tick the cut-in hands over: it is in the ego's lane, in its end state.
            if (last == "cut" && r.maneuver != "cut" && !ended) {
                ended = true;
                CAPTURE(r.t);
                CHECK(r.lane == r.ego_lane);
                CHECK(std::fabs(r.gap - c.gap) <= std::max(2.0, 0.2 * c.gap) + 0.5);
                CHECK(std::fabs(r.dv - c.dv) <= 1.1);
            }
            last = r.maneuver;
        }
        CHECK(entered);
        CHECK(ended);
        CHECK(result.vehicles[1].fallback_plans == 0);
    }
}

}  // namespace cut_in_test
