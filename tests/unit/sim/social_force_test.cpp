// Properties of the pedestrian social force model, each over a family of cases: free walking and
// arrival, stopping, passing other pedestrians, keeping clear of standing and moving cars, and
// finite results for arbitrary finite input. Every loop is bounded by a step count.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "runtime/sim/social_force.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace social_force_test {

namespace sf = sdv::sim::social_force;
using sdv::road::Vec2;

namespace {

constexpr double kDt = 1.0 / 30.0;
constexpr int kHz = 30;
const sf::Params kP{};
const double kR = kP.body_radius;

struct Walker {
    sf::State s;
    Vec2 target;
    double speed;
};

Vec2 unit(double angle) { return {std::cos(angle), std::sin(angle)}; }

// A car moving at constant velocity (zero for a parked one).
sf::Obstacle car_at(const sf::Obstacle& car0, double t) {
    sf::Obstacle c = car0;
    c.centre = car0.centre + t * car0.v;
    return c;
}

// A small lockstep world: every walker's force from one snapshot, then all step.
class Crowd {
public:
    explicit Crowd(std::vector<Walker> w, std::vector<sf::Obstacle> cars = {})
        : walkers_(std::move(w)), cars0_(std::move(cars)) {}

    void tick() {
        const std::vector<sf::Obstacle> cars = cars_now();
        std::vector<sf::State> next;
        for (std::size_t i = 0; i < walkers_.size(); ++i) {
            std::vector<sf::Neighbour> others;
            for (std::size_t j = 0; j < walkers_.size(); ++j)
                if (j != i) others.push_back({walkers_[j].s.p, walkers_[j].s.v, kR});
            const Walker& w = walkers_[i];
            const Vec2 f = sf::force(kP, w.s, kR, w.target, w.speed, others, cars);
            next.push_back(sf::step(kP, w.s, f, w.speed, kDt));
        }
        for (std::size_t i = 0; i < walkers_.size(); ++i) walkers_[i].s = next[i];
        t_ += kDt;
    }

    const Walker& operator[](std::size_t i) const { return walkers_[i]; }
    double time() const { return t_; }
    std::vector<sf::Obstacle> cars_now() const {
        std::vector<sf::Obstacle> cars;
        for (const auto& c : cars0_) cars.push_back(car_at(c, t_));
        return cars;
    }

private:
    std::vector<Walker> walkers_;
    std::vector<sf::Obstacle> cars0_;
    double t_ = 0;
};

bool finite(Vec2 a) { return std::isfinite(a.x) && std::isfinite(a.y); }

}  // namespace

TEST_CASE("free walk: reaches the desired speed in a few tau, straight to the target, then stands") {
    for (double v0 : {0.5, 1.0, 1.4, 2.0, 2.5}) {
        for (int k = 0; k < 8; ++k) {
            CAPTURE(v0);
            CAPTURE(k);
            const Vec2 start{3.0, -2.0};
            const Vec2 dir = unit(k * std::numbers::pi / 4 + 0.1);
            const Vec2 target = start + 25.0 * dir;
            Crowd crowd({{{start, {}}, target, v0}});

            double max_offtrack = 0, max_along = 0, max_speed = 0;
            const int steps_4tau = static_cast<int>(4 * kP.relaxation_time * kHz);
            for (int i = 0; i < 60 * kHz; ++i) {
                crowd.tick();
                const Vec2 rel = crowd[0].s.p - start;
                max_offtrack = std::max(max_offtrack, std::abs(cross(dir, rel)));
                max_along = std::max(max_along, dot(dir, rel));
                max_speed = std::max(max_speed, norm(crowd[0].s.v));
                if (i + 1 == steps_4tau) CHECK(norm(crowd[0].s.v) == doctest::Approx(v0).epsilon(0.03));
            }
            CHECK(max_speed <= v0 * 1.001);
            CHECK(max_offtrack < 1e-6);
            CHECK(max_along < 25.0 + 0.05);  // no overshoot past the target
            CHECK(distance(crowd[0].s.p, target) < 0.3);
            for (int i = 0; i < 5 * kHz; ++i) {
                crowd.tick();
                CHECK(norm(crowd[0].s.v) < 0.05);
                CHECK(distance(crowd[0].s.p, target) < 0.3);
            }
        }
    }
}

