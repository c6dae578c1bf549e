// The social force model: see social_force.h for the model and where each constant comes from.
#include "runtime/sim/social_force.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sdv::sim::social_force {

namespace {

// Input clamps. Far beyond any map or any walker, and small enough that differences, squares
// and sums of clamped values stay finite in double precision.
constexpr double kMaxCoord = 1e7;   // m
constexpr double kMaxSpeed = 1e3;   // m/s
constexpr double kMaxSize = 1e4;    // m (radii, box lengths)
constexpr double kMaxForce = 1e6;   // m/s² accepted by step()
// exp() arguments are capped here: deep overlaps still push hard (e^20 ≈ 5·10⁸) but finitely.
constexpr double kMaxExponent = 20.0;
// Below this a length or speed counts as zero when a direction is needed.
constexpr double kTiny = 1e-9;

double clamp_finite(double x, double limit) {
    return std::isnan(x) ? 0.0 : std::clamp(x, -limit, limit);  // ±inf → ±limit, NaN → 0
}

double clamp_size(double x) { return std::max(0.0, clamp_finite(x, kMaxSize)); }

Vec2 clamp_vec(Vec2 a, double limit) { return {clamp_finite(a.x, limit), clamp_finite(a.y, limit)}; }

// |a| without std::hypot's overflow guard, which costs a third of the run time: every vector
// here is built from clamped inputs, so x² + y² stays far below the double range.
double length(Vec2 a) { return std::sqrt(dot(a, a)); }

Vec2 unit_or(Vec2 a, Vec2 fallback) {
    const double n = length(a);
    return n > kTiny ? (1.0 / n) * a : fallback;
}

Vec2 left_of(Vec2 a) { return {-a.y, a.x}; }

// strength·exp(−gap/range): the exponential repulsion every term of the model shares.
double decay(double strength, double gap, double range) {
    const double r = std::max(range, kTiny);
    return strength * std::exp(std::min(-gap / r, kMaxExponent));
}

// λ + (1 − λ)(1 + cos)/2: full weight straight ahead, λ straight behind.
double anisotropy(double lambda, double cosine) {
    return lambda + (1.0 - lambda) * 0.5 * (1.0 + std::clamp(cosine, -1.0, 1.0));
}

Obstacle sanitized(const Obstacle& o) {
    return {clamp_vec(o.centre, kMaxCoord), clamp_finite(o.yaw, kMaxCoord), clamp_size(o.length),
            clamp_size(o.width), clamp_vec(o.v, kMaxSpeed)};
}

// Signed distance and outward normal from a sanitized box to a clamped point.
BoxContact contact(const Obstacle& o, Vec2 p) {
    const Vec2 ax{std::cos(o.yaw), std::sin(o.yaw)};
    const Vec2 ay = left_of(ax);
    const Vec2 rel = p - o.centre;
    const double qx = dot(rel, ax), qy = dot(rel, ay);
    const double hx = 0.5 * o.length, hy = 0.5 * o.width;
    const Vec2 outside{qx - std::clamp(qx, -hx, hx), qy - std::clamp(qy, -hy, hy)};
    const double d = length(outside);
    if (d > 0.0) {
        const Vec2 n = (1.0 / d) * outside;
        return {d, n.x * ax + n.y * ay};
    }
    // Inside or on the outline: leave through the nearest side.
    const double depth_x = hx - std::abs(qx), depth_y = hy - std::abs(qy);
    if (depth_x <= depth_y) return {-depth_x, (qx < 0 ? -1.0 : 1.0) * ax};
    return {-depth_y, (qy < 0 ? -1.0 : 1.0) * ay};
}

// Desired-velocity relaxation, slowed on the last metres so the pedestrian stops on the target.
Vec2 desired_force(const Params& P, const State& s, Vec2 target, double v0) {
    const Vec2 to_target = target - s.p;
    const double dist = length(to_target);
    const double speed = std::min(v0, dist / std::max(P.arrival_time, kTiny));
    const Vec2 desired = speed * unit_or(to_target, {});
    return (1.0 / std::max(P.relaxation_time, kTiny)) * (desired - s.v);
}

// Which way to side-step from `o`: ±left_of(own heading), or zero when not closing in.
// The reference picks the side by the sign of v_i × v_j alone, which sends two walkers that meet
// with a small lateral offset to the same world side (they swap sides and touch). We choose
// the side that keeps the line of sight turning the way it already turns, as ships do (a
// constant bearing is a collision course); on an exact collision course both go left, as the
// reference does head-on. `own`: unit_or(s.v, {}); `distance`: length(o.p − s.p).
Vec2 side_step(const State& s, Vec2 own, const Neighbour& o, double distance) {
    const Vec2 r = o.p - s.p, dv = o.v - s.v;
    if (dot(r, dv) >= 0) return {};  // not getting closer: nothing to evade
    const double turn = cross(r, dv);
    if (std::abs(turn) <= kTiny * distance * length(dv)) return left_of(own);  // dead ahead
    // Moving along +left changes dv by −left; keep sign(turn) growing.
    const double ahead = dot(r, own);
    if (ahead == 0) return {};
    return (turn * ahead > 0 ? -1.0 : 1.0) * left_of(own);
}

// The other pedestrian's push on us [N]: body repulsion plus the evasive effect. `own`:
// unit_or(s.v, {}), the same for every neighbour (computed once by the caller, as `walk_dir`).
Vec2 pedestrian_force(const Params& P, const State& s, Vec2 own, double radius, Vec2 walk_dir,
                      const Neighbour& o) {
    const Vec2 away = s.p - o.p;
    const double distance = length(away);
    // Coincident centres: part along the relative velocity (opposite for the two), else +x.
    const Vec2 n = distance > kTiny ? (1.0 / distance) * away : unit_or(s.v - o.v, {1.0, 0.0});
    const double gap = distance - (radius + o.radius);
    Vec2 f = decay(P.ped_strength, gap, P.ped_range) * n;
    // Evading is walking: one who stands (no walking direction) keeps only the body force.
    if (walk_dir == Vec2{}) return f;

    const Vec2 theirs = unit_or(o.v, {});
    const Vec2 reflected = theirs - (2.0 * dot(theirs, own)) * own;
    const double w = anisotropy(P.ped_anisotropy, -dot(walk_dir, n));
    f = f + w * (decay(P.evade_reflect_strength, gap, P.evade_reflect_range) * reflected +
                 decay(P.evade_side_strength, gap, P.evade_side_range) * side_step(s, own, o, distance));
    return f;
}

// Which way round an obstacle that stands in the way: +1 left, −1 right of the walking
// direction. Behind it if it moves across our way. Else the way we already slide along its
// outline (t = the outline's direction here): our velocity is the only memory a pure function
// has, and without it the desired force and the detour can balance on a slanted side. Else, from
// a standstill, round the nearer edge of the silhouette seen along the walking direction; dead
// centre, left (the pedestrians' tie rule).
double detour_side(const Params& P, const Obstacle& o, const State& s, Vec2 t, Vec2 walk_dir) {
    const double across = cross(walk_dir, o.v);
    if (std::abs(across) > kTiny) return across > 0 ? -1.0 : 1.0;
    const Vec2 left = left_of(walk_dir);
    const double slide = dot(s.v, t);
    if (std::abs(slide) > P.detour_commit_speed && dot(t, left) != 0)
        return (slide > 0) == (dot(t, left) > 0) ? 1.0 : -1.0;
    const Vec2 ax{std::cos(o.yaw), std::sin(o.yaw)};
    const Vec2 hx = (0.5 * o.length) * ax, hy = (0.5 * o.width) * left_of(ax);
    double leftmost = -std::numeric_limits<double>::infinity();
    double rightmost = std::numeric_limits<double>::infinity();
    for (const Vec2 corner : {hx + hy, hx - hy, -1.0 * hx + hy, -1.0 * hx - hy}) {
        const double lateral = cross(walk_dir, o.centre + corner - s.p);
        leftmost = std::max(leftmost, lateral);
        rightmost = std::min(rightmost, lateral);
    }
    // Going left means clearing `leftmost`, going right clearing −`rightmost`.
    return leftmost + rightmost > kTiny ? -1.0 : 1.0;
}

// The detour push's direction: along the outline (perpendicular to the outward normal n),
// toward the chosen side. Not in the reference, where a pedestrian facing a car broadside stops
// in front of it for good (the desired force and the repulsion balance).
Vec2 detour(const Params& P, const Obstacle& o, const State& s, Vec2 n, Vec2 walk_dir) {
    const Vec2 t = left_of(n);
    const Vec2 side = detour_side(P, o, s, t, walk_dir) * left_of(walk_dir);
    const double along = dot(t, side);
    if (along == 0) return side;
    return along > 0 ? t : -1.0 * t;
}

// A vehicle's or object's push on us [N], from the nearest point of its outline.
Vec2 obstacle_force(const Params& P, const State& s, double radius, Vec2 walk_dir,
                    const Obstacle& o) {
    const BoxContact c = contact(o, s.p);
    const double gap = c.distance - radius;
    // Ahead of a moving vehicle counts more than behind it. The reference uses the heading even
    // when the car stands still (and so halves the push behind a parked car); a standing or
    // reversing car is measured by where it moves, and a standing one weighs fully all round.
    const Vec2 motion = unit_or(o.v, {});
    const double w = motion == Vec2{} ? 1.0
                                      : anisotropy(P.obstacle_anisotropy,
                                                   dot(motion, unit_or(s.p - o.centre, {})));
    const double push = w * decay(P.obstacle_strength, gap, P.obstacle_range) +
                        P.obstacle_body * std::max(0.0, -gap);
    const double in_the_way = std::max(0.0, -dot(walk_dir, c.normal));
    const double around = in_the_way * decay(P.evade_side_strength, gap, P.evade_side_range);
    return push * c.normal + around * detour(P, o, s, c.normal, walk_dir);
}

}  // namespace

