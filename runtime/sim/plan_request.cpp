#include "runtime/sim/plan_request.h"

#include <algorithm>

#include "runtime/catalog/catalog.h"
#include "runtime/sim/pedestrian.h"

namespace sdv::sim {
namespace {

using catalog::ManeuverKind;

planner::Sampled to_sampled(const ir::Sampled& s) {
    return {s.value, s.lo, s.hi, s.samples, static_cast<planner::SampleMethod>(static_cast<int>(s.method)), s.sigma};
}

// A driver ahead moving at least this fast is still on its way to the point (m/s).
constexpr double kQueueMoving = 1.5;

// The centre at which a driver stops for a point ahead (`stop_s`, the centre on it), short of the
// drivers queued before it. Those in the own lane ahead whose rear is short of the point stand
// there too: where they are if at rest, and if `shared` (a red line or a pedestrian: everyone's
// stop), one behind the other up to the point if still moving. Each leaves the standstill gap of
// `follow` to the one ahead. Without this a stop planned to the point through a slower driver
// ahead (predicted at constant speed) and only the collision check, too late, held it back.
double queue_point(const Leaves& l, double stop_s, bool shared) {
    const double len = l.a.v->length;
    const double gap = planner::default_config(ManeuverKind::follow).stop_distance;
    thread_local std::vector<const Seen*> ahead;
    ahead.clear();
    for (const Seen& s : l.view.seen) {
        if (l.w.snapshot[static_cast<size_t>(s.index)].pedestrian || l.view.band_of(s.f.d) != 0) continue;
        if (s.f.s - l.view.self.s <= 0.5 * (s.length + len)) continue;  // beside or behind
        if (s.f.s - 0.5 * s.length < stop_s + 0.5 * len) ahead.push_back(&s);
    }
    std::sort(ahead.begin(), ahead.end(), [](const Seen* a, const Seen* b) { return a->f.s > b->f.s; });
    double slot = stop_s + 0.5 * len;  // the front bumper's limit
    for (const Seen* s : ahead) {
        const double front = s->f.s + 0.5 * s->length;
        const double rest = shared && s->f.s_d >= kQueueMoving ? std::max(slot, front) : front;
        slot = std::min(slot, rest - s->length - gap);
    }
    return slot - 0.5 * len;
}

}  // namespace

void apply_params(const ir::Node& n, planner::ManeuverConfig& cfg) {
    const auto& defs = catalog::maneuvers()[static_cast<size_t>(n.leaf)].params;
    for (size_t i = 0; i < defs.size() && i < n.params.size(); ++i) {
        const ir::ParamValue& v = n.params[i];
        if (v.given) planner::set_field(cfg, defs[i].field, to_sampled(v.number), v.choice);
    }
}

void make_request(const Leaves& l, int32_t sel, PlanInputs& out) {
    const World& w = l.w;
    const Agent& a = l.a;
    const Driver& d = *a.driver;
    planner::ManeuverConfig& cfg = out.config;
    planner::PlanRequest& req = out.request;
    cfg = planner::default_config(ManeuverKind::keep_velocity);
    req = planner::PlanRequest{};
    out.obstacles.clear();
    for (const Seen& s : l.view.seen) {
        // A driver passes a pedestrian with room to spare: its footprint, grown by a margin on
        // every side, is what a trajectory must not touch.
        const double grow = w.snapshot[static_cast<size_t>(s.index)].pedestrian ? 2 * kPedestrianMargin : 0.0;
        out.obstacles.push_back({s.index, {s.f.s, s.f.s_d, 0, s.f.d, s.f.d_d, 0}, s.length + grow, s.width + grow,
                                 w.snapshot[static_cast<size_t>(s.index)].is_static, s.d_min, s.d_max});
    }
    const double lw = a.lane != kNoLane ? w.net.lane(a.lane).width : 3.5;
    req.current_lane = {0, 0.5 * lw, -0.5 * lw};
    req.target_lane = req.current_lane;
    if (sel >= 0) {
        const ir::Node& n = d.tree->instance().nodes[static_cast<size_t>(sel)];
        const auto kind = static_cast<ManeuverKind>(n.leaf);
        cfg = planner::default_config(kind);
        apply_params(n, cfg);
        auto index_of = [&](const Seen* s) -> int {
            if (s == nullptr) return -1;
            for (size_t i = 0; i < out.obstacles.size(); ++i) {
                if (out.obstacles[i].id == s->index) return static_cast<int>(i);
            }
            return -1;
        };
        if (kind == ManeuverKind::follow) req.leader = index_of(l.vehicle(n, "leader", true));
        if (kind == ManeuverKind::cut_in) {
            req.target_vehicle = index_of(l.vehicle(n, "target", false));
            // In the target lane, the end state is kept at the time the last lane-change plan
            // set for it (a shrinking horizon, while not shorter than the shortest sampled
            // duration); after that (or once done) a full duration ahead again.
            const Driver::CutIn& c = d.cut_in;
            const double shortest = std::min(cfg.duration.value, cfg.duration.lo);
            if (c.node == sel && c.in_lane && !c.done && c.due - l.t_start >= shortest) cfg.duration = planner::Sampled::single(c.due - l.t_start);
        }
        if ((kind == ManeuverKind::lane_change || kind == ManeuverKind::cut_in) && d.target_lane != kNoLane) {
            const auto& ln = w.net.lane(a.lane);
            const double side = d.target_lane == ln.left ? 1.0 : -1.0;
            req.target_lane = {side * lw, side * lw + 0.5 * lw, side * lw - 0.5 * lw};
        }
        if (kind == ManeuverKind::stop) {
            const auto which = cfg.stop_at;
            req.stop_s = l.view.self.s;
            for (size_t i = 0; i < d.path.size(); ++i) {
                const auto& ln = w.net.lane(d.path[i]);
                if (which == planner::StopTarget::goal && d.path[i] == a.goal_lane) {
                    // The centre at the goal: the goal's own semantics (reached within 4 m of
                    // the centre, SPEC §8), which the reference's stop triggers are tuned to.
                    req.stop_s = d.path_start[i] + a.goal_s;
                    break;
                }
                if (which == planner::StopTarget::stop_line) {
                    if (const auto* line = ln.stop_line_from(l.view.self.s - 1 - d.path_start[i])) {
                        req.stop_s = d.path_start[i] + line->s - 0.5 * a.v->length;
                        break;
                    }
                }
            }
            if (which == planner::StopTarget::position) {
                if (cfg.stop_position) req.stop_s = *cfg.stop_position;
                req.stop_s += d.path_start.empty() ? 0 : d.path_start.front();
            }
            if (which == planner::StopTarget::goal && a.goal_lane == kNoLane) cfg.stop_at = planner::StopTarget::now;
            if (which == planner::StopTarget::pedestrian) {
                // The stop of `pedestrian_crossing`; with nobody to yield to, a stop now.
                const auto y = pedestrian_ahead(l, kPedestrianLookAhead);
                if (y) req.stop_s = y->stop_s;
                else cfg.stop_at = planner::StopTarget::now;
            }
            if (cfg.stop_at != planner::StopTarget::now) {
                const bool shared = which == planner::StopTarget::stop_line || which == planner::StopTarget::pedestrian;
                const double queued = queue_point(l, req.stop_s - cfg.stop_before, shared);
                // The gap to the driver ahead is the queue's, whatever `distance` the stop keeps
                // before its point.
                if (queued < req.stop_s - cfg.stop_before) req.stop_s = queued + cfg.stop_before;
            }
        }
    }
    const auto& self = l.view.self;
    req.start = {self.s, self.s_d, self.s_dd, self.d, self.d_d, self.d_dd};
    req.length_m = a.v->length;
    req.width_m = a.v->width;
    req.config = &cfg;
    req.obstacles = out.obstacles;
    req.speed_limit_mps = a.lane != kNoLane ? w.net.lane(a.lane).speed_limit : 0;
    req.seed = w.seed;
    req.vehicle = static_cast<uint32_t>(a.index);
    req.plan_number = d.plan_count;
}

}  // namespace sdv::sim
