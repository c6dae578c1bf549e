#include "runtime/road/builtin_road.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sdv::road {
namespace {

constexpr double kStep = 0.5;  // m between sampled points
constexpr double kMaxLength = 1e5;

std::vector<std::string> validate(const RoadSpec& s) {
    std::vector<std::string> errs;
    if (s.lanes_forward < 0 || s.lanes_backward < 0 || s.lanes_forward + s.lanes_backward == 0 ||
        s.lanes_forward > 8 || s.lanes_backward > 8) {
        errs.push_back("road '" + s.name + "': lane counts must be 0..8 per direction, at least one lane");
    }
    if (!(s.lane_width_m >= 1 && s.lane_width_m <= 10)) errs.push_back("road '" + s.name + "': lane width must be 1..10 m");
    if (!(s.speed_limit_mps > 0 && s.speed_limit_mps <= 100)) errs.push_back("road '" + s.name + "': speed limit must be in (0, 100] m/s");
    if (s.segments.empty()) errs.push_back("road '" + s.name + "': no segments");
    double total = 0;
    // The reference line runs between the directions: a left arc has the backward lanes on its
    // inside, a right arc the forward lanes. The radius must exceed what lies inside.
    const double inside_left = s.lane_width_m * s.lanes_backward + 0.5;
    const double inside_right = s.lane_width_m * s.lanes_forward + 0.5;
    for (size_t i = 0; i < s.segments.size(); ++i) {
        const auto& g = s.segments[i];
        if (!(g.length_m > 0) || !std::isfinite(g.length_m) || g.length_m > kMaxLength) {
            errs.push_back("road '" + s.name + "': segment " + std::to_string(i + 1) + " has an invalid length");
        }
        const double inside = g.radius_m > 0 ? inside_left : inside_right;
        if (g.kind == Segment::arc && !(std::fabs(g.radius_m) > inside && std::isfinite(g.radius_m))) {
            errs.push_back("road '" + s.name + "': arc " + std::to_string(i + 1) +
                           " is tighter than the lanes on its inside (radius must exceed " + std::to_string(inside) + " m)");
        }
        total += g.length_m;
    }
    if (!(total <= kMaxLength)) errs.push_back("road '" + s.name + "': longer than 100 km");
    return errs;
}

}  // namespace

std::vector<Vec2> road_reference(const RoadSpec& spec) {
    std::vector<Vec2> pts = {spec.origin};
    Vec2 p = spec.origin;
    double th = spec.heading_rad;
    for (const auto& g : spec.segments) {
        const int n = std::max(1, static_cast<int>(std::ceil(g.length_m / kStep)));
        const double step = g.length_m / n;
        if (g.kind == Segment::straight) {
            const Vec2 start = p;
            for (int i = 1; i <= n; ++i) pts.push_back(start + (step * i) * Vec2{std::cos(th), std::sin(th)});
            p = pts.back();
        } else {
            // Exact circle: centre to the left (radius > 0) or right.
            const double r = g.radius_m;
            const Vec2 c = p + r * Vec2{-std::sin(th), std::cos(th)};
            const double th0 = th;
            for (int i = 1; i <= n; ++i) {
                const double a = th0 + step * i / r;
                pts.push_back(c + r * Vec2{std::sin(a), -std::cos(a)});
            }
            th = th0 + g.length_m / r;
            p = pts.back();
        }
    }
    return pts;
}

