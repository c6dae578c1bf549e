#include "runtime/sim/perception.h"

#include <algorithm>
#include <cmath>

namespace sdv::sim {

void View::build(const World& w, const Agent& a, double t0, double t_start) {
    w_ = &w;
    own_length_ = a.v->length;
    lane_width = a.lane != kNoLane ? w.net.lane(a.lane).width : 3.5;
    const Driver& dr = *a.driver;
    const auto& ref = *dr.ref;
    // Own state at the plan start, along the plan in force.
    road::CartesianState c{a.x, a.vx, a.ax, a.y, a.vy, a.ay};
    std::optional<planner::FrenetState> in_plan;
    if (dr.plan) {
        in_plan = dr.plan->traj.at(t_start - dr.plan->start);
        const planner::FrenetState& f = *in_plan;
        c = dr.plan->ref->to_cartesian({f.s, f.s_d, f.s_dd, f.d, f.d_d, f.d_dd});
    }
    self = ref.to_frenet(c, dr.ref_s);
    if (in_plan && dr.plan->ref != dr.ref) {
        // A new reference line (a lane change completed, or the path was rebuilt): converting
        // accelerations through two lines' curvature amplifies the kinks of map centre lines,
        // so they carry over from the plan's frame (the lines are near-parallel here).
        self.s_dd = in_plan->s_dd;
        self.d_dd = in_plan->d_dd;
    }
    self.s_dd = std::clamp(self.s_dd, -kMaxStartAcc, kMaxStartAcc);
    self.d_dd = std::clamp(self.d_dd, -kMaxStartLatAcc, kMaxStartLatAcc);
    // At rest the brakes hold: the end of a stopping plan's deceleration does not carry into the
    // next plan (it would make every start from standstill roll backwards first).
    if (std::fabs(self.s_d) < kRestSpeed) self.s_dd = 0;
    // Nearly stopped and still braking: the brakes bring it to rest within 0.2 s and
    // hold it there; the plan starts from that, not from a deceleration that would reverse it.
    if (self.s_d >= 0 && self.s_d < 0.1 && self.s_dd < -5.0 * self.s_d) self.s_dd = -5.0 * self.s_d;
    seen.clear();
    const double h = ref.heading(self.s), hc = std::cos(h), hs = std::sin(h);
    const Snap& me = w.snapshot[static_cast<size_t>(a.index)];
    // Neighbours from the grid (a hair beyond the range: the exact test is below), ascending.
    thread_local std::vector<int> near;
    w.grid.query(me.x, me.y, w.scenario.sensor_range * (1 + 1e-9) + 1e-6, near);
    for (const int jj : near) {
        const auto j = static_cast<size_t>(jj);
        if (jj == a.index) continue;
        const Snap& o = w.snapshot[j];
        if (!o.active) continue;
        const double dist = std::sqrt((o.x - me.x) * (o.x - me.x) + (o.y - me.y) * (o.y - me.y));
        if (dist > w.scenario.sensor_range) continue;
        Seen s;
        s.index = static_cast<int>(j);
        // Hinted by the displacement along the line's heading at the driver, accepted within
        // 25 m of the line (several lanes over; a global search where that misses).
        const double along = (o.x - c.x) * hc + (o.y - c.y) * hs;
        s.f = ref.to_frenet({o.x, o.vx, 0, o.y, o.vy, 0}, std::max(0.0, self.s + along), 25.0);
        // Constant velocity in Frenet up to the plan start.
        const double lat = t_start - t0;
        s.f.s += s.f.s_d * lat;
        s.f.d += s.f.d_d * lat;
        s.f.s_dd = s.f.d_dd = 0;
        s.length = o.length;
        s.width = o.width;
        s.speed = o.speed;
        s.dist = dist;
        // A driven vehicle moving along this frame (within 30°) stops moving sideways where its
        // plan in force ends (its lane's centre, the lane it changes into, a swerve's offset).
        if (!std::isnan(o.lateral_to_go) && o.speed > 0.5 && s.f.s_d > 0.85 * o.speed) {
            const double target = s.f.d - s.f.d_d * (t_start - t0) + o.lateral_to_go;  // from the snapshot's d
            s.d_min = std::min(s.f.d, target) - 0.3;
            s.d_max = std::max(s.f.d, target) + 0.3;
        }
        seen.push_back(s);
    }
}

int View::band_of(double d) const {
    const double w = lane_width;
    if (std::fabs(d) < 0.5 * w) return 0;
    if (d > 0 && d < 1.5 * w) return 1;
    if (d < 0 && d > -1.5 * w) return -1;
    return 9;
}

const Seen* View::nearest(int band, int where, bool objects) const {
    const Seen* best = nullptr;
    double best_ds = INFINITY;
    for (const Seen& s : seen) {
        if (!objects && w_->snapshot[static_cast<size_t>(s.index)].is_object) continue;
        if (band_of(s.f.d) != band) continue;
        const double ds = s.f.s - self.s;
        const double half = 0.5 * (s.length + own_length_);
        const int pos = ds > half ? 1 : ds < -half ? -1 : 0;
        if (pos != where) continue;
        if (std::fabs(ds) < best_ds) {
            best_ds = std::fabs(ds);
            best = &s;
        }
    }
    return best;
}

const Seen* View::find(int index) const {
    for (const Seen& s : seen) {
        if (s.index == index) return &s;
    }
    return nullptr;
}

}  // namespace sdv::sim
