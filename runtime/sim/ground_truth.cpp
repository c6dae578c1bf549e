#include "runtime/sim/ground_truth.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "runtime/sim/collision.h"

namespace sdv::sim {
namespace {

// Faster than this along the lane than the one ahead, the one behind is closing in; slower
// differences are numerical noise, not an approach (no TTC of thousands of seconds).
constexpr double kClosing = 0.1;  // m/s
// The one behind drives forward (headway is defined) above this speed along the lane.
constexpr double kMoving = 0.1;  // m/s
// Pairs are measured while their centres are within the sensor range, and at least this.
constexpr double kPairRange = 100;  // m

// A footprint with its heading as a unit vector (computed once per tick).
struct Frame {
    Vec2 centre, heading;
    double length = 0, width = 0;
    // Half the extent along a unit axis `u`.
    double half_extent(Vec2 u) const {
        return 0.5 * length * std::fabs(road::dot(heading, u)) + 0.5 * width * std::fabs(road::cross(heading, u));
    }
};

// Lateral clearance of two footprints across the heading `h` of one of them: the gap between
// them across it while they overlap along it (side by side); INFINITY when they do not.
// `reach`: the sum of their half diagonals, a bound of the overlap along h.
double lateral_clearance(const Frame& a, const Frame& b, Vec2 h, double reach) {
    const Vec2 d = b.centre - a.centre;
    const double along = std::fabs(road::dot(d, h));
    if (along >= reach || along >= a.half_extent(h) + b.half_extent(h)) return INFINITY;
    const Vec2 n{-h.y, h.x};
    return std::max(0.0, std::fabs(road::dot(d, n)) - a.half_extent(n) - b.half_extent(n));
}

// |a| without std::hypot's overflow guard, for the bounds below (they allow for far more rounding).
double length(Vec2 a) { return std::sqrt(road::dot(a, a)); }

// The point of the footprint `f` nearest to p (p itself inside it).
Vec2 nearest_point(const Frame& f, Vec2 p) {
    const Vec2 d = p - f.centre, n{-f.heading.y, f.heading.x};
    const double along = std::clamp(road::dot(d, f.heading), -0.5 * f.length, 0.5 * f.length);
    const double across = std::clamp(road::dot(d, n), -0.5 * f.width, 0.5 * f.width);
    return f.centre + along * f.heading + across * n;
}

using PairSample = GroundTruth::Sample;

void fold(PairMetrics& m, const PairSample& s) {
    m.min_clearance = std::min(m.min_clearance, s.clearance);
    m.min_gap = std::min(m.min_gap, s.gap);
    m.min_lateral = std::min(m.min_lateral, s.lateral);
    m.min_ttc = std::min(m.min_ttc, s.ttc);
    m.min_headway = std::min(m.min_headway, s.headway);
}

void fold(VehicleMetrics& m, const Agent& a, std::optional<double> jerk) {
    if (jerk) m.max_jerk = std::max(m.max_jerk, *jerk);
    m.min_acc = std::min(m.min_acc, a.accel);
    m.max_acc = std::max(m.max_acc, a.accel);
    m.min_speed = std::min(m.min_speed, a.speed);
    m.max_speed = std::max(m.max_speed, a.speed);
}

}  // namespace

GroundTruth::GroundTruth(size_t n, RunResult& out) : out_(out), n_(n), index_(n), named_(n), lanes_(n) { out.vehicles.resize(n); }

uint32_t GroundTruth::pair_index(int i, int j) {
    auto& row = index_[static_cast<size_t>(i)];
    auto it = std::lower_bound(row.begin(), row.end(), std::make_pair(j, uint32_t{0}));
    if (it == row.end() || it->first != j) {
        it = row.insert(it, {j, static_cast<uint32_t>(out_.pairs.size())});
        PairMetrics m;
        m.a = i;
        m.b = j;
        out_.pairs.push_back(m);
        for (auto& win : out_.windows) win.pairs.push_back(m);
        touching_tick_.push_back(-2);
        deferred_.emplace_back();
    }
    return it->second;
}

void GroundTruth::fold_late(uint32_t pair, double clearance, double t) {
    out_.pairs[pair].min_clearance = std::min(out_.pairs[pair].min_clearance, clearance);
    for (auto& win : out_.windows) {
        if (win.contains(t)) win.pairs[pair].min_clearance = std::min(win.pairs[pair].min_clearance, clearance);
    }
}

void GroundTruth::finish() {
    for (uint32_t k = 0; k < deferred_.size(); ++k) {
        const Deferred& d = deferred_[k];
        if (d.pending) fold_late(k, gap(d.a, d.b), d.t);
    }
    deferred_.clear();
    std::vector<uint32_t> order(out_.pairs.size());
    for (uint32_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) {
        return std::make_pair(out_.pairs[x].a, out_.pairs[x].b) < std::make_pair(out_.pairs[y].a, out_.pairs[y].b);
    });
    auto permute = [&](std::vector<PairMetrics>& v) {
        std::vector<PairMetrics> sorted;
        sorted.reserve(v.size());
        for (uint32_t k : order) sorted.push_back(v[k]);
        v = std::move(sorted);
    };
    permute(out_.pairs);
    for (auto& win : out_.windows) permute(win.pairs);
    index_.assign(n_, {});
}

