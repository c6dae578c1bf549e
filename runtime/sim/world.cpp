// Building a run's world from the IR: the road network (built-in road, junction or Lanelet2
// map), the light programs, and every agent placed at its start with its model, route and, for
// SDVs, its driver.
#include "runtime/sim/world.h"

#include <algorithm>
#include <cstdio>

#include "runtime/road/builtin_road.h"
#include "runtime/road/commonroad_reader.h"
#include "runtime/sim/agents.h"
#include "runtime/sim/path.h"

namespace sdv::sim {

std::string fmt(double v, int digits) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    std::string s = buf;
    if (s == "-0.0000" || s == "-0.000" || s == "-0.00") s = s.substr(1);
    return s;
}

std::string World::where(const ir::SourceLoc& l) const {
    const std::string file = l.file < program.files.size() ? program.files[l.file] : "?";
    return file + ":" + std::to_string(l.line) + ":" + std::to_string(l.col);
}

std::optional<double> World::goal_distance(const Agent& a) const {
    if (a.driver && a.driver->ref) {
        const Driver& d = *a.driver;
        for (size_t i = 0; i < d.path.size(); ++i) {
            if (d.path[i] == a.goal_lane) return std::fabs(d.path_start[i] + a.goal_s - d.ref_s);
        }
        return std::nullopt;
    }
    if (a.lane != a.goal_lane) return std::nullopt;
    return std::fabs(a.goal_s - a.lane_s);
}

std::string World::light_state(int32_t light, double t) const {
    if (light < 0 || static_cast<size_t>(light) >= net.lights.size()) return "green";
    auto it = programs.find(net.lights[static_cast<size_t>(light)].name);
    if (it == programs.end() || it->second->phases.empty()) return "green";
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

std::string World::locate(const ir::Position& pos, LaneId& lane, double& s) const {
    if (pos.xy) {
        auto l = net.locate({pos.x, pos.y}, pos.has_heading ? std::optional<double>(pos.heading) : std::nullopt);
        if (l.lane == kNoLane) return "position is not on any lane";
        lane = l.lane;
        s = l.s;
        return "";
    }
    auto id = net.find(pos.lane);
    if (!id) return "lane '" + pos.lane + "' does not exist on the road";
    lane = *id;
    s = pos.s;
    // Built-in roads measure positions from the road's start; backward lanes run the other way.
    const ir::Road& road = program.roads.at(static_cast<size_t>(scenario.road));
    if (road.kind == ir::RoadKind::road && pos.lane.find(".-") != std::string::npos) {
        s = net.lane(lane).length - pos.s;
    }
    if (s < 0 || s > net.lane(lane).length + 1e-6) {
        return "position s = " + fmt(pos.s, 1) + " m is off lane '" + pos.lane + "' (" + fmt(net.lane(lane).length, 1) + " m long)";
    }
    return "";
}

namespace {

// The IR road in full, as the key of a shared network.
std::string road_key(const ir::Road& r) {
    std::string k = std::to_string(static_cast<int>(r.kind)) + "|" + r.name + "|" + std::to_string(r.lanes_forward) + "|" +
                    std::to_string(r.lanes_backward) + "|" + r.control + "|" + r.map_file + "|" +
                    std::to_string(r.has_origin);
    char buf[64];
    for (double x : {r.lane_width, r.speed_limit, r.origin_x, r.origin_y, r.heading, r.arm_length, r.origin_lat,
                     r.origin_lon, r.origin_alt}) {
        std::snprintf(buf, sizeof buf, "|%.17g", x);
        k += buf;
    }
    for (const auto& seg : r.segments) {
        std::snprintf(buf, sizeof buf, "|%d:%.17g:%.17g", seg.arc ? 1 : 0, seg.length, seg.radius);
        k += buf;
    }
    for (const auto& c : r.crosswalks) {
        std::snprintf(buf, sizeof buf, ":%.17g:%.17g:%d", c.at, c.width, c.signalised ? 1 : 0);
        k += "|xw:" + c.name + ":" + c.arm + buf;
    }
    return k;
}

std::vector<road::CrosswalkSpec> crosswalk_specs(const ir::Road& r) {
    std::vector<road::CrosswalkSpec> out;
    for (const auto& c : r.crosswalks) {
        road::CrosswalkSpec x;
        x.name = c.name;
        x.arm = c.arm;
        x.width_m = c.width;
        x.signalised = c.signalised;
        (r.kind == ir::RoadKind::junction ? x.gap_m : x.s_m) = c.at;
        out.push_back(std::move(x));
    }
    return out;
}

}  // namespace

// The network of the scenario's road, prepared (every reference line and the index of locate
// built, so that threads only read it); an error message, or "".
std::string World::make_road(road::RoadNetwork& out) const {
    const ir::Road& r = program.roads.at(static_cast<size_t>(scenario.road));
    const std::string at = where(r.loc);
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
            spec.crosswalks = crosswalk_specs(r);
            auto b = road::build_road(spec);
            if (!b.errors.empty()) return at + ": " + b.errors.front();
            out = std::move(b.network);
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
            spec.crosswalks = crosswalk_specs(r);
            auto b = road::build_junction(spec);
            if (!b.errors.empty()) return at + ": " + b.errors.front();
            out = std::move(b.network);
            break;
        }
        case ir::RoadKind::lanelet2: {
            std::optional<road::GeoOrigin> origin;
            if (r.has_origin) origin = road::GeoOrigin{r.origin_lat, r.origin_lon, r.origin_alt};
            auto l = road::load_map(r.map_file, origin);  // Lanelet2 or CommonRoad, by content
            if (!l.errors.empty()) return at + ": map '" + r.map_file + "': " + l.errors.front();
            out = std::move(*l.network);
            break;
        }
    }
    out.prepare();
    return "";
}

