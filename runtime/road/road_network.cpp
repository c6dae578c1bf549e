#include "runtime/road/road_network.h"

#include <algorithm>
#include <unordered_map>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

namespace sdv::road {

void Lane::add_stop_line(double s, const std::vector<int32_t>& lights) {
    auto it = std::lower_bound(stop_lines.begin(), stop_lines.end(), s - 0.01,
                               [](const StopLine& l, double v) { return l.s < v; });
    if (it == stop_lines.end() || it->s > s + 0.01) it = stop_lines.insert(it, StopLine{s, {}});
    for (const int32_t l : lights) {
        if (std::find(it->traffic_lights.begin(), it->traffic_lights.end(), l) == it->traffic_lights.end()) it->traffic_lights.push_back(l);
    }
}

const StopLine* Lane::stop_line_from(double s) const {
    for (const StopLine& l : stop_lines) {
        if (l.s >= s) return &l;
    }
    return nullptr;
}


double polyline_length(const std::vector<Vec2>& pts) {
    double l = 0;
    for (size_t i = 1; i < pts.size(); ++i) l += distance(pts[i - 1], pts[i]);
    return l;
}

std::vector<Vec2> offset_polyline(const std::vector<Vec2>& pts, double d) {
    std::vector<Vec2> out;
    out.reserve(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) {
        // Normal from the neighbouring points (central difference inside, one-sided at ends).
        const Vec2 a = pts[i > 0 ? i - 1 : i], b = pts[i + 1 < pts.size() ? i + 1 : i];
        const Vec2 t = b - a;
        const double n = norm(t);
        if (n == 0) {
            out.push_back(pts[i]);
            continue;
        }
        out.push_back(pts[i] + (d / n) * Vec2{-t.y, t.x});
    }
    return out;
}

LaneId RoadNetwork::add_lane(Lane lane) {
    lane.id = static_cast<LaneId>(lanes_.size());
    lane.length = polyline_length(lane.centre);
    lanes_.push_back(std::move(lane));
    refs_.emplace_back();
    return lanes_.back().id;
}

void RoadNetwork::connect(LaneId from, LaneId to) {
    auto& s = lane_mut(from).successors;
    if (std::find(s.begin(), s.end(), to) == s.end()) s.push_back(to);
    auto& p = lane_mut(to).predecessors;
    if (std::find(p.begin(), p.end(), from) == p.end()) p.push_back(from);
}

void RoadNetwork::set_neighbours(LaneId right, LaneId left, bool same_direction) {
    lane_mut(right).left = left;
    lane_mut(right).left_same_direction = same_direction;
    if (same_direction) {
        lane_mut(left).right = right;
        lane_mut(left).right_same_direction = true;
    } else {
        lane_mut(left).left = right;  // opposite lanes are each other's left neighbour
        lane_mut(left).left_same_direction = false;
    }
}

std::optional<LaneId> RoadNetwork::find(const std::string& name) const {
    for (const auto& l : lanes_) {
        if (l.name == name) return l.id;
    }
    return std::nullopt;
}

const ReferenceLine& RoadNetwork::reference(LaneId id) const {
    auto& slot = refs_.at(static_cast<size_t>(id));
    if (!slot) slot = ReferenceLine::build(lane(id).centre);
    if (!slot) {
        // add_lane refuses centre lines a reference line cannot be built from, so this only
        // guards against misuse: a straight stub along the lane's first point.
        const Vec2 p = lane(id).centre.empty() ? Vec2{} : lane(id).centre.front();
        const std::vector<Vec2> stub = {p, p + Vec2{1, 0}};
        slot = ReferenceLine::build(stub);
    }
    return *slot;
}

void RoadNetwork::Box::add(Vec2 p) {
    x0 = std::min(x0, p.x);
    y0 = std::min(y0, p.y);
    x1 = std::max(x1, p.x);
    y1 = std::max(y1, p.y);
}

double RoadNetwork::Box::distance2(Vec2 p) const {
    const double dx = std::max({x0 - p.x, 0.0, p.x - x1});
    const double dy = std::max({y0 - p.y, 0.0, p.y - y1});
    return dx * dx + dy * dy;
}

namespace {

// Whether a box at squared distance d2 is certainly farther than `limit` (a distance): the
// comparison is made with a margin, so that rounding never skips a box that holds the minimum.
bool beyond(double d2, double limit) { return d2 > limit * limit * (1 + 1e-9) + 1e-12; }

}  // namespace

void RoadNetwork::prepare() {
    for (const auto& l : lanes_) (void)reference(l.id);
    boxes_.assign(lanes_.size(), {});
    for (size_t i = 0; i < lanes_.size(); ++i) {
        const auto& c = lanes_[i].centre;
        LaneBoxes& b = boxes_[i];
        b.chunks.resize((c.size() + kChunk - 1) / kChunk);
        for (size_t k = 0; k < c.size(); ++k) {
            b.all.add(c[k]);
            b.chunks[k / kChunk].add(c[k]);
        }
    }
}

double RoadNetwork::nearest_point(const Lane& l, Vec2 p) const {
    double near = INFINITY;
    const size_t i = static_cast<size_t>(l.id);
    if (i >= boxes_.size() || boxes_[i].chunks.size() * kChunk < l.centre.size()) {
        for (const auto& q : l.centre) near = std::min(near, distance(p, q));
        return near;
    }
    const auto& chunks = boxes_[i].chunks;
    auto scan = [&](size_t k) {
        const size_t end = std::min(l.centre.size(), (k + 1) * kChunk);
        for (size_t j = k * kChunk; j < end; ++j) near = std::min(near, distance(p, l.centre[j]));
    };
    // The nearest box first (a tight bound at once), then every box that may hold a nearer
    // point: box distance <= the distance of every point inside it. The minimum is the same in
    // any order.
    size_t first = 0;
    double first_d2 = INFINITY;
    for (size_t k = 0; k < chunks.size(); ++k) {
        const double d2 = chunks[k].distance2(p);
        if (d2 < first_d2) {
            first_d2 = d2;
            first = k;
        }
    }
    scan(first);
    for (size_t k = 0; k < chunks.size(); ++k) {
        if (k != first && !beyond(chunks[k].distance2(p), near)) scan(k);
    }
    return near;
}

RoadNetwork::Location RoadNetwork::locate(Vec2 p, std::optional<double> heading) const {
    Location best;
    double best_score = INFINITY;
    for (const auto& l : lanes_) {
        if (l.centre.size() < 2) continue;
        // Cheap bounds first: the lane's box, then the distance to the polyline's points (the
        // box distance is at most that, so the box skips only lanes the points would).
        const size_t i = static_cast<size_t>(l.id);
        if (i < boxes_.size() && beyond(boxes_[i].all.distance2(p), best_score + l.length)) continue;
        const double near = nearest_point(l, p);
        if (near > best_score + l.length) continue;
        const auto& ref = reference(l.id);
        const FrenetState f = ref.project(p);
        double score = std::fabs(f.d);
        if (f.s < 0) score += -f.s;
        if (f.s > ref.length()) score += f.s - ref.length();
        if (heading) {
            double dh = std::remainder(*heading - ref.heading(std::clamp(f.s, 0.0, ref.length())), 2 * M_PI);
            if (std::fabs(dh) > M_PI / 2) score += 100;
        }
        if (score < best_score) {
            best_score = score;
            best = {l.id, f.s, f.d};
        }
    }
    return best;
}

}  // namespace sdv::road

