#include "runtime/sim/leaves.h"

#include <cmath>

#include "runtime/catalog/catalog.h"
#include "runtime/sim/plan_request.h"

namespace sdv::sim {

using catalog::ManeuverKind;

const ir::ParamValue* leaf_param(const ir::Node& n, const char* name) {
    const auto& defs = n.kind == ir::NodeKind::maneuver ? catalog::maneuvers()[static_cast<size_t>(n.leaf)].params
                                                        : catalog::conditions()[static_cast<size_t>(n.leaf)].params;
    for (size_t i = 0; i < defs.size() && i < n.params.size(); ++i) {
        if (defs[i].name == name) return n.params[i].given ? &n.params[i] : nullptr;
    }
    return nullptr;
}

double leaf_number(const ir::Node& n, const char* name, const ir::TreeInstance& tree, uint64_t seed, int agent) {
    const auto* p = leaf_param(n, name);
    if (p == nullptr) return NAN;
    if (n.kind == ir::NodeKind::condition && p->number.hi > p->number.lo) {
        const auto node = static_cast<uint32_t>(&n - tree.nodes.data());
        const auto slot = static_cast<uint32_t>(p - n.params.data());
        planner::RandomStream rng(seed, static_cast<uint32_t>(agent), 0x80000000u | (node << 8) | slot);
        return p->number.lo + (p->number.hi - p->number.lo) * rng.uniform();
    }
    return p->number.value;
}

const ir::ParamValue* Leaves::param(const ir::Node& n, const char* name) const { return leaf_param(n, name); }

double Leaves::num(const ir::Node& n, const char* name) const {
    return leaf_number(n, name, a.driver->tree->instance(), w.seed, a.index);
}

const Seen* Leaves::vehicle(const ir::Node& n, const char* name, bool default_leader) const {
    const auto* p = param(n, name);
    if (p == nullptr || p->vehicle.kind == ir::VehicleRef::Kind::none) return default_leader ? view.nearest(0, 1) : nullptr;
    switch (p->vehicle.kind) {
        case ir::VehicleRef::Kind::vehicle: return view.find(p->vehicle.vehicle);
        case ir::VehicleRef::Kind::zone: {
            const std::string& z = catalog::vehicle_zones()[static_cast<size_t>(p->vehicle.zone)];
            if (z == "front") return view.nearest(0, 1);
            if (z == "back") return view.nearest(0, -1);
            if (z == "left") return view.nearest(1, 0);
            if (z == "right") return view.nearest(-1, 0);
            if (z == "front_left") return view.nearest(1, 1);
            if (z == "front_right") return view.nearest(-1, 1);
            if (z == "back_left") return view.nearest(1, -1);
            if (z == "back_right") return view.nearest(-1, -1);
            return nullptr;
        }
        default: return nullptr;
    }
}

bool Leaves::condition(const ir::Node& n, int32_t index) {
    const auto table = condition_table();
    const auto kind = static_cast<size_t>(n.leaf);
    return kind < table.size() && table[kind].fn(*this, n, index);
}

bt::Status Leaves::maneuver(const ir::Node& n, int32_t index) {
    const auto kind = static_cast<ManeuverKind>(n.leaf);
    Driver& d = *a.driver;
    switch (kind) {
        case ManeuverKind::follow: return vehicle(n, "leader", true) != nullptr ? bt::Status::success : bt::Status::failure;
        case ManeuverKind::cut_in: {
            const Seen* t = vehicle(n, "target", false);
            if (t == nullptr) return bt::Status::failure;
            Driver::CutIn& c = d.cut_in;
            const bool fresh = c.node != index || (c.ticked != d.plan_count && c.ticked + 1 != d.plan_count);
            if (fresh) c = {index, d.plan_count, t_start, -1, 0, false, false};
            c.ticked = d.plan_count;
            // Ended (done or given up): not repeated while the tree keeps ticking it every cycle.
            if (c.done) return bt::Status::failure;
            planner::ManeuverConfig cfg = planner::default_config(kind);
            apply_params(n, cfg);
            // Not in its end state within twice its longest duration: it gives up.
            if (t_start - c.since > 2 * std::max(cfg.duration.value, cfg.duration.hi)) {
                c.done = true;
                return bt::Status::failure;
            }
            if (!c.in_lane) {
                const bt::Status s = lane_move(n, kind);
                // Already in the lane it would cut into: nothing to cut in front of.
                if (s == bt::Status::success && !switched) return bt::Status::failure;
                if (switched) c.in_lane = true;
                return s == bt::Status::failure ? s : bt::Status::running;
            }
            // In the target lane: on until the end state, gap and relative speed, is reached.
            const double ahead = cfg.gap_from_reference ? 2 * a.v->length : 0.5 * (a.v->length + t->length);
            const double gap = view.self.s - t->f.s - ahead;
            const double dv = view.self.s_d - t->f.s_d;
            const double lo = std::min(cfg.delta_s.value, cfg.delta_s.lo), hi = std::max(cfg.delta_s.value, cfg.delta_s.hi);
            const double tol = std::max(2.0, 0.2 * std::max(std::fabs(lo), std::fabs(hi)));
            const bool due = c.due >= 0 && t_start >= c.due - 1e-9;
            c.done = due && gap >= lo - tol && gap <= hi + tol && std::fabs(dv - cfg.delta_v) <= 1.0;
            return c.done ? bt::Status::success : bt::Status::running;
        }
        case ManeuverKind::lane_change: return lane_move(n, kind);
        default: return bt::Status::success;
    }
}

bt::Status Leaves::lane_move(const ir::Node& n, catalog::ManeuverKind kind) {
    Driver& d = *a.driver;
    const catalog::ParamDef* def = catalog::maneuver(kind).find_param("lane");
    const auto* given = param(n, "lane");
    const int choice = given != nullptr ? given->choice : def->def ? static_cast<int>(def->def->value) : -1;
    const auto& l = w.net.lane(a.lane);
    int side = 0;  // +1 left, −1 right
    if (choice >= 0 && static_cast<size_t>(choice) < def->choices.size()) {
        const std::string& word = def->choices[static_cast<size_t>(choice)];
        if (word == "left") side = 1;
        else if (word == "right") side = -1;
        else if (word == "target") {
            const Seen* t = vehicle(n, "target", false);
            side = t == nullptr ? 0 : view.band_of(t->f.d);
            if (side == 9) side = 0;
        } else if (word == "route") {
            for (size_t r = 0; r + 1 < a.route.size(); ++r) {
                if (a.route[r].lane == a.lane && a.route[r + 1].by_lane_change) side = a.route[r + 1].lane == l.left ? 1 : -1;
            }
        }
    }
    if (side == 0) {
        // Already in the target lane (a swerve, or the cut-in target is beside us).
        return bt::Status::success;
    }
    const LaneId nb = side > 0 ? l.left : l.right;
    const bool same = side > 0 ? l.left_same_direction : l.right_same_direction;
    if (nb == kNoLane || !same) return bt::Status::failure;
    const double lw = l.width, target_d = side * lw;
    // Two vehicles moving into the same lane side by side (now or in 4 s): the one that began
    // later aborts back to its lane; began in the same cycle: the one farther from the target
    // lane's centre, then the higher vehicle index.
    if (d.lane_move_target != nb) {
        d.lane_move_target = nb;
        d.lane_move_since = t0;
    }
    for (const Seen& s : view.seen) {
        const Snap& o = w.snapshot[static_cast<size_t>(s.index)];
        if (o.target_lane != nb) continue;
        const double ds = s.f.s - view.self.s, dv = s.f.s_d - view.self.s_d;
        const double reach = 0.5 * (s.length + a.v->length) + 5.0;
        if (std::min(std::fabs(ds), std::fabs(ds + 4.0 * dv)) > reach) continue;
        const double mine = std::fabs(view.self.d - target_d), theirs = std::fabs(s.f.d - target_d);
        const bool later = o.lane_move_since < d.lane_move_since - 1e-9;
        const bool together = std::fabs(o.lane_move_since - d.lane_move_since) <= 1e-9;
        if (later || (together && (mine > theirs + 0.05 || (std::fabs(mine - theirs) <= 0.05 && s.index < a.index)))) {
            d.lane_move_target = kNoLane;
            return bt::Status::failure;
        }
    }
    // Done when the whole footprint is inside the target lane.
    if (std::fabs(view.self.d - target_d) + 0.5 * a.v->width <= 0.5 * lw + 1e-6) {
        d.target_lane = nb;
        switched = true;
        return bt::Status::success;
    }
    d.target_lane = nb;
    return bt::Status::running;
}

}  // namespace sdv::sim
