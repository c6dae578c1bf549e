// The two users of the segment grid in road_network.cpp, find_crossings and mark_junctions, test
// only segments that share a cell (testing every pair was fuzz findings 14 and 17: seconds for maps
// of a few KB). Property: on random networks of short and long segments, each finds exactly what
// testing every pair of segments finds.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "runtime/road/road_network.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace segment_grid_test {

using namespace sdv::road;

namespace {

// Random polylines for the brute-force comparisons below: a walk of `points` points whose steps
// are mostly short (as sampled lanes are) with some long ones, turning at most 40° per step.
std::vector<Vec2> random_line(std::mt19937_64& rng, size_t points, double box) {
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Vec2> pts = {{box * u(rng), box * u(rng)}};
    double heading = 2 * M_PI * u(rng);
    for (size_t i = 1; i < points; ++i) {
        heading += (u(rng) - 0.5) * 1.4;
        const double step = u(rng) < 0.8 ? 0.2 + 0.5 * u(rng) : 5 + 60 * u(rng);
        pts.push_back(pts.back() + step * Vec2{std::cos(heading), std::sin(heading)});
    }
    return pts;
}

// Where segments a0→a1 and b0→b1 cross, strictly inside both (random coordinates never touch).
std::optional<Vec2> crossing(Vec2 a0, Vec2 a1, Vec2 b0, Vec2 b1) {
    const Vec2 r = a1 - a0, s = b1 - b0;
    const double den = cross(r, s);
    if (den == 0) return std::nullopt;
    const double t = cross(b0 - a0, s) / den, v = cross(b0 - a0, r) / den;
    if (t < 0 || t > 1 || v < 0 || v > 1) return std::nullopt;
    return a0 + t * r;
}

// `count` lanes named l0, l1, ... on random lines of `min_points` to `min_points + spread - 1` points.
void add_random_lanes(RoadNetwork& net, std::mt19937_64& rng, size_t count, size_t min_points, size_t spread, double box) {
    for (size_t i = 0; i < count; ++i) {
        Lane l;
        l.name = "l" + std::to_string(i);
        l.centre = random_line(rng, min_points + rng() % spread, box);
        net.add_lane(l);
    }
}

// Whether a lane's centre line meets that of another it `may_meet`, by testing every pair of
// their segments with `meets`: what mark_junctions must have marked. Checks each lane; counts
// the lanes marked and those spared (meeting only lanes they may meet).
struct Marks {
    size_t marked = 0, spared = 0;
};
template <class Meets, class MayMeet>
Marks check_marks_against_every_pair(const RoadNetwork& net, Meets&& meets, MayMeet&& may_meet) {
    const auto& all = net.lanes();
    Marks marks;
    for (size_t i = 0; i < all.size(); ++i) {
        bool want = false, touches = false;
        for (size_t j = 0; j < all.size() && !want; ++j) {
            if (i == j) continue;
            const auto& a = all[i].centre;
            const auto& b = all[j].centre;
            bool met = false;
            for (size_t p = 0; p + 1 < a.size() && !met; ++p)
                for (size_t q = 0; q + 1 < b.size() && !met; ++q) met = meets(a[p], a[p + 1], b[q], b[q + 1]);
            touches = touches || met;
            want = met && may_meet(all[i], all[j]);
        }
        CHECK_MESSAGE(all[i].in_junction == want, all[i].name);
        marks.marked += want;
        marks.spared += touches && !want;
    }
    return marks;
}
template <class Meets>
size_t check_marks_against_every_pair(const RoadNetwork& net, Meets&& meets) {
    return check_marks_against_every_pair(net, meets, [](const Lane&, const Lane&) { return true; }).marked;
}

// A walk on the 0.5 m lattice inside [0, box]²: 2 to `max_points` points, steps of 0.5 m along,
// across or diagonal to the axes.
std::vector<Vec2> lattice_walk(std::mt19937_64& rng, double box, size_t max_points) {
    const auto nodes = static_cast<uint64_t>(2 * box) + 1;
    Vec2 p{0.5 * static_cast<double>(rng() % nodes), 0.5 * static_cast<double>(rng() % nodes)};
    std::vector<Vec2> pts{p};
    const size_t points = 2 + rng() % (max_points - 1);
    while (pts.size() < points) {
        const Vec2 step{0.5 * (static_cast<double>(rng() % 3) - 1), 0.5 * (static_cast<double>(rng() % 3) - 1)};
        const Vec2 q = p + step;
        if ((step.x == 0 && step.y == 0) || q.x < 0 || q.y < 0 || q.x > box || q.y > box) continue;
        pts.push_back(p = q);
    }
    return pts;
}

// Whether two segments of the lattice meet, exactly: they are not parallel and each reaches the
// other's line within its ends.
bool touch(Vec2 a0, Vec2 a1, Vec2 b0, Vec2 b1) {
    const Vec2 r = a1 - a0, s = b1 - b0;
    double den = cross(r, s), tn = cross(b0 - a0, s), un = cross(b0 - a0, r);
    if (den == 0) return false;
    if (den < 0) den = -den, tn = -tn, un = -un;
    return tn >= 0 && tn <= den && un >= 0 && un <= den;
}

// Parallel straight lines sampled every 0.5 m, at a random angle, length (20-220 m) and place
// within 1,000 km of the origin, `gap` apart (on each other, 0.1 µm, 1 mm, 10 cm or 1 m): line(i)
// is the i-th, i gaps across from the first.
struct StraightLines {
    double angle = 0, length = 0, gap = 0;
    Vec2 origin, along, across;
    size_t pieces = 0;