namespace sdv::road {
namespace {

// The most lanes and crosswalks that may pass through one cell of the segment grid (a 2 m square
// for sampled lanes): the real maps of ../shared/data have up to 6 (ll2_mapping_example.osm), and
// the grid's work grows with the square of it (fuzz finding 18: 500 lanelets stacked on two
// ways, 83 KB, took 21 s under ASan; at 32, lanes stacked 32 deep along 3 km took 1.4 s).
constexpr size_t kMaxLinesAtOnePlace = 16;
// The most pieces of centre line (segments, 0.5 m or shorter for sampled lanes) of lanes and
// crosswalks in one cell: what 16 straight lines give along an axis (6 each), where the
// busiest real map has 28. The grid's work per segment grows with it: lanelets whose bounds
// zigzag inside one square put thousands of segments there without ever meeting (fuzz finding
// 20: 8 lanelets folded 500 times each into one square, 560 KB, took 12 s under ASan).
constexpr size_t kMaxSegmentsAtOnePlace = 96;
// A line with more pieces than this in one cell folds back on itself (a straight one has at
// most 8, the curves of the real maps 9): said in the message.
constexpr size_t kFoldedSegments = 12;

// Half the strip along a lane is never counted longer than this: a crosswalk almost parallel
// to a lane would otherwise cover the whole lane.
constexpr double kMaxHalfExtent = 10.0;

// Where segment p0→p1 meets q0→q1: the parameter along each. The ends are included with a
// little slack, so that a crossing through a vertex is found (in both segments: the caller
// merges the two) however the rounding falls.
std::optional<std::pair<double, double>> meet(Vec2 p0, Vec2 p1, Vec2 q0, Vec2 q1) {
    constexpr double kSlack = 1e-9;
    const Vec2 r = p1 - p0, s = q1 - q0;
    const double den = cross(r, s);
    if (den == 0) return std::nullopt;  // parallel: touching along a line is no crossing
    const double t = cross(q0 - p0, s) / den, u = cross(q0 - p0, r) / den;
    if (t < -kSlack || t > 1 + kSlack || u < -kSlack || u > 1 + kSlack) return std::nullopt;
    return std::pair{std::clamp(t, 0.0, 1.0), u};
}

// A segment of a polyline: its owner's index, the index of its first point, and the lowest cell
// of its box (two segments share cells from the larger of their lowest cells on: that one cell
// is where they are tested, once).
struct Seg {
    uint32_t line;
    uint32_t k;
    int32_t cx0, cy0;
    bool first_shared_cell(const Seg& o, uint64_t key) const {
        return key == key_of(std::max(cx0, o.cx0), std::max(cy0, o.cy0));
    }
    static uint64_t key_of(int64_t cx, int64_t cy) {
        return (static_cast<uint64_t>(static_cast<uint32_t>(cx)) << 32) | static_cast<uint32_t>(cy);
    }
};

// The segments of polylines in a uniform grid of square cells no smaller than the longest
// segment, so that each segment, its box widened by the meeting test's slack, lies in at most
// 2 x 2 cells: the grid is linear in the points, and two segments that meet share the cell of
// their meeting point; a pair is tested only in the first cell the two share. Testing every
// segment against every other took 22 s for a 6.6 KB map (fuzz finding 14, junctions) and 47 s
// under ASan for an 898-byte one (finding 17, crossings).
class SegmentGrid {
public:
    explicit SegmentGrid(double cell) : cell_(cell) {}