TEST_CASE("desired speed 0: a walker comes to rest within about v*tau") {
    for (double v : {0.5, 1.4, 2.5}) {
        for (int k = 0; k < 6; ++k) {
            CAPTURE(v);
            CAPTURE(k);
            const Vec2 dir = unit(k * 1.1);
            // The target stays ahead: speed 0 alone must stop the walker.
            Crowd crowd({{{{0, 0}, v * dir}, 100.0 * dir, 0.0}});
            for (int i = 0; i < 5 * kHz; ++i) crowd.tick();
            CHECK(norm(crowd[0].s.v) < 0.01);
            CHECK(norm(crowd[0].s.p) <= v * kP.relaxation_time + 0.05);
        }
    }
}

namespace {

// Bodies may touch by this much: the reference's 0.08 m body range lets two runners meeting
// head-on at 2.5 m/s each press 2 cm into each other before they part.
constexpr double kTouch = 0.03;

// Runs two walkers for 40 s; returns the smallest centre distance seen.
double pass(Crowd& crowd) {
    double closest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 40 * kHz; ++i) {
        crowd.tick();
        closest = std::min(closest, distance(crowd[0].s.p, crowd[1].s.p));
    }
    return closest;
}

}  // namespace

TEST_CASE("two pedestrians head-on, slightly offset, pass without touching and arrive") {
    for (double v0 : {1.0, 1.4, 2.0, 2.5}) {
        for (double offset : {0.0, 0.05, 0.15, 0.3, 0.5, -0.2}) {
            CAPTURE(v0);
            CAPTURE(offset);
            Crowd crowd({{{{-10, 0}, {}}, {10, 0}, v0}, {{{10, offset}, {}}, {-10, offset}, v0}});
            CHECK(pass(crowd) >= 2 * kR - kTouch);
            CHECK(distance(crowd[0].s.p, crowd[0].target) < 0.3);
            CHECK(distance(crowd[1].s.p, crowd[1].target) < 0.3);
        }
    }
}

TEST_CASE("two pedestrians crossing at 90 degrees keep apart and arrive") {
    for (double v0 : {1.0, 1.4, 2.0}) {
        for (double lead : {-0.6, -0.3, 0.0, 0.2, 0.5}) {  // head start of the second walker [m]
            CAPTURE(v0);
            CAPTURE(lead);
            Crowd crowd({{{{-10, 0}, {}}, {10, 0}, v0}, {{{0, -10 + lead}, {}}, {0, 10}, v0}});
            CHECK(pass(crowd) >= 2 * kR - kTouch);
            CHECK(distance(crowd[0].s.p, crowd[0].target) < 0.3);
            CHECK(distance(crowd[1].s.p, crowd[1].target) < 0.3);
        }
    }
}

TEST_CASE("a parked car between a pedestrian and its target is never entered, only walked round") {
    for (double yaw : {0.0, 0.4, 0.8, std::numbers::pi / 2, 2.0, 2.5, 3.0}) {
        for (double lateral : {0.0, 0.2, 1.0, 2.0, -1.5}) {
            for (double v0 : {1.0, 1.4, 2.5}) {
                CAPTURE(yaw);
                CAPTURE(lateral);
                CAPTURE(v0);
                const sf::Obstacle car{{0, 0}, yaw, 4.5, 1.8, {}};
                Crowd crowd({{{{lateral, -8}, {}}, {lateral, 8}, v0}}, {car});
                double closest = std::numeric_limits<double>::infinity();
                for (int i = 0; i < 40 * kHz; ++i) {
                    crowd.tick();
                    closest = std::min(closest, sf::box_contact(car, crowd[0].s.p).distance);
                }
                CHECK(closest >= kR);  // the disc, not just its centre, stays out
                CHECK(distance(crowd[0].s.p, crowd[0].target) < 0.3);
            }
        }
    }
}

namespace {

// Smallest gap between a walker's disc and the moving car over 20 s.
double car_gap(Crowd& crowd) {
    double closest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 20 * kHz; ++i) {
        crowd.tick();
        closest = std::min(closest, sf::box_contact(crowd.cars_now()[0], crowd[0].s.p).distance - kR);
    }
    return closest;
}

}  // namespace

