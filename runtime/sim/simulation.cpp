// The simulation loop and the SDV planning cycle. Conditions (catalog §3.5) are evaluated on
// the driver's Frenet view of the snapshot: own state at the plan start, every perceived
// vehicle projected into its reference line. Zones split the surroundings by lane band (own,
// left, right: |d| within half a lane width of the band's centre) and by position along s
// (ahead, beside: overlapping along s, behind).
#include "runtime/sim/simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <thread>

#include "runtime/bt/behavior_tree.h"
#include "runtime/catalog/catalog.h"
#include "runtime/planner/planner.h"
#include "runtime/road/builtin_road.h"
#include "runtime/road/lanelet2_reader.h"
#include "runtime/road/routing.h"
#include "runtime/sim/collision.h"

namespace sdv::sim {
namespace {

using catalog::ConditionKind;
using catalog::ManeuverKind;
using road::LaneId;
using road::kNoLane;

constexpr double kPathAhead = 300.0;  // m of lanes in a reference line ahead of the vehicle
constexpr double kPathBehind = 60.0;

std::string fmt(double v, int digits = 4) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    std::string s = buf;
    if (s == "-0.0000" || s == "-0.000" || s == "-0.00") s = s.substr(1);
    return s;
}

std::string loc_text(const ir::Program& p, const ir::SourceLoc& l) {
    const std::string file = l.file < p.files.size() ? p.files[l.file] : "?";
    return file + ":" + std::to_string(l.line) + ":" + std::to_string(l.col);
}

// A plan in force: a Frenet trajectory in its own frame, from its start time.
struct ActivePlan {
    planner::Trajectory traj;
    double start = 0;
    std::shared_ptr<const road::ReferenceLine> ref;
};

// What every planner reads: the state of all vehicles at t0 (immutable during planning).
struct Snap {
    double x = 0, y = 0, yaw = 0, vx = 0, vy = 0, speed = 0, accel = 0;
    double length = 4.5, width = 1.8;
    LaneId lane = kNoLane;
    bool is_static = false;
    double stopped_since = -1;
    int32_t maneuver = -1;
};

// Another vehicle as one driver sees it.
struct Seen {
    int index = -1;
    road::FrenetState f;
    double length = 4.5, width = 1.8;
    double speed = 0;
    double dist = 0;
};

struct Agent {
    const ir::Vehicle* v = nullptr;
    int index = 0;
    // Cartesian state
    double x = 0, y = 0, yaw = 0, vx = 0, vy = 0, ax = 0, ay = 0;
    double speed = 0, accel = 0, prev_accel = 0;
    LaneId lane = kNoLane;
    double lane_s = 0, lane_d = 0;
    double stopped_since = -1;
    // SDV
    std::unique_ptr<bt::BehaviorTree> tree;
    std::vector<LaneId> path;
    std::vector<double> path_start;  // s where each path lane starts on `ref`
    std::shared_ptr<const road::ReferenceLine> ref;
    double ref_s = -1;  // last projection on `ref` (search hint)
    std::optional<ActivePlan> plan, pending;
    std::vector<road::RouteStep> route;
    LaneId goal_lane = kNoLane;
    double goal_s = 0;
    bool goal_reached = false;
    double goal_dist = -1;  // along-track distance to the goal once within reach (< 0: not yet)
    LaneId stopped_line = kNoLane;  // the lane at whose stop line the vehicle last came to a stop
    double stopped_gap = 0;         // its front bumper's distance to that line then
    int32_t maneuver = -1;  // selected node
    std::string maneuver_name = "none";
    LaneId target_lane = kNoLane;  // of a running lane change / cut-in
    uint32_t plan_count = 0;
    // `wait` timers: node index → (time first ticked, plan_count of the last tick).
    std::map<int32_t, std::pair<double, uint32_t>> waits;
    // Per-cycle results (written by the planning thread, applied in order).
    std::string trace;
    bool fallback = false;
    int candidates = 0;
    double plan_us = 0;
};

class World;

// Bounds of the start accelerations of a plan: no vehicle accelerates beyond them (the
// catalog's default max_long_acc and max_lat_acc).
constexpr double kMaxStartAcc = 12.0;    // m/s²
constexpr double kMaxStartLatAcc = 4.9;  // m/s²
constexpr double kRestSpeed = 0.01;      // m/s: slower than this a vehicle is at rest

// Leaves of one SDV's tree, evaluated against its view of the snapshot.
class Context : public bt::TickContext {
public:
    Context(World& w, Agent& a, double t0, double t_start) : w_(w), a_(a), t0_(t0), t_start_(t_start) {}
    bool condition(const ir::Node& n, int32_t index) override;
    bt::Status maneuver(const ir::Node& n, int32_t index) override;
    void view();  // (re)build the Frenet view (after a reference-line switch too)

    road::FrenetState self;
    std::vector<Seen> seen;
    bool switched = false;  // a lane change completed during this cycle

private:
    friend class World;
    double num(const ir::Node& n, const char* name) const;
    const ir::ParamValue* param(const ir::Node& n, const char* name) const;
    const Seen* vehicle(const ir::Node& n, const char* name, bool default_leader) const;
    // band −1 right, 0 own, 1 left; where 1 ahead, 0 beside, −1 behind; static objects unless
    // `objects` is false.
    const Seen* nearest(int band, int where, bool objects = true) const;
    int band_of(double d) const;
    double lane_width() const;

    World& w_;
    Agent& a_;
    double t0_, t_start_;
};

class World {
public:
    World(const ir::Program& p, int scenario, const RunOptions& opt) : p_(p), sc_(p.scenarios.at(static_cast<size_t>(scenario))), opt_(opt) {}

    std::string init();
    RunResult run();

    const ir::Program& p_;
    const ir::Scenario& sc_;
    RunOptions opt_;
    road::RoadNetwork net_;
    std::vector<Agent> agents_;
    std::vector<Snap> snap_;
    double dt_ = 1.0 / 30;
    double latency_ = 1.0 / 3;
    uint64_t seed_ = 0;
    std::map<std::string, const ir::LightProgram*> programs_;

