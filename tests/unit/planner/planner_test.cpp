// The planner against analytic results and constructed scenes.
#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "runtime/planner/planner.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace planner_test {

using namespace sdv::planner;

namespace {

double jerk_energy(const Poly& p, double T, const std::function<double(double)>& extra = nullptr) {
    const int n = 2000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const double t = (i + 0.5) * T / n;
        const double j = p.j(t) + (extra ? extra(t) : 0.0);
        sum += j * j * T / n;
    }
    return sum;
}

PlanResult run(const ManeuverConfig& cfg, PlanRequest req, std::vector<Obstacle> obs = {}) {
    req.config = &cfg;
    req.obstacles = obs;
    static PlanWorkspace ws;
    ws.keep_candidates = true;
    return plan(req, ws);
}

LaneBand lane_at(double center) { return {center, center + 1.75, center - 1.75}; }

}  // namespace

TEST_CASE("quintic meets its boundary conditions") {
    const Poly p = Poly::quintic(1, 2, 0.5, 40, 8, -1, 4);
    CHECK(p.x(0) == doctest::Approx(1));
    CHECK(p.v(0) == doctest::Approx(2));
    CHECK(p.a(0) == doctest::Approx(0.5));
    CHECK(p.x(4) == doctest::Approx(40));
    CHECK(p.v(4) == doctest::Approx(8));
    CHECK(p.a(4) == doctest::Approx(-1));
}

TEST_CASE("quartic meets its boundary conditions") {
    const Poly p = Poly::quartic(3, 10, 1, 14, 0, 3);
    CHECK(p.x(0) == doctest::Approx(3));
    CHECK(p.v(0) == doctest::Approx(10));
    CHECK(p.a(0) == doctest::Approx(1));
    CHECK(p.v(3) == doctest::Approx(14));
    CHECK(p.a(3) == doctest::Approx(0).epsilon(1e-12));
}

TEST_CASE("the quintic is jerk-minimal among curves with the same boundary conditions") {
    const double T = 4;
    const Poly p = Poly::quintic(0, 10, 0, 45, 12, 0, T);
    const double base = jerk_energy(p, T);
    // t³(T − t)³ has zero value, slope and curvature at both ends: adding it keeps the
    // boundary conditions; its third derivative changes the jerk.
    for (double eps : {-0.01, -0.001, 0.001, 0.01}) {
        auto bump_jerk = [&](double t) {
            // d³/dt³ of eps·t³(T−t)³
            const double u = T - t;
            return eps * (6 * u * u * u - 54 * t * u * u + 54 * t * t * u - 6 * t * t * t);
        };
        CHECK(jerk_energy(p, T, bump_jerk) > base);
    }
}

TEST_CASE("linear sampling gives the documented sets") {
    RandomStream rng(1, 0, 0);
    std::vector<double> v;
    sample(Sampled::spread(14, 10, 3), rng, v);
    REQUIRE(v.size() == 3);
    CHECK(v[0] == doctest::Approx(12.6));
    CHECK(v[1] == doctest::Approx(14));
    CHECK(v[2] == doctest::Approx(15.4));
    v.clear();
    sample(Sampled::spread(3, 20, 6), rng, v);
    REQUIRE(v.size() == 6);
    for (int i = 0; i < 6; ++i) CHECK(v[static_cast<size_t>(i)] == doctest::Approx(2.4 + 0.24 * i));
    v.clear();
    sample(Sampled::spread(1, 200, 3), rng, v);  // magnitude: lower end clipped at 0
    CHECK(v[0] == 0.0);
}

TEST_CASE("random streams are reproducible and keyed by vehicle and plan") {
    RandomStream a(7, 1, 2), b(7, 1, 2), c(7, 2, 2), d(7, 1, 3);
    const double x = a.uniform();
    CHECK(x == b.uniform());
    CHECK(x != c.uniform());
    CHECK(x != d.uniform());
    Sampled s{10, 8, 12, 50, SampleMethod::normal, 1.0};
    std::vector<double> v;
    RandomStream r(1, 1, 1);
    sample(s, r, v);
    for (double y : v) {
        CHECK(y >= 8);
        CHECK(y <= 12);
    }
}