std::string World::build_road() {
    if (options.roads) {
        const std::string key = road_key(program.roads.at(static_cast<size_t>(scenario.road)));
        std::string error;
        auto shared = options.roads->network(key, [&](road::RoadNetwork& n) { return make_road(n); }, error);
        if (!shared) return error;
        net = *shared;  // a copy of the prepared network: far cheaper than building it
        paths = options.roads->paths(key);
    } else if (auto e = make_road(net); !e.empty()) {
        return e;
    }
    for (const auto& l : scenario.lights) {
        programs[l.name] = &l;
        const bool known = std::any_of(net.lights.begin(), net.lights.end(), [&](const road::TrafficLight& x) { return x.name == l.name; });
        if (!known) {
            std::string names;
            for (const auto& x : net.lights) names += (names.empty() ? "" : ", ") + x.name;
            return where(l.loc) + ": the road has no traffic light '" + l.name + "' (its lights: " +
                   (names.empty() ? "none" : names) + ")";
        }
    }
    return "";
}

std::string World::point(const ir::Position& pos, road::Vec2& out) const {
    if (pos.xy) {
        out = {pos.x, pos.y};
        return "";
    }
    LaneId lane = kNoLane;
    double s = 0;
    if (auto e = locate(pos, lane, s); !e.empty()) return e;
    const auto c = net.reference(lane).to_cartesian({s, 0, 0, pos.offset, 0, 0});
    out = {c.x, c.y};
    return "";
}

