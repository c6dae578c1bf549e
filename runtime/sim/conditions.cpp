// The catalog's conditions (docs/catalog.md), one function each, dispatched by catalog::ConditionKind
// through condition_table(). Each reads the driver's view (own state at the plan's start, the
// perceived agents) and the road; `wait` and stop_for_light (lights.cpp) keep state.
#include <algorithm>
#include <array>
#include <cmath>

#include "runtime/catalog/catalog.h"
#include "runtime/planner/sampling.h"
#include "runtime/sim/leaves.h"
#include "runtime/sim/pedestrian.h"

namespace sdv::sim {
namespace {

using catalog::ConditionKind;

bool in(double x, double lo, double hi) { return (std::isnan(lo) || x >= lo) && (std::isnan(hi) || x <= hi); }

// Whether a vehicle parameter names another agent (rather than the driver itself).
bool names_other(const ir::ParamValue* p) {
    return p != nullptr && p->vehicle.kind != ir::VehicleRef::Kind::self && p->vehicle.kind != ir::VehicleRef::Kind::none;
}

const Snap& snap(const Leaves& l, int index) { return l.w.snapshot[static_cast<size_t>(index)]; }

bool sim_time(Leaves& l, const ir::Node& n, int32_t) { return in(l.t0, l.num(n, "after"), l.num(n, "before")); }

bool vehicle_state(Leaves& l, const ir::Node& n, int32_t) {
    road::FrenetState f = l.view.self;
    double speed = l.view.self.s_d, acc = snap(l, l.a.index).accel;
    if (names_other(l.param(n, "vehicle"))) {
        const Seen* s = l.vehicle(n, "vehicle", false);
        if (s == nullptr) return false;
        f = s->f;
        speed = s->speed;
        acc = snap(l, s->index).accel;
    }
    return in(f.s, l.num(n, "s_min"), l.num(n, "s_max")) && in(f.d, l.num(n, "d_min"), l.num(n, "d_max")) &&
           in(speed, l.num(n, "speed_min"), l.num(n, "speed_max")) && in(acc, l.num(n, "acc_min"), l.num(n, "acc_max"));
}

bool delta_state(Leaves& l, const ir::Node& n, int32_t) {
    const Seen* s = l.vehicle(n, "vehicle", false);
    if (s == nullptr) return false;
    const auto& self = l.view.self;
    return in(s->f.s - self.s, l.num(n, "ds_min"), l.num(n, "ds_max")) && in(s->f.d - self.d, l.num(n, "dd_min"), l.num(n, "dd_max")) &&
           in(s->speed - self.s_d, l.num(n, "dv_min"), l.num(n, "dv_max"));
}

bool gap(Leaves& l, const ir::Node& n, int32_t) {
    const Seen* s = nullptr;
    if (const auto* lane = l.param(n, "lane")) {
        const int band = lane->choice == 0 ? 1 : lane->choice == 2 ? -1 : 0;
        s = l.view.nearest(band, 1);
    } else {
        s = l.vehicle(n, "vehicle", true);
    }
    if (s == nullptr) return !std::isnan(l.num(n, "min")) || !std::isnan(l.num(n, "time_min"));  // nobody: gap is infinite
    const auto& self = l.view.self;
    const double g = std::fabs(s->f.s - self.s) - 0.5 * (s->length + l.a.v->length);
    const double tgap = self.s_d > 0.1 ? g / self.s_d : INFINITY;
    return in(g, l.num(n, "min"), l.num(n, "max")) && in(tgap, l.num(n, "time_min"), l.num(n, "time_max"));
}

bool ttc(Leaves& l, const ir::Node& n, int32_t) {
    const Seen* s = l.vehicle(n, "vehicle", true);
    if (s == nullptr) return false;
    const auto& self = l.view.self;
    const double ds = s->f.s - self.s;
    const double g = std::fabs(ds) - 0.5 * (s->length + l.a.v->length);
    const double closing = ds >= 0 ? self.s_d - s->f.s_d : s->f.s_d - self.s_d;
    if (closing <= 0) return false;
    return std::max(g, 0.0) / closing < l.num(n, "max");
}

bool distance(Leaves& l, const ir::Node& n, int32_t) {
    const Seen* s = l.vehicle(n, "vehicle", false);
    return s != nullptr && in(s->dist, l.num(n, "min"), l.num(n, "max"));
}

bool lane_occupied(Leaves& l, const ir::Node& n, int32_t) {
    const auto* lane = l.param(n, "lane");
    const int band = lane == nullptr || lane->choice == 1 ? 0 : lane->choice == 0 ? 1 : -1;
    const double objects = l.num(n, "objects");
    const Seen* s = l.view.nearest(band, 1, std::isnan(objects) || objects != 0);
    if (s == nullptr) return false;
    const double g = s->f.s - l.view.self.s - 0.5 * (s->length + l.a.v->length);
    const double tg = l.num(n, "time_gap");
    if (!std::isnan(tg)) return g <= tg * std::max(l.view.self.s_d, 0.0);
    return g <= l.num(n, "distance");
}

bool can_lane_change(Leaves& l, const ir::Node& n, int32_t) {
    const auto* lane = l.param(n, "lane");
    const bool left = lane == nullptr || lane->choice == 0;
    const auto& ln = l.w.net.lane(l.a.lane);
    const LaneId nb = left ? ln.left : ln.right;
    const bool same = left ? ln.left_same_direction : ln.right_same_direction;
    if (nb == kNoLane || !same) return false;
    const double g = l.num(n, "gap");
    for (const Seen& s : l.view.seen) {
        if (l.view.band_of(s.f.d) != (left ? 1 : -1)) continue;
        if (std::fabs(s.f.s - l.view.self.s) < g + 0.5 * (s.length + l.a.v->length)) return false;
    }
    return true;
}

// vehicle_moving, vehicle_stopped, vehicle_parked: of the driver or of another agent.
const Snap* subject(Leaves& l, const ir::Node& n) {
    int idx = l.a.index;
    if (names_other(l.param(n, "vehicle"))) {
        const Seen* s = l.vehicle(n, "vehicle", false);
        if (s == nullptr) return nullptr;
        idx = s->index;
    }
    return &snap(l, idx);
}

bool vehicle_moving(Leaves& l, const ir::Node& n, int32_t) {
    const Snap* o = subject(l, n);
    return o != nullptr && std::fabs(o->speed) > l.num(n, "min_speed");
}

bool vehicle_stopped(Leaves& l, const ir::Node& n, int32_t) {
    const Snap* o = subject(l, n);
    return o != nullptr && std::fabs(o->speed) <= l.num(n, "max_speed");
}

bool vehicle_parked(Leaves& l, const ir::Node& n, int32_t) {
    const Snap* o = subject(l, n);
    return o != nullptr && o->stopped_since >= 0 && l.t0 - o->stopped_since >= l.num(n, "duration");
}

bool reached_goal(Leaves& l, const ir::Node& n, int32_t) {
    if (l.a.goal_lane == kNoLane) return false;
    const Driver& d = *l.a.driver;
    for (size_t i = 0; i < d.path.size(); ++i) {
        if (d.path[i] == l.a.goal_lane) {
            const double gs = d.path_start[i] + l.a.goal_s;
            return gs - l.view.self.s <= l.num(n, "distance");
        }
    }
    return false;
}

bool at_lane_change_segment(Leaves& l, const ir::Node& n, int32_t) {
    const auto& route = l.a.route;
    for (size_t r = 0; r + 1 < route.size(); ++r) {
        if (route[r].lane == l.a.lane && route[r + 1].by_lane_change) {
            const auto* lane = l.param(n, "lane");
            const bool left = route[r + 1].lane == l.w.net.lane(l.a.lane).left;
            if (lane == nullptr || lane->choice == 2) return true;
            return (lane->choice == 0) == left;
        }
    }
    return false;
}

// approaching_stop, traffic_light and intersection_type look along the path for the next stop
// line or junction lane.
bool along_path(Leaves& l, const ir::Node& n, ConditionKind kind) {
    const Driver& d = *l.a.driver;
    const double self_s = l.view.self.s;
    const double look = kind == ConditionKind::intersection_type ? 200.0 : l.num(n, "distance");
    for (size_t i = 0; i < d.path.size(); ++i) {
        const auto& ln = l.w.net.lane(d.path[i]);
        const double start = d.path_start[i];
        if (start > self_s + look) break;
        const road::StopLine* line = ln.stop_line_from(self_s - 0.5 - start);  // a lane may have several
        const bool stop_ahead = line != nullptr && start + line->s <= self_s + look;
        if (kind == ConditionKind::approaching_stop) {
            const auto* k = l.param(n, "kind");
            const int want = k == nullptr ? 2 : k->choice;
            if (stop_ahead && want != 1) return true;
            if (ln.in_junction && start >= self_s && start <= self_s + look && want != 0) return true;
            continue;
        }
        if (kind == ConditionKind::traffic_light) {
            if (!stop_ahead || line->traffic_lights.empty()) continue;
            const auto* st = l.param(n, "state");
            const std::string state = l.w.light_state(line->traffic_lights.front(), l.t0);
            static const char* kStates[] = {"red", "yellow", "green"};
            return st != nullptr && state == kStates[st->choice];
        }
        // intersection type of the next stop / junction
        if (stop_ahead || ln.in_junction) {
            const auto* ty = l.param(n, "type");
            const int want = ty == nullptr ? 3 : ty->choice;
            const bool lit = !(stop_ahead ? line->traffic_lights : ln.traffic_lights).empty();
            const int have = lit ? 1 : ln.all_way_stop ? 0 : ln.right_of_way >= 0 ? 2 : 3;
            return want == have;
        }
    }
    if (kind == ConditionKind::intersection_type) {
        const auto* ty = l.param(n, "type");
        return ty != nullptr && ty->choice == 3;
    }
    return false;
}

bool approaching_stop(Leaves& l, const ir::Node& n, int32_t) { return along_path(l, n, ConditionKind::approaching_stop); }
bool traffic_light(Leaves& l, const ir::Node& n, int32_t) { return along_path(l, n, ConditionKind::traffic_light); }
bool intersection_type(Leaves& l, const ir::Node& n, int32_t) { return along_path(l, n, ConditionKind::intersection_type); }

bool yield_role(Leaves& l, const ir::Node& n, int32_t) {
    const auto& ln = l.w.net.lane(l.a.lane);
    if (ln.right_of_way < 0) return false;
    const auto& row = l.w.net.rights_of_way[static_cast<size_t>(ln.right_of_way)];
    const bool yields = std::find(row.yield.begin(), row.yield.end(), l.a.lane) != row.yield.end();
    const auto* role = l.param(n, "role");
    return role != nullptr && (role->choice == 0) == yields;
}

bool intersection_occupied(Leaves& l, const ir::Node& n, int32_t) {
    for (const Seen& s : l.view.seen) {
        const LaneId ol = snap(l, s.index).lane;
        if (ol != kNoLane && l.w.net.lane(ol).in_junction && s.dist < 60 + l.num(n, "distance")) return true;
    }
    return false;
}

// First come, first served among vehicles that came to rest at their all-way-stop lines, by
// when each first came to rest there (re-positioning up to the line keeps its place); ties by
// vehicle order. The junction must be clear, and no one who stopped at its line may be pulling
// away from it: that one has the turn until it is in the junction (else two go at once). An
// impatient driver may go out of turn (a draw per planning cycle, keyed by seed, vehicle, cycle).
bool all_way_stop_turn(Leaves& l, const ir::Node& n, int32_t) {
    const Snap& m = snap(l, l.a.index);
    if (m.stopped_since < 0) return false;
    const double mine = m.stopped_line == m.lane ? m.stopped_line_since : m.stopped_since;
    bool out_of_turn = false;
    for (const Seen& s : l.view.seen) {
        const Snap& o = snap(l, s.index);
        if (o.lane == kNoLane || s.dist >= 40) continue;
        const auto& ol = l.w.net.lane(o.lane);
        if (ol.in_junction) return false;
        if (!ol.all_way_stop || o.stopped_line != o.lane) continue;
        if (o.stopped_since < 0) return false;  // pulling away: its turn
        out_of_turn = out_of_turn || o.stopped_line_since < mine || (o.stopped_line_since == mine && s.index < l.a.index);
    }
    if (!out_of_turn) return true;
    const double after = l.num(n, "impatient_after");
    if (after <= 0 || l.t0 - mine <= after) return false;
    planner::RandomStream rng(l.w.seed, static_cast<uint32_t>(l.a.index), 0x40000000u | l.a.driver->plan_count);
    return rng.uniform() < l.num(n, "impatient_chance");
}

bool out_of_route(Leaves& l, const ir::Node&, int32_t) {
    if (l.a.goal_lane == kNoLane) return false;
    const auto& path = l.a.driver->path;
    const bool on = std::find(path.begin(), path.end(), l.a.lane) != path.end() &&
                    std::find(path.begin(), path.end(), l.a.goal_lane) != path.end();
    return !on;
}

bool wait(Leaves& l, const ir::Node& n, int32_t index) {
    Driver& d = *l.a.driver;
    auto [it, fresh] = d.waits.try_emplace(index, l.t0, d.plan_count);
    if (!fresh && it->second.second + 1 != d.plan_count && it->second.second != d.plan_count) it->second.first = l.t0;
    it->second.second = d.plan_count;
    return l.t0 - it->second.first >= l.num(n, "time") - 1e-9;
}

bool stopped_at_line(Leaves& l, const ir::Node& n, int32_t) {
    return l.a.stopped_line == l.a.lane && l.a.stopped_gap <= l.num(n, "distance");
}

enum class Arrive { junction, stop_line, crossing };

// The s of the first crosswalk crossing on `lane` at or after s (nullopt: none).
std::optional<double> crossing_after(const road::RoadNetwork& net, LaneId lane, double s) {
    std::optional<double> best;
    for (const auto& c : net.crosswalks) {
        for (const auto& x : c.crossings) {
            const double near = x.s - x.half_extent;
            if (x.lane == lane && near >= s - 0.5 && (!best || near < *best)) best = near;
        }
    }
    return best;
}

// Distance from (lane, s) along the lanes to the next junction lane (0 inside one), stop line or
// crosswalk ahead, the shortest over successors, up to `limit` (INFINITY beyond).
double distance_to(const road::RoadNetwork& net, LaneId lane, double s, Arrive at, double limit, int depth = 0) {
    if (lane == kNoLane || depth > 12) return INFINITY;
    const auto& ln = net.lane(lane);
    if (at == Arrive::junction && ln.in_junction) return 0;
    if (const auto* line = at == Arrive::stop_line ? ln.stop_line_from(s - 0.5) : nullptr) return std::max(0.0, line->s - s);
    if (at == Arrive::crossing) {
        if (auto x = crossing_after(net, lane, s)) return std::max(0.0, *x - s);
    }
    const double rest = std::max(0.0, ln.length - s);
    if (rest >= limit) return INFINITY;
    double best = INFINITY;
    for (const LaneId next : ln.successors) best = std::min(best, rest + distance_to(net, next, 0, at, limit - rest, depth + 1));
    return best;
}

bool time_to_arrival(Leaves& l, const ir::Node& n, int32_t) {
    constexpr double kLimit = 300;
    const auto* at_param = l.param(n, "at");
    const Arrive at = at_param == nullptr ? Arrive::junction : static_cast<Arrive>(at_param->choice);
    double dist = INFINITY, speed = 0;
    if (names_other(l.param(n, "vehicle"))) {
        const Seen* s = l.vehicle(n, "vehicle", false);
        if (s == nullptr) return false;
        const Snap& o = snap(l, s->index);
        // Its front bumper, predicted like everything it perceives (constant speed to t_start).
        dist = distance_to(l.w.net, o.lane, o.lane_s + 0.5 * o.length + o.speed * (l.t_start - l.t0), at, kLimit);
        speed = o.speed;
    } else {
        // Along the driver's own path, from its front bumper.
        const Driver& d = *l.a.driver;
        const double front = l.view.self.s + 0.5 * l.a.v->length;
        for (size_t i = 0; i < d.path.size(); ++i) {
            const auto& ln = l.w.net.lane(d.path[i]);
            const double start = d.path_start[i], end = start + ln.length;
            if (end < front) continue;
            if (start > front + kLimit) break;
            if (at == Arrive::junction && ln.in_junction) {
                dist = std::max(0.0, start - front);
                break;
            }
            if (const auto* line = at == Arrive::stop_line ? ln.stop_line_from(front - 0.5 - start) : nullptr) {
                dist = std::max(0.0, start + line->s - front);
                break;
            }
            if (at == Arrive::crossing) {
                if (auto x = crossing_after(l.w.net, d.path[i], front - start)) {
                    dist = std::max(0.0, start + *x - front);
                    break;
                }
            }
        }
        speed = l.view.self.s_d;
    }
    // Never arriving (standing, or nothing ahead) is an infinite time: it passes `min`, not `max`.
    const double t = dist == 0 ? 0 : speed > 0.1 ? dist / speed : INFINITY;
    return in(t, l.num(n, "min"), l.num(n, "max"));
}

bool pedestrian_crossing(Leaves& l, const ir::Node& n, int32_t) { return pedestrian_ahead(l, l.num(n, "distance")).has_value(); }

// Pedestrians' conditions: answered in pedestrian_leaves.cpp (E0411 keeps them out of vehicles' trees).
bool for_pedestrians(Leaves&, const ir::Node&, int32_t) { return false; }

constexpr size_t kConditionKinds = static_cast<size_t>(ConditionKind::accept_gap) + 1;

// Indexed by catalog::ConditionKind; each entry names its kind, so that tests/unit/sim can check
// the table against the catalog entry by entry.
constexpr std::array<ConditionEntry, kConditionKinds> kTable = {{
    {ConditionKind::sim_time, sim_time},
    {ConditionKind::vehicle_state, vehicle_state},
    {ConditionKind::delta_state, delta_state},
    {ConditionKind::gap, gap},
    {ConditionKind::ttc, ttc},
    {ConditionKind::distance, distance},
    {ConditionKind::lane_occupied, lane_occupied},
    {ConditionKind::can_lane_change, can_lane_change},
    {ConditionKind::vehicle_moving, vehicle_moving},
    {ConditionKind::vehicle_stopped, vehicle_stopped},
    {ConditionKind::vehicle_parked, vehicle_parked},
    {ConditionKind::reached_goal, reached_goal},
    {ConditionKind::at_lane_change_segment, at_lane_change_segment},
    {ConditionKind::approaching_stop, approaching_stop},
    {ConditionKind::traffic_light, traffic_light},
    {ConditionKind::stop_for_light, stop_for_light},
    {ConditionKind::intersection_type, intersection_type},
    {ConditionKind::yield_role, yield_role},
    {ConditionKind::intersection_occupied, intersection_occupied},
    {ConditionKind::all_way_stop_turn, all_way_stop_turn},
    {ConditionKind::out_of_route, out_of_route},
    {ConditionKind::wait, wait},
    {ConditionKind::stopped_at_line, stopped_at_line},
    {ConditionKind::time_to_arrival, time_to_arrival},
    {ConditionKind::pedestrian_crossing, pedestrian_crossing},
    {ConditionKind::has_target_crosswalk, for_pedestrians},
    {ConditionKind::approaching_crosswalk, for_pedestrians},
    {ConditionKind::at_crosswalk_entrance, for_pedestrians},
    {ConditionKind::on_crosswalk, for_pedestrians},
    {ConditionKind::crosswalk_exit_reached, for_pedestrians},
    {ConditionKind::crosswalk_has_light, for_pedestrians},
    {ConditionKind::pedestrian_light, for_pedestrians},
    {ConditionKind::can_cross_before_red, for_pedestrians},
    {ConditionKind::accept_gap, for_pedestrians},
}};

constexpr bool in_kind_order() {
    for (size_t i = 0; i < kTable.size(); ++i) if (static_cast<size_t>(kTable[i].kind) != i) return false;
    return true;
}
static_assert(in_kind_order(), "the condition table must follow catalog::ConditionKind");

}  // namespace

std::span<const ConditionEntry> condition_table() { return kTable; }

}  // namespace sdv::sim