TEST_CASE("default configurations produce the reference's candidate counts") {
    const std::vector<std::pair<ManeuverKind, int>> expected = {
        {ManeuverKind::keep_velocity, 18}, {ManeuverKind::follow, 10}, {ManeuverKind::lane_change, 6},
        {ManeuverKind::cut_in, 30},        {ManeuverKind::stop, 6},    {ManeuverKind::reverse, 18}};
    for (auto [kind, n] : expected) {
        const auto cfg = default_config(kind);
        CHECK(candidate_count(cfg) == n);
        PlanRequest req;
        req.start = {0, 10, 0, 0, 0, 0};
        req.target_lane = lane_at(3.5);
        req.stop_s = 50;
        std::vector<Obstacle> obs = {{1, {60, 10, 0, 0, 0, 0}, 4.5, 1.8, false},
                                     {2, {5, 8, 0, 3.5, 0, 0}, 4.5, 1.8, false}};
        req.leader = 0;
        req.target_vehicle = 1;
        CHECK(run(cfg, req, obs).record.candidates == n);
    }
}

TEST_CASE("each feasibility cause is triggered by a constructed case") {
    PlanRequest req;
    req.start = {0, 10, 0, 0, 0, 0};
    req.target_lane = lane_at(3.5);
    auto only = [](const PlanResult& r, RejectCause c) {
        return r.record.feasible == 0 && r.record.rejections[static_cast<size_t>(c)] == r.record.candidates;
    };
    {
        auto cfg = default_config(ManeuverKind::keep_velocity);
        cfg.common.max_long_jerk = 1e-3;
        CHECK(only(run(cfg, req), RejectCause::long_jerk));
    }
    {
        auto cfg = default_config(ManeuverKind::lane_change);
        cfg.common.max_lat_jerk = 1e-3;
        CHECK(only(run(cfg, req), RejectCause::lat_jerk));
    }
    {
        auto cfg = default_config(ManeuverKind::keep_velocity);
        cfg.speed = Sampled::single(18);
        cfg.common.max_long_acc = 0.1;
        CHECK(only(run(cfg, req), RejectCause::long_acc));
    }
    {
        auto cfg = default_config(ManeuverKind::lane_change);
        cfg.common.max_lat_acc = 0.1;
        CHECK(only(run(cfg, req), RejectCause::lat_acc));
    }
    {
        auto cfg = default_config(ManeuverKind::keep_velocity);
        CHECK(only(run(cfg, req, {{1, {15, 0, 0, 0, 0, 0}, 4.5, 1.8, true}}), RejectCause::collision));
    }
    {
        auto cfg = default_config(ManeuverKind::keep_velocity);
        cfg.common.lat_offset = Sampled::single(1.5);
        CHECK(only(run(cfg, req), RejectCause::off_lane));
    }
    {
        auto cfg = default_config(ManeuverKind::keep_velocity);
        PlanRequest back = req;
        back.start.s_d = -1;  // already rolling backwards
        CHECK(only(run(cfg, back), RejectCause::direction));
    }
}

TEST_CASE("follow settles at the time gap behind a constant-speed leader") {
    const auto cfg = default_config(ManeuverKind::follow);
    PlanRequest req;
    req.start = {0, 10, 0, 0, 0, 0};
    req.leader = 0;
    const Obstacle leader{1, {45, 10, 0, 0, 0, 0}, 4.5, 1.8, false};
    auto r = run(cfg, req, {leader});
    REQUIRE(!r.record.fallback);
    const double T = r.trajectory.duration;
    const auto end = r.trajectory.at(T);
    const double gap = (45 + 10 * T) - end.s - 4.5;
    CHECK(gap == doctest::Approx(cfg.time_gap * 10).epsilon(1e-9));
    CHECK(end.s_d == doctest::Approx(10));
}

TEST_CASE("follow closes in on a distant leader at the driver's pace instead of stopping") {
    auto cfg = default_config(ManeuverKind::follow);
    PlanRequest req;
    req.start = {0, 10, 0, 0, 0, 0};
    req.leader = 0;
    const Obstacle leader{1, {150, 10, 0, 0, 0, 0}, 4.5, 1.8, false};
    auto r = run(cfg, req, {leader});
    REQUIRE(!r.record.fallback);
    const auto end = r.trajectory.at(r.trajectory.duration);
    CHECK(end.s_d == doctest::Approx(13));  // the leader's speed + 3 m/s
    cfg.follow_speed = 11.5;                // the driver's own speed caps it
    r = run(cfg, req, {leader});
    REQUIRE(!r.record.fallback);
    CHECK(r.trajectory.at(r.trajectory.duration).s_d == doctest::Approx(11.5));
}