// Pedestrians and path agents: where they are is a point, on a lane or not; they need no route.
std::string World::place_walking(Agent& a) {
    const std::string vwhere = where(a.v->loc) + ": " + (a.v->pedestrian ? "pedestrian '" : "vehicle '") + a.v->name + "'";
    road::Vec2 p;
    double yaw = 0;
    if (a.v->kind == ir::VehicleKind::path) {
        // Its points, with the speed from each on (default: the previous point's, the first:
        // its start speed), and the distance along the path at each.
        double speed = a.v->speed;
        for (const auto& wp : a.v->trajectory) {
            road::Vec2 q;
            if (auto e = point(wp.position, q); !e.empty()) return where(wp.position.loc) + ": " + vwhere + ": a point of its path is off the road: " + e;
            if (wp.speed >= 0) speed = wp.speed;
            a.path_cum.push_back(a.path_points.empty() ? 0.0 : a.path_cum.back() + distance(a.path_points.back(), q));
            a.path_points.push_back(q);
            a.path_speeds.push_back(speed);
        }
        if (a.path_points.size() < 2 || !(a.path_cum.back() > 0)) return vwhere + ": its path needs two distinct points";
        if (!a.v->meet.empty()) {
            for (size_t i = 0; i < scenario.vehicles.size(); ++i) {
                if (scenario.vehicles[i].name == a.v->meet && static_cast<int>(i) != a.index) a.meet = static_cast<int32_t>(i);
            }
            if (a.meet < 0) return vwhere + ": meets '" + a.v->meet + "', which is not another agent of the scenario";
        }
        p = a.path_points.front();
        const road::Vec2 d = a.path_points[1] - a.path_points[0];
        yaw = std::atan2(d.y, d.x);
        const double v0 = a.path_speeds.front();
        place(a, {p.x, v0 * std::cos(yaw), 0, p.y, v0 * std::sin(yaw), 0});
        a.yaw = yaw;
    } else {
        const ir::Position& start = a.v->kind == ir::VehicleKind::trajectory && !a.v->trajectory.empty() ? a.v->trajectory.front().position : a.v->start;
        if (auto e = point(start, p); !e.empty()) return vwhere + " starts off the road: " + e;
        if (a.v->kind == ir::VehicleKind::sdv) {
            a.walker = std::make_unique<Walker>();
            Walker& k = *a.walker;
            k.tree = std::make_unique<bt::BehaviorTree>(&program.instances.at(static_cast<size_t>(a.v->tree)));
            k.base_speed = k.speed = a.v->speed;
            if (a.v->goal) {
                if (auto e = point(*a.v->goal, k.goal); !e.empty()) {
                    return where(a.v->goal->loc) + ": the goal of pedestrian '" + a.v->name + "' is off the road: " + e;
                }
                k.has_goal = true;
            }
        }
        // Facing its given heading, else its goal, else along the lane it stands by.
        if (start.xy && start.has_heading) {
            yaw = start.heading;
        } else if (a.walker && a.walker->has_goal && distance(a.walker->goal, p) > 1e-6) {
            yaw = std::atan2(a.walker->goal.y - p.y, a.walker->goal.x - p.x);
        } else if (const auto found = net.locate(p); found.lane != kNoLane) {
            yaw = net.reference(found.lane).heading(std::clamp(found.s, 0.0, net.reference(found.lane).length()));
        }
        const double v0 = a.v->kind == ir::VehicleKind::sdv ? a.v->speed : 0.0;
        place(a, {p.x, v0 * std::cos(yaw), 0, p.y, v0 * std::sin(yaw), 0});
        a.yaw = yaw;
    }
    a.model->advance(*this, a, 0, 0);  // its lane and lane coordinates
    enter_later(a);
    return "";
}

void World::enter_later(Agent& a) const {
    if (a.v->kind != ir::VehicleKind::trajectory || a.v->trajectory.empty() || a.v->trajectory.front().time <= 0) return;
    a.enters_at = a.v->trajectory.front().time;
    a.active = false;
}