BuildResult build_road(const RoadSpec& spec) {
    BuildResult out;
    out.errors = validate(spec);
    if (!out.errors.empty()) return out;
    const std::vector<Vec2> ref = road_reference(spec);
    out.length = 0;
    for (const auto& g : spec.segments) out.length += g.length_m;
    const double w = spec.lane_width_m;
    std::vector<LaneId> fwd(static_cast<size_t>(spec.lanes_forward) + 1, kNoLane);
    std::vector<LaneId> bwd(static_cast<size_t>(spec.lanes_backward) + 1, kNoLane);
    // A lane `d` to the side of a line running in its driving direction (left positive).
    auto add = [&](const std::string& name, const std::vector<Vec2>& line, double d) {
        Lane l;
        l.name = name;
        l.centre = offset_polyline(line, d);
        l.left_bound = offset_polyline(line, d + 0.5 * w);
        l.right_bound = offset_polyline(line, d - 0.5 * w);
        l.width = w;
        l.speed_limit = spec.speed_limit_mps;
        return out.network.add_lane(std::move(l));
    };
    for (int k = 1; k <= spec.lanes_forward; ++k) {
        fwd[static_cast<size_t>(k)] = add(spec.name + "." + std::to_string(k), ref, -(spec.lanes_forward - k + 0.5) * w);
    }
    const std::vector<Vec2> rev(ref.rbegin(), ref.rend());
    for (int k = 1; k <= spec.lanes_backward; ++k) {
        // To the right of the reversed reference line.
        bwd[static_cast<size_t>(k)] = add(spec.name + ".-" + std::to_string(k), rev, -(k - 0.5) * w);
    }
    for (int k = 1; k < spec.lanes_forward; ++k) out.network.set_neighbours(fwd[static_cast<size_t>(k)], fwd[static_cast<size_t>(k + 1)], true);
    for (int k = 1; k < spec.lanes_backward; ++k) out.network.set_neighbours(bwd[static_cast<size_t>(k + 1)], bwd[static_cast<size_t>(k)], true);
    if (spec.lanes_forward > 0 && spec.lanes_backward > 0) {
        out.network.set_neighbours(fwd[static_cast<size_t>(spec.lanes_forward)], bwd[1], false);
    }
    return out;
}

