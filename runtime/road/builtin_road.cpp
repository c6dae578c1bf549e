#include "runtime/road/builtin_road.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sdv::road {
namespace {

constexpr double kStep = 0.5;  // m between sampled points
constexpr double kMaxLength = 1e5;
// Crosswalk ends lie this far beyond the outermost lane edges (on the kerb); stop lines this far
// before a crosswalk.
constexpr double kKerb = 2.0;
constexpr double kStopGap = 1.0;

struct Arm {
    const char* name;
    Vec2 dir;  // from the centre outwards
};
const Arm kArms[4] = {{"north", {0, 1}}, {"east", {1, 0}}, {"south", {0, -1}}, {"west", {-1, 0}}};

int arm_index(const std::string& name) {
    for (int a = 0; a < 4; ++a) {
        if (name == kArms[a].name) return a;
    }
    return -1;
}

// Points from a to b at most kStep apart.
std::vector<Vec2> sampled_line(Vec2 a, Vec2 b) {
    std::vector<Vec2> pts;
    const int m = std::max(1, static_cast<int>(std::ceil(distance(a, b) / kStep)));
    for (int i = 0; i <= m; ++i) pts.push_back(a + (static_cast<double>(i) / m) * (b - a));
    return pts;
}

// The checks every crosswalk spec shares, by road or junction: name and width, and names
// unique. `where` prefixes each message ("road 'r'").
void validate_crosswalk_basics(const std::vector<CrosswalkSpec>& cws, const std::string& where,
                               std::vector<std::string>& errs) {
    for (size_t i = 0; i < cws.size(); ++i) {
        const auto& c = cws[i];
        const std::string at = where + ": crosswalk '" + c.name + "'";
        if (c.name.empty()) errs.push_back(where + ": crosswalk " + std::to_string(i + 1) + " has no name");
        if (!(c.width_m >= 1 && c.width_m <= 20)) errs.push_back(at + ": width must be 1..20 m");
        for (size_t k = 0; k < i; ++k) {
            if (cws[k].name == c.name) errs.push_back(at + ": defined twice");
        }
    }
}

// Two crosswalks whose strips overlap, by the position of their centre lines along the same
// line (the road's reference line, or the distance out along a junction arm).
bool strips_overlap(double pos_a, double width_a, double pos_b, double width_b) {
    return std::fabs(pos_a - pos_b) < 0.5 * (width_a + width_b);
}

void validate_road_crosswalks(const RoadSpec& s, double length, std::vector<std::string>& errs) {
    const std::string where = "road '" + s.name + "'";
    validate_crosswalk_basics(s.crosswalks, where, errs);
    for (size_t i = 0; i < s.crosswalks.size(); ++i) {
        const auto& c = s.crosswalks[i];
        const std::string at = where + ": crosswalk '" + c.name + "'";
        // The whole strip lies on the road.
        if (!(c.s_m >= 0.5 * c.width_m && c.s_m <= length - 0.5 * c.width_m)) {
            errs.push_back(at + ": s = " + std::to_string(c.s_m) + " m is outside the road (its strip must lie within 0.." +
                           std::to_string(length) + " m)");
        }
        for (size_t k = 0; k < i; ++k) {
            const auto& o = s.crosswalks[k];
            if (strips_overlap(c.s_m, c.width_m, o.s_m, o.width_m) && std::isfinite(c.width_m) && std::isfinite(o.width_m)) {
                errs.push_back(at + ": overlaps crosswalk '" + o.name + "' (closer than their widths)");
            }
        }
    }
}

// Position and heading of a built-in road's reference line at s, exactly as road_reference
// samples it.
std::pair<Vec2, double> reference_pose(const RoadSpec& spec, double s) {
    Vec2 p = spec.origin;
    double th = spec.heading_rad;
    for (const auto& g : spec.segments) {
        const double ds = std::min(s, g.length_m);
        if (g.kind == Segment::straight) {
            p = p + ds * Vec2{std::cos(th), std::sin(th)};
        } else {
            const double r = g.radius_m;
            const Vec2 c = p + r * Vec2{-std::sin(th), std::cos(th)};
            th += ds / r;
            p = c + r * Vec2{std::sin(th), -std::cos(th)};
        }
        s -= ds;
        if (s <= 0) break;
    }
    return {p, th};
}

// A straight crosswalk strip whose centre line runs from a to b.
Crosswalk make_crosswalk(std::string name, Vec2 a, Vec2 b, double width) {
    Crosswalk cw;
    cw.name = std::move(name);
    cw.centre = sampled_line(a, b);
    cw.left_bound = offset_polyline(cw.centre, 0.5 * width);
    cw.right_bound = offset_polyline(cw.centre, -0.5 * width);
    cw.width = width;
    return cw;
}

// The s at which lane `id` enters the (straight) strip of `cw`, walking back from where it
// crosses the centre line at `s_cross` to the last point outside the strip, then bisecting.
double entry_s(const RoadNetwork& net, LaneId id, const Crosswalk& cw, double s_cross) {
    const auto& ref = net.reference(id);
    const Vec2 c0 = cw.centre.front(), dir = cw.centre.back() - cw.centre.front();
    const Vec2 n = (1.0 / norm(dir)) * Vec2{-dir.y, dir.x};
    auto inside = [&](double s) { return std::fabs(dot(ref.point(s) - c0, n)) < 0.5 * cw.width; };
    double in = s_cross, out = s_cross;
    for (double step = 0.1; out > 0 && inside(out); step *= 1.5) {
        in = out;
        out = std::max(0.0, out - step);
    }
    if (inside(out)) return 0.0;  // the lane starts inside the strip
    for (int i = 0; i < 50; ++i) {
        const double mid = 0.5 * (in + out);
        (inside(mid) ? in : out) = mid;
    }
    return 0.5 * (in + out);
}

// Where lane `id`'s stop line for `cw` goes: kStopGap before it enters the strip (negative when
// there is no room on the lane).
double stop_s_before(const RoadNetwork& net, LaneId id, const Crosswalk& cw, double s_cross) {
    return entry_s(net, id, cw, s_cross) - kStopGap;
}

// The crossing of lane `id` by `cw` (the first, by s; nullptr if none).
const Crosswalk::Crossing* crossing_of(const Crosswalk& cw, LaneId id) {
    const Crosswalk::Crossing* best = nullptr;
    for (const auto& c : cw.crossings) {
        if (c.lane == id && (!best || c.s < best->s)) best = &c;
    }
    return best;
}

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
    validate_road_crosswalks(s, total, errs);
    return errs;
}

