// The simulated pedestrian's motion model and its way (pedestrian.h).
#include "runtime/sim/pedestrian.h"

#include <algorithm>
#include <cmath>

#include "runtime/sim/agents.h"
#include "runtime/sim/social_force.h"

namespace sdv::sim {
namespace {

using road::Vec2;

// Neighbours farther than this exert no noticeable force (the largest range of the model is
// under 1 m; a car's box is measured from its centre, so add half a bus).
constexpr double kNeighbourRadius = 12.0;  // m
// A standing pedestrian (desired speed 0, or at its target) does not evade (social_force.h):
// only body forces move it, and those of anything farther than this gap are negligible (the
// obstacle force, the longer-ranged, is 1500 N · e^(−2/0.25) = 0.5 N there: under 0.01 m/s²).
constexpr double kStandReach = 2.0;  // m
// A standing pedestrian slower than this has come to rest.
constexpr double kRestSpeed = 0.005;  // m/s
// A pedestrian at rest keeps its feet against a push (per unit mass) weaker than this: a standing
// neighbour's body 0.3 m away, and the pull of a target within the stand distance.
constexpr double kHold = 0.5;  // m/s²
// ... also when it is only creeping (pushed apart from a neighbour, slower than this).
constexpr double kCreep = 0.05;  // m/s
// Without a goal a pedestrian walks straight ahead: toward a point this far along its heading.
constexpr double kAhead = 1000.0;  // m
// Slower than this a pedestrian shuffles in place (jostled in a crowd): it keeps facing where it
// faced.
constexpr double kTurnSpeed = 0.3;  // m/s
constexpr double kRelocate = 1.0;  // m walked between two searches of the lane it is by
constexpr double kStripEdge = 0.1;  // m a crosser keeps from the crosswalk's side edges

// std::hypot(dx, dy) > r, as std::hypot decides it, for r of a few metres: the squares decide
// but within a relative 1e-9 of r, far beyond the rounding of either (std::hypot cost more than
// the rest of gathering a neighbour).
bool beyond(double dx, double dy, double r) {
    const double d2 = dx * dx + dy * dy;
    if (d2 < r * r * (1 - 1e-9)) return false;
    if (d2 > r * r * (1 + 1e-9)) return true;
    return std::hypot(dx, dy) > r;
}

class WalkerModel final : public AgentModel {
public:
    const char* kind() const override { return "pedestrian"; }
    void advance(const World& w, Agent& a, double t, int tick) const override {
        (void)t;
        const double was_x = a.x, was_y = a.y;
        if (tick > 0) move(w, a);
        // At rest where it was: still where it was on the road.
        if (tick > 0 && a.x == was_x && a.y == was_y && a.lane != kNoLane) return;
        // The lane it is by: searched over the whole network once it has moved kRelocate from
        // where it was last searched (a walker's lane changes slowly), else projected on it.
        road::RoadNetwork::Location at{a.lane, 0, 0};
        if (a.lane == kNoLane || !(std::hypot(a.x - a.walker->located_x, a.y - a.walker->located_y) < kRelocate)) {
            at = w.net.locate({a.x, a.y});
            a.walker->located_x = a.x;
            a.walker->located_y = a.y;
        } else {
            const auto f = w.net.reference(a.lane).project({a.x, a.y}, a.lane_s);
            at = {a.lane, f.s, f.d};
        }
        a.lane = at.lane;
        if (a.lane != kNoLane) {
            a.lane_s = at.s;
            a.lane_d = at.d;
            a.centre_lane = at.s >= 0 && at.s <= w.net.lane(a.lane).length ? centre_lane(w.net, a.lane, at.d) : kNoLane;
        }
    }

private:
    // One social-force step over the previous tick's snapshot (the neighbours as they were).
    static void move(const World& w, Agent& a) {
        static const social_force::Params params;
        thread_local std::vector<int> near;
        thread_local std::vector<social_force::Neighbour> peds;
        thread_local std::vector<social_force::Obstacle> boxes;
        peds.clear();
        boxes.clear();
        const Intent in = intent(w, a);
        const double radius = 0.5 * std::max(a.v->length, a.v->width);
        // Standing, it gathers only the bodies within reach: their centres are at most the
        // largest half diagonal of any agent beyond their outline.
        const bool standing = social_force::standing(params, {a.x, a.y}, in.target, in.speed);
        const double reach = standing ? radius + kStandReach + w.widest_reach : kNeighbourRadius;
        if (!w.snapshot.empty()) {
            w.grid.query(a.x, a.y, reach, near);
            for (const int j : near) {
                if (j == a.index) continue;
                const Snap& o = w.snapshot[static_cast<size_t>(j)];
                if (!o.active || beyond(o.x - a.x, o.y - a.y, reach)) continue;
                if (o.pedestrian) {
                    peds.push_back({{o.x, o.y}, {o.vx, o.vy}, 0.5 * std::max(o.length, o.width)});
                } else {
                    boxes.push_back({{o.x, o.y}, o.yaw, o.length, o.width, {o.vx, o.vy}});
                }
            }
        }
        const social_force::State s{{a.x, a.y}, {a.vx, a.vy}};
        const Vec2 f = social_force::force(params, s, radius, in.target, in.speed, peds, boxes);
        social_force::State n = social_force::step(params, s, f, in.speed, w.dt);
        // Standing, it comes to rest once it has slowed to a standstill, and at rest (or
        // creeping) it keeps its feet against pushes weaker than kHold.
        if (standing && (norm(n.v) < kRestSpeed || (norm(s.v) < kCreep && norm(f) < kHold))) n = {s.p, {}};
        const double old_speed = a.speed;
        a.x = n.p.x;
        a.y = n.p.y;
        a.vx = n.v.x;
        a.vy = n.v.y;
        a.ax = f.x;
        a.ay = f.y;
        a.speed = norm(n.v);
        if (a.speed > kTurnSpeed) a.yaw = std::atan2(n.v.y, n.v.x);
        a.accel = (a.speed - old_speed) / w.dt;
        // The far end of the crosswalk reached: the crossing is done; back at the entrance
        // (turn_back): approaching it again.
        Walker& k = *a.walker;
        if (k.crosswalk >= 0) {
            const auto& c = w.net.crosswalks[static_cast<size_t>(k.crosswalk)];
            const Vec2 p{a.x, a.y};
            if (k.phase == Walker::Phase::crossing && distance(p, crosswalk_point(c, k, 1 - k.entrance)) <= k.arrive) {
                k.phase = Walker::Phase::done;
            } else if (k.phase == Walker::Phase::back && distance(p, crosswalk_point(c, k, k.entrance)) <= k.arrive) {
                k.phase = Walker::Phase::approaching;
            }
        }
    }
};

// The pedestrian signal state of a light state, through `inverse`.
std::string signal_of(const std::string& light, bool inverse) {
    if (!inverse) return light;
    return light == "red" ? "green" : "red";
}

}  // namespace

std::shared_ptr<const AgentModel> make_walker_model() { return std::make_shared<WalkerModel>(); }

Vec2 crosswalk_end(const road::Crosswalk& c, int end) { return end == 0 ? c.centre.front() : c.centre.back(); }

// The unit normal (left of the centre line's direction) at an end of a crosswalk.
Vec2 crosswalk_normal(const road::Crosswalk& c, int end) {
    const size_t n = c.centre.size();
    const Vec2 d = end == 0 ? c.centre[1] - c.centre[0] : c.centre[n - 1] - c.centre[n - 2];
    const double len = std::max(norm(d), 1e-9);
    return {-d.y / len, d.x / len};
}

Vec2 crosswalk_point(const road::Crosswalk& c, const Walker& k, int end) {
    return crosswalk_end(c, end) + k.cross_offset * crosswalk_normal(c, end);
}

double crosswalk_offset(const road::Crosswalk& c, int entrance, Vec2 p, double radius) {
    const double room = std::max(0.0, 0.5 * c.width - radius - kStripEdge);
    return std::clamp(dot(p - crosswalk_end(c, entrance), crosswalk_normal(c, entrance)), -room, room);
}

Intent intent(const World& w, const Agent& a) {
    const Walker& k = *a.walker;
    if (k.crosswalk >= 0 && k.phase != Walker::Phase::done && k.phase != Walker::Phase::none) {
        const auto& c = w.net.crosswalks[static_cast<size_t>(k.crosswalk)];
        const Vec2 to = crosswalk_point(c, k, k.phase == Walker::Phase::crossing ? 1 - k.entrance : k.entrance);
        return {to, k.speed};
    }
    if (k.has_goal) return {k.goal, k.speed};
    return {{a.x + kAhead * std::cos(a.yaw), a.y + kAhead * std::sin(a.yaw)}, k.speed};
}

std::vector<WayCrosswalk> crosswalks_on_way(const World& w, Vec2 p, Vec2 goal, double max_detour) {
    std::vector<WayCrosswalk> out;
    const double straight = distance(p, goal);
    for (size_t i = 0; i < w.net.crosswalks.size(); ++i) {
        const auto& c = w.net.crosswalks[i];
        if (c.centre.size() < 2 || c.crossings.empty()) continue;
        const int entrance = distance(p, crosswalk_end(c, 0)) <= distance(p, crosswalk_end(c, 1)) ? 0 : 1;
        // Crossing it brings the pedestrian nearer to its goal: its far end is the nearer one.
        if (distance(crosswalk_end(c, 1 - entrance), goal) >= distance(crosswalk_end(c, entrance), goal)) continue;
        const double to = distance(p, crosswalk_end(c, entrance));
        const double detour = to + c.length + distance(crosswalk_end(c, 1 - entrance), goal) - straight;
        if (detour > max_detour) continue;
        out.push_back({static_cast<int32_t>(i), entrance, detour, to});
    }
    std::stable_sort(out.begin(), out.end(), [](const WayCrosswalk& x, const WayCrosswalk& y) { return x.distance < y.distance; });
    return out;
}

std::string pedestrian_signal(const World& w, int32_t crosswalk, double t) {
    if (crosswalk < 0) return "";
    const auto& c = w.net.crosswalks[static_cast<size_t>(crosswalk)];
    if (c.light < 0) return "";
    return signal_of(w.light_state(c.light, t), c.light_inverse);
}

double time_until_red(const World& w, int32_t crosswalk, double t) {
    if (crosswalk < 0) return INFINITY;
    const auto& c = w.net.crosswalks[static_cast<size_t>(crosswalk)];
    if (c.light < 0) return INFINITY;
    if (signal_of(w.light_state(c.light, t), c.light_inverse) == "red") return 0;
    auto it = w.programs.find(w.net.lights[static_cast<size_t>(c.light)].name);
    if (it == w.programs.end() || it->second->phases.empty()) return INFINITY;  // a fixed state
    // Walk the program's phase boundaries from t for one cycle.
    const auto& ph = it->second->phases;
    double total = 0;
    for (const auto& x : ph) total += x.duration;
    if (!(total > 0)) return INFINITY;
    double u = std::fmod(t + it->second->offset, total);
    size_t k = 0;
    while (k + 1 < ph.size() && u >= ph[k].duration) u -= ph[k++].duration;
    double left = ph[k].duration - u;
    for (size_t n = 1; n <= ph.size(); ++n) {
        const auto& next = ph[(k + n) % ph.size()];
        if (signal_of(next.state, c.light_inverse) == "red") return left;
        left += next.duration;
    }
    return INFINITY;
}

}  // namespace sdv::sim
