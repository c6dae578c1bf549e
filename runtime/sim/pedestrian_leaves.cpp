// The leaves of a pedestrian's tree (docs/catalog.md, pedestrian maneuvers and conditions): the
// conditions read the snapshot, the road and the pedestrian's way; the maneuvers set its intent
// (world.h `Walker`), which its motion model follows from the next tick.
#include <algorithm>
#include <cmath>

#include "runtime/catalog/catalog.h"
#include "runtime/sim/leaves.h"
#include "runtime/sim/pedestrian.h"

namespace sdv::sim {
namespace {

using catalog::ConditionKind;
using catalog::ManeuverKind;
using road::Vec2;
using Phase = Walker::Phase;

constexpr double kArrivalHorizon = 300.0;  // m: a vehicle farther along its lanes never arrives
constexpr double kMovingSpeed = 0.1;       // m/s: slower than this a vehicle never arrives

bool in(double x, double lo, double hi) { return (std::isnan(lo) || x >= lo) && (std::isnan(hi) || x <= hi); }

// Where segment ab meets segment cd, as the fraction along ab (nullopt: they do not meet).
std::optional<double> meet(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const Vec2 r = b - a, q = d - c;
    const double den = cross(r, q);
    if (std::fabs(den) < 1e-12) return std::nullopt;
    const double t = cross(c - a, q) / den, u = cross(c - a, r) / den;
    if (t < 0 || t > 1 || u < 0 || u > 1) return std::nullopt;
    return t;
}

class PedestrianLeaves final : public bt::TickContext {
public:
    PedestrianLeaves(const World& world, Agent& agent, double t) : w(world), a(agent), k(*agent.walker), t0(t) {}

    bool condition(const ir::Node& n, int32_t index) override {
        const Vec2 p{a.x, a.y};
        switch (static_cast<ConditionKind>(n.leaf)) {
            case ConditionKind::sim_time: return in(t0, num(n, "after"), num(n, "before"));
            case ConditionKind::wait: {
                auto [it, fresh] = k.waits.try_emplace(index, t0, k.cycles);
                if (!fresh && it->second.second + 1 != k.cycles && it->second.second != k.cycles) it->second.first = t0;
                it->second.second = k.cycles;
                return t0 - it->second.first >= num(n, "time") - 1e-9;
            }
            case ConditionKind::reached_goal: return k.has_goal && distance(p, k.goal) <= num(n, "distance");
            case ConditionKind::distance: {
                const Snap* o = other(n);
                return o != nullptr && in(std::hypot(o->x - a.x, o->y - a.y), num(n, "min"), num(n, "max"));
            }
            case ConditionKind::vehicle_moving: {
                const Snap* o = subject(n);
                return o != nullptr && std::fabs(o->speed) > num(n, "min_speed");
            }
            case ConditionKind::vehicle_stopped: {
                const Snap* o = subject(n);
                return o != nullptr && std::fabs(o->speed) <= num(n, "max_speed");
            }
            case ConditionKind::time_to_arrival: {
                const Snap* o = other(n);
                if (o == nullptr) return false;
                const double t = arrival(*o);
                return std::isfinite(t) && in(t, num(n, "min"), num(n, "max"));
            }
            case ConditionKind::has_target_crosswalk: return target_phase();
            case ConditionKind::approaching_crosswalk: {
                if (!k.has_goal) return false;
                const auto on_way = crosswalks_on_way(w, p, k.goal, num(n, "max_detour"));
                const bool crossed = k.phase == Phase::done;  // the one it has just crossed does not count
                return std::any_of(on_way.begin(), on_way.end(), [&](const WayCrosswalk& c) {
                    return !(crossed && c.crosswalk == k.crosswalk) && c.distance <= num(n, "distance");
                });
            }
            case ConditionKind::at_crosswalk_entrance:
                return target_phase() && k.phase != Phase::crossing && distance(p, end(k.entrance)) <= num(n, "distance");
            case ConditionKind::on_crosswalk: return k.crosswalk >= 0 && (k.phase == Phase::crossing || k.phase == Phase::back);
            case ConditionKind::crosswalk_exit_reached:
                return k.crosswalk >= 0 && k.phase == Phase::crossing && distance(p, end(1 - k.entrance)) <= num(n, "distance");
            case ConditionKind::crosswalk_has_light: return target_phase() && crosswalk().light >= 0;
            case ConditionKind::pedestrian_light: {
                const auto* state = param(n, "state");
                if (!target_phase() || state == nullptr) return false;
                const auto& choices = catalog::condition(ConditionKind::pedestrian_light).params[0].choices;
                return pedestrian_signal(w, k.crosswalk, t0) == choices[static_cast<size_t>(state->choice)];
            }
            case ConditionKind::can_cross_before_red: {
                if (!target_phase()) return false;
                const double left = time_until_red(w, k.crosswalk, t0);
                if (std::isinf(left)) return true;
                const double rest = k.phase == Phase::crossing ? distance(p, end(1 - k.entrance))
                                                               : distance(p, end(k.entrance)) + crosswalk().length;
                return rest / std::max(k.base_speed, kMovingSpeed) + num(n, "margin") < left;
            }
            case ConditionKind::accept_gap: return accept_gap(num(n, "time"), num(n, "distance"));
            default: return false;  // vehicle conditions: the checker keeps them out of pedestrians' trees
        }
    }