void validate_junction_crosswalks(const JunctionSpec& s, std::vector<std::string>& errs) {
    const std::string where = "junction '" + s.name + "'";
    validate_crosswalk_basics(s.crosswalks, where, errs);
    for (size_t i = 0; i < s.crosswalks.size(); ++i) {
        const auto& c = s.crosswalks[i];
        const std::string at = where + ": crosswalk '" + c.name + "'";
        if (arm_index(c.arm) < 0) errs.push_back(at + ": unknown arm '" + c.arm + "' (expected north, east, south or west)");
        // The strip and the stop line before it fit on the arm.
        const double max_gap = s.arm_length_m - c.width_m - kStopGap;
        if (!(c.gap_m >= 0 && c.gap_m <= max_gap)) {
            errs.push_back(at + ": gap must be 0.." + std::to_string(std::max(0.0, max_gap)) +
                           " m (the crosswalk and the stop line before it must fit on the arm)");
        }
        for (size_t k = 0; k < i; ++k) {
            const auto& o = s.crosswalks[k];
            if (o.arm == c.arm && strips_overlap(c.gap_m + 0.5 * c.width_m, c.width_m, o.gap_m + 0.5 * o.width_m, o.width_m)) {
                errs.push_back(at + ": overlaps crosswalk '" + o.name + "' (closer than their widths)");
            }
        }
    }
}

// A signalised road crosswalk's light: the vehicles' light, named as the crosswalk, on every
// lane it crosses, each with a stop line before it; pedestrians walk while it is red.
void add_road_crosswalk_light(RoadNetwork& net, Crosswalk& cw, Vec2 position, const std::string& at,
                              std::vector<std::string>& errs) {
    TrafficLight tl;
    tl.id = static_cast<int32_t>(net.lights.size());
    tl.name = cw.name;
    tl.position = position;
    for (const auto& x : cw.crossings) {
        const double stop = stop_s_before(net, x.lane, cw, x.s);
        Lane& lane = net.lane_mut(x.lane);
        if (stop < 0) {
            errs.push_back(at + ": no room for the stop line before it on lane '" + lane.name + "'");
            continue;
        }
        tl.lanes.push_back(x.lane);
        lane.add_stop_line(stop, {tl.id});
        lane.traffic_lights.push_back(tl.id);
    }
    cw.light = tl.id;
    cw.light_inverse = true;
    net.lights.push_back(std::move(tl));
}

