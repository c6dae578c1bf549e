// The agent models of vehicles: SDVs, trajectory and path vehicles, static objects, external
// vehicles; and of pedestrians that follow waypoints (simulated pedestrians: pedestrian.cpp).
#include "runtime/sim/agents.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "runtime/sim/pedestrian.h"

namespace sdv::sim {
namespace {

// Follows the plan in force (the pending one takes over at its start time); the lane is the
// path lane under the vehicle.
class SdvModel final : public AgentModel {
public:
    explicit SdvModel(bool ego) : ego_(ego) {}
    const char* kind() const override { return ego_ ? "ego" : "sdv"; }
    void advance(const World& w, Agent& a, double t, int tick) const override {
        (void)w;
        (void)tick;
        Driver& d = *a.driver;
        if (d.pending && t + 1e-9 >= d.pending->start) {
            d.plan = std::move(d.pending);
            d.pending.reset();
        }
        const planner::FrenetState f = d.plan->traj.at(t - d.plan->start);
        place(a, d.plan->ref->to_cartesian({f.s, f.s_d, f.s_dd, f.d, f.d_d, f.d_dd}), d.plan->ref->heading(f.s));
        // In the plan's own frame the vehicle stands at (s, d) of its plan; in another (the
        // path was rebuilt since) it is projected.
        const auto probe = d.plan->ref == d.ref ? road::FrenetState{f.s, f.s_d, f.s_dd, f.d, f.d_d, f.d_dd}
                                                : d.ref->project({a.x, a.y}, d.ref_s);
        d.ref_s = probe.s;
        for (size_t i = 0; i < d.path.size(); ++i) {
            if (probe.s + 1e-9 >= d.path_start[i]) {
                a.lane = d.path[i];
                a.lane_s = probe.s - d.path_start[i];
                a.lane_d = probe.d;
            }
        }
        const road::Lane& l = w.net.lane(a.lane);
        // Past the end of the last lane of its path, where no lane follows: off the network.
        a.past_road_end = a.lane == d.path.back() && l.successors.empty() && a.lane_s > l.length;
        a.centre_lane = a.past_road_end ? kNoLane : centre_lane(w.net, a.lane, a.lane_d);
    }

private:
    bool ego_;
};

// Coordinates on the lane under a non-SDV agent.
void localise(const World& w, Agent& a, bool relocate) {
    double s = 0, d = 0;
    if (relocate) {
        // locate() projected onto the lane it found: the same projection as below.
        const auto found = w.net.locate({a.x, a.y}, a.yaw);
        a.lane = found.lane;
        s = found.s;
        d = found.d;
    } else if (a.lane != kNoLane) {
        const auto f = w.net.reference(a.lane).project({a.x, a.y});
        s = f.s;
        d = f.d;
    }
    if (a.lane != kNoLane) {
        a.lane_s = s;
        a.lane_d = d;
        a.centre_lane = s >= 0 && s <= w.net.lane(a.lane).length ? centre_lane(w.net, a.lane, a.lane_d) : kNoLane;
    }
}

// Linear interpolation between time-stamped waypoints (the reference's TV and TP; a path's
// points are timed when the agent is placed: PV, PP); at rest after the last one.
class TrajectoryModel final : public AgentModel {
public:
    explicit TrajectoryModel(const char* kind) : kind_(kind) {}
    const char* kind() const override { return kind_; }
    void advance(const World& w, Agent& a, double t, int tick) const override {
        if (tick > 0) {
            const auto& wp = a.v->trajectory;
            size_t k = 0;
            while (k + 2 < wp.size() && wp[k + 1].time <= t) ++k;
            const auto pos = [&](size_t i) {
                const ir::Position& at = wp[i].position;
                if (at.xy) return road::CartesianState{at.x, 0, 0, at.y, 0, 0};  // exactly there, on a lane or not
                LaneId l;
                double s;
                w.locate(at, l, s);
                return w.net.reference(l).to_cartesian({s, 0, 0, at.offset, 0, 0});
            };
            const auto p0 = pos(k), p1 = pos(k + 1);
            const double span = std::max(1e-9, wp[k + 1].time - wp[k].time);
            const double f = std::clamp((t - wp[k].time) / span, 0.0, 1.0);
            road::CartesianState c;
            c.x = p0.x + f * (p1.x - p0.x);
            c.y = p0.y + f * (p1.y - p0.y);
            c.vx = t <= wp.back().time ? (p1.x - p0.x) / span : 0;
            c.vy = t <= wp.back().time ? (p1.y - p0.y) / span : 0;
            const double old_speed = a.speed;
            place(a, c);
            a.accel = (a.speed - old_speed) / w.dt;
        }
        localise(w, a, true);
    }

private:
    const char* kind_;
};

// Along its path at the speed its points give, interpolated linearly in the distance walked
// (the reference's PV and PP, Actor.follow_path): each tick the speed at the distance walked so
// far, then the distance advanced at that speed. At rest at the last point.
// A path agent meeting another (GeoScenario's ensured collision, Actor.follow_path): where the
// other's heading crosses the rest of the path, the speed that gets there when the other does at
// its speed (last tick's snapshot); nullopt while it heads for no point ahead on the path.
std::optional<double> meeting_speed(const World& w, const Agent& a, size_t k) {
    if (static_cast<size_t>(a.meet) >= w.snapshot.size()) return std::nullopt;
    const Snap& o = w.snapshot[static_cast<size_t>(a.meet)];
    const double speed = std::hypot(o.vx, o.vy);
    if (!o.active || speed < 0.1) return std::nullopt;
    const road::Vec2 from{o.x, o.y}, dir{o.vx / speed, o.vy / speed};
    const auto& pts = a.path_points;
    for (size_t j = k; j + 1 < pts.size(); ++j) {
        const road::Vec2 seg = pts[j + 1] - pts[j];
        const double den = road::cross(dir, seg);
        if (std::fabs(den) < 1e-12) continue;
        const road::Vec2 q = pts[j] - from;
        const double along = road::cross(q, seg) / den;  // along the other's heading
        const double u = road::cross(q, dir) / den;      // along the segment
        if (along <= 0 || u < 0 || u > 1) continue;
        const double remaining = a.path_cum[j] + u * (a.path_cum[j + 1] - a.path_cum[j]) - a.path_s;
        if (remaining <= 0) continue;
        const double vmax = a.v->pedestrian ? 10.0 : 100.0;  // the checker's speed limits
        return std::min(vmax, remaining * speed / along);
    }
    return std::nullopt;
}

class PathModel final : public AgentModel {
public:
    explicit PathModel(const char* kind) : kind_(kind) {}
    const char* kind() const override { return kind_; }
    void advance(const World& w, Agent& a, double t, int tick) const override {
        (void)t;
        const auto& pts = a.path_points;
        const auto& speeds = a.path_speeds;
        const auto& cum = a.path_cum;
        if (tick > 0 && pts.size() >= 2) {
            size_t k = 0;
            while (k + 2 < cum.size() && a.path_s > cum[k + 1]) ++k;
            const double span = std::max(1e-9, cum[k + 1] - cum[k]);
            const double f = std::clamp((a.path_s - cum[k]) / span, 0.0, 1.0);
            double v = a.path_s >= cum.back() ? 0.0 : speeds[k] + f * (speeds[k + 1] - speeds[k]);
            if (a.meet >= 0 && a.path_s < cum.back()) {
                if (auto m = meeting_speed(w, a, k)) v = *m;
            }
            a.path_s = std::min(cum.back(), a.path_s + v * w.dt);
            while (k + 2 < cum.size() && a.path_s > cum[k + 1]) ++k;
            const double seg = std::max(1e-9, cum[k + 1] - cum[k]);
            const double g = std::clamp((a.path_s - cum[k]) / seg, 0.0, 1.0);
            const road::Vec2 dir = (1.0 / seg) * (pts[k + 1] - pts[k]);
            const road::Vec2 p = pts[k] + g * (pts[k + 1] - pts[k]);
            const double moving = a.path_s >= cum.back() ? 0.0 : v;
            const double old_speed = a.speed;
            place(a, {p.x, moving * dir.x, 0, p.y, moving * dir.y, 0});
            if (moving <= 0.05) a.yaw = std::atan2(dir.y, dir.x);
            a.accel = (a.speed - old_speed) / w.dt;
        }
        localise(w, a, true);
    }

private:
    const char* kind_;
};

class StaticModel final : public AgentModel {
public:
    const char* kind() const override { return "static"; }
    void advance(const World& w, Agent& a, double t, int tick) const override {
        (void)t;
        (void)tick;
        localise(w, a, false);
    }
};

// Driven from outside (co-simulation): takes the state its client set for this tick; without
// one (tick 0, or a step with no update) it stays as it is.
class ExternalModel final : public AgentModel {
public:
    const char* kind() const override { return "external"; }
    void advance(const World& w, Agent& a, double t, int tick) const override {
        (void)t;
        if (tick > 0 && a.external) {
            const Agent::ExternalState& e = *a.external;
            a.x = e.x;
            a.y = e.y;
            a.yaw = e.yaw;
            a.speed = e.speed;
            a.accel = e.accel;
            a.vx = e.speed * std::cos(e.yaw);
            a.vy = e.speed * std::sin(e.yaw);
            a.ax = e.accel * std::cos(e.yaw);
            a.ay = e.accel * std::sin(e.yaw);
            if (!e.active) a.past_road_end = true;  // it leaves the run, as off the road's end
            a.external.reset();
        }
        localise(w, a, true);
    }
};

}  // namespace

std::shared_ptr<const AgentModel> make_model(const ir::Vehicle& v) {
    if (v.pedestrian) {
        if (v.kind == ir::VehicleKind::sdv) return make_walker_model();
        if (v.kind == ir::VehicleKind::path) return std::make_shared<PathModel>("pedestrian");
        return std::make_shared<TrajectoryModel>("pedestrian");
    }
    switch (v.kind) {
        case ir::VehicleKind::sdv: return std::make_shared<SdvModel>(v.is_ego);
        case ir::VehicleKind::trajectory: return std::make_shared<TrajectoryModel>(v.is_ego ? "ego" : "trajectory");
        case ir::VehicleKind::path: return std::make_shared<PathModel>(v.is_ego ? "ego" : "path");
        case ir::VehicleKind::static_object: return std::make_shared<StaticModel>();
        case ir::VehicleKind::external: return std::make_shared<ExternalModel>();
    }
    return std::make_shared<StaticModel>();
}

LaneId centre_lane(const road::RoadNetwork& net, LaneId lane, double d) {
    const road::Lane& l = net.lane(lane);
    const double half = 0.5 * l.width;
    if (std::fabs(d) <= half) return lane;
    const LaneId side = d > 0 ? l.left : l.right;
    if (side == kNoLane) return kNoLane;
    // The neighbour's band, next to this lane's edge.
    return std::fabs(d) <= half + net.lane(side).width ? side : kNoLane;
}

void place(Agent& a, const road::CartesianState& c, std::optional<double> lane_heading) {
    a.x = c.x;
    a.y = c.y;
    a.vx = c.vx;
    a.vy = c.vy;
    a.ax = c.ax;
    a.ay = c.ay;
    const double v = std::hypot(c.vx, c.vy);
    if (v > 0.05) {
        a.yaw = std::atan2(c.vy, c.vx);
        // A car's heading stays within a steering angle's reach of its lane, however slowly it
        // moves sideways in the Frenet plan. Moving against the lane (reverse) it still faces
        // along the lane: its heading is opposite to its motion and its speed negative.
        if (lane_heading) {
            constexpr double kMaxRelative = 0.5;  // rad
            const bool reversing = a.vx * std::cos(*lane_heading) + a.vy * std::sin(*lane_heading) < 0;
            if (reversing) a.yaw = std::atan2(-c.vy, -c.vx);
            const double rel = std::remainder(a.yaw - *lane_heading, 2 * M_PI);
            a.yaw = *lane_heading + std::clamp(rel, -kMaxRelative, kMaxRelative);
        }
    }
    // Signed speed: negative when moving against the heading (reverse).
    const double along = c.vx * std::cos(a.yaw) + c.vy * std::sin(a.yaw);
    a.speed = along >= 0 ? v : -v;
    a.accel = c.ax * std::cos(a.yaw) + c.ay * std::sin(a.yaw);
}

}  // namespace sdv::sim