    std::vector<Vec2> line(size_t i) const {
        std::vector<Vec2> pts;
        for (size_t k = 0; k <= pieces; ++k) pts.push_back(origin + (0.5 * static_cast<double>(k)) * along + (gap * static_cast<double>(i)) * across);
        return pts;
    }
};

StraightLines straight_lines(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    const double gaps[] = {0, 1e-7, 1e-3, 0.1, 1};
    StraightLines s;
    s.angle = 2 * M_PI * u(rng);
    s.length = 20 + 200 * u(rng);
    s.gap = gaps[rng() % 5];
    const double x = 2e6 * (u(rng) - 0.5);
    s.origin = {x, 2e6 * (u(rng) - 0.5)};
    s.along = {std::cos(s.angle), std::sin(s.angle)};
    s.across = {-s.along.y, s.along.x};
    s.pieces = static_cast<size_t>(s.length / 0.5);
    return s;
}

}  // namespace

// find_crossings looks only at the segments near a crosswalk (a grid; testing every lane segment
// against every crosswalk segment took 47 s under ASan for an 898-byte map, fuzz finding 17): it
// must find what testing every pair finds, on networks of every shape.
TEST_CASE("find_crossings finds every crossing that testing every pair of segments finds") {
    std::mt19937_64 rng(17);
    for (int round = 0; round < 40; ++round) {
        CAPTURE(round);
        RoadNetwork net;
        add_random_lanes(net, rng, 1 + rng() % 6, 20, 200, 80);
        const size_t walks = 1 + rng() % 4;
        for (size_t i = 0; i < walks; ++i) {
            Crosswalk cw;
            cw.centre = random_line(rng, 2 + rng() % 60, 80);
            cw.width = 3;
            net.crosswalks.push_back(cw);
        }
        find_crossings(net);
        for (const auto& cw : net.crosswalks) {
            // Expected: every crossing point, by lane, in order along the lane's polyline.
            struct Want {
                LaneId lane;
                double s_poly;
                Vec2 p;
            };
            std::vector<Want> want;
            for (const auto& l : net.lanes()) {
                std::vector<std::pair<double, Vec2>> on_lane;
                double s = 0;
                for (size_t i = 0; i + 1 < l.centre.size(); ++i) {
                    for (size_t k = 0; k + 1 < cw.centre.size(); ++k) {
                        if (auto p = crossing(l.centre[i], l.centre[i + 1], cw.centre[k], cw.centre[k + 1]))
                            on_lane.emplace_back(s + distance(l.centre[i], *p), *p);
                    }
                    s += distance(l.centre[i], l.centre[i + 1]);
                }
                std::sort(on_lane.begin(), on_lane.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
                for (const auto& [s_poly, p] : on_lane) want.push_back({l.id, s_poly, p});
            }
            REQUIRE(cw.crossings.size() == want.size());
            for (size_t i = 0; i < want.size(); ++i) {
                CHECK(cw.crossings[i].lane == want[i].lane);
                // Its s: the crossing point projected on the lane's reference line, sought near
                // its arc length along the polyline.
                const auto& ref = net.reference(want[i].lane);
                const double s = std::clamp(ref.project(want[i].p, want[i].s_poly).s, 0.0, ref.length());
                CHECK(cw.crossings[i].s == doctest::Approx(s).epsilon(1e-9));
            }
        }
    }
}

// mark_junctions tests only the segments that share a cell of the grid (fuzz finding 14): on
// random lanes with no relations between them, it must mark exactly the lanes that testing
// every pair of segments finds crossing another.
TEST_CASE("mark_junctions marks exactly the lanes that testing every pair of segments finds") {
    std::mt19937_64 rng(14);
    for (int round = 0; round < 60; ++round) {
        CAPTURE(round);
        RoadNetwork net;
        add_random_lanes(net, rng, 2 + rng() % 8, 2, 150, 200);
        mark_junctions(net);
        check_marks_against_every_pair(net, [](Vec2 a0, Vec2 a1, Vec2 b0, Vec2 b1) { return crossing(a0, a1, b0, b1).has_value(); });
    }
}

// The same on lanes drawn on a 0.5 m lattice in a 12 m box: centre lines that touch at vertices,
// end on another's segment, overlap along a line, and end exactly on the grid's 2 m cell edges,
// where the sweep of each cell (segments whose widened boxes overlap) and the cell a pair is
// tested in decide. On the lattice the brute force is exact: two segments meet when they are not
// parallel and each reaches the other's line within its ends.
TEST_CASE("mark_junctions marks exactly the lanes that testing every pair finds, on lanes that touch") {
    std::mt19937_64 rng(20);
    size_t marked = 0, unmarked = 0;
    for (int round = 0; round < 200; ++round) {
        CAPTURE(round);
        RoadNetwork net;
        const size_t count = 2 + rng() % 10;
        for (size_t i = 0; i < count; ++i) {
            Lane l;
            l.name = "l" + std::to_string(i);
            l.centre = lattice_walk(rng, 12, 24);
            net.add_lane(l);
        }
        mark_junctions(net);
        const size_t m = check_marks_against_every_pair(net, touch);
        marked += m;
        unmarked += net.lanes().size() - m;
    }
    CHECK(marked > 100);
    CHECK(unmarked > 100);
}

// Lanes allowed to meet are left out pair by pair: neighbours, successors and predecessors (either
// way round) and the two lanes of a two-way lanelet ("<id>" and "<id>:inv"). On the lattice of
// the case above, with random relations, mark_junctions marks exactly the lanes that testing
// every pair of other lanes finds.
TEST_CASE("mark_junctions leaves out exactly the lanes that may meet: neighbours, successors, predecessors, one lanelet's two") {
    std::mt19937_64 rng(21);
    Marks total;
    for (int round = 0; round < 200; ++round) {
        CAPTURE(round);
        RoadNetwork net;
        const size_t count = 2 + rng() % 8;
        for (size_t i = 0; i < count; ++i) {
            Lane l;
            // Every third lane after the first is the other direction of the lane before it.
            l.name = i > 0 && i % 3 == 0 ? net.lanes()[i - 1].name + ":inv" : "l" + std::to_string(i);
            l.centre = lattice_walk(rng, 8, 17);
            net.add_lane(l);
        }
        // Random relations, each on one side only: mark_junctions must read them both ways.
        for (size_t i = 0; i < count; ++i) {
            Lane& l = net.lane_mut(static_cast<LaneId>(i));
            auto other = [&] { return static_cast<LaneId>(rng() % count); };
            switch (rng() % 5) {
                case 0: l.left = other(); break;
                case 1: l.right = other(); break;
                case 2: l.successors.push_back(other()); break;
                case 3: l.predecessors.push_back(other()); break;
                default: break;
            }
        }
        auto may_meet = [&](const Lane& a, const Lane& b) {
            auto relates = [](const Lane& x, LaneId y) {
                auto has = [y](const std::vector<LaneId>& v) { return std::find(v.begin(), v.end(), y) != v.end(); };
                return x.left == y || x.right == y || has(x.successors) || has(x.predecessors);
            };
            auto line = [](const std::string& n) { return n.size() > 4 && n.substr(n.size() - 4) == ":inv" ? n.substr(0, n.size() - 4) : n; };
            return !relates(a, b.id) && !relates(b, a.id) && line(a.name) != line(b.name);
        };
        mark_junctions(net);
        const Marks marks = check_marks_against_every_pair(net, touch, may_meet);
        total.marked += marks.marked;
        total.spared += marks.spared;
    }
    CHECK(total.marked > 100);
    CHECK(total.spared > 50);  // lanes that touch only lanes they may meet
}

// Lanes that lie on each other or run side by side along a cell, however close, are never
// paired segment by segment: 16 lanelets stacked on the same two ways along 6 km (99 km of lanes,
// what the limits let through) took 2-3 s under ASan when every pair of their overlapping
// segments was tested (fuzz finding 21). Property: straight lanes sampled every 0.5 m, stacked or
// 0.1 µm to 1 m apart, at any angle, anywhere within 1,000 km: no pair of segments examined, no
// lane marked; and a lane across them examines a bounded number of pairs and marks them all.
TEST_CASE("mark_junctions examines no pair of segments of straight lanes along each other, at any angle") {
    std::mt19937_64 rng(22);
    for (int round = 0; round < 60; ++round) {
        CAPTURE(round);
        const StraightLines s = straight_lines(rng);
        const double angle = s.angle, length = s.length, gap = s.gap;
        CAPTURE(angle);
        CAPTURE(gap);
        RoadNetwork net;
        const size_t count = 2 + rng() % 15;
        for (size_t i = 0; i < count; ++i) {
            Lane l;
            l.name = "l" + std::to_string(i);
            l.centre = s.line(i);
            net.add_lane(l);
        }
        CHECK(mark_junctions(net) == 0);
        for (const auto& l : net.lanes()) CHECK_FALSE(l.in_junction);
        // A lane across them all in the middle meets every one.
        Lane cross_lane;
        cross_lane.name = "across";
        const Vec2 mid = s.origin + (0.5 * length) * s.along;
        const double reach = 2 + gap * static_cast<double>(count);
        for (double d = -reach; d <= reach + gap * static_cast<double>(count); d += 0.5) cross_lane.centre.push_back(mid + d * s.across);
        net.add_lane(cross_lane);
        const size_t examined = mark_junctions(net);
        CHECK(examined > 0);
        CHECK(examined <= 16 * count * cross_lane.centre.size());
        for (const auto& l : net.lanes()) CHECK_MESSAGE(l.in_junction, l.name);
    }
}

// A lane that ends on lanes stacked along a straight line, from either side at any angle, meets
// every one of them: its last segment and theirs overlap across the line by no more than the
// rounding of the coordinates, so either may start first in the sweep across the cell.
TEST_CASE("mark_junctions marks a lane ending on stacked straight lanes, and all of them") {
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> u(0, 1);
    for (int round = 0; round < 300; ++round) {
        CAPTURE(round);
        const double angle = 2 * M_PI * u(rng), length = 20 + 100 * u(rng);
        const Vec2 origin{2e4 * (u(rng) - 0.5), 2e4 * (u(rng) - 0.5)};
        const Vec2 along{std::cos(angle), std::sin(angle)};
        RoadNetwork net;
        const size_t count = 2 + rng() % 6;
        const auto pieces = static_cast<size_t>(length / 0.5);
        for (size_t i = 0; i < count; ++i) {
            Lane l;
            l.name = "l" + std::to_string(i);
            for (size_t k = 0; k <= pieces; ++k) l.centre.push_back(origin + (0.5 * static_cast<double>(k)) * along);
            net.add_lane(l);
        }
        // Ends on a vertex of the line from either side, at right angles (the stacked lanes' pieces
        // then lie along the cell's direction) or at 20° to 160°.
        const Vec2 end = net.lanes()[0].centre[1 + rng() % (pieces - 1)];
        const double in = angle + (u(rng) < 0.5 ? 1 : -1) * (round % 2 ? M_PI / 2 : 0.35 + 2.4 * u(rng));
        Lane t;
        t.name = "t";
        for (int k = 6; k >= 0; --k) t.centre.push_back(end - (0.5 * k) * Vec2{std::cos(in), std::sin(in)});
        t.centre.back() = end;
        net.add_lane(t);
        mark_junctions(net);
        for (const auto& l : net.lanes()) CHECK_MESSAGE(l.in_junction, l.name);
    }
}

// Crosswalks drawn along lanes, on them or beside them, never cross them and are never paired
// with them segment by segment: 8 lanes and 8 crosswalks on the same line along 6 km took 0.5 s
// in a release build, about 10 s under ASan, sorting millions of pairs (fuzz finding 22).
// Property: straight lanes and crosswalks sampled every 0.5 m, on each other or 0.1 µm to 1 m
// apart, at any angle and place: no pair examined, no crossing; and a crosswalk across them all
// crosses each lane once, at the middle, examining a bounded number of pairs.
TEST_CASE("find_crossings examines no pair of a crosswalk along a lane, and finds one across them") {
    std::mt19937_64 rng(24);
    for (int round = 0; round < 60; ++round) {
        CAPTURE(round);
        const StraightLines s = straight_lines(rng);
        const double angle = s.angle, gap = s.gap;
        const size_t pieces = s.pieces;
        CAPTURE(angle);
        CAPTURE(gap);
        RoadNetwork net;
        const size_t lanes = 1 + rng() % 8, walks = 1 + rng() % 8;
        for (size_t i = 0; i < lanes; ++i) {
            Lane l;
            l.name = "l" + std::to_string(i);
            l.centre = s.line(i);
            net.add_lane(l);
        }
        for (size_t i = 0; i < walks; ++i) {
            Crosswalk cw;
            cw.centre = s.line(lanes + i);
            net.crosswalks.push_back(cw);
        }
        CHECK(find_crossings(net) == 0);
        for (const auto& cw : net.crosswalks) CHECK(cw.crossings.empty());
        // A crosswalk across them all in the middle, between two of the lanes' points.
        Crosswalk over;
        const Vec2 mid = s.origin + (0.5 * static_cast<double>(pieces / 2) + 0.25) * s.along;
        const double reach = 2 + gap * static_cast<double>(lanes + walks);
        for (double d = -2; d <= reach; d += 0.5) over.centre.push_back(mid + d * s.across);
        net.crosswalks.push_back(over);
        const size_t examined = find_crossings(net);
        CHECK(examined > 0);
        CHECK(examined <= 16 * (lanes + walks) * over.centre.size());
        const auto& found = net.crosswalks.back().crossings;
        REQUIRE(found.size() == lanes);
        for (size_t i = 0; i < lanes; ++i) {
            CHECK(found[i].lane == static_cast<LaneId>(i));
            CHECK(found[i].s == doctest::Approx(0.5 * static_cast<double>(pieces / 2) + 0.25).epsilon(1e-6));
        }
    }
}

}  // namespace segment_grid_test