// The pairs the expectations name, then one set of metrics per distinct window of them.
void GroundTruth::start(const World& w) {
    started_ = true;
    for (const Agent& a : w.agents) half_diagonal_.push_back(0.5 * std::hypot(a.v->length, a.v->width));
    for (const ir::Expect& e : w.scenario.expects) {
        if (e.vehicles.size() != 2 || e.vehicles[0] == e.vehicles[1]) continue;
        const int i = std::min(e.vehicles[0], e.vehicles[1]), j = std::max(e.vehicles[0], e.vehicles[1]);
        if (i < 0 || static_cast<size_t>(j) >= n_) continue;
        auto& list = named_[static_cast<size_t>(i)];
        if (std::find(list.begin(), list.end(), j) == list.end()) list.push_back(j);
        pair_index(i, j);
    }
    for (int32_t root : w.scenario.expect_roots) {
        const ir::Expect& e = w.scenario.expects[static_cast<size_t>(root)];
        if (!e.after && !e.before) continue;
        const double after = e.after.value_or(-INFINITY), before = e.before.value_or(INFINITY);
        const bool known = std::any_of(out_.windows.begin(), out_.windows.end(),
                                       [&](const WindowMetrics& m) { return m.after == after && m.before == before; });
        if (known) continue;
        WindowMetrics m;
        m.after = after;
        m.before = before;
        m.pairs = out_.pairs;
        m.vehicles.resize(out_.vehicles.size());
        out_.windows.push_back(std::move(m));
    }
}

GroundTruth::OnLane GroundTruth::on_lane(const World& w, const Agent& a) const {
    OnLane o;
    o.lane = a.centre_lane;
    if (o.lane == kNoLane) return o;
    const road::ReferenceLine& ref = w.net.reference(o.lane);
    // An SDV's lane is the lane of its path under it, which is the target lane from the start
    // of a lane change: its centre may still be in the other one.
    o.s = a.lane == o.lane ? a.lane_s : ref.project({a.x, a.y}).s;
    const double h = ref.heading(o.s);
    o.speed = a.vx * std::cos(h) + a.vy * std::sin(h);
    return o;
}

void GroundTruth::observe(World& w, double t, int tick, Pool* pool) {
    if (!started_) start(w);
    now_.clear();
    for (auto& m : out_.windows) {
        if (m.contains(t)) now_.push_back(&m);
    }
    for (size_t i = 0; i < w.agents.size(); ++i) {
        if (w.agents[i].active) lanes_[i] = on_lane(w, w.agents[i]);
    }
    measure_pairs(w, t, tick, pool);
    measure_vehicles(w, t, tick);
}