TEST_CASE("follow never goes faster than the driver's own speed behind a faster leader") {
    auto cfg = default_config(ManeuverKind::follow);
    cfg.follow_speed = 15;
    PlanRequest req;
    req.start = {0, 15, 0, 0, 0, 0};
    req.leader = 0;
    const Obstacle leader{1, {40, 20, 0, 0, 0, 0}, 4.5, 1.8, false};
    auto r = run(cfg, req, {leader});
    REQUIRE(!r.record.fallback);
    const double T = r.trajectory.duration;
    for (int k = 0; k <= 20; ++k) CHECK(r.trajectory.at(T * k / 20).s_d <= 15 + 1e-9);
}

TEST_CASE("a follower at constant speed behind never vetoes the leader's braking") {
    auto cfg = default_config(ManeuverKind::stop);
    cfg.stop_at = StopTarget::now;
    PlanRequest req;
    req.start = {100, 12, 0, 0, 0, 0};
    const Obstacle tailgater{1, {92, 12, 0, 0, 0, 0}, 4.5, 1.8, false};  // 3.5 m behind, same speed
    auto r = run(cfg, req, {tailgater});
    CHECK_FALSE(r.record.fallback);
    CHECK(r.record.rejections[static_cast<size_t>(RejectCause::collision)] == 0);
}

TEST_CASE("a stop from rest well short of its point drives up to it instead of crawling") {
    auto cfg = default_config(ManeuverKind::stop);
    cfg.stop_at = StopTarget::position;
    PlanRequest req;
    req.start = {0, 0, 0, 0, 0, 0};
    req.stop_s = 20;
    auto r = run(cfg, req, {});
    REQUIRE(!r.record.fallback);
    // At most the longest duration factor (1.4) times the rest-to-rest time at 2 m/s² peak
    // (was 40 s: 2·Δs / 1 m/s).
    CHECK(r.trajectory.duration <= 1.4 * std::sqrt(5.77 * 20 / 2.0) + 1e-9);
    CHECK(r.trajectory.at(r.trajectory.duration).s == doctest::Approx(20).epsilon(1e-6));
}

TEST_CASE("stop ends within 0.1 m of the stop point at rest") {
    auto cfg = default_config(ManeuverKind::stop);
    cfg.stop_at = StopTarget::stop_line;
    PlanRequest req;
    req.start = {0, 12, 0, 0, 0, 0};
    req.stop_s = 60;
    auto r = run(cfg, req);
    REQUIRE(!r.record.fallback);
    const auto end = r.trajectory.at(r.trajectory.duration);
    CHECK(std::fabs(end.s - 60) < 0.1);
    CHECK(std::fabs(end.s_d) < 1e-6);
    CHECK(r.trajectory.at(r.trajectory.duration + 5).s == doctest::Approx(end.s));  // stays
}

TEST_CASE("cut-in ends in the target lane at the requested gap") {
    auto cfg = default_config(ManeuverKind::cut_in);
    cfg.delta_s = Sampled::single(5);
    cfg.delta_v = -3;
    PlanRequest req;
    req.start = {20, 16, 0, 3.5, 0, 0};
    req.current_lane = lane_at(3.5);
    req.target_lane = lane_at(0);
    req.target_vehicle = 0;
    const Obstacle ego{1, {0, 13, 0, 0, 0, 0}, 4.5, 1.8, false};
    auto r = run(cfg, req, {ego});
    REQUIRE(!r.record.fallback);
    const double T = r.trajectory.duration;
    const auto end = r.trajectory.at(T);
    CHECK(end.d == doctest::Approx(0).epsilon(1e-9));
    // delta_s is the bumper gap: the target's front (centre + 2.25 m) to the own rear.
    CHECK(end.s - (0 + 13 * T) == doctest::Approx(0.5 * (4.5 + 4.5) + 5));
    CHECK(end.s_d == doctest::Approx(10));
    // gap_from = reference (GeoScenario Server): delta_s beyond two own lengths from its centre.
    cfg.gap_from_reference = true;
    auto ref = run(cfg, req, {ego});
    REQUIRE(!ref.record.fallback);
    const double Tr = ref.trajectory.duration;
    CHECK(ref.trajectory.at(Tr).s - 13 * Tr == doctest::Approx(2 * 4.5 + 5));
}