    bt::Status maneuver(const ir::Node& n, int32_t) override {
        const auto speed = [&] { return std::max(0.0, num(n, "speed")); };
        switch (static_cast<ManeuverKind>(n.leaf)) {
            case ManeuverKind::walk:
                k.base_speed = k.speed = speed();
                k.arrive = num(n, "arrive");
                if (const auto* m = param(n, "meet"); m != nullptr && m->vehicle.kind == ir::VehicleRef::Kind::vehicle && target_phase()) {
                    k.speed = meeting_speed(w.snapshot[static_cast<size_t>(m->vehicle.vehicle)]);
                }
                return bt::Status::success;
            case ManeuverKind::stand: k.speed = 0; return bt::Status::success;
            case ManeuverKind::wait_at_crosswalk:
                if (!target_phase() || k.phase == Phase::crossing) return bt::Status::failure;
                k.phase = Phase::approaching;
                k.base_speed = k.speed = speed();
                return bt::Status::success;
            case ManeuverKind::enter_crosswalk:
                if (!target_phase()) return bt::Status::failure;
                k.phase = Phase::crossing;
                k.base_speed = k.speed = speed();
                return bt::Status::success;
            case ManeuverKind::exit_crosswalk:
                if (!target_phase()) return bt::Status::failure;
                k.phase = Phase::done;
                k.base_speed = k.speed = speed();
                return bt::Status::success;
            case ManeuverKind::turn_back:
                if (k.crosswalk < 0 || k.phase != Phase::crossing) return bt::Status::failure;
                k.phase = Phase::back;
                k.base_speed = k.speed = speed();
                return bt::Status::success;
            case ManeuverKind::select_crosswalk: return select(n);
            case ManeuverKind::speed_up:
                k.speed = std::min(num(n, "max_speed"), std::max(k.base_speed, kMovingSpeed) * num(n, "factor"));
                return bt::Status::success;
            default: return bt::Status::failure;  // vehicle maneuvers: kept out by the checker
        }
    }

private:
    const ir::ParamValue* param(const ir::Node& n, const char* name) const { return leaf_param(n, name); }
    double num(const ir::Node& n, const char* name) const { return leaf_number(n, name, k.tree->instance(), w.seed, a.index); }

    // The agent a `vehicle` parameter names, within sensor range (null: none).
    const Snap* other(const ir::Node& n) const {
        const auto* p = param(n, "vehicle");
        if (p == nullptr || p->vehicle.kind != ir::VehicleRef::Kind::vehicle) return nullptr;
        const Snap& o = w.snapshot[static_cast<size_t>(p->vehicle.vehicle)];
        const bool seen = o.active && std::hypot(o.x - a.x, o.y - a.y) <= w.scenario.sensor_range;
        return seen ? &o : nullptr;
    }
    const Snap* subject(const ir::Node& n) const {
        const auto* p = param(n, "vehicle");
        if (p == nullptr || p->vehicle.kind != ir::VehicleRef::Kind::vehicle) return &w.snapshot[static_cast<size_t>(a.index)];
        return other(n);
    }

    // The speed that brings it to where the vehicle's heading crosses its target crosswalk's
    // centre line when the vehicle gets there (sp/ManeuverModels.plan_keep_in_lane); 0 while the
    // vehicle heads for no point of it. At most 10 m/s.
    double meeting_speed(const Snap& o) const {
        const double v = std::hypot(o.vx, o.vy);
        if (!o.active || v < 0.1) return 0;
        const Vec2 from{o.x, o.y}, dir{o.vx / v, o.vy / v};
        const auto& c = crosswalk().centre;
        for (size_t j = 0; j + 1 < c.size(); ++j) {
            const Vec2 seg = c[j + 1] - c[j];
            const double den = road::cross(dir, seg);
            if (std::fabs(den) < 1e-12) continue;
            const Vec2 q = c[j] - from;
            const double along = road::cross(q, seg) / den;
            const double u = road::cross(q, dir) / den;
            if (along <= 0 || u < 0 || u > 1) continue;
            const Vec2 meet = c[j] + u * seg;
            return std::min(10.0, distance({a.x, a.y}, meet) * v / along);
        }
        return 0;
    }

