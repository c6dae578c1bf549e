// The all-way stop, in whole runs at several traffic and planning rates (sdv's 30 / 3 Hz, the
// reference's 40 / 5 Hz, and others), pinned by properties over every tick rather than by one
// scenario's numbers: every vehicle comes to rest at its stop line before it enters the
// junction; no two vehicles are in the junction at once; they enter in the order they came to
// rest (first come, first served); and every one gets through to its goal (no stall, no crawl).
// Before the stop rule kept the plan in force at the stop point, at 5 Hz the four vehicles
// crept over their lines for 20 s and entered together.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"
#include "tests/unit/io/compile_text.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace all_way_stop_test {

using namespace sdv;

namespace {

// The reference's all-way-stop handling (its handle_intersection.btree): while moving, stop at
// the line; at rest, hold while the junction is occupied or it is not this vehicle's turn.
const char* kTrees = R"(
import "std/drive.sdv"
import "std/junction.sdv"
tree aws(speed: speed = 10 m/s, after: time = 0 s, chance: number = 0) {
    fallback {
        sequence {
            condition intersection_type(type = all_way_stop)
            fallback {
                sequence {
                    condition vehicle_moving(min_speed = 0.05 m/s)
                    maneuver stop(at = stop_line)
                }
                sequence {
                    condition intersection_occupied()
                    maneuver stop(at = stop_line)
                }
                sequence {
                    not condition all_way_stop_turn(impatient_after = after, impatient_chance = chance)
                    maneuver stop(at = stop_line)
                }
            }
        }
        subtree std.drive(speed = speed)
    }
}
)";

std::string scenario(double traffic, double planning, const std::string& arrivals) {
    return std::string(kTrees) + R"(
junction x {
    lanes 1
    arm_length 100 m
    control stop_signs
}
scenario aws {
    road x
    timeout 60 s
    rate traffic )" + std::to_string(traffic) + R"( Hz
    rate planning )" + std::to_string(planning) + R"( Hz
)" + arrivals + R"(
    expect no_collision()
}
)";
}

// Four vehicles, one per arm, going straight; `starts` are their distances along the approach.
// `tree` is the aws tree's call.
std::string four(double s, double n, double e, double w, const std::string& tree = "aws()") {
    auto car = [&](const std::string& name, const std::string& from, const std::string& to, double at) {
        return "    vehicle " + name + ": sdv { start lane " + from + ".in at " + std::to_string(at) + " m  speed 8 m/s  goal lane " + to +
               ".out at 60 m  tree " + tree + " }\n";
    };
    return car("s", "south", "north", s) + car("n", "north", "south", n) + car("e", "east", "west", e) + car("w", "west", "east", w);
}

}  // namespace

TEST_CASE("all-way stop: rest at the line, one at a time, first come first served, everyone through, at every rate") {
    struct Rates {
        double traffic, planning;
    };
    for (Rates r : {Rates{30, 3}, Rates{40, 5}, Rates{20, 2}, Rates{60, 10}, Rates{30, 5}}) {
        for (const auto& arrivals : {four(40, 40, 40, 40), four(40, 30, 20, 10), four(10, 45, 30, 45)}) {
            CAPTURE(r.traffic);
            CAPTURE(r.planning);
            CAPTURE(arrivals);
            auto p = test::compile_text(scenario(r.traffic, r.planning, arrivals));
            REQUIRE(p);
            sim::Simulation sim(*p, 0, {});
            REQUIRE(sim.start().empty());
            const sim::World& w = sim.world();
            const size_t n = w.agents.size();
            std::vector<road::LaneId> last(n, road::kNoLane);
            std::vector<double> rested(n, -1), entered(n, -1);
            while (sim.step()) {
                int inside = 0;
                for (size_t i = 0; i < n; ++i) {
                    const sim::Agent& a = w.agents[i];
                    if (!a.active || a.lane == road::kNoLane) continue;
                    const auto& lane = w.net.lane(a.lane);
                    inside += lane.in_junction;
                    if (lane.in_junction && entered[i] < 0) {
                        entered[i] = sim.time();
                        // It came to rest at the stop line of the lane it comes from.
                        CHECK_MESSAGE(a.stopped_line == last[i], a.v->name << " entered without stopping at its line");
                        CHECK(a.stopped_gap <= 5.0);
                    }
                    if (!lane.in_junction) last[i] = a.lane;
                    if (a.stopped_line != road::kNoLane && rested[i] < 0 && entered[i] < 0 && a.stopped_since >= 0) rested[i] = a.stopped_since;
                }
                CHECK_MESSAGE(inside <= 1, "two vehicles in the junction at " << sim.time() << " s");
            }
            const auto result = sim.finish();
            for (size_t i = 0; i < n; ++i) {
                CHECK_MESSAGE(entered[i] >= 0, w.agents[i].v->name << " never entered the junction");
                bool goal = false;
                for (const auto& e : result.events) goal = goal || (e.kind == "goal_reached" && e.vehicles.front() == static_cast<int>(i));
                CHECK_MESSAGE(goal, w.agents[i].v->name << " did not reach its goal in 60 s");
            }
            // First come, first served: whoever came to rest at its line earlier entered earlier.
            for (size_t i = 0; i < n; ++i) {
                for (size_t j = 0; j < n; ++j) {
                    if (rested[i] >= 0 && rested[j] >= 0 && rested[i] + 0.5 < rested[j]) {
                        CHECK_MESSAGE(entered[i] < entered[j], w.agents[i].v->name << " rested at " << rested[i] << " s, "
                                                                                   << w.agents[j].v->name << " at " << rested[j]
                                                                                   << " s, but entered after it");
                    }
                }
            }
        }
    }
}

TEST_CASE("impatient drivers at an all-way stop: out of turn at times, never two in the junction, reproducibly") {
    // After 1 s at the line, a coin per planning cycle: some go out of turn, but only into an
    // empty junction while nobody pulls away; the same seed gives the same order.
    const std::string arrivals = four(40, 38, 36, 34, "aws(after = 1 s, chance = 0.5)");
    auto p = test::compile_text(scenario(40, 5, arrivals));
    REQUIRE(p);
    std::vector<std::vector<double>> runs;
    for (int run = 0; run < 2; ++run) {
        sim::Simulation sim(*p, 0, {});
        REQUIRE(sim.start().empty());
        const sim::World& w = sim.world();
        std::vector<double> entered(w.agents.size(), -1);
        while (sim.step()) {
            int inside = 0;
            for (size_t i = 0; i < w.agents.size(); ++i) {
                const sim::Agent& a = w.agents[i];
                if (!a.active || a.lane == road::kNoLane || !w.net.lane(a.lane).in_junction) continue;
                ++inside;
                if (entered[i] < 0) entered[i] = sim.time();
            }
            CHECK_MESSAGE(inside <= 1, "two vehicles in the junction at " << sim.time() << " s");
        }
        for (double e : entered) CHECK(e >= 0);
        runs.push_back(entered);
    }
    CHECK(runs[0] == runs[1]);
}

}  // namespace all_way_stop_test