void GroundTruth::measure_pairs(World& w, double t, int tick, Pool* pool) {
    auto& agents = w.agents;
    const size_t n = agents.size();
    // Plain locals: the workers of `pool` read them (a thread_local would be theirs, empty).
    std::vector<Box> boxes(n);
    std::vector<Frame> frames(n);
    const std::vector<double>& half_diagonal = half_diagonal_;
    for (size_t i = 0; i < n; ++i) {
        const Agent& a = agents[i];
        boxes[i] = {{a.x, a.y}, a.yaw, a.v->length, a.v->width};
        frames[i] = {{a.x, a.y}, {std::cos(a.yaw), std::sin(a.yaw)}, a.v->length, a.v->width};
    }
    const double range = std::max(w.scenario.sensor_range, kPairRange);
    // Two pedestrians are a pair only when an expectation names them (below): a pedestrian's
    // row looks its neighbours up among the other agents alone, not in the crowd round it.
    vehicle_x_.resize(n);
    vehicle_y_.resize(n);
    is_vehicle_.resize(n);
    for (size_t i = 0; i < n; ++i) {
        vehicle_x_[i] = agents[i].x;
        vehicle_y_[i] = agents[i].y;
        is_vehicle_[i] = agents[i].active && !agents[i].v->pedestrian ? 1 : 0;
    }
    vehicles_.build(vehicle_x_, vehicle_y_, is_vehicle_, range);
    // 1. Per vehicle i (in parallel, reading only): the samples of its pairs with j > i within
    // range or named by an expectation.
    rows_.resize(n);
    auto measure_row = [&](size_t i) {
        auto& row = rows_[i];
        row.clear();
        if (!agents[i].active) return;
        thread_local std::vector<int> near;
        (agents[i].v->pedestrian ? vehicles_ : w.grid).query(agents[i].x, agents[i].y, range, near, static_cast<int>(i));
        const auto& named = named_[i];
        if (!named.empty()) {
            near.insert(near.end(), named.begin(), named.end());
            std::sort(near.begin(), near.end());
            near.erase(std::unique(near.begin(), near.end()), near.end());
        }
        const auto& pairs = index_[i];
        auto pair = pairs.begin();  // the first of i's pairs with j at or after this neighbour
        for (const int jj : near) {
            const auto j = static_cast<size_t>(jj);
            if (!agents[j].active) continue;
            // Two pedestrians never collide (below): their pair is measured only when an
            // expectation names it, which keeps crowds cheap.
            if (agents[i].v->pedestrian && agents[j].v->pedestrian && std::find(named.begin(), named.end(), jj) == named.end()) continue;
            while (pair != pairs.end() && pair->first < jj) ++pair;
            const bool known = pair != pairs.end() && pair->first == jj;
            const uint32_t pi = known ? pair->second : 0;
            const bool was_touching = known && touching_tick_[pi] == tick - 1;
            // The exact box distance only when it could lower a minimum (of the run or of a
            // window holding this tick): a lower bound from the centres and the half
            // diagonals first.
            double need = known ? out_.pairs[pi].min_clearance : INFINITY;
            if (known) {
                for (const WindowMetrics* m : now_) need = std::max(need, m->pairs[pi].min_clearance);
            }
            // A deferred tick (below) counts with its upper bound, where it is in the same
            // windows as this one.
            Deferred* const before = known && deferred_[pi].pending ? &deferred_[pi] : nullptr;
            const bool same_windows =
                before != nullptr && std::all_of(out_.windows.begin(), out_.windows.end(), [&](const WindowMetrics& m) {
                    return m.contains(before->t) == m.contains(t);
                });
            if (same_windows) need = std::min(need, before->upper);
            PairSample s;
            const double dx = boxes[j].centre.x - boxes[i].centre.x, dy = boxes[j].centre.y - boxes[i].centre.y;
            const double centre = std::sqrt(dx * dx + dy * dy);
            const double reach = half_diagonal[i] + half_diagonal[j];
            // A lower bound of the box distance: the centres less the half diagonals, and the
            // gap of the two boxes' projections on i's axes (a separating axis), which is tight
            // for vehicles side by side or in line.
            double bound = centre - reach;
            const Vec2 d{dx, dy}, hi = frames[i].heading, ni{-hi.y, hi.x};
            for (const Vec2 u : {hi, ni}) {
                bound = std::max(bound, std::fabs(road::dot(d, u)) - frames[i].half_extent(u) - frames[j].half_extent(u));
            }
            const bool close = bound < need || bound <= 0 || was_touching;
            // Apart (bound > 0), the clearance counts only if it is the pair's least, which a
            // later tick may rule out: a pair closing in on the kerb at 12 m/s would otherwise
            // compute its exact distance at every tick for seconds. The bounds: from one box's
            // point nearest to the other's centre, its distance to that box (upper) and to that
            // centre less the half diagonal (lower), with room for the rounding of either.
            const double slack =
                1e-6 + 1e-9 * std::max({std::fabs(dx), std::fabs(dy), std::fabs(boxes[i].centre.x), std::fabs(boxes[i].centre.y)});
            double late = INFINITY, late_t = 0;
            if (close && known && !was_touching && bound > slack) {
                const Vec2 qi = nearest_point(frames[i], frames[j].centre);
                const Vec2 qj = nearest_point(frames[j], qi);
                const double lower = std::max({bound, length(qi - frames[j].centre) - half_diagonal[j],
                                               length(nearest_point(frames[j], frames[i].centre) - frames[i].centre) - half_diagonal[i]});
                const Deferred now{boxes[i], boxes[j], lower - slack, length(qi - qj) + slack, t, true};
                if (before == nullptr || (same_windows && now.upper < before->lower)) {
                    deferred_[pi] = now;  // the earlier tick is not the least
                } else if (!(same_windows && before->upper < now.lower)) {  // else this one is not
                    late = gap(before->a, before->b);
                    late_t = before->t;
                    *before = now;
                }
            } else if (close) {
                s.clearance = gap(boxes[i], boxes[j]);
            }
            // Pedestrians brushing past each other in a crowd are not a traffic collision (the
            // social force keeps their bodies apart); every other contact is.
            const bool hit = close && s.clearance <= 0 && !(agents[i].v->pedestrian && agents[j].v->pedestrian);
            s.lateral = std::min(lateral_clearance(frames[i], frames[j], frames[i].heading, reach),
                                 lateral_clearance(frames[i], frames[j], frames[j].heading, reach));
            // Along the lane, while both centres are in the same lane or the one ahead is in
            // the lane that directly follows: `ds` from i's centre to j's (positive: j ahead).
            const OnLane& li = lanes_[i];
            const OnLane& lj = lanes_[j];
            std::optional<double> ds;
            if (li.lane != kNoLane && lj.lane != kNoLane) {
                const auto follows = [&](LaneId from, LaneId to) {
                    const auto& succ = w.net.lane(from).successors;
                    return std::find(succ.begin(), succ.end(), to) != succ.end();
                };
                if (li.lane == lj.lane) {
                    ds = lj.s - li.s;
                } else if (follows(li.lane, lj.lane)) {
                    ds = w.net.reference(li.lane).length() - li.s + lj.s;
                } else if (follows(lj.lane, li.lane)) {
                    ds = -(w.net.reference(lj.lane).length() - lj.s + li.s);
                }
            }
            if (ds) {
                const bool j_ahead = *ds >= 0;
                const OnLane& behind = j_ahead ? li : lj;
                const OnLane& ahead = j_ahead ? lj : li;
                s.gap = std::max(0.0, std::fabs(*ds) - 0.5 * (agents[i].v->length + agents[j].v->length));
                if (behind.speed > kMoving) s.headway = s.gap / behind.speed;
                const double closing = behind.speed - ahead.speed;
                if (closing > kClosing) s.ttc = s.gap / closing;
            }
            row.push_back({jj, s, hit, late, late_t, known ? int64_t{pi} : -1});
        }
    };
    if (pool != nullptr) {
        pool->run(n, measure_row, 256);
    } else {
        for (size_t i = 0; i < n; ++i) measure_row(i);
    }
    // 2. In vehicle order: new pairs, collision events, the folds.
    for (size_t i = 0; i < n; ++i) {
        for (const auto& m : rows_[i]) {
            const uint32_t pi = m.pair >= 0 ? static_cast<uint32_t>(m.pair) : pair_index(static_cast<int>(i), m.j);
            const bool was_touching = touching_tick_[pi] == tick - 1;
            const auto j = static_cast<size_t>(m.j);
            if (m.hit && !was_touching) {
                const double rel = std::hypot(agents[i].vx - agents[j].vx, agents[i].vy - agents[j].vy);
                out_.events.push_back({t, "collision", {static_cast<int>(i), m.j}, rel, impact_zone(boxes[i], boxes[j])});
            }
            if (m.hit) touching_tick_[pi] = tick;
            fold(out_.pairs[pi], m.s);
            for (WindowMetrics* win : now_) fold(win->pairs[pi], m.s);
            if (m.late < INFINITY) fold_late(pi, m.late, m.late_t);
        }
    }
}