    // The cell size for polylines whose longest segment is this long: at least 2 m.
    static double cell_for(double longest) { return std::max(2.0, longest); }
    static double longest_segment(const std::vector<Vec2>& pts) {
        double longest = 0;
        for (size_t k = 0; k + 1 < pts.size(); ++k) longest = std::max(longest, distance(pts[k], pts[k + 1]));
        return longest;
    }

    void add(const std::vector<Vec2>& pts, uint32_t line) {
        for (size_t k = 0; k + 1 < pts.size(); ++k) {
            Seg seg{line, static_cast<uint32_t>(k), 0, 0};
            bool lowest = true;
            for_cells(pts[k], pts[k + 1], [&](int64_t cx, int64_t cy) {
                if (lowest) seg.cx0 = static_cast<int32_t>(cx), seg.cy0 = static_cast<int32_t>(cy), lowest = false;
                cells_[Seg::key_of(cx, cy)].push_back(seg);
            });
        }
    }

    // Every segment sharing a cell with p→q, once: in the first cell they share.
    template <class F>
    void near(Vec2 p, Vec2 q, F&& f) const {
        Seg query{0, 0, 0, 0};
        bool lowest = true;
        for_cells(p, q, [&](int64_t cx, int64_t cy) {
            if (lowest) query.cx0 = static_cast<int32_t>(cx), query.cy0 = static_cast<int32_t>(cy), lowest = false;
            const uint64_t key = Seg::key_of(cx, cy);
            auto it = cells_.find(key);
            if (it == cells_.end()) return;
            for (const Seg& s : it->second)
                if (s.first_shared_cell(query, key)) f(s);
        });
    }