    std::string light_state(int32_t light, double t) const;
    std::string road_json() const;
    std::shared_ptr<const road::ReferenceLine> build_path(Agent& a, LaneId from);
    void plan_agent(Agent& a, double t0);
    void place(Agent& a, const road::CartesianState& c, std::optional<double> lane_heading = std::nullopt);
    std::string init_position(Agent& a, const ir::Position& pos, LaneId& lane, double& s);
    // |goal s − own s| along the vehicle's path (or its lane); nullopt when the goal lane is
    // not ahead on it.
    std::optional<double> goal_distance(const Agent& a) const;
};

// ---------------------------------------------------------------------------------- world

std::optional<double> World::goal_distance(const Agent& a) const {
    if (a.v->kind == ir::VehicleKind::sdv && a.ref) {
        for (size_t i = 0; i < a.path.size(); ++i) {
            if (a.path[i] == a.goal_lane) return std::fabs(a.path_start[i] + a.goal_s - a.ref_s);
        }
        return std::nullopt;
    }
    if (a.lane != a.goal_lane) return std::nullopt;
    return std::fabs(a.goal_s - a.lane_s);
}

std::string World::light_state(int32_t light, double t) const {
    if (light < 0 || static_cast<size_t>(light) >= net_.lights.size()) return "green";
    auto it = programs_.find(net_.lights[static_cast<size_t>(light)].name);
    if (it == programs_.end() || it->second->phases.empty()) return "green";
    const auto& ph = it->second->phases;
    double total = 0;
    for (const auto& x : ph) total += x.duration;
    double u = std::fmod(t + it->second->offset, total);
    for (const auto& x : ph) {
        if (u < x.duration) return x.state;
        u -= x.duration;
    }
    return ph.back().state;
}

std::shared_ptr<const road::ReferenceLine> World::build_path(Agent& a, LaneId from) {
    a.path.clear();
    a.path_start.clear();
    std::vector<road::Vec2> pts;
    double len = 0;
    // One predecessor behind, so that vehicles behind project well.
    const auto& first = net_.lane(from);
    if (!first.predecessors.empty()) {
        const auto& pre = net_.lane(first.predecessors.front());
        const double skip = std::max(0.0, pre.length - kPathBehind);
        double acc = 0;
        for (size_t i = 0; i < pre.centre.size(); ++i) {
            if (i > 0) acc += road::distance(pre.centre[i - 1], pre.centre[i]);
            if (acc >= skip) pts.push_back(pre.centre[i]);
        }
    }
    const double behind = road::polyline_length(pts);
    LaneId cur = from;
    double s0 = behind;
    for (int guard = 0; guard < 64 && cur != kNoLane && len < kPathAhead + behind; ++guard) {
        const auto& l = net_.lane(cur);
        a.path.push_back(cur);
        a.path_start.push_back(s0);
        for (const auto& q : l.centre) {
            if (pts.empty() || road::distance(pts.back(), q) > 1e-3) pts.push_back(q);
        }
        s0 += l.length;
        len = s0;
        // Next lane: along the route when it continues by a successor, else the first successor.
        LaneId next = kNoLane;
        for (size_t r = 0; r + 1 < a.route.size(); ++r) {
            if (a.route[r].lane == cur && !a.route[r + 1].by_lane_change) next = a.route[r + 1].lane;
        }
        if (next == kNoLane && !l.successors.empty()) {
            // Prefer going straight (lowest turn change) deterministically: the first successor.
            next = l.successors.front();
            for (LaneId sc : l.successors) {
                if (net_.lane(sc).turn == road::Turn::straight) next = sc;
            }
        }
        if (std::find(a.path.begin(), a.path.end(), next) != a.path.end()) break;  // loops
        cur = next;
    }
    auto ref = road::ReferenceLine::build(pts);
    if (!ref) return nullptr;
    // Lane starts measured on the fitted line.
    for (size_t i = 0; i < a.path.size(); ++i) {
        a.path_start[i] = ref->project(net_.lane(a.path[i]).centre.front(), a.path_start[i]).s;
    }
    return std::make_shared<const road::ReferenceLine>(std::move(*ref));
}

void World::place(Agent& a, const road::CartesianState& c, std::optional<double> lane_heading) {
    a.x = c.x;
    a.y = c.y;
    a.vx = c.vx;
    a.vy = c.vy;
    a.ax = c.ax;
    a.ay = c.ay;
    const double v = std::hypot(c.vx, c.vy);
    if (v > 0.05) {
        a.yaw = std::atan2(c.vy, c.vx);
        // A car's heading stays within a steering angle's reach of its lane, however slowly it
        // moves sideways in the Frenet plan (reverse: the opposite direction).
        if (lane_heading) {
            constexpr double kMaxRelative = 0.5;  // rad
            const double fwd = *lane_heading + ((a.vx * std::cos(*lane_heading) + a.vy * std::sin(*lane_heading)) < 0 ? M_PI : 0.0);
            const double rel = std::remainder(a.yaw - fwd, 2 * M_PI);
            a.yaw = fwd + std::clamp(rel, -kMaxRelative, kMaxRelative);
        }
    }
    // Signed speed: negative when moving against the heading (reverse).
    const double along = c.vx * std::cos(a.yaw) + c.vy * std::sin(a.yaw);
    a.speed = along >= 0 ? v : -v;
    a.accel = c.ax * std::cos(a.yaw) + c.ay * std::sin(a.yaw);
}

std::string World::init_position(Agent& a, const ir::Position& pos, LaneId& lane, double& s) {
    if (pos.xy) {
        auto l = net_.locate({pos.x, pos.y}, pos.has_heading ? std::optional<double>(pos.heading) : std::nullopt);
        if (l.lane == kNoLane) return "position is not on any lane";
        lane = l.lane;
        s = l.s;
        return "";
    }
    auto id = net_.find(pos.lane);
    if (!id) return "lane '" + pos.lane + "' does not exist on the road";
    lane = *id;
    s = pos.s;
    // Built-in roads measure positions from the road's start; backward lanes run the other way.
    const ir::Road& road = p_.roads.at(static_cast<size_t>(sc_.road));
    if (road.kind == ir::RoadKind::road && pos.lane.find(".-") != std::string::npos) {
        s = net_.lane(lane).length - pos.s;
    }
    if (s < 0 || s > net_.lane(lane).length + 1e-6) {
        return "position s = " + fmt(pos.s, 1) + " m is off lane '" + pos.lane + "' (" + fmt(net_.lane(lane).length, 1) + " m long)";
    }
    (void)a;
    return "";
}

std::string World::init() {
    dt_ = 1.0 / sc_.traffic_rate;
    latency_ = sc_.planning_latency >= 0 ? sc_.planning_latency : 1.0 / sc_.planning_rate;
    seed_ = opt_.seed.value_or(sc_.seed);
    const ir::Road& r = p_.roads.at(static_cast<size_t>(sc_.road));
    const std::string where = loc_text(p_, r.loc);
    switch (r.kind) {
        case ir::RoadKind::road: {
            road::RoadSpec spec;
            spec.name = r.name;
            spec.lanes_forward = r.lanes_forward;
            spec.lanes_backward = r.lanes_backward;
            spec.lane_width_m = r.lane_width;
            spec.speed_limit_mps = r.speed_limit;
            spec.origin = {r.origin_x, r.origin_y};
            spec.heading_rad = r.heading;
            for (const auto& s : r.segments) {
                spec.segments.push_back({s.arc ? road::Segment::arc : road::Segment::straight, s.length, s.radius});
            }
            auto b = road::build_road(spec);
            if (!b.errors.empty()) return where + ": " + b.errors.front();
            net_ = std::move(b.network);
            break;
        }
        case ir::RoadKind::junction: {
            road::JunctionSpec spec;
            spec.name = r.name;
            spec.lanes_per_direction = r.lanes_forward;
            spec.lane_width_m = r.lane_width;
            spec.speed_limit_mps = r.speed_limit;
            spec.arm_length_m = r.arm_length;
            spec.control = r.control == "traffic_lights"  ? road::JunctionSpec::traffic_lights
                           : r.control == "two_way_stops" ? road::JunctionSpec::two_way_stops
                           : r.control == "none"          ? road::JunctionSpec::none
                                                          : road::JunctionSpec::stop_signs;
            auto b = road::build_junction(spec);
            if (!b.errors.empty()) return where + ": " + b.errors.front();
            net_ = std::move(b.network);
            break;
        }
        case ir::RoadKind::lanelet2: {
            std::optional<road::GeoOrigin> origin;
            if (r.has_origin) origin = road::GeoOrigin{r.origin_lat, r.origin_lon, r.origin_alt};
            auto l = road::load_lanelet2(r.map_file, origin);
            if (!l.errors.empty()) return where + ": map '" + r.map_file + "': " + l.errors.front();
            net_ = std::move(*l.network);
            break;
        }
    }
    // Reference lines are built lazily by the network: build them all now, before any thread
    // reads them.
    for (const auto& l : net_.lanes()) (void)net_.reference(l.id);
    for (const auto& l : sc_.lights) {
        programs_[l.name] = &l;
        const bool known = std::any_of(net_.lights.begin(), net_.lights.end(), [&](const road::TrafficLight& x) { return x.name == l.name; });
        if (!known) {
            std::string names;
            for (const auto& x : net_.lights) names += (names.empty() ? "" : ", ") + x.name;
            return loc_text(p_, l.loc) + ": the road has no traffic light '" + l.name + "' (its lights: " +
                   (names.empty() ? "none" : names) + ")";
        }
    }

    agents_.resize(sc_.vehicles.size());
    for (size_t i = 0; i < sc_.vehicles.size(); ++i) {
        Agent& a = agents_[i];
        a.v = &sc_.vehicles[i];
        a.index = static_cast<int>(i);
        const std::string vwhere = loc_text(p_, a.v->loc) + ": vehicle '" + a.v->name + "'";
        LaneId lane = kNoLane;
        double s = 0;
        const ir::Position& start = a.v->kind == ir::VehicleKind::trajectory && !a.v->trajectory.empty()
                                        ? a.v->trajectory.front().position
                                        : a.v->start;
        if (auto e = init_position(a, start, lane, s); !e.empty()) return vwhere + " starts off the road: " + e;
        const auto& ref0 = net_.reference(lane);
        road::FrenetState f{s, a.v->speed, 0, start.offset, 0, 0};
        if (start.xy) f = ref0.project({start.x, start.y});
        f.s_d = a.v->speed;
        place(a, ref0.to_cartesian(f));
        a.yaw = start.xy && start.has_heading ? start.heading : ref0.heading(std::clamp(f.s, 0.0, ref0.length()));
        a.lane = lane;
        a.lane_s = f.s;
        a.lane_d = f.d;
        if (a.v->goal) {
            LaneId gl = kNoLane;
            double gs = 0;
            if (auto e = init_position(a, *a.v->goal, gl, gs); !e.empty()) {
                return loc_text(p_, a.v->goal->loc) + ": the goal of vehicle '" + a.v->name + "' is off the road: " + e;
            }
            a.goal_lane = gl;
            a.goal_s = gs;
            auto route = road::shortest_route(net_, lane, gl);
            if (route.steps.empty()) {
                return loc_text(p_, a.v->goal->loc) + ": the goal of vehicle '" + a.v->name + "' is unreachable: " + route.error;
            }
            a.route = route.steps;
        }
        if (a.v->kind == ir::VehicleKind::sdv) {
            a.tree = std::make_unique<bt::BehaviorTree>(&p_.instances.at(static_cast<size_t>(a.v->tree)));
            a.ref = build_path(a, lane);
            if (!a.ref) return vwhere + ": cannot build a reference line from lane '" + net_.lane(lane).name + "'";
            // Initial plan: keep the start speed until the first plan takes over.
            const road::FrenetState f0 = a.ref->to_frenet({a.x, a.vx, 0, a.y, a.vy, 0}, 0);
            planner::Trajectory tr;
            tr.s = planner::Poly::quadratic(f0.s, f0.s_d, 0);
            tr.d = planner::Poly::quadratic(f0.d, 0, 0);
            tr.duration = 1e6;
            a.plan = ActivePlan{tr, 0.0, a.ref};
        }
    }
    return "";
}

// The geometry a viewer needs, in metres, rounded to centimetres: lane centre lines and bounds
// (every ~1 m), stop lines, lights with the lanes they control and their programs.
std::string World::road_json() const {
    std::ostringstream o;
    auto pts = [&](const std::vector<road::Vec2>& v) {
        o << "[";
        double since = 1e9;
        bool first = true;
        for (size_t i = 0; i < v.size(); ++i) {
            if (i > 0) since += road::distance(v[i - 1], v[i]);
            if (since < 1.0 && i + 1 != v.size()) continue;
            since = 0;
            o << (first ? "" : ",") << "[" << fmt(v[i].x, 2) << "," << fmt(v[i].y, 2) << "]";
            first = false;
        }
        o << "]";
    };
    o << "{\"lanes\":[";
    for (size_t i = 0; i < net_.lanes().size(); ++i) {
        const auto& l = net_.lanes()[i];
        o << (i ? "," : "") << "{\"name\":\"" << l.name << "\",\"centre\":";
        pts(l.centre);
        o << ",\"left\":";
        pts(l.left_bound);
        o << ",\"right\":";
        pts(l.right_bound);
        if (l.stop_line_s) {
            const auto p = net_.reference(l.id).point(*l.stop_line_s);
            o << ",\"stop_line\":[" << fmt(p.x, 2) << "," << fmt(p.y, 2) << "]";
        }
        o << "}";
    }
    o << "],\"lights\":[";
    for (size_t i = 0; i < net_.lights.size(); ++i) {
        const auto& tl = net_.lights[i];
        o << (i ? "," : "") << "{\"name\":\"" << tl.name << "\",\"position\":[" << fmt(tl.position.x, 2) << ","
          << fmt(tl.position.y, 2) << "],\"lanes\":[";
        for (size_t k = 0; k < tl.lanes.size(); ++k) o << (k ? "," : "") << "\"" << net_.lane(tl.lanes[k]).name << "\"";
        o << "],\"program\":[";
        if (auto it = programs_.find(tl.name); it != programs_.end()) {
            for (size_t k = 0; k < it->second->phases.size(); ++k) {
                const auto& ph = it->second->phases[k];
                o << (k ? "," : "") << "{\"state\":\"" << ph.state << "\",\"duration\":" << fmt(ph.duration, 3) << "}";
            }
        }
        o << "],\"offset\":" << fmt(programs_.count(tl.name) ? programs_.at(tl.name)->offset : 0.0, 3) << "}";
    }
    o << "]}\n";
    return o.str();
}

// ---------------------------------------------------------------------------------- context

double Context::lane_width() const { return a_.lane != kNoLane ? w_.net_.lane(a_.lane).width : 3.5; }

int Context::band_of(double d) const {
    const double w = lane_width();
    if (std::fabs(d) < 0.5 * w) return 0;
    if (d > 0 && d < 1.5 * w) return 1;
    if (d < 0 && d > -1.5 * w) return -1;
    return 9;
}

void Context::view() {
    const auto& ref = *a_.ref;
    // Own state at the plan start, along the plan in force.
    road::CartesianState c{a_.x, a_.vx, a_.ax, a_.y, a_.vy, a_.ay};
    std::optional<planner::FrenetState> in_plan;
    if (a_.plan) {
        in_plan = a_.plan->traj.at(t_start_ - a_.plan->start);
        const planner::FrenetState& f = *in_plan;
        c = a_.plan->ref->to_cartesian({f.s, f.s_d, f.s_dd, f.d, f.d_d, f.d_dd});
    }
    self = ref.to_frenet(c);
    if (in_plan && a_.plan->ref != a_.ref) {
        // A new reference line (a lane change completed, or the path was rebuilt): converting
        // accelerations through two lines' curvature amplifies the kinks of map centre lines,
        // so they carry over from the plan's frame (the lines are near-parallel here).
        self.s_dd = in_plan->s_dd;
        self.d_dd = in_plan->d_dd;
    }
    self.s_dd = std::clamp(self.s_dd, -kMaxStartAcc, kMaxStartAcc);
    self.d_dd = std::clamp(self.d_dd, -kMaxStartLatAcc, kMaxStartLatAcc);
    // At rest the brakes hold: the end of a stopping plan's deceleration does not carry into the
    // next plan (it would make every start from standstill roll backwards first).
    if (std::fabs(self.s_d) < kRestSpeed) self.s_dd = 0;
    seen.clear();
    const Snap& me = w_.snap_[static_cast<size_t>(a_.index)];
    for (size_t j = 0; j < w_.snap_.size(); ++j) {
        if (static_cast<int>(j) == a_.index) continue;
        const Snap& o = w_.snap_[j];
        const double dist = std::hypot(o.x - me.x, o.y - me.y);
        if (dist > w_.sc_.sensor_range) continue;
        Seen s;
        s.index = static_cast<int>(j);
        s.f = ref.to_frenet({o.x, o.vx, 0, o.y, o.vy, 0});
        // Constant velocity in Frenet up to the plan start.
        const double lat = t_start_ - t0_;
        s.f.s += s.f.s_d * lat;
        s.f.d += s.f.d_d * lat;
        s.f.s_dd = s.f.d_dd = 0;
        s.length = o.length;
        s.width = o.width;
        s.speed = o.speed;
        s.dist = dist;
        seen.push_back(s);
    }
}

const ir::ParamValue* Context::param(const ir::Node& n, const char* name) const {
    const auto& defs = n.kind == ir::NodeKind::maneuver ? catalog::maneuvers()[static_cast<size_t>(n.leaf)].params
                                                        : catalog::conditions()[static_cast<size_t>(n.leaf)].params;
    for (size_t i = 0; i < defs.size() && i < n.params.size(); ++i) {
        if (defs[i].name == name) return n.params[i].given ? &n.params[i] : nullptr;
    }
    return nullptr;
}

double Context::num(const ir::Node& n, const char* name) const {
    const auto* p = param(n, name);
    if (p == nullptr) return NAN;
    // A condition threshold given as a range is one draw per vehicle, node and run: a driver's
    // acceptance gap varies between drivers, not from tick to tick.
    if (n.kind == ir::NodeKind::condition && p->number.hi > p->number.lo) {
        const auto node = static_cast<uint32_t>(&n - a_.tree->instance().nodes.data());
        const auto slot = static_cast<uint32_t>(p - n.params.data());
        planner::RandomStream rng(w_.seed_, static_cast<uint32_t>(a_.index), 0x80000000u | (node << 8) | slot);
        return p->number.lo + (p->number.hi - p->number.lo) * rng.uniform();
    }
    return p->number.value;
}

const Seen* Context::nearest(int band, int where, bool objects) const {
    const Seen* best = nullptr;
    double best_ds = INFINITY;
    for (const Seen& s : seen) {
        if (!objects && w_.snap_[static_cast<size_t>(s.index)].is_static) continue;
        if (band_of(s.f.d - (band * 0.0)) != band) continue;
        const double ds = s.f.s - self.s;
        const double half = 0.5 * (s.length + a_.v->length);
        const int pos = ds > half ? 1 : ds < -half ? -1 : 0;
        if (pos != where) continue;
        if (std::fabs(ds) < best_ds) {
            best_ds = std::fabs(ds);
            best = &s;
        }
    }
    return best;
}

const Seen* Context::vehicle(const ir::Node& n, const char* name, bool default_leader) const {
    const auto* p = param(n, name);
    if (p == nullptr || p->vehicle.kind == ir::VehicleRef::Kind::none) return default_leader ? nearest(0, 1) : nullptr;
    switch (p->vehicle.kind) {
        case ir::VehicleRef::Kind::vehicle:
            for (const Seen& s : seen) {
                if (s.index == p->vehicle.vehicle) return &s;
            }
            return nullptr;
        case ir::VehicleRef::Kind::zone: {
            const std::string& z = catalog::vehicle_zones()[static_cast<size_t>(p->vehicle.zone)];
            if (z == "front") return nearest(0, 1);
            if (z == "back") return nearest(0, -1);
            if (z == "left") return nearest(1, 0);
            if (z == "right") return nearest(-1, 0);
            if (z == "front_left") return nearest(1, 1);
            if (z == "front_right") return nearest(-1, 1);
            if (z == "back_left") return nearest(1, -1);
            if (z == "back_right") return nearest(-1, -1);
            return nullptr;
        }
        default: return nullptr;
    }
}

bool Context::condition(const ir::Node& n, int32_t index) {
    const auto kind = static_cast<ConditionKind>(n.leaf);
    auto in = [](double x, double lo, double hi) { return (std::isnan(lo) || x >= lo) && (std::isnan(hi) || x <= hi); };
    const Snap& me = w_.snap_[static_cast<size_t>(a_.index)];
    (void)index;
    switch (kind) {
        case ConditionKind::sim_time: return in(t0_, num(n, "after"), num(n, "before"));
        case ConditionKind::vehicle_state: {
            const auto* p = param(n, "vehicle");
            road::FrenetState f = self;
            double speed = self.s_d, acc = me.accel;
            if (p != nullptr && p->vehicle.kind != ir::VehicleRef::Kind::self && p->vehicle.kind != ir::VehicleRef::Kind::none) {
                const Seen* s = vehicle(n, "vehicle", false);
                if (s == nullptr) return false;
                f = s->f;
                speed = s->speed;
                acc = w_.snap_[static_cast<size_t>(s->index)].accel;
            }
            return in(f.s, num(n, "s_min"), num(n, "s_max")) && in(f.d, num(n, "d_min"), num(n, "d_max")) &&
                   in(speed, num(n, "speed_min"), num(n, "speed_max")) && in(acc, num(n, "acc_min"), num(n, "acc_max"));
        }
        case ConditionKind::delta_state: {
            const Seen* s = vehicle(n, "vehicle", false);
            if (s == nullptr) return false;
            return in(s->f.s - self.s, num(n, "ds_min"), num(n, "ds_max")) && in(s->f.d - self.d, num(n, "dd_min"), num(n, "dd_max")) &&
                   in(s->speed - self.s_d, num(n, "dv_min"), num(n, "dv_max"));
        }
        case ConditionKind::gap: {
            const Seen* s = nullptr;
            if (const auto* lane = param(n, "lane")) {
                const int band = lane->choice == 0 ? 1 : lane->choice == 2 ? -1 : 0;
                s = nearest(band, 1);
            } else {
                s = vehicle(n, "vehicle", true);
            }
            if (s == nullptr) return !std::isnan(num(n, "min")) || !std::isnan(num(n, "time_min"));  // nobody: gap is infinite
            const double gap = std::fabs(s->f.s - self.s) - 0.5 * (s->length + a_.v->length);
            const double tgap = self.s_d > 0.1 ? gap / self.s_d : INFINITY;
            return in(gap, num(n, "min"), num(n, "max")) && in(tgap, num(n, "time_min"), num(n, "time_max"));
        }
        case ConditionKind::ttc: {
            const Seen* s = vehicle(n, "vehicle", true);
            if (s == nullptr) return false;
            const double ds = s->f.s - self.s;
            const double gap = std::fabs(ds) - 0.5 * (s->length + a_.v->length);
            const double closing = ds >= 0 ? self.s_d - s->f.s_d : s->f.s_d - self.s_d;
            if (closing <= 0) return false;
            return std::max(gap, 0.0) / closing < num(n, "max");
        }
        case ConditionKind::distance: {
            const Seen* s = vehicle(n, "vehicle", false);
            return s != nullptr && in(s->dist, num(n, "min"), num(n, "max"));
        }
        case ConditionKind::lane_occupied: {
            const auto* lane = param(n, "lane");
            const int band = lane == nullptr || lane->choice == 1 ? 0 : lane->choice == 0 ? 1 : -1;
            const double objects = num(n, "objects");
            const Seen* s = nearest(band, 1, std::isnan(objects) || objects != 0);
            if (s == nullptr) return false;
            const double gap = s->f.s - self.s - 0.5 * (s->length + a_.v->length);
            const double tg = num(n, "time_gap");
            if (!std::isnan(tg)) return gap <= tg * std::max(self.s_d, 0.0);
            return gap <= num(n, "distance");
        }
        case ConditionKind::can_lane_change: {
            const auto* lane = param(n, "lane");
            const bool left = lane == nullptr || lane->choice == 0;
            const auto& l = w_.net_.lane(a_.lane);
            const LaneId nb = left ? l.left : l.right;
            const bool same = left ? l.left_same_direction : l.right_same_direction;
            if (nb == kNoLane || !same) return false;
            const double gap = num(n, "gap");
            for (const Seen& s : seen) {
                if (band_of(s.f.d) != (left ? 1 : -1)) continue;
                if (std::fabs(s.f.s - self.s) < gap + 0.5 * (s.length + a_.v->length)) return false;
            }
            return true;
        }
        case ConditionKind::vehicle_moving:
        case ConditionKind::vehicle_stopped:
        case ConditionKind::vehicle_parked: {
            const auto* p = param(n, "vehicle");
            int idx = a_.index;
            if (p != nullptr && p->vehicle.kind != ir::VehicleRef::Kind::self && p->vehicle.kind != ir::VehicleRef::Kind::none) {
                const Seen* s = vehicle(n, "vehicle", false);
                if (s == nullptr) return false;
                idx = s->index;
            }
            const Snap& o = w_.snap_[static_cast<size_t>(idx)];
            if (kind == ConditionKind::vehicle_moving) return std::fabs(o.speed) > num(n, "min_speed");
            if (kind == ConditionKind::vehicle_stopped) return std::fabs(o.speed) <= num(n, "max_speed");
            return o.stopped_since >= 0 && t0_ - o.stopped_since >= num(n, "duration");
        }
        case ConditionKind::reached_goal: {
            if (a_.goal_lane == kNoLane) return false;
            for (size_t i = 0; i < a_.path.size(); ++i) {
                if (a_.path[i] == a_.goal_lane) {
                    const double gs = a_.path_start[i] + a_.goal_s;
                    return gs - self.s <= num(n, "distance");
                }
            }
            return false;
        }
        case ConditionKind::at_lane_change_segment: {
            for (size_t r = 0; r + 1 < a_.route.size(); ++r) {
                if (a_.route[r].lane == a_.lane && a_.route[r + 1].by_lane_change) {
                    const auto* lane = param(n, "lane");
                    const auto& l = w_.net_.lane(a_.lane);
                    const bool left = a_.route[r + 1].lane == l.left;
                    if (lane == nullptr || lane->choice == 2) return true;
                    return (lane->choice == 0) == left;
                }
            }
            return false;
        }
        case ConditionKind::approaching_stop:
        case ConditionKind::traffic_light:
        case ConditionKind::intersection_type: {
            const double look = kind == ConditionKind::intersection_type ? 200.0 : num(n, "distance");
            for (size_t i = 0; i < a_.path.size(); ++i) {
                const auto& l = w_.net_.lane(a_.path[i]);
                const double start = a_.path_start[i];
                if (start > self.s + look) break;
                const bool stop_ahead = l.stop_line_s && start + *l.stop_line_s >= self.s - 0.5 &&
                                        start + *l.stop_line_s <= self.s + look;
                if (kind == ConditionKind::approaching_stop) {
                    const auto* k = param(n, "kind");
                    const int want = k == nullptr ? 2 : k->choice;
                    if (stop_ahead && want != 1) return true;
                    if (l.in_junction && start >= self.s && start <= self.s + look && want != 0) return true;
                    continue;
                }
                if (kind == ConditionKind::traffic_light) {
                    if (!stop_ahead || l.traffic_lights.empty()) continue;
                    const auto* st = param(n, "state");
                    const std::string state = w_.light_state(l.traffic_lights.front(), t0_);
                    static const char* kStates[] = {"red", "yellow", "green"};
                    return st != nullptr && state == kStates[st->choice];
                }
                // intersection type of the next stop / junction
                if (stop_ahead || l.in_junction) {
                    const auto* ty = param(n, "type");
                    const int want = ty == nullptr ? 3 : ty->choice;
                    const int have = !l.traffic_lights.empty() ? 1 : l.all_way_stop ? 0 : l.right_of_way >= 0 ? 2 : 3;
                    return want == have;
                }
            }
            if (kind == ConditionKind::intersection_type) {
                const auto* ty = param(n, "type");
                return ty != nullptr && ty->choice == 3;
            }
            return false;
        }
        case ConditionKind::yield_role: {
            const auto& l = w_.net_.lane(a_.lane);
            if (l.right_of_way < 0) return false;
            const auto& row = w_.net_.rights_of_way[static_cast<size_t>(l.right_of_way)];
            const bool yields = std::find(row.yield.begin(), row.yield.end(), a_.lane) != row.yield.end();
            const auto* role = param(n, "role");
            return role != nullptr && (role->choice == 0) == yields;
        }
        case ConditionKind::intersection_occupied: {
            for (const Seen& s : seen) {
                const LaneId ol = w_.snap_[static_cast<size_t>(s.index)].lane;
                if (ol != kNoLane && w_.net_.lane(ol).in_junction && s.dist < 60 + num(n, "distance")) return true;
            }
            return false;
        }
        case ConditionKind::out_of_route: {
            if (a_.goal_lane == kNoLane) return false;
            const bool on = std::find(a_.path.begin(), a_.path.end(), a_.lane) != a_.path.end() &&
                            std::find(a_.path.begin(), a_.path.end(), a_.goal_lane) != a_.path.end();
            return !on;
        }
        case ConditionKind::stopped_at_line: return a_.stopped_line == a_.lane && a_.stopped_gap <= num(n, "distance");
        case ConditionKind::wait: {
            auto [it, fresh] = a_.waits.try_emplace(index, t0_, a_.plan_count);
            if (!fresh && it->second.second + 1 != a_.plan_count && it->second.second != a_.plan_count) it->second.first = t0_;
            it->second.second = a_.plan_count;
            return t0_ - it->second.first >= num(n, "time") - 1e-9;
        }
        case ConditionKind::all_way_stop_turn: {
            // First come, first served among vehicles stopped at all-way-stop lines; ties by
            // vehicle order. The junction must be clear.
            const Snap& m = w_.snap_[static_cast<size_t>(a_.index)];
            if (m.stopped_since < 0) return false;
            for (const Seen& s : seen) {
                const Snap& o = w_.snap_[static_cast<size_t>(s.index)];
                if (o.lane == kNoLane) continue;
                const auto& ol = w_.net_.lane(o.lane);
                if (ol.in_junction && s.dist < 40) return false;
                if (ol.all_way_stop && o.stopped_since >= 0 && s.dist < 40 &&
                    (o.stopped_since < m.stopped_since || (o.stopped_since == m.stopped_since && s.index < a_.index))) {
                    return false;
                }
            }
            return true;
        }
    }
    return false;
}

bt::Status Context::maneuver(const ir::Node& n, int32_t index) {
    const auto kind = static_cast<ManeuverKind>(n.leaf);
    (void)index;
    switch (kind) {
        case ManeuverKind::follow: return vehicle(n, "leader", true) != nullptr ? bt::Status::success : bt::Status::failure;
        case ManeuverKind::lane_change:
        case ManeuverKind::cut_in: {
            if (kind == ManeuverKind::cut_in && vehicle(n, "target", false) == nullptr) return bt::Status::failure;
            const auto* lane = param(n, "lane");
            const auto& l = w_.net_.lane(a_.lane);
            int side = 0;  // +1 left, −1 right
            if (lane != nullptr) {
                const std::string& word = catalog::maneuver(kind).find_param("lane")->choices[static_cast<size_t>(lane->choice)];
                if (word == "left") side = 1;
                else if (word == "right") side = -1;
                else if (word == "target") {
                    const Seen* t = vehicle(n, "target", false);
                    side = t == nullptr ? 0 : band_of(t->f.d);
                    if (side == 9) side = 0;
                } else if (word == "route") {
                    for (size_t r = 0; r + 1 < a_.route.size(); ++r) {
                        if (a_.route[r].lane == a_.lane && a_.route[r + 1].by_lane_change) side = a_.route[r + 1].lane == l.left ? 1 : -1;
                    }
                }
            }
            if (side == 0) {
                // Already in the target lane (a swerve, or the cut-in target is beside us).
                return bt::Status::success;
            }
            const LaneId nb = side > 0 ? l.left : l.right;
            const bool same = side > 0 ? l.left_same_direction : l.right_same_direction;
            if (nb == kNoLane || !same) return bt::Status::failure;
            const double w = l.width, target_d = side * w;
            // Done when the whole footprint is inside the target lane.
            if (std::fabs(self.d - target_d) + 0.5 * a_.v->width <= 0.5 * w + 1e-6) {
                a_.target_lane = nb;
                switched = true;
                return bt::Status::success;
            }
            a_.target_lane = nb;
            return bt::Status::running;
        }
        default: return bt::Status::success;
    }
}

// ---------------------------------------------------------------------------------- planning

planner::Sampled to_sampled(const ir::Sampled& s) {
    return {s.value, s.lo, s.hi, s.samples, static_cast<planner::SampleMethod>(static_cast<int>(s.method)), s.sigma};
}

void World::plan_agent(Agent& a, double t0) {
    const auto started = std::chrono::steady_clock::now();
    const double t_start = t0 + latency_;
    Context ctx(*this, a, t0, t_start);
    // Rebuild the frame when the vehicle nears the end of its reference line.
    if (a.ref && a.lane != kNoLane) {
        const auto probe = a.ref->project({a.x, a.y});
        if (probe.s > a.ref->length() - 120 || std::fabs(probe.d) > 6) {
            if (auto r = build_path(a, a.lane)) {
                a.ref = r;
                a.ref_s = -1;
            }
        }
    }
    ctx.view();
    std::vector<bt::Visit> visits;
    a.tree->tick(ctx, opt_.trace ? &visits : nullptr);
    if (ctx.switched && a.target_lane != kNoLane) {
        // A lane change / cut-in completed: switch to the new lane's frame, tick once more.
        // A change off the route re-plans the route from the new lane (when the goal is still
        // reachable from it; out_of_route reports when it is not).
        const bool on_route = std::any_of(a.route.begin(), a.route.end(), [&](const road::RouteStep& r) { return r.lane == a.target_lane; });
        if (a.goal_lane != kNoLane && !on_route) {
            auto route = road::shortest_route(net_, a.target_lane, a.goal_lane);
            if (!route.steps.empty()) a.route = route.steps;
        }
        if (auto r = build_path(a, a.target_lane)) {
            a.ref = r;
            a.ref_s = -1;
            a.lane = a.target_lane;
        }
        a.target_lane = kNoLane;
        ctx.switched = false;
        ctx.view();
        a.tree->tick(ctx, opt_.trace ? &visits : nullptr);
    }
    const int32_t sel = a.tree->selected();
    planner::ManeuverConfig cfg = planner::default_config(ManeuverKind::keep_velocity);
    planner::PlanRequest req;
    std::vector<planner::Obstacle> obstacles;
    for (const Seen& s : ctx.seen) {
        obstacles.push_back({s.index, {s.f.s, s.f.s_d, 0, s.f.d, s.f.d_d, 0}, s.length, s.width, snap_[static_cast<size_t>(s.index)].is_static});
    }
    const double w = a.lane != kNoLane ? net_.lane(a.lane).width : 3.5;
    req.current_lane = {0, 0.5 * w, -0.5 * w};
    req.target_lane = req.current_lane;
    if (sel >= 0) {
        const ir::Node& n = a.tree->instance().nodes[static_cast<size_t>(sel)];
        a.maneuver = sel;
        a.maneuver_name = n.name;
        const auto kind = static_cast<ManeuverKind>(n.leaf);
        cfg = planner::default_config(kind);
        auto p = [&](const char* name) { return ctx.param(n, name); };
        auto nv = [&](const char* name, double& out) {
            if (const auto* x = p(name)) out = x->number.value;
        };
        auto sv = [&](const char* name, planner::Sampled& out) {
            if (const auto* x = p(name)) out = to_sampled(x->number);
        };
        auto bv = [&](const char* name, bool& out) {
            if (const auto* x = p(name)) out = x->number.value != 0;
        };
        planner::CommonConfig& k = cfg.common;
        nv("max_long_jerk", k.max_long_jerk);
        nv("max_lat_jerk", k.max_lat_jerk);
        nv("max_long_acc", k.max_long_acc);
        nv("max_lat_acc", k.max_lat_acc);
        bv("collision", k.collision);
        bv("off_lane", k.off_lane);
        bv("direction", k.direction);
        nv("w_time", k.w_time);
        nv("w_efficiency", k.w_efficiency);
        nv("w_lane_offset", k.w_lane_offset);
        nv("w_long_jerk", k.w_long_jerk);
        nv("w_lat_jerk", k.w_lat_jerk);
        nv("w_long_acc", k.w_long_acc);
        nv("w_lat_acc", k.w_lat_acc);
        nv("w_proximity", k.w_proximity);
        nv("expected_offset", k.expected_offset);
        nv("expected_acc", k.expected_acc);
        nv("expected_jerk", k.expected_jerk);
        sv("lat_offset", k.lat_offset);
        if (const auto* x = p("eval_points")) k.eval_points = static_cast<int>(x->number.value);
        sv("speed", cfg.speed);
        sv("duration", cfg.duration);
        nv("max_speed_change", cfg.max_speed_change);
        nv("time_gap", cfg.time_gap);
        nv("stop_distance", cfg.stop_distance);
        sv("delta_s", cfg.delta_s);
        nv("delta_v", cfg.delta_v);
        nv("delta_a", cfg.delta_a);
        sv("duration_factor", cfg.duration_factor);
        nv("distance", cfg.stop_before);
        auto index_of = [&](const Seen* s) -> int {
            if (s == nullptr) return -1;
            for (size_t i = 0; i < obstacles.size(); ++i) {
                if (obstacles[i].id == s->index) return static_cast<int>(i);
            }
            return -1;
        };
        if (kind == ManeuverKind::follow) req.leader = index_of(ctx.vehicle(n, "leader", true));
        if (kind == ManeuverKind::cut_in) req.target_vehicle = index_of(ctx.vehicle(n, "target", false));
        if ((kind == ManeuverKind::lane_change || kind == ManeuverKind::cut_in) && a.target_lane != kNoLane) {
            const auto& l = net_.lane(a.lane);
            const double side = a.target_lane == l.left ? 1.0 : -1.0;
            req.target_lane = {side * w, side * w + 0.5 * w, side * w - 0.5 * w};
        }
        if (kind == ManeuverKind::stop) {
            const auto* at = p("at");
            const int which = at != nullptr ? at->choice : 3;
            cfg.stop_at = static_cast<planner::StopTarget>(which);
            req.stop_s = ctx.self.s;
            for (size_t i = 0; i < a.path.size(); ++i) {
                const auto& l = net_.lane(a.path[i]);
                if (which == 0 && a.path[i] == a.goal_lane) {
                    req.stop_s = a.path_start[i] + a.goal_s;
                    break;
                }
                if (which == 1 && l.stop_line_s && a.path_start[i] + *l.stop_line_s >= ctx.self.s - 1) {
                    req.stop_s = a.path_start[i] + *l.stop_line_s - 0.5 * a.v->length;
                    break;
                }
            }
            if (which == 2) {
                nv("position", req.stop_s);
                req.stop_s += a.path_start.empty() ? 0 : a.path_start.front();
            }
            if (which == 0 && a.goal_lane == kNoLane) cfg.stop_at = planner::StopTarget::now;
        }
    }
    req.start = {ctx.self.s, ctx.self.s_d, ctx.self.s_dd, ctx.self.d, ctx.self.d_d, ctx.self.d_dd};
    req.length_m = a.v->length;
    req.width_m = a.v->width;
    req.config = &cfg;
    req.obstacles = obstacles;
    req.speed_limit_mps = a.lane != kNoLane ? net_.lane(a.lane).speed_limit : 0;
    req.seed = seed_;
    req.vehicle = static_cast<uint32_t>(a.index);
    req.plan_number = a.plan_count++;
    thread_local planner::PlanWorkspace ws;
    ws.keep_candidates = opt_.trace;
    planner::PlanResult result = planner::plan(req, ws);
    a.pending = ActivePlan{result.trajectory, t_start, a.ref};
    a.fallback = result.record.fallback;
    a.candidates = result.record.candidates;
    a.plan_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - started).count();
    if (opt_.trace) {
        std::ostringstream o;
        o << "{\"time\":" << fmt(t0) << ",\"vehicle\":\"" << a.v->name << "\",\"plan\":" << req.plan_number
          << ",\"nodes\":[";
        for (size_t i = 0; i < visits.size(); ++i) {
            const auto& node = a.tree->instance().nodes[static_cast<size_t>(visits[i].node)];
            o << (i ? "," : "") << "{\"node\":\"" << node.path << "\",\"status\":\"" << bt::to_string(visits[i].status) << "\"}";
        }
        o << "],\"maneuver\":\"" << a.maneuver_name << "\",\"kind\":\"" << catalog::maneuver(cfg.kind).name
          << "\",\"candidates\":" << result.record.candidates << ",\"feasible\":" << result.record.feasible << ",\"rejected\":{";
        for (size_t c = 0; c < planner::kCauseCount; ++c) {
            o << (c ? "," : "") << "\"" << planner::to_string(static_cast<planner::RejectCause>(c)) << "\":" << result.record.rejections[c];
        }
        const auto& wc = result.record.winner_cost;
        o << "},\"winner\":" << result.record.winner << ",\"fallback\":" << (result.record.fallback ? "true" : "false")
          << ",\"cost\":{\"time\":" << fmt(wc.time) << ",\"efficiency\":" << fmt(wc.efficiency) << ",\"lane_offset\":" << fmt(wc.lane_offset)
          << ",\"long_jerk\":" << fmt(wc.long_jerk) << ",\"lat_jerk\":" << fmt(wc.lat_jerk) << ",\"long_acc\":" << fmt(wc.long_acc)
          << ",\"lat_acc\":" << fmt(wc.lat_acc) << ",\"proximity\":" << fmt(wc.proximity) << ",\"total\":" << fmt(wc.total) << "}";
        o << ",\"start\":{\"s\":" << fmt(req.start.s) << ",\"s_d\":" << fmt(req.start.s_d) << ",\"s_dd\":" << fmt(req.start.s_dd)
          << ",\"d\":" << fmt(req.start.d) << ",\"d_d\":" << fmt(req.start.d_d) << ",\"d_dd\":" << fmt(req.start.d_dd) << "}";
        // Every candidate as a world-frame polyline (6 points), with its outcome, for viewers.
        o << ",\"paths\":[";
        for (size_t c = 0; c < ws.candidates.size(); ++c) {
            const planner::Candidate& cand = ws.candidates[c];
            const char* status = static_cast<int>(c) == result.record.winner ? "winner"
                                 : cand.feasible                              ? "feasible"
                                                                              : planner::to_string(cand.cause);
            o << (c ? "," : "") << "{\"status\":\"" << status << "\",\"xy\":[";
            constexpr int kPoints = 6;
            for (int k = 0; k < kPoints; ++k) {
                const double t = cand.duration * k / (kPoints - 1);
                const auto p = a.ref->to_cartesian({cand.s.x(t), cand.s.v(t), 0, cand.d.x(t), 0, 0});
                o << (k ? "," : "") << fmt(p.x, 2) << "," << fmt(p.y, 2);
            }
            o << "]}";
        }
        o << "]}\n";
        a.trace = o.str();
    }
}

