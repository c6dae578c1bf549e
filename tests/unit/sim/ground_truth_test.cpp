// Ground truth's least clearance of a pair: computed lazily (a tick at which the pair closes in
// waits until a later one rules it out), it is still exactly the least over every tick of the
// box distance, for the run and for every window.
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "runtime/sim/collision.h"
#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"
#include "tests/unit/io/compile_text.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace ground_truth_test {

using namespace sdv;

namespace {

sim::Box box(const sim::Agent& a) { return {{a.x, a.y}, a.yaw, a.v->length, a.v->width}; }

}  // namespace

TEST_CASE("a pair's least clearance is the least box distance over every tick, in the run and in each window") {
    // An SDV passing a pedestrian on the kerb and one crossing ahead of it, a van driving the
    // other way past all three; the pairs an expectation names are measured at every tick.
    const std::string text = R"(
import "std/drive.sdv"
import "std/pedestrian.sdv"
road main {
    lanes 1 forward, 1 backward
    straight 300 m
    crosswalk zebra at 150 m width 4 m
}
scenario s {
    road main
    timeout 30 s
    vehicle car: sdv { start lane 1 at 10 m speed 12 m/s goal lane 1 at 280 m tree std.drive(speed = 12 m/s) }
    vehicle van: trajectory { trajectory { 0 s: lane -1 at 290 m   25 s: lane -1 at 20 m } }
    pedestrian kerb: sdp { start at (120 m, -5 m) goal at (126 m, -5 m) speed 1.2 m/s tree std.walk(speed = 1.2 m/s) }
    pedestrian crosser: sdp { start at (150 m, -8 m) goal at (151 m, 8 m) speed 1.4 m/s tree std.walk(speed = 1.4 m/s) }
    expect min_clearance(car, kerb) > 0.1 m
    expect min_clearance(car, crosser) > 0.1 m during 5 s .. 15 s
    expect min_clearance(car, van) > 0.1 m after 8 s
    expect min_clearance(van, crosser) > 0.1 m before 12 s
    expect min_clearance(kerb, crosser) > 0.1 m during 0 s .. 30 s
}
)";
    auto p = test::compile_text(text);
    REQUIRE(p);
    sim::Simulation s(*p, 0, {});
    REQUIRE(s.start().empty());
    // The least box distance per pair (a < b) over the run and over each window's ticks.
    const std::vector<std::pair<double, double>> windows = {{-INFINITY, INFINITY}, {5, 15}, {8, INFINITY}, {-INFINITY, 12}, {0, 30}};
    std::map<std::pair<std::pair<int, int>, size_t>, double> least;
    auto observe = [&] {
        const sim::World& w = s.world();
        const double t = s.time();
        for (size_t i = 0; i < w.agents.size(); ++i) {
            for (size_t j = i + 1; j < w.agents.size(); ++j) {
                const double g = sim::gap(box(w.agents[i]), box(w.agents[j]));
                for (size_t k = 0; k < windows.size(); ++k) {
                    if (t < windows[k].first - 1e-9 || t > windows[k].second + 1e-9) continue;
                    auto [it, fresh] = least.try_emplace({{static_cast<int>(i), static_cast<int>(j)}, k}, g);
                    if (!fresh) it->second = std::min(it->second, g);
                }
            }
        }
    };
    observe();
    while (s.step()) observe();
    const sim::RunResult r = s.finish();
    REQUIRE(r.error.empty());
    auto check = [&](const std::vector<sim::PairMetrics>& pairs, size_t k) {
        for (const auto& m : pairs) {
            if (!std::isfinite(m.min_clearance)) continue;  // a pair named only in other windows
            CAPTURE(m.a);
            CAPTURE(m.b);
            CAPTURE(k);
            CHECK(m.min_clearance == least.at({{m.a, m.b}, k}));
        }
    };
    // Every pair of this small scene is within the pair range at every tick: the run measures
    // them all.
    CHECK(r.pairs.size() == 6);
    check(r.pairs, 0);
    for (const auto& win : r.windows) {
        for (size_t k = 1; k < windows.size(); ++k) {
            if (win.after == windows[k].first && win.before == windows[k].second) check(win.pairs, k);
        }
    }
    CHECK(r.windows.size() == 4);
}

}  // namespace ground_truth_test