    const std::unordered_map<uint64_t, std::vector<Seg>>& cells() const { return cells_; }

    // More than the meeting test's slack (1e-9 of a segment's length) beyond either end: two
    // segments that meet have boxes closer than this.
    double widen() const { return 1e-6 + 1e-8 * cell_; }

private:
    template <class F>
    void for_cells(Vec2 p, Vec2 q, F&& f) const {
        const double widen = this->widen();
        const auto x0 = static_cast<int64_t>(std::floor((std::min(p.x, q.x) - widen) / cell_));
        const auto x1 = static_cast<int64_t>(std::floor((std::max(p.x, q.x) + widen) / cell_));
        const auto y0 = static_cast<int64_t>(std::floor((std::min(p.y, q.y) - widen) / cell_));
        const auto y1 = static_cast<int64_t>(std::floor((std::max(p.y, q.y) + widen) / cell_));
        for (int64_t cx = x0; cx <= x1; ++cx)
            for (int64_t cy = y0; cy <= y1; ++cy) f(cx, cy);
    }

    double cell_;
    std::unordered_map<uint64_t, std::vector<Seg>> cells_;
};

// A segment in the sweep of one cell of the grid: its extents across and along the cell's main
// direction, widened by the grid's slack (two segments that meet have extents that overlap in
// both), the segment's index in the cell and the index of its line in the caller's list.
struct Extent {
    double n0, n1, d0, d1;
    uint32_t seg, run;
};

// The sine of the angle within which a segment lies along a cell's direction. Two such segments
// whose extents across overlap lie on each other (within a few µm): no crossing, as `meet` says
// of parallel segments, so the sweeps never pair them: lanelets stacked on the same ways, or
// crosswalks drawn along lanes, would otherwise be tested piece against piece along their whole
// length (fuzz findings 21 and 22).
constexpr double kAlong = 1e-6;

// A cell's frame: its main direction, the doubled-angle mean of the segments added (weighted by
// their length squared: a sum of (dx² - dy², 2 dx dy), so that opposite directions agree); and
// the segments' extents in it, put in two lists, those slanted to the direction and those along
// it, each sorted by where it starts across. Lanes that run side by side along a cell, however
// close, do not overlap across it and are never paired.
class CellSweep {
public:
    void clear() { c2_ = s2_ = 0; }
    void add_direction(Vec2 d) {
        c2_ += d.x * d.x - d.y * d.y;
        s2_ += 2 * d.x * d.y;
    }
    void fix_frame() {
        const double angle = 0.5 * std::atan2(s2_, c2_);
        along_ = {std::cos(angle), std::sin(angle)};
        across_ = {-along_.y, along_.x};
    }
    // Adds p→q to `slanted` or `flat` (call after fix_frame; sort both with `sort` before sweeping).
    void add(Vec2 p, Vec2 q, double widen, uint32_t seg, uint32_t run, std::vector<Extent>& slanted, std::vector<Extent>& flat) const {
        const double np = dot(p, across_), nq = dot(q, across_), dp = dot(p, along_), dq = dot(q, along_);
        const Extent e{std::min(np, nq) - widen, std::max(np, nq) + widen, std::min(dp, dq) - widen, std::max(dp, dq) + widen, seg, run};
        (std::fabs(np - nq) <= kAlong * std::fabs(dp - dq) ? flat : slanted).push_back(e);
    }
    static void sort(std::vector<Extent>& v) {
        std::sort(v.begin(), v.end(), [](const Extent& a, const Extent& b) { return a.n0 < b.n0; });
    }

private:
    double c2_ = 0, s2_ = 0;
    Vec2 along_{1, 0}, across_{0, 1};
};

bool overlap_along(const Extent& a, const Extent& b) { return a.d0 <= b.d1 && b.d0 <= a.d1; }

// Every pair of `v` (sorted) whose extents across overlap, once: from the one that starts first.
template <class F>
void pairs_within(const std::vector<Extent>& v, F&& f) {
    for (size_t a = 0; a < v.size(); ++a)
        for (size_t b = a + 1; b < v.size() && v[b].n0 <= v[a].n1; ++b) f(v[a], v[b]);
}

// Every pair (a of `as`, b of `bs`, both sorted) whose extents across overlap, once: b starts
// within a's extent, or before it and reaches into it.
template <class F>
void pairs_between(const std::vector<Extent>& as, const std::vector<Extent>& bs, F&& f) {
    size_t j = 0;
    for (const Extent& a : as) {
        while (j < bs.size() && bs[j].n0 < a.n0) ++j;
        for (size_t g = j; g < bs.size() && bs[g].n0 <= a.n1; ++g) f(a, bs[g]);
    }
    size_t i = 0;
    for (const Extent& b : bs) {
        while (i < as.size() && as[i].n0 <= b.n0) ++i;
        for (size_t g = i; g < as.size() && as[g].n0 <= b.n1; ++g) f(as[g], b);
    }
}

struct Hit {
    double s_poly;  // along the lane's polyline
    Vec2 p;
    double half_extent;
};

// Where the crosswalk's centre line meets the lane's, given the pairs of segments (lane
// segment, crosswalk segment) that may meet, in order: in order along the lane, one hit per
// place.
std::vector<Hit> hits(const Crosswalk& cw, const Lane& lane, const std::vector<std::pair<uint32_t, uint32_t>>& pairs) {
    constexpr double kSamePlace = 1e-6;  // m: one crossing found in two segments
    const auto& c = lane.centre;
    const auto& w = cw.centre;
    std::vector<Hit> out;
    double s = 0;  // polyline length up to point i
    size_t i = 0;
    for (const auto& [li, k] : pairs) {
        for (; i < li; ++i) s += norm(c[i + 1] - c[i]);
        const auto hit = meet(c[li], c[li + 1], w[k], w[k + 1]);
        if (!hit) continue;
        const Vec2 dl = c[li + 1] - c[li], dw = w[k + 1] - w[k];
        const double sine = std::fabs(cross(dl, dw)) / (norm(dl) * norm(dw));
        const double half = sine > 0 ? std::min(kMaxHalfExtent, 0.5 * cw.width / sine) : kMaxHalfExtent;
        out.push_back({s + hit->first * norm(dl), c[li] + hit->first * dl, half});
    }
    std::sort(out.begin(), out.end(), [](const Hit& a, const Hit& b) { return a.s_poly < b.s_poly; });
    out.erase(std::unique(out.begin(), out.end(), [&](const Hit& a, const Hit& b) { return b.s_poly - a.s_poly < kSamePlace; }),
              out.end());
    return out;
}

}  // namespace

std::optional<std::string> crowded_place(const RoadNetwork& net) {
    const auto& lanes = net.lanes();
    double longest = 0;
    for (const auto& l : lanes) longest = std::max(longest, SegmentGrid::longest_segment(l.centre));
    for (const auto& c : net.crosswalks) longest = std::max(longest, SegmentGrid::longest_segment(c.centre));
    const double cell = SegmentGrid::cell_for(longest);
    SegmentGrid grid(cell);
    for (const auto& l : lanes) grid.add(l.centre, static_cast<uint32_t>(l.id));
    for (size_t i = 0; i < net.crosswalks.size(); ++i) grid.add(net.crosswalks[i].centre, static_cast<uint32_t>(lanes.size() + i));
    // The lines of a cell and the one with the most segments there (the first of equals): a
    // line's segments are contiguous in a cell (added line by line).
    struct Lines {
        size_t count = 0, most_n = 0;
        uint32_t most = 0;
    };
    auto lines_in = [](const std::vector<Seg>& segs) {
        Lines r;
        for (size_t u = 0, v = 0; u < segs.size(); u = v) {
            while (v < segs.size() && segs[v].line == segs[u].line) ++v;
            ++r.count;
            if (v - u > r.most_n) r.most = segs[u].line, r.most_n = v - u;
        }
        return r;
    };
    // The crowded cell of smallest key, so that the message does not depend on the hash order.
    std::optional<uint64_t> worst;
    for (const auto& [key, segs] : grid.cells()) {
        const bool crowded = segs.size() > kMaxSegmentsAtOnePlace || lines_in(segs).count > kMaxLinesAtOnePlace;
        if (crowded && (!worst || key < *worst)) worst = key;
    }
    if (!worst) return std::nullopt;
    const auto& segs = grid.cells().at(*worst);
    auto name_of = [&](uint32_t line) {
        return line < lanes.size() ? "lanelet " + lanes[line].name : "crosswalk " + net.crosswalks[line - lanes.size()].name;
    };
    auto corner = [&](uint32_t c) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.0f", static_cast<double>(static_cast<int32_t>(c)) * cell);
        return std::string(buf);
    };
    const std::string square = "the " + corner(1) + " m square at (" + corner(static_cast<uint32_t>(*worst >> 32)) + ", " +
                               corner(static_cast<uint32_t>(*worst)) + ")";
    const Lines lines = lines_in(segs);
    if (lines.count > kMaxLinesAtOnePlace) {
        return name_of(segs.front().line) + ": more than " + std::to_string(kMaxLinesAtOnePlace) +
               " lanes and crosswalks pass through " + square + "; sdv reads maps of at most " +
               std::to_string(kMaxLinesAtOnePlace) + " at one place (are lanelets stacked on each other?)";
    }
    // Too many pieces of line: name the line with the most of them there.
    return name_of(lines.most) + ": " + std::to_string(segs.size()) + " pieces of lane and crosswalk centre lines lie in " +
           square + ", " + std::to_string(lines.most_n) + " of them its own; sdv reads maps of at most " +
           std::to_string(kMaxSegmentsAtOnePlace) + " in one place (pieces of 0.5 m; " +
           (lines.most_n > kFoldedSegments ? "does the lanelet fold back on itself?)" : "are lanelets stacked on each other?)");
}