BuildResult build_junction(const JunctionSpec& spec) {
    BuildResult out;
    const std::string& j = spec.name;
    if (!(spec.arm_length_m >= 10 && spec.arm_length_m <= 1e4) || spec.lanes_per_direction < 1 ||
        spec.lanes_per_direction > 4 || !(spec.lane_width_m >= 1 && spec.lane_width_m <= 10) ||
        !(spec.speed_limit_mps > 0 && spec.speed_limit_mps <= 100)) {
        out.errors.push_back("junction '" + j + "': invalid dimensions");
        return out;
    }
    const int n = spec.lanes_per_direction;
    const double w = spec.lane_width_m;
    const double half = n * w;  // half the junction box
    const double L = spec.arm_length_m;
    struct Arm {
        const char* name;
        Vec2 dir;  // from the centre outwards
    };
    const Arm arms[4] = {{"north", {0, 1}}, {"east", {1, 0}}, {"south", {0, -1}}, {"west", {-1, 0}}};
    auto suffix = [&](int k) { return n > 1 ? "." + std::to_string(k) : std::string(); };
    auto line = [](Vec2 a, Vec2 b) {
        std::vector<Vec2> pts;
        const int m = std::max(1, static_cast<int>(std::ceil(distance(a, b) / kStep)));
        for (int i = 0; i <= m; ++i) pts.push_back(a + (static_cast<double>(i) / m) * (b - a));
        return pts;
    };
    LaneId in[4][5], outl[4][5];
    for (int a = 0; a < 4; ++a) {
        const Vec2 u = arms[a].dir;
        const Vec2 right_of_in{-u.y, u.x};  // driving in (−u), the right side is +(−u)⊥
        for (int k = 1; k <= n; ++k) {
            // Incoming lane k: offset to the right of its driving direction (−u).
            const double off = (n - k + 0.5) * w;
            Lane li;
            li.name = j + "." + arms[a].name + ".in" + suffix(k);
            const Vec2 side = off * right_of_in;
            li.centre = line(u * (half + L) + side, u * half + side);
            li.left_bound = offset_polyline(li.centre, 0.5 * w);
            li.right_bound = offset_polyline(li.centre, -0.5 * w);
            li.width = w;
            li.speed_limit = spec.speed_limit_mps;
            li.stop_line_s = polyline_length(li.centre);
            li.all_way_stop = spec.control == JunctionSpec::stop_signs;
            in[a][k] = out.network.add_lane(std::move(li));
            Lane lo;
            lo.name = j + "." + arms[a].name + ".out" + suffix(k);
            const Vec2 oside = -off * right_of_in;
            lo.centre = line(u * half + oside, u * (half + L) + oside);
            lo.left_bound = offset_polyline(lo.centre, 0.5 * w);
            lo.right_bound = offset_polyline(lo.centre, -0.5 * w);
            lo.width = w;
            lo.speed_limit = spec.speed_limit_mps;
            outl[a][k] = out.network.add_lane(std::move(lo));
        }
        for (int k = 1; k < n; ++k) {
            out.network.set_neighbours(in[a][k], in[a][k + 1], true);
            out.network.set_neighbours(outl[a][k], outl[a][k + 1], true);
        }
        out.network.set_neighbours(in[a][n], outl[a][n], false);
    }
    // Connectors: from arm a lane k to arm b lane k, as a quadratic Bézier through the corner.
    for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) {
            if (a == b) continue;
            const int rel = (b - a + 4) % 4;  // 1: to the east of north → left turn for a car coming from north? see below
            // Coming from arm a (driving −u_a), leaving by arm b: b opposite a is straight; the
            // arm to the driver's left is a left turn.
            Turn turn = rel == 2 ? Turn::straight : (rel == 1 ? Turn::left : Turn::right);
            for (int k = 1; k <= n; ++k) {
                const Lane& li = out.network.lane(in[a][k]);
                const Lane& lo = out.network.lane(outl[b][k]);
                const Vec2 p0 = li.centre.back(), p2 = lo.centre.front();
                std::vector<Vec2> pts;
                if (turn == Turn::straight) {
                    pts = line(p0, p2);
                } else {
                    // Control point: intersection of the incoming and outgoing directions.
                    const Vec2 da = -1.0 * arms[a].dir, db = arms[b].dir;
                    const double det = cross(da, db);
                    const double t = det != 0 ? cross(p2 - p0, db) / det : 0.0;
                    const Vec2 c = p0 + t * da;
                    const int m = 40;
                    for (int i = 0; i <= m; ++i) {
                        const double s = static_cast<double>(i) / m;
                        pts.push_back((1 - s) * (1 - s) * p0 + 2 * (1 - s) * s * c + s * s * p2);
                    }
                }
                Lane lc;
                lc.name = j + "." + arms[a].name + "_to_" + arms[b].name + suffix(k);
                lc.centre = pts;
                lc.left_bound = offset_polyline(pts, 0.5 * w);
                lc.right_bound = offset_polyline(pts, -0.5 * w);
                lc.width = w;
                lc.speed_limit = spec.speed_limit_mps;
                lc.in_junction = true;
                lc.turn = turn;
                const LaneId id = out.network.add_lane(std::move(lc));
                out.network.connect(in[a][k], id);
                out.network.connect(id, outl[b][k]);
            }
        }
    }
    if (spec.control == JunctionSpec::two_way_stops) {
        RightOfWay row;
        const auto index = static_cast<int32_t>(out.network.rights_of_way.size());
        for (int a = 0; a < 4; ++a) {
            for (int k = 1; k <= n; ++k) {
                (a % 2 == 0 ? row.yield : row.priority).push_back(in[a][k]);  // arms 0, 2: north, south
                out.network.lane_mut(in[a][k]).right_of_way = index;
            }
        }
        out.network.rights_of_way.push_back(std::move(row));
    }
    if (spec.control == JunctionSpec::traffic_lights) {
        for (int g = 0; g < 2; ++g) {
            TrafficLight tl;
            tl.id = g;
            tl.name = j + (g == 0 ? ".ns" : ".ew");
            for (int a : {g, g + 2}) {  // north/south = arms 0, 2; east/west = 1, 3
                for (int k = 1; k <= n; ++k) {
                    tl.lanes.push_back(in[a][k]);
                    out.network.lane_mut(in[a][k]).traffic_lights.push_back(g);
                }
            }
            tl.position = out.network.lane(tl.lanes[0]).centre.back();
            out.network.lights.push_back(std::move(tl));
        }
    }
    out.length = L;
    return out;
}

}  // namespace sdv::road