TEST_CASE("a car driving across the pedestrian's way: no overlap") {
    // The walker goes from y = -6 to y = 6 across a lane along x; the car's timing is chosen so
    // that it is passing x = 0 when the walker would reach it, so walking blindly would hit it.
    for (double u : {3.0, 5.0, 8.0}) {
        for (double frac : {0.1, 0.5, 0.9}) {
            for (double v0 : {1.0, 1.4, 2.0}) {
                CAPTURE(u);
                CAPTURE(frac);
                CAPTURE(v0);
                const double reach = (6.0 - 0.9 - kR) / v0 + kP.relaxation_time;  // walker at lane edge
                const double front_at_0 = reach - frac * 4.5 / u;                 // car front at x = 0
                const double x0 = -u * front_at_0 - 2.25;
                const sf::Obstacle car{{x0, 0}, 0.0, 4.5, 1.8, {u, 0}};
                const Walker w{{{0, -6}, {}}, {0, 6}, v0};

                Crowd blind({w});
                double blind_gap = std::numeric_limits<double>::infinity();
                for (int i = 0; i < 20 * kHz; ++i) {  // the same walk, not seeing the car
                    blind.tick();
                    const sf::Obstacle c = car_at(car, blind.time());
                    blind_gap = std::min(blind_gap, sf::box_contact(c, blind[0].s.p).distance - kR);
                }
                REQUIRE(blind_gap < 0);  // the scenario is a real conflict

                Crowd crowd({w}, {car});
                CHECK(car_gap(crowd) >= 0.0);  // the disc never touches the car
                CHECK(distance(crowd[0].s.p, crowd[0].target) < 0.3);
            }
        }
    }
}

TEST_CASE("robustness: random finite input gives finite, capped results, deterministically") {
    std::mt19937_64 rng(20240611);
    std::uniform_real_distribution<double> unit01(0.0, 1.0);
    std::uniform_int_distribution<int> pick(0, 9);
    const double huge = std::numeric_limits<double>::max();
    // Mostly ordinary magnitudes, sometimes zero, tiny, huge or the largest double.
    auto scalar = [&] {
        switch (pick(rng)) {
            case 0: return 0.0;
            case 1: return (unit01(rng) - 0.5) * 1e-300;
            case 2: return (unit01(rng) - 0.5) * 1e12;
            case 3: return unit01(rng) < 0.5 ? huge : -huge;
            default: return (unit01(rng) - 0.5) * 40.0;
        }
    };
    auto vec = [&] { return Vec2{scalar(), scalar()}; };

    for (int n = 0; n < 10000; ++n) {
        CAPTURE(n);
        sf::Params p{};
        if (n % 7 == 0) {  // degenerate parameters too
            p.ped_range = p.obstacle_range = p.evade_side_range = 0.0;
            p.relaxation_time = p.arrival_time = 0.0;
            p.mass = 0.0;
        }
        const sf::State s{vec(), vec()};
        std::vector<sf::Neighbour> peds;
        std::vector<sf::Obstacle> cars;
        for (int i = pick(rng) % 4; i > 0; --i)
            peds.push_back({pick(rng) < 3 ? s.p : vec(), pick(rng) < 3 ? s.v : vec(), std::abs(scalar())});
        for (int i = pick(rng) % 3; i > 0; --i)
            cars.push_back({pick(rng) < 3 ? s.p : vec(), scalar(), scalar(), scalar(), vec()});
        const Vec2 target = pick(rng) < 3 ? s.p : vec();
        const double radius = std::abs(scalar()), v0 = scalar(), dt = pick(rng) < 8 ? kDt : scalar();

        const Vec2 f = sf::force(p, s, radius, target, v0, peds, cars);
        REQUIRE(finite(f));
        const sf::State next = sf::step(p, s, f, v0, dt);
        REQUIRE(finite(next.p));
        REQUIRE(finite(next.v));
        CHECK(norm(next.v) <= sf::speed_cap(p, v0) * (1 + 1e-12));
        const Vec2 again = sf::force(p, s, radius, target, v0, peds, cars);
        CHECK((again.x == f.x && again.y == f.y));
    }
}

TEST_CASE("box contact: signed distance to the outline, normal pointing out") {
    const sf::Obstacle car{{1, 2}, std::numbers::pi / 2, 4.0, 2.0, {}};  // along y, 2 m wide
    CHECK(sf::box_contact(car, {1, 2 + 3}).distance == doctest::Approx(1.0));
    CHECK(sf::box_contact(car, {1 + 3, 2}).distance == doctest::Approx(2.0));
    const auto inside = sf::box_contact(car, {1.8, 2});
    CHECK(inside.distance == doctest::Approx(-0.2));
    CHECK(inside.normal.x == doctest::Approx(1.0));
    const auto centre = sf::box_contact(car, {1, 2});
    CHECK(centre.distance == doctest::Approx(-1.0));
    CHECK(norm(centre.normal) == doctest::Approx(1.0));
}

}  // namespace social_force_test