size_t find_crossings(RoadNetwork& net) {
    const auto& lanes = net.lanes();
    double longest = 0;
    for (const auto& l : lanes) longest = std::max(longest, SegmentGrid::longest_segment(l.centre));
    for (const auto& c : net.crosswalks) longest = std::max(longest, SegmentGrid::longest_segment(c.centre));
    SegmentGrid grid(SegmentGrid::cell_for(longest));
    // Lanes and then crosswalks in one grid (crosswalk i is line first_walk + i): in each cell
    // shared by both, the pairs of a lane's segment and a crosswalk's whose extents overlap in
    // the cell's frame are tested, in the first cell they share.
    const auto first_walk = static_cast<uint32_t>(lanes.size());
    if (!net.crosswalks.empty()) {
        for (const auto& l : lanes) grid.add(l.centre, static_cast<uint32_t>(l.id));
        for (size_t i = 0; i < net.crosswalks.size(); ++i) grid.add(net.crosswalks[i].centre, first_walk + static_cast<uint32_t>(i));
    }
    struct Pair {
        uint32_t walk, lane, li, k;  // a crosswalk, a lane, the lane's segment li and the crosswalk's k, which meet
        bool operator<(const Pair& o) const { return std::tie(walk, lane, li, k) < std::tie(o.walk, o.lane, o.li, o.k); }
    };
    std::vector<Pair> pairs;
    CellSweep sweep;
    std::vector<Extent> lane_slanted, lane_flat, walk_slanted, walk_flat;
    const double widen = grid.widen();
    size_t examined = 0;
    auto points = [&](uint32_t line) -> const std::vector<Vec2>& {
        return line < first_walk ? lanes[line].centre : net.crosswalks[line - first_walk].centre;
    };
    for (const auto& cell : grid.cells()) {
        const uint64_t key = cell.first;
        const std::vector<Seg>& segs = cell.second;
        // Lanes' segments come first in a cell (added first).
        if (segs.front().line >= first_walk || segs.back().line < first_walk) continue;
        sweep.clear();
        for (const Seg& sg : segs) sweep.add_direction(points(sg.line)[sg.k + 1] - points(sg.line)[sg.k]);
        sweep.fix_frame();
        lane_slanted.clear(), lane_flat.clear(), walk_slanted.clear(), walk_flat.clear();
        for (uint32_t u = 0; u < segs.size(); ++u) {
            const auto& c = points(segs[u].line);
            const bool walk = segs[u].line >= first_walk;
            sweep.add(c[segs[u].k], c[segs[u].k + 1], widen, u, 0, walk ? walk_slanted : lane_slanted, walk ? walk_flat : lane_flat);
        }
        for (auto* v : {&lane_slanted, &lane_flat, &walk_slanted, &walk_flat}) CellSweep::sort(*v);
        auto test = [&](const Extent& l, const Extent& w) {
            ++examined;
            if (!overlap_along(l, w)) return;
            const Seg& sl = segs[l.seg];
            const Seg& sw = segs[w.seg];
            if (!sl.first_shared_cell(sw, key)) return;
            const auto& c = lanes[sl.line].centre;
            const auto& x = net.crosswalks[sw.line - first_walk].centre;
            if (meet(c[sl.k], c[sl.k + 1], x[sw.k], x[sw.k + 1])) pairs.push_back({sw.line - first_walk, sl.line, sl.k, sw.k});
        };
        pairs_between(lane_slanted, walk_slanted, test);
        pairs_between(lane_slanted, walk_flat, test);
        pairs_between(lane_flat, walk_slanted, test);
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<std::pair<uint32_t, uint32_t>> of_lane;
    size_t from = 0;
    for (size_t i = 0; i < net.crosswalks.size(); ++i) {
        Crosswalk& cw = net.crosswalks[i];
        cw.id = static_cast<int32_t>(i);
        cw.length = polyline_length(cw.centre);
        cw.crossings.clear();
        while (from < pairs.size() && pairs[from].walk == i) {
            const uint32_t lane = pairs[from].lane;
            of_lane.clear();
            for (; from < pairs.size() && pairs[from].walk == i && pairs[from].lane == lane; ++from) of_lane.emplace_back(pairs[from].li, pairs[from].k);
            const Lane& l = lanes[lane];
            for (const Hit& h : hits(cw, l, of_lane)) {
                // The s of the lane's reference line (what stop lines and agents use), sought
                // near the polyline's arc length.
                const auto& ref = net.reference(l.id);
                const double s = std::clamp(ref.project(h.p, h.s_poly).s, 0.0, ref.length());
                cw.crossings.push_back({l.id, s, h.half_extent});
            }
        }
    }
    return examined;
}

size_t mark_junctions(RoadNetwork& net) {
    const auto& lanes = net.lanes();
    // Lanes that may meet without forming a junction, in both directions: neighbours, successors
    // and predecessors; and the two lanes of a two-way lanelet ("<id>" and "<id>:inv"), one centre
    // line: lanes whose names without ":inv" are the same have the same `line_of`.
    std::vector<std::vector<uint32_t>> exempt(lanes.size());
    std::vector<uint32_t> line_of(lanes.size());
    {
        std::unordered_map<std::string, uint32_t> lines;
        for (size_t i = 0; i < lanes.size(); ++i) {
            const Lane& l = lanes[i];
            const std::string& n = l.name;
            const bool inv = n.size() > 4 && n.compare(n.size() - 4, 4, ":inv") == 0;
            line_of[i] = lines.emplace(inv ? n.substr(0, n.size() - 4) : n, static_cast<uint32_t>(lines.size())).first->second;
            auto both = [&](LaneId other) {
                if (other < 0 || static_cast<size_t>(other) >= lanes.size()) return;
                exempt[i].push_back(static_cast<uint32_t>(other));
                exempt[static_cast<size_t>(other)].push_back(static_cast<uint32_t>(i));
            };
            both(l.left);
            both(l.right);
            for (const LaneId s : l.successors) both(s);
            for (const LaneId p : l.predecessors) both(p);
        }
        for (auto& e : exempt) {
            std::sort(e.begin(), e.end());
            e.erase(std::unique(e.begin(), e.end()), e.end());
        }
    }
    auto may_meet = [&](uint32_t a, uint32_t b) {
        return line_of[a] != line_of[b] && !std::binary_search(exempt[a].begin(), exempt[a].end(), b);
    };
    // Only segments that share a cell of the grid are tested: linear in the map's size, where
    // testing every pair of lanes segment by segment took minutes on a small map of long
    // lanelets (fuzz finding 14); the result is that of testing every pair.
    double longest = 0;
    for (const auto& l : lanes) longest = std::max(longest, SegmentGrid::longest_segment(l.centre));
    SegmentGrid grid(SegmentGrid::cell_for(longest));
    for (const auto& l : lanes) grid.add(l.centre, static_cast<uint32_t>(l.id));
    std::vector<char> in(lanes.size(), 0);
    // In each cell: the pairs of its lanes that are still open (not both marked yet, and allowed
    // to meet); then the segments of lanes with an open pair in the cell's frame (CellSweep):
    // only segments of an open pair whose extents overlap across and along its direction are
    // tested, and never two that lie along it.
    struct Run {
        uint32_t lane, begin, end;  // a lane's segments in the cell: segs[begin, end)
        bool live;                  // in an open pair
    };
    std::vector<Run> runs;
    std::vector<char> open;
    CellSweep sweep;
    std::vector<Extent> slanted, flat;
    const double widen = grid.widen();
    size_t examined = 0;  // the marks do not depend on the order of the cells; this count does
    for (const auto& cell : grid.cells()) {
        const uint64_t key = cell.first;  // not a structured binding: the lambda below captures it
        const std::vector<Seg>& segs = cell.second;
        runs.clear();
        for (uint32_t u = 0, v = 0; u < segs.size(); u = v) {
            while (v < segs.size() && segs[v].line == segs[u].line) ++v;
            runs.push_back({segs[u].line, u, v, false});
        }
        const size_t n = runs.size();
        if (n < 2) continue;
        open.assign(n * n, 0);
        bool any = false;
        for (size_t i = 0; i < n; ++i) {
            for (size_t j = i + 1; j < n; ++j) {
                const uint32_t a = runs[i].lane, b = runs[j].lane;
                if ((in[a] && in[b]) || !may_meet(a, b)) continue;
                open[i * n + j] = open[j * n + i] = 1;
                runs[i].live = runs[j].live = any = true;
            }
        }
        if (!any) continue;
        sweep.clear();
        for (const Run& r : runs) {
            const auto& c = lanes[r.lane].centre;
            for (uint32_t u = r.begin; r.live && u < r.end; ++u) sweep.add_direction(c[segs[u].k + 1] - c[segs[u].k]);
        }
        sweep.fix_frame();
        slanted.clear();
        flat.clear();
        for (uint32_t i = 0; i < n; ++i) {
            const auto& c = lanes[runs[i].lane].centre;
            for (uint32_t u = runs[i].begin; runs[i].live && u < runs[i].end; ++u)
                sweep.add(c[segs[u].k], c[segs[u].k + 1], widen, u, i, slanted, flat);
        }
        CellSweep::sort(slanted);
        CellSweep::sort(flat);
        auto test = [&](const Extent& a, const Extent& b) {
            ++examined;
            if (!open[a.run * n + b.run] || !overlap_along(a, b)) return;
            const Seg& su = segs[a.seg];
            const Seg& sv = segs[b.seg];
            if ((in[su.line] && in[sv.line]) || !su.first_shared_cell(sv, key)) return;
            const auto& l = lanes[su.line].centre;
            const auto& m = lanes[sv.line].centre;
            if (meet(l[su.k], l[su.k + 1], m[sv.k], m[sv.k + 1])) in[su.line] = in[sv.line] = 1;
        };
        pairs_within(slanted, test);
        pairs_between(slanted, flat, test);
    }
    for (size_t i = 0; i < lanes.size(); ++i) {
        if (in[i]) net.lane_mut(static_cast<LaneId>(i)).in_junction = true;
    }
    return examined;
}

}  // namespace sdv::road