BoxContact box_contact(const Obstacle& box, Vec2 p) {
    return contact(sanitized(box), clamp_vec(p, kMaxCoord));
}

bool standing(const Params& P, Vec2 p, Vec2 target, double desired_speed) {
    const double v0 = std::max(0.0, clamp_finite(desired_speed, kMaxSpeed));
    return !(v0 > 0) || length(clamp_vec(target, kMaxCoord) - clamp_vec(p, kMaxCoord)) < P.stand_distance;
}

double speed_cap(const Params& P, double desired_speed) {
    const double v0 = std::max(0.0, clamp_finite(desired_speed, kMaxSpeed));
    const double cap = std::max(P.max_speed_factor * v0, P.min_speed_cap);
    return std::max(0.0, std::min(cap, P.max_speed));
}

Vec2 force(const Params& P, const State& state, double radius, Vec2 target, double desired_speed,
           std::span<const Neighbour> peds, std::span<const Obstacle> obstacles) {
    const State s{clamp_vec(state.p, kMaxCoord), clamp_vec(state.v, kMaxSpeed)};
    const double r = clamp_size(radius);
    const Vec2 goal = clamp_vec(target, kMaxCoord);
    const double v0 = std::max(0.0, clamp_finite(desired_speed, kMaxSpeed));

    const Vec2 walk_dir = standing(P, s.p, goal, v0) ? Vec2{} : unit_or(goal - s.p, {});
    const Vec2 own = unit_or(s.v, {});
    Vec2 push{};  // newtons
    for (const Neighbour& n : peds) {
        const Neighbour o{clamp_vec(n.p, kMaxCoord), clamp_vec(n.v, kMaxSpeed), clamp_size(n.radius)};
        push = push + pedestrian_force(P, s, own, r, walk_dir, o);
    }
    for (const Obstacle& o : obstacles) push = push + obstacle_force(P, s, r, walk_dir, sanitized(o));

    const Vec2 total = desired_force(P, s, goal, v0) + (1.0 / std::max(P.mass, kTiny)) * push;
    // Sums of many capped exponentials can still overflow for absurd parameter values.
    return clamp_vec(total, kMaxForce);
}

State step(const Params& P, const State& state, Vec2 f, double desired_speed, double dt) {
    const State s{clamp_vec(state.p, kMaxCoord), clamp_vec(state.v, kMaxSpeed)};
    const double h = std::clamp(clamp_finite(dt, 1.0), 0.0, 1.0);
    Vec2 v = s.v + h * clamp_vec(f, kMaxForce);
    const double cap = speed_cap(P, desired_speed);
    const double speed = length(v);
    if (speed > cap) v = (speed > 0 ? cap / speed : 0.0) * v;
    return {clamp_vec(s.p + h * v, kMaxCoord), v};
}

}  // namespace sdv::sim::social_force