constexpr double kPedestrianGoalReach = 1.0;  // m

void GroundTruth::measure_vehicles(World& w, double t, int tick) {
    auto& agents = w.agents;
    for (size_t i = 0; i < agents.size(); ++i) {
        Agent& a = agents[i];
        if (!a.active) continue;
        VehicleMetrics& vm = out_.vehicles[i];
        // The centre off every lane: one event per episode (pedestrians walk beside the lanes).
        const bool off = !a.v->pedestrian && a.centre_lane == kNoLane;
        if (off && !a.off_lanes) out_.events.push_back({t, "off_road", {static_cast<int>(i)}, 0, ""});
        a.off_lanes = off;
        std::optional<double> jerk;
        if (tick > 0) jerk = std::fabs(a.accel - a.prev_accel) / w.dt;
        fold(vm, a, jerk);
        for (WindowMetrics* m : now_) fold(m->vehicles[i], a, jerk);
        a.prev_accel = a.accel;
        // Stopping at a stop line (the front bumper within 5 m before it) is remembered.
        if (a.lane != kNoLane && std::fabs(a.speed) < 0.1) {
            const auto& l = w.net.lane(a.lane);
            const double front = a.lane_s + 0.5 * a.v->length;
            const auto* line = l.stop_line_from(front - 0.5);
            const double g = line != nullptr ? line->s - front : -1;
            if (g >= -0.5 && g <= 5.0 && (a.stopped_line != a.lane || g < a.stopped_gap)) {
                if (a.stopped_line != a.lane) a.stopped_line_since = t;
                a.stopped_line = a.lane;
                a.stopped_gap = std::max(0.0, g);
            }
        }
        if (a.walker && a.walker->has_goal && !a.goal_reached &&
            std::hypot(a.x - a.walker->goal.x, a.y - a.walker->goal.y) <= kPedestrianGoalReach) {
            // A pedestrian's goal is a point: reached within a stride of it.
            a.goal_reached = true;
            vm.reached_goal = true;
            out_.events.push_back({t, "goal_reached", {static_cast<int>(i)}, 0, ""});
            if (a.v->goal_ends_run) ended_ = true;
        }
        if (a.goal_lane != kNoLane && !a.goal_reached) {
            // Within 4 m along and 2 m across the goal the vehicle may keep closing in; the
            // goal is reached when the along-track distance stops decreasing (overshot when
            // it is then faster than 1 m/s), as in the reference implementation.
            const std::optional<double> dist = w.goal_distance(a);
            if (dist && (a.goal_dist >= 0 || (*dist <= 4.0 && std::fabs(a.lane_d) <= 2.0))) {
                if (a.goal_dist >= 0 && *dist >= a.goal_dist - 1e-9) {
                    a.goal_reached = true;
                    vm.reached_goal = true;
                    out_.events.push_back({t, std::fabs(a.speed) > 1.0 ? "goal_overshot" : "goal_reached", {static_cast<int>(i)}, 0, ""});
                    if (a.v->goal_ends_run) ended_ = true;
                } else {
                    a.goal_dist = *dist;
                }
            }
        }
    }
}

}  // namespace sdv::sim
