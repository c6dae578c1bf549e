// Drivers yielding to pedestrians: who, among the pedestrians a driver perceives, it must let
// pass, and where it stops for them (the `pedestrian_crossing` condition and `stop(at =
// pedestrian)`, docs/pedestrians.md).
#include <algorithm>
#include <cmath>

#include "runtime/sim/leaves.h"
#include "runtime/sim/pedestrian.h"

namespace sdv::sim {
namespace {

using road::Vec2;

constexpr double kEntranceZone = 3.0;   // m beyond the carriageway's edge where a pedestrian waits to enter
constexpr double kStripMargin = 0.5;    // m beside the strip that still counts as on it
constexpr double kNearLane = 2.5;       // m beyond the driver's lane edge: close enough to yield
constexpr double kStandingSpeed = 0.2;  // m/s
constexpr double kBeforeCrosswalk = 1.0;   // m between the front bumper and the crosswalk's edge
constexpr double kBeforePedestrian = 2.0;  // m between the front bumper and a pedestrian off crosswalks
constexpr double kHeadingOnto = 0.5;  // cos of the angle within which a walker heads onto the carriageway
constexpr double kFacing = 0.3;  // cos of the angle within which a standing pedestrian faces the crosswalk
constexpr double kEntering = 3.0;  // s: a pedestrian walking into the lane within this is yielded to

// Where p is along a polyline (arc length, possibly < 0 or > length beyond its ends) and how far
// beside it.
struct Along {
    double s = 0, off = INFINITY;
};
Along along(const std::vector<Vec2>& line, Vec2 p) {
    Along best;
    double s0 = 0;
    for (size_t i = 0; i + 1 < line.size(); ++i) {
        const Vec2 d = line[i + 1] - line[i];
        const double len = norm(d);
        if (len < 1e-9) continue;
        double u = dot(p - line[i], d) / len;
        const bool first = i == 0, last = i + 2 == line.size();
        const double clamped = std::clamp(u, first ? -INFINITY : 0.0, last ? INFINITY : len);
        const Vec2 q = line[i] + (clamped / len) * d;
        const double off = distance(p, q);
        if (off < best.off) best = {s0 + clamped, off};
        s0 += len;
    }
    return best;
}

// The part of a crosswalk over the lanes it crosses, as arc lengths along its centre line (the
// rest is kerb, island or verge).
std::pair<double, double> carriageway(const road::RoadNetwork& net, const road::Crosswalk& c) {
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& x : c.crossings) {
        const auto& ref = net.reference(x.lane);
        const double a = along(c.centre, ref.point(std::clamp(x.s, 0.0, ref.length()))).s;
        const double half = 0.5 * net.lane(x.lane).width;
        lo = std::min(lo, a - half);
        hi = std::max(hi, a + half);
    }
    if (lo > hi) return {0.0, c.length};
    return {lo, hi};
}

}  // namespace

std::optional<Yield> pedestrian_ahead(const Leaves& l, double distance_limit) {
    const World& w = l.w;
    const Agent& a = l.a;
    const Driver& d = *a.driver;
    const double front = l.view.self.s + 0.5 * a.v->length;
    const double half_lane = 0.5 * l.view.lane_width;
    std::optional<Yield> best;
    auto consider = [&](int who, double front_stop) {
        const double stop_s = front_stop - 0.5 * a.v->length;
        if (!best || stop_s < best->stop_s) best = Yield{who, stop_s};
    };
    // The crosswalks across its path ahead, each where its front would stop before it.
    for (size_t i = 0; i < d.path.size(); ++i) {
        const double start = d.path_start[i];
        if (start > front + distance_limit) break;
        for (const auto& c : w.net.crosswalks) {
            for (const auto& x : c.crossings) {
                if (x.lane != d.path[i]) continue;
                const double edge = start + x.s - x.half_extent;
                // Already on it (its front past the near edge), or beyond the look-ahead.
                if (edge < front - 0.5 || edge - front > distance_limit) continue;
                const auto [road_lo, road_hi] = carriageway(w.net, c);
                // Those `along` could place on the strip are within its arc length plus its
                // offset of the centre line's first point: a cheap test first (with room for
                // rounding), which leaves the exact one to decide (`along` costs two hypot a
                // segment, for every pedestrian in sensor range).
                const double reach = std::max(std::fabs(road_lo - kEntranceZone), std::fabs(road_hi + kEntranceZone)) +
                                     0.5 * c.width + kStripMargin;
                const double reach2 = (reach * (1 + 1e-9) + 1e-6) * (reach * (1 + 1e-9) + 1e-6);
                for (const Seen& s : l.view.seen) {
                    const Snap& o = w.snapshot[static_cast<size_t>(s.index)];
                    if (!o.pedestrian) continue;
                    // Near its lane, or walking toward it (tested first: it is cheap); off the
                    // carriageway (on the kerb part of the crosswalk or at its end), only when
                    // heading onto it.
                    const bool near = std::fabs(s.f.d) <= half_lane + kNearLane;
                    const bool toward = s.f.d * s.f.d_d < -0.05;
                    if (!near && !toward) continue;
                    if (c.centre.empty()) continue;  // `along` places no one on it
                    const Vec2 from_first = Vec2{o.x, o.y} - c.centre.front();
                    if (dot(from_first, from_first) > reach2) continue;
                    const Along at = along(c.centre, {o.x, o.y});
                    if (at.off > 0.5 * c.width + kStripMargin || at.s < road_lo - kEntranceZone || at.s > road_hi + kEntranceZone) continue;
                    if (at.s < road_lo || at.s > road_hi) {
                        // Walking onto the carriageway, or standing there waiting to cross (a
                        // simulated pedestrian's intent shows; one that follows waypoints waits
                        // when it faces the crosswalk, one who has crossed faces away from it).
                        Vec2 into = at.s < road_lo ? c.centre[1] - c.centre[0] : c.centre[c.centre.size() - 2] - c.centre.back();
                        into = (1.0 / std::max(norm(into), 1e-9)) * into;
                        const bool standing = std::hypot(o.vx, o.vy) < kStandingSpeed;
                        const bool waits = o.intent ? o.crossing_at == c.id : dot({std::cos(o.yaw), std::sin(o.yaw)}, into) > kFacing;
                        const double speed = std::hypot(o.vx, o.vy);
                        if (standing ? !waits : dot({o.vx, o.vy}, into) <= kHeadingOnto * speed) continue;
                    }
                    consider(s.index, edge - kBeforeCrosswalk);
                }
            }
        }
    }
    // A pedestrian in its lane ahead, or walking into it within kEntering, on no crosswalk it
    // yields at.
    for (const Seen& s : l.view.seen) {
        const Snap& o = w.snapshot[static_cast<size_t>(s.index)];
        if (!o.pedestrian) continue;
        const double outside = std::fabs(s.f.d) - (half_lane + 0.5 * std::max(o.length, o.width));
        const bool entering = s.f.d * s.f.d_d < 0 && outside < kEntering * std::fabs(s.f.d_d);
        if (outside > 0 && !entering) continue;
        const double back = s.f.s - 0.5 * o.length;
        if (back < front - 0.5 || back - front > distance_limit) continue;
        consider(s.index, back - kBeforePedestrian);
    }
    return best;
}

}  // namespace sdv::sim