TEST_CASE("keep_velocity, lane_change and reverse reach their targets") {
    PlanRequest req;
    req.start = {0, 10, 0, 0, 0, 0};
    req.target_lane = lane_at(3.5);
    {
        auto cfg = default_config(ManeuverKind::keep_velocity);
        cfg.speed = Sampled::single(14);
        auto r = run(cfg, req);
        CHECK(r.trajectory.at(r.trajectory.duration).s_d == doctest::Approx(14));
    }
    {
        auto r = run(default_config(ManeuverKind::lane_change), req);
        REQUIRE(!r.record.fallback);
        CHECK(r.trajectory.at(r.trajectory.duration).d == doctest::Approx(3.5));
    }
    {
        PlanRequest rq = req;
        rq.start.s_d = 0;
        auto r = run(default_config(ManeuverKind::reverse), rq);
        REQUIRE(!r.record.fallback);
        const auto end = r.trajectory.at(r.trajectory.duration);
        CHECK(end.s < 0);
        CHECK(end.s_d < -4);
    }
}

TEST_CASE("nothing feasible: emergency brake fallback") {
    auto cfg = default_config(ManeuverKind::keep_velocity);
    PlanRequest req;
    req.start = {0, 10, 0, 0, 0, 0};
    auto r = run(cfg, req, {{1, {3, 0, 0, 0, 0, 0}, 4.5, 1.8, true}});
    CHECK(r.record.fallback);
    CHECK(r.record.feasible == 0);
    const double T = r.trajectory.duration;
    CHECK(T == doctest::Approx(2 * 10.0 / cfg.common.max_long_acc));
    CHECK(r.trajectory.at(T).s_d == doctest::Approx(0).epsilon(1e-9));
    CHECK(r.trajectory.at(T + 10).s == doctest::Approx(r.trajectory.at(T).s));  // stays stopped
    for (double t = 0; t <= T; t += T / 50) {
        CHECK(std::fabs(r.trajectory.s.a(t)) <= cfg.common.max_long_acc + 1e-9);  // within the limit
        CHECK(r.trajectory.s.v(t) >= -1e-9);                                     // never backwards
    }
}

TEST_CASE("the cheapest feasible candidate wins; the record adds up") {
    auto cfg = default_config(ManeuverKind::keep_velocity);
    PlanRequest req;
    req.start = {0, 14, 0, 0, 0, 0};
    auto r = run(cfg, req);
    int rejected = 0;
    for (int x : r.record.rejections) rejected += x;
    CHECK(r.record.feasible + rejected == r.record.candidates);
    // At its nominal speed and duration the middle candidate (speed 14, T = 3 s) is cheapest.
    CHECK(r.trajectory.at(r.trajectory.duration).s_d == doctest::Approx(14));
    CHECK(r.record.winner_cost.total >= 0);
}

TEST_CASE("passing within the margin of a parked vehicle: driving on is feasible, coming closer is not") {
    // A 20 m parked truck beside the lane, its centre 2.9 m to the right of the car's: the
    // circles (1.17 m and 1.54 m) clear, the 0.3 m margin does not. Candidates that keep or open
    // the gap are feasible, so the car drives past instead of braking beside it; a lateral target
    // towards the truck is still rejected.
    auto cfg = default_config(ManeuverKind::keep_velocity);
    cfg.common.off_lane = false;
    PlanRequest req;
    req.current_lane = lane_at(0);
    req.start = {0, 5, 0, 0, 0, 0};
    const Obstacle truck{1, {10, 0, 0, -2.9, 0, 0}, 20, 1.8, true};
    for (double lat : {0.0, 0.3, -0.6}) {
        CAPTURE(lat);
        cfg.common.lat_offset = Sampled::single(lat);
        auto r = run(cfg, req, {truck});
        if (lat >= 0) {
            CHECK(!r.record.fallback);
            CHECK(r.trajectory.at(1.0).s_d > 4);
        } else {
            CHECK(r.record.fallback);
        }
    }
    // The truck 2.2 m across: the circles overlap (a contact): no candidate gets out that way.
    cfg.common.lat_offset = Sampled::single(0.0);
    auto r = run(cfg, req, {{1, {10, 0, 0, -2.2, 0, 0}, 20, 1.8, true}});
    CHECK(r.record.fallback);
}

}  // namespace planner_test