std::string World::place_agent(Agent& a) {
    if (a.v->pedestrian || a.v->kind == ir::VehicleKind::path) return place_walking(a);
    const std::string vwhere = where(a.v->loc) + ": vehicle '" + a.v->name + "'";
    LaneId lane = kNoLane;
    double s = 0;
    const ir::Position& start = a.v->kind == ir::VehicleKind::trajectory && !a.v->trajectory.empty()
                                    ? a.v->trajectory.front().position
                                    : a.v->start;
    if (auto e = locate(start, lane, s); !e.empty()) return vwhere + " starts off the road: " + e;
    const auto& ref0 = net.reference(lane);
    road::FrenetState f{s, a.v->speed, 0, start.offset, 0, 0};
    if (start.xy) f = ref0.project({start.x, start.y});
    f.s_d = a.v->speed;
    place(a, ref0.to_cartesian(f));
    // A driven vehicle starts along the lane it stands in (a given heading only chooses among
    // overlapping lanes); others keep the heading they are given.
    const bool keep_heading = start.xy && start.has_heading && a.v->kind != ir::VehicleKind::sdv;
    a.yaw = keep_heading ? start.heading : ref0.heading(std::clamp(f.s, 0.0, ref0.length()));
    a.lane = lane;
    a.lane_s = f.s;
    a.lane_d = f.d;
    a.centre_lane = centre_lane(net, lane, f.d);
    // The route: through every lane the vehicle's `route` names, in order, then to its goal;
    // shortest between consecutive ones.
    std::vector<LaneId> via;
    for (const std::string& name : a.v->route) {
        const auto id = net.find(name);
        if (!id) return vwhere + ": its route names lane '" + name + "', which the road does not have";
        via.push_back(*id);
    }
    if (a.v->goal) {
        LaneId gl = kNoLane;
        double gs = 0;
        if (auto e = locate(*a.v->goal, gl, gs); !e.empty()) {
            return where(a.v->goal->loc) + ": the goal of vehicle '" + a.v->name + "' is off the road: " + e;
        }
        a.goal_lane = gl;
        a.goal_s = gs;
        via.push_back(gl);
    }
    LaneId from = lane;
    for (size_t k = 0; k < via.size(); ++k) {
        if (via[k] == from && k > 0) continue;
        auto route = road::shortest_route(net, from, via[k]);
        if (route.steps.empty()) {
            const bool to_goal = a.v->goal && k + 1 == via.size();
            return (to_goal ? where(a.v->goal->loc) + ": the goal of vehicle '" + a.v->name + "' is unreachable: "
                            : vwhere + ": its route has no way on: ") +
                   route.error;
        }
        a.route.insert(a.route.end(), route.steps.begin() + (a.route.empty() ? 0 : 1), route.steps.end());
        from = via[k];
    }
    if (a.v->kind == ir::VehicleKind::trajectory && a.v->trajectory.size() >= 2) {
        // Under way from its first waypoint: at t = 0 it has its first segment's velocity, as
        // at every later tick (drivers must not see it standing at its start).
        a.model->advance(*this, a, std::max(0.0, a.v->trajectory.front().time), 1);
        a.accel = 0;
    }
    enter_later(a);
    if (a.v->kind == ir::VehicleKind::sdv) {
        a.driver = std::make_unique<Driver>();
        Driver& d = *a.driver;
        d.tree = std::make_unique<bt::BehaviorTree>(&program.instances.at(static_cast<size_t>(a.v->tree)));
        d.ref = build_path(net, a.route, d, lane, f.s, *paths);
        if (!d.ref) return vwhere + ": cannot build a reference line from lane '" + net.lane(lane).name + "'";
        // Initial plan: keep the start speed until the first plan takes over.
        const road::FrenetState f0 = d.ref->to_frenet({a.x, a.vx, 0, a.y, a.vy, 0}, d.path_start.front() + f.s);
        d.ref_s = f0.s;
        planner::Trajectory tr;
        tr.s = planner::Poly::quadratic(f0.s, f0.s_d, 0);
        tr.d = planner::Poly::quadratic(f0.d, 0, 0);
        tr.duration = 1e6;
        d.plan = ActivePlan{tr, 0.0, d.ref};
    }
    return "";
}

std::string World::init() {
    dt = 1.0 / scenario.traffic_rate;
    latency = scenario.planning_latency >= 0 ? scenario.planning_latency : 1.0 / scenario.planning_rate;
    seed = options.seed.value_or(scenario.seed);
    if (auto e = build_road(); !e.empty()) return e;
    agents.resize(scenario.vehicles.size());
    for (size_t i = 0; i < scenario.vehicles.size(); ++i) {
        Agent& a = agents[i];
        a.v = &scenario.vehicles[i];
        a.index = static_cast<int>(i);
        a.model = make_model(*a.v);
        if (auto e = place_agent(a); !e.empty()) return e;
        widest_reach = std::max(widest_reach, 0.5 * std::hypot(a.v->length, a.v->width));
    }
    return "";
}

}  // namespace sdv::sim