// ---------------------------------------------------------------------------------- the loop

RunResult World::run() {
    RunResult out;
    out.scenario = sc_.name;
    const auto wall0 = std::chrono::steady_clock::now();
    const int total_ticks = static_cast<int>(std::llround(sc_.timeout / dt_));
    const int period = std::max(1, static_cast<int>(std::llround(sc_.traffic_rate / sc_.planning_rate)));
    const size_t n = agents_.size();
    out.vehicles.resize(n);
    for (size_t i = 0; i < n; ++i) {
        for (size_t j = i + 1; j < n; ++j) {
            PairMetrics m;
            m.a = static_cast<int>(i);
            m.b = static_cast<int>(j);
            out.pairs.push_back(m);
        }
    }
    std::vector<std::vector<bool>> touching(n, std::vector<bool>(n, false));
    std::ostringstream csv;
    csv << "time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver\n";
    std::string decisions;
    const int threads = std::max(1, opt_.threads);
    bool ended = false;  // a vehicle whose goal ends the run reached it
    int last_tick = 0;
    for (int tick = 0; tick <= total_ticks; ++tick) {
        const auto tick0 = std::chrono::steady_clock::now();
        const double t = tick * dt_;
        // 1. Advance every vehicle to time t.
        for (Agent& a : agents_) {
            if (a.v->kind == ir::VehicleKind::sdv) {
                if (a.pending && t + 1e-9 >= a.pending->start) {
                    a.plan = std::move(a.pending);
                    a.pending.reset();
                }
                const planner::FrenetState f = a.plan->traj.at(t - a.plan->start);
                place(a, a.plan->ref->to_cartesian({f.s, f.s_d, f.s_dd, f.d, f.d_d, f.d_dd}), a.plan->ref->heading(f.s));
                // Current lane: the path lane under the vehicle; lane coordinates from the path.
                const auto probe = a.ref->project({a.x, a.y}, std::max(0.0, a.ref_s));
                a.ref_s = probe.s;
                for (size_t i = 0; i < a.path.size(); ++i) {
                    if (probe.s + 1e-9 >= a.path_start[i]) {
                        a.lane = a.path[i];
                        a.lane_s = probe.s - a.path_start[i];
                        a.lane_d = probe.d;
                    }
                }
            } else if (a.v->kind == ir::VehicleKind::trajectory && tick > 0) {
                const auto& wp = a.v->trajectory;
                size_t k = 0;
                while (k + 2 < wp.size() && wp[k + 1].time <= t) ++k;
                const auto pos = [&](size_t i) {
                    LaneId l;
                    double s;
                    init_position(a, wp[i].position, l, s);
                    return net_.reference(l).to_cartesian({s, 0, 0, wp[i].position.offset, 0, 0});
                };
                const auto p0 = pos(k), p1 = pos(k + 1);
                const double span = std::max(1e-9, wp[k + 1].time - wp[k].time);
                const double f = std::clamp((t - wp[k].time) / span, 0.0, 1.0);
                road::CartesianState c;
                c.x = p0.x + f * (p1.x - p0.x);
                c.y = p0.y + f * (p1.y - p0.y);
                c.vx = t <= wp.back().time ? (p1.x - p0.x) / span : 0;
                c.vy = t <= wp.back().time ? (p1.y - p0.y) / span : 0;
                const double old_speed = a.speed;
                place(a, c);
                a.accel = (a.speed - old_speed) / dt_;
            }
            if (a.v->kind != ir::VehicleKind::sdv && a.v->kind != ir::VehicleKind::static_object) {
                const auto loc = net_.locate({a.x, a.y}, a.yaw);
                a.lane = loc.lane;
            }
            if (a.lane != kNoLane && a.v->kind != ir::VehicleKind::sdv) {
                const auto f = net_.reference(a.lane).project({a.x, a.y});
                a.lane_s = f.s;
                a.lane_d = f.d;
            }
            if (std::fabs(a.speed) < 0.1) {
                if (a.stopped_since < 0) a.stopped_since = t;
            } else {
                a.stopped_since = -1;
            }
        }
        // 2. Snapshot.
        snap_.resize(n);
        for (size_t i = 0; i < n; ++i) {
            const Agent& a = agents_[i];
            snap_[i] = {a.x, a.y, a.yaw, a.vx, a.vy, a.speed, a.accel, a.v->length, a.v->width, a.lane,
                        a.v->kind == ir::VehicleKind::static_object, a.stopped_since, a.maneuver};
        }
        // 3. Ground truth: collisions, gaps, TTC, headway, per-vehicle extremes, goals.
        std::vector<Box> boxes(n);
        for (size_t i = 0; i < n; ++i) boxes[i] = {{agents_[i].x, agents_[i].y}, agents_[i].yaw, agents_[i].v->length, agents_[i].v->width};
        size_t pi = 0;
        for (size_t i = 0; i < n; ++i) {
            for (size_t j = i + 1; j < n; ++j, ++pi) {
                PairMetrics& m = out.pairs[pi];
                // The exact box distance only when it could matter: a lower bound from the
                // centres and the half diagonals first.
                const double centre = road::distance(boxes[i].centre, boxes[j].centre);
                const double reach = 0.5 * (std::hypot(boxes[i].length, boxes[i].width) + std::hypot(boxes[j].length, boxes[j].width));
                const bool near = centre - reach < m.min_gap || touching[i][j] || centre <= reach;
                const double g = near ? gap(boxes[i], boxes[j]) : centre - reach;
                m.min_gap = std::min(m.min_gap, g);
                const bool hit = near && g <= 0;
                if (hit && !touching[i][j]) {
                    const double rel = std::hypot(agents_[i].vx - agents_[j].vx, agents_[i].vy - agents_[j].vy);
                    out.events.push_back({t, "collision", {static_cast<int>(i), static_cast<int>(j)}, rel, impact_zone(boxes[i], boxes[j])});
                }
                touching[i][j] = hit;
                // Longitudinal relations when one is ahead of the other in the same lane.
                for (int dir = 0; dir < 2; ++dir) {
                    const Agent& f = agents_[dir ? j : i];
                    const Agent& l = agents_[dir ? i : j];
                    const Vec2 h{std::cos(f.yaw), std::sin(f.yaw)};
                    const Vec2 rel{l.x - f.x, l.y - f.y};
                    const double lon = road::dot(rel, h), lat = std::fabs(road::cross(h, rel));
                    if (lon <= 0 || lat > 0.5 * (f.v->width + l.v->width)) continue;
                    const double bumper = lon - 0.5 * (f.v->length + l.v->length);
                    if (f.speed > 0.1) m.min_headway = std::min(m.min_headway, std::max(0.0, bumper) / f.speed);
                    const double closing = f.speed - (l.vx * h.x + l.vy * h.y);
                    if (closing > 0.01) m.min_ttc = std::min(m.min_ttc, std::max(0.0, bumper) / closing);
                }
            }
        }
        for (size_t i = 0; i < n; ++i) {
            Agent& a = agents_[i];
            VehicleMetrics& vm = out.vehicles[i];
            vm.max_speed = std::max(vm.max_speed, std::fabs(a.speed));
            vm.max_acc = std::max(vm.max_acc, std::fabs(a.accel));
            if (tick > 0) vm.max_jerk = std::max(vm.max_jerk, std::fabs(a.accel - a.prev_accel) / dt_);
            a.prev_accel = a.accel;
            // Stopping at a stop line (the front bumper within 5 m before it) is remembered.
            if (a.lane != kNoLane && std::fabs(a.speed) < 0.1) {
                const auto& l = net_.lane(a.lane);
                const double gap = l.stop_line_s ? *l.stop_line_s - (a.lane_s + 0.5 * a.v->length) : -1;
                if (gap >= -0.5 && gap <= 5.0 && (a.stopped_line != a.lane || gap < a.stopped_gap)) {
                    a.stopped_line = a.lane;
                    a.stopped_gap = std::max(0.0, gap);
                }
            }
            if (a.goal_lane != kNoLane && !a.goal_reached) {
                // Within 4 m along and 2 m across the goal the vehicle may keep closing in; the
                // goal is reached when the along-track distance stops decreasing (overshot when
                // it is then faster than 1 m/s), as in the reference implementation.
                const std::optional<double> dist = goal_distance(a);
                if (dist && (a.goal_dist >= 0 || (*dist <= 4.0 && std::fabs(a.lane_d) <= 2.0))) {
                    if (a.goal_dist >= 0 && *dist >= a.goal_dist - 1e-9) {
                        a.goal_reached = true;
                        vm.reached_goal = true;
                        out.events.push_back({t, std::fabs(a.speed) > 1.0 ? "goal_overshot" : "goal_reached", {static_cast<int>(i)}, 0, ""});
                        if (a.v->goal_ends_run) ended = true;
                    } else {
                        a.goal_dist = *dist;
                    }
                }
            }
        }
        // 4. Output rows.
        for (size_t i = 0; i < n; ++i) {
            const Agent& a = agents_[i];
            const char* kind = a.v->kind == ir::VehicleKind::sdv ? (a.v->is_ego ? "ego" : "sdv")
                               : a.v->kind == ir::VehicleKind::trajectory ? (a.v->is_ego ? "ego" : "trajectory")
                                                                          : "static";
            csv << fmt(t) << "," << tick << "," << a.v->name << "," << kind << "," << fmt(a.x) << "," << fmt(a.y) << ","
                << fmt(a.yaw) << "," << fmt(a.speed) << "," << fmt(a.accel) << "," << fmt(a.lane_s) << "," << fmt(a.lane_d) << ","
                << (a.lane != kNoLane ? net_.lane(a.lane).name : "") << "," << (a.v->kind == ir::VehicleKind::sdv ? a.maneuver_name : "") << "\n";
        }
        last_tick = tick;
        if (tick == total_ticks || ended) break;
        // 5. Planning of the SDVs due at this tick, in parallel, applied in vehicle order.
        std::vector<Agent*> due;
        for (Agent& a : agents_) {
            if (a.v->kind == ir::VehicleKind::sdv && (tick + a.index) % period == 0) due.push_back(&a);
        }
        if (threads > 1 && due.size() > 1) {
            std::vector<std::thread> pool;
            const size_t k = std::min<size_t>(static_cast<size_t>(threads), due.size());
            for (size_t w = 0; w < k; ++w) {
                pool.emplace_back([&, w] {
                    for (size_t d = w; d < due.size(); d += k) plan_agent(*due[d], t);
                });
            }
            for (auto& th : pool) th.join();
        } else {
            for (Agent* a : due) plan_agent(*a, t);
        }
        for (Agent* a : due) {
            VehicleMetrics& vm = out.vehicles[static_cast<size_t>(a->index)];
            ++vm.plans;
            out.timing.plan_us.push_back(a->plan_us);
            out.timing.candidates += a->candidates;
            if (a->fallback) {
                if (!vm.fallback_used) out.events.push_back({t, "fallback", {a->index}, 0, ""});
                vm.fallback_used = true;
            }
            decisions += a->trace;
            a->trace.clear();
        }
        out.timing.tick_us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - tick0).count());
        if (opt_.realtime) {
            const auto target = wall0 + std::chrono::duration<double>((tick + 1) * dt_);
            std::this_thread::sleep_until(target);
        }
        if (opt_.progress && tick % 30 == 0) opt_.progress(static_cast<double>(tick) / total_ticks);
    }
    out.ticks = last_tick;
    out.duration = last_tick * dt_;
    out.timed_out = !ended;
    if (out.timed_out) out.events.push_back({out.duration, "timeout", {}, 0, ""});
    std::stable_sort(out.events.begin(), out.events.end(), [](const Event& a, const Event& b) { return a.time < b.time; });
    out.trajectories_csv = csv.str();
    out.road_json = road_json();
    out.decisions_jsonl = std::move(decisions);
    out.timing.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    // Expectations.
    std::function<bool(int32_t, std::optional<double>&)> eval = [&](int32_t i, std::optional<double>& value) -> bool {
        const ir::Expect& e = sc_.expects[static_cast<size_t>(i)];
        std::optional<double> ignored;
        switch (e.kind) {
            case ir::Expect::Kind::not_: return !eval(e.lhs, ignored);
            case ir::Expect::Kind::and_: return eval(e.lhs, ignored) && eval(e.rhs, ignored);
            case ir::Expect::Kind::or_: return eval(e.lhs, ignored) || eval(e.rhs, ignored);
            case ir::Expect::Kind::call: break;
        }
        auto pair = [&](int a, int b) -> const PairMetrics& {
            for (const auto& m : out.pairs) {
                if ((m.a == a && m.b == b) || (m.a == b && m.b == a)) return m;
            }
            static const PairMetrics kNone;
            return kNone;
        };
        const auto kind = static_cast<catalog::ExpectKind>(e.function);
        double x = 0;
        switch (kind) {
            case catalog::ExpectKind::collision:
                for (const Event& ev : out.events) {
                    if (ev.kind != "collision") continue;
                    bool match = true;
                    for (int v : e.vehicles) match = match && std::find(ev.vehicles.begin(), ev.vehicles.end(), v) != ev.vehicles.end();
                    if (match) return true;
                }
                return false;
            case catalog::ExpectKind::no_collision:
                return std::none_of(out.events.begin(), out.events.end(), [](const Event& ev) { return ev.kind == "collision"; });
            case catalog::ExpectKind::reached_goal: return out.vehicles[static_cast<size_t>(e.vehicles[0])].reached_goal;
            case catalog::ExpectKind::fallback_used: return out.vehicles[static_cast<size_t>(e.vehicles[0])].fallback_used;
            case catalog::ExpectKind::timeout: return out.timed_out;
            case catalog::ExpectKind::min_gap: x = pair(e.vehicles[0], e.vehicles[1]).min_gap; break;
            case catalog::ExpectKind::min_ttc: x = pair(e.vehicles[0], e.vehicles[1]).min_ttc; break;
            case catalog::ExpectKind::min_headway: x = pair(e.vehicles[0], e.vehicles[1]).min_headway; break;
            case catalog::ExpectKind::max_jerk: x = out.vehicles[static_cast<size_t>(e.vehicles[0])].max_jerk; break;
            case catalog::ExpectKind::max_acc: x = out.vehicles[static_cast<size_t>(e.vehicles[0])].max_acc; break;
            case catalog::ExpectKind::max_speed: x = out.vehicles[static_cast<size_t>(e.vehicles[0])].max_speed; break;
        }
        value = x;
        if (e.cmp == "<") return x < e.bound;
        if (e.cmp == "<=") return x <= e.bound;
        if (e.cmp == ">") return x > e.bound;
        return x >= e.bound;
    };
    for (int32_t root : sc_.expect_roots) {
        ExpectResult r;
        r.text = sc_.expects[static_cast<size_t>(root)].text;
        r.loc = sc_.expects[static_cast<size_t>(root)].loc;
        r.passed = eval(root, r.value);
        out.expectations.push_back(r);
    }
    return out;
}

}  // namespace

bool RunResult::passed() const {
    return error.empty() && std::all_of(expectations.begin(), expectations.end(), [](const ExpectResult& e) { return e.passed; });
}

RunResult simulate(const ir::Program& program, int scenario, const RunOptions& options) {
    RunResult out;
    if (scenario < 0 || static_cast<size_t>(scenario) >= program.scenarios.size()) {
        out.error = "no such scenario";
        return out;
    }
    World world(program, scenario, options);
    if (auto e = world.init(); !e.empty()) {
        out.error = e;
        out.scenario = program.scenarios[static_cast<size_t>(scenario)].name;
        return out;
    }
    return world.run();
}

}  // namespace sdv::sim