// The crosswalks of a road: across all its lanes at s_m, perpendicular to the reference line,
// from the right kerb to the left one. A strip that does not cross every lane exactly once (a
// bend too tight for it) is an error.
void add_road_crosswalks(const RoadSpec& spec, BuildResult& out) {
    RoadNetwork& net = out.network;
    const double right = spec.lanes_forward * spec.lane_width_m + kKerb;
    const double left = spec.lanes_backward * spec.lane_width_m + kKerb;
    std::vector<Vec2> positions;
    for (const auto& c : spec.crosswalks) {
        const auto [p, th] = reference_pose(spec, c.s_m);
        const Vec2 normal{-std::sin(th), std::cos(th)};
        net.crosswalks.push_back(make_crosswalk(spec.name + "." + c.name, p - right * normal, p + left * normal, c.width_m));
        positions.push_back(p);
    }
    find_crossings(net);
    for (size_t i = 0; i < spec.crosswalks.size(); ++i) {
        const auto& c = spec.crosswalks[i];
        Crosswalk& cw = net.crosswalks[i];
        const std::string at = "road '" + spec.name + "': crosswalk '" + c.name + "'";
        bool once = true;
        for (const auto& l : net.lanes()) {
            const auto times = std::count_if(cw.crossings.begin(), cw.crossings.end(), [&](const auto& x) { return x.lane == l.id; });
            if (times != 1) {
                out.errors.push_back(at + ": crosses lane '" + l.name + "' " + std::to_string(times) +
                                     " times, not once (the road bends too tightly there)");
                once = false;
            }
        }
        if (c.signalised && once) add_road_crosswalk_light(net, cw, positions[i], at, out.errors);
    }
}

// The crosswalks of a junction: across an arm's lanes, both ways, `gap_m` out from the junction
// box, centre line running counter-clockwise around the junction. The arm's incoming lanes stop
// before it; with traffic lights it follows the light of the traffic parallel to it.
void add_junction_crosswalks(const JunctionSpec& spec, const std::vector<std::vector<LaneId>>& incoming, BuildResult& out) {
    RoadNetwork& net = out.network;
    const double half = spec.lanes_per_direction * spec.lane_width_m;
    for (const auto& c : spec.crosswalks) {
        const int a = arm_index(c.arm);
        const Vec2 u = kArms[a].dir, across{-u.y, u.x};
        const Vec2 mid = (half + c.gap_m + 0.5 * c.width_m) * u;
        Crosswalk cw = make_crosswalk(spec.name + "." + c.name, mid - (half + kKerb) * across, mid + (half + kKerb) * across, c.width_m);
        if (spec.control == JunctionSpec::traffic_lights) {
            // North and south arms are walked east–west, alongside the east–west traffic.
            const std::string parallel = spec.name + (a % 2 == 0 ? ".ew" : ".ns");
            for (const auto& tl : net.lights) {
                if (tl.name == parallel) cw.light = tl.id;
            }
        }
        net.crosswalks.push_back(std::move(cw));
    }
    find_crossings(net);
    for (size_t i = 0; i < spec.crosswalks.size(); ++i) {
        const Crosswalk& cw = net.crosswalks[i];
        for (LaneId l : incoming[static_cast<size_t>(arm_index(spec.crosswalks[i].arm))]) {
            const Crosswalk::Crossing* x = crossing_of(cw, l);
            if (!x) continue;
            // The junction's stop line moves before the crosswalk, with its lights.
            const double stop = stop_s_before(net, l, cw, x->s);
            Lane& lane = net.lane_mut(l);
            if (stop >= 0 && !lane.stop_lines.empty() && lane.stop_lines.back().s > stop) lane.stop_lines.back().s = stop;
        }
    }
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
    add_road_crosswalks(spec, out);  // last: it finds the crossings of the complete network
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
    validate_junction_crosswalks(spec, out.errors);
    if (!out.errors.empty()) return out;
    const int n = spec.lanes_per_direction;
    const double w = spec.lane_width_m;
    const double half = n * w;  // half the junction box
    const double L = spec.arm_length_m;
    const auto& arms = kArms;
    auto suffix = [&](int k) { return n > 1 ? "." + std::to_string(k) : std::string(); };
    const auto line = sampled_line;
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
            li.add_stop_line(polyline_length(li.centre));
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
                    Lane& lane = out.network.lane_mut(in[a][k]);
                    lane.stop_lines.back().traffic_lights.push_back(g);
                    lane.traffic_lights.push_back(g);
                }
            }
            tl.position = out.network.lane(tl.lanes[0]).centre.back();
            out.network.lights.push_back(std::move(tl));
        }
    }
    std::vector<std::vector<LaneId>> incoming(4);
    for (int a = 0; a < 4; ++a) incoming[static_cast<size_t>(a)].assign(&in[a][1], &in[a][n + 1]);
    add_junction_crosswalks(spec, incoming, out);  // last: it finds the crossings of the complete network
    out.length = L;
    return out;
}

}  // namespace sdv::road