    bool target_phase() const {
        return k.crosswalk >= 0 && (k.phase == Phase::approaching || k.phase == Phase::crossing || k.phase == Phase::back);
    }
    const road::Crosswalk& crosswalk() const { return w.net.crosswalks[static_cast<size_t>(k.crosswalk)]; }
    Vec2 end(int e) const { return crosswalk_point(crosswalk(), k, e); }

    // The part of its way where vehicles cross it: its target crosswalk (from where it is on it),
    // else the straight way to where it walks.
    std::pair<Vec2, Vec2> way() const {
        const Vec2 p{a.x, a.y};
        if (target_phase()) return {k.phase == Phase::crossing ? p : end(k.entrance), end(1 - k.entrance)};
        return {p, intent(w, a).target};
    }

    // When a vehicle's front reaches the way along its lanes at its speed (+inf: never, within
    // kArrivalHorizon; 0: its front is past the way's line while its body still covers it is not
    // detected, the motion model keeps the pedestrian off its box).
    double arrival(const Snap& o) const {
        if (o.lane == kNoLane || o.pedestrian || o.is_static || o.speed < kMovingSpeed) return INFINITY;
        const auto [w0, w1] = way();
        LaneId lane = o.lane;
        double skip = o.lane_s + 0.5 * o.length;  // from its front bumper
        double travelled = 0;
        for (int depth = 0; depth < 16 && lane != kNoLane && travelled < kArrivalHorizon; ++depth) {
            const auto& c = w.net.lane(lane).centre;
            double s = 0;
            for (size_t i = 0; i + 1 < c.size(); ++i) {
                const double len = distance(c[i], c[i + 1]);
                if (s + len >= skip) {
                    const double f0 = std::clamp((skip - s) / std::max(len, 1e-9), 0.0, 1.0);
                    const Vec2 from = c[i] + f0 * (c[i + 1] - c[i]);
                    if (auto f = meet(from, c[i + 1], w0, w1)) {
                        return (travelled + *f * distance(from, c[i + 1])) / o.speed;
                    }
                    travelled += distance(from, c[i + 1]);
                }
                s += len;
            }
            const auto& succ = w.net.lane(lane).successors;
            lane = succ.empty() ? kNoLane : succ.front();
            skip = 0;
        }
        return INFINITY;
    }

    bool accept_gap(double time, double dist) const {
        for (const Snap& o : w.snapshot) {
            if (&o == &w.snapshot[static_cast<size_t>(a.index)] || !o.active || o.pedestrian || o.is_static) continue;
            if (std::hypot(o.x - a.x, o.y - a.y) > w.scenario.sensor_range) continue;
            const double t = arrival(o);
            if (std::isfinite(t) && t * o.speed <= dist && t < time) return false;
        }
        return true;
    }

    bt::Status select(const ir::Node& n) {
        if (!k.has_goal) return bt::Status::failure;
        if (k.crosswalk >= 0 && (k.phase == Phase::crossing || k.phase == Phase::back)) return bt::Status::success;
        auto on_way = crosswalks_on_way(w, {a.x, a.y}, k.goal, num(n, "max_detour"));
        // Never the one it has just crossed (however the way looks from its far end).
        if (k.phase == Phase::done) {
            std::erase_if(on_way, [&](const WayCrosswalk& c) { return c.crosswalk == k.crosswalk; });
        }
        if (on_way.empty()) return bt::Status::failure;
        const WayCrosswalk* pick = &on_way.front();
        const auto* by = param(n, "by");
        if (by != nullptr && by->choice == 1) {
            for (const auto& c : on_way) {
                if (pedestrian_signal(w, c.crosswalk, t0) == "green") {
                    pick = &c;
                    break;
                }
            }
        }
        if (pick->crosswalk != k.crosswalk || k.phase == Phase::none || k.phase == Phase::done) {
            k.crosswalk = pick->crosswalk;
            k.entrance = pick->entrance;
            k.phase = Phase::approaching;
            const auto& c = w.net.crosswalks[static_cast<size_t>(k.crosswalk)];
            k.cross_offset = crosswalk_offset(c, k.entrance, {a.x, a.y}, 0.5 * std::max(a.v->length, a.v->width));
        }
        return bt::Status::success;
    }

    const World& w;
    Agent& a;
    Walker& k;
    const double t0;
};

}  // namespace

void walk_cycle(const World& w, Agent& a, double t) {
    Walker& k = *a.walker;
    ++k.cycles;
    k.cycle_time = t;
    PedestrianLeaves leaves(w, a, t);
    k.visits.clear();
    k.tree->tick(leaves, w.options.trace ? &k.visits : nullptr);
    k.maneuver = k.tree->selected();
    k.maneuver_name = k.maneuver >= 0 ? k.tree->instance().nodes[static_cast<size_t>(k.maneuver)].name : "none";
}

}  // namespace sdv::sim
