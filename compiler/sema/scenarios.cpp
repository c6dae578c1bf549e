// Scenario checks: settings (road, timeout, seed, rates), vehicles (kind, size, start, goal,
// route, tree, trajectory), positions and lane references on the scenario's road, start
// overlaps, traffic light programs and expectations, each written into the IR scenario.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>

#include "compiler/sema/checker_internal.h"
#include "compiler/sema/overlaps.h"

namespace sdv::compiler::sema {

void Checker::check_scenario(const ast::ScenarioDecl& written, ir::Program& program) {
    const size_t errors_before = diags_->error_count();
    // Agent templates become agents first: everything below sees v1 .. v50 as if written.
    const ast::ScenarioDecl& s = expand_templates(written);
    const size_t instances_before = program.instances.size();
    ir::Scenario sc;
    sc.name = s.name.text;
    sc.loc = loc(s.name.range);
    ScenarioCtx ctx;
    ctx.name = s.name.text;
    const std::string where = "scenario '" + s.name.text + "'";
    for (const auto& other : program.scenarios) {
        if (other.name == sc.name) error("E0108", s.name.range, "duplicate scenario '" + sc.name + "'");
    }
    auto set = settings_map(s.settings,
                            {"road", "timeout", "seed", "rate traffic", "rate planning",
                             "rate latency", "rate sensor_range"},
                            where);
    // `rate X` keys carry the word after `rate`; unknown ones are reported by settings_map
    // as "rate foo", so point at the word with a clearer message there.
    if (auto* r = set["road"]) {
        const std::string name = r->values[0].lo.name.str();
        const RoadSym* found = nullptr;
        for (const auto& rs : roads_) {
            if (rs.name == name) found = &rs;
        }
        if (found == nullptr) {
            std::vector<std::string> names;
            for (const auto& rs : roads_) names.push_back(rs.name);
            auto* d = error("E0109", r->values[0].range, "unknown road '" + name + "'");
            add_suggestion(*d, name, names);
        } else {
            ctx.road = found;
        }
    } else {
        auto* d = error("E0501", s.name.range, where + " has no road");
        d->notes.push_back({{}, "add 'road NAME' naming a road, junction or map"});
    }
    read_setting(set, "timeout", Dim::time, 0, catalog::kMaxScenarioTime, true, sc.timeout);
    if (auto* t = set["seed"]) {
        // Parsed from the text: a double would round seeds above 2^53.
        const std::string& text = t->values[0].lo.quantity.text;
        errno = 0;
        sc.seed = std::strtoull(text.c_str(), nullptr, 10);
        if (errno == ERANGE) {
            error("E0301", t->values[0].range, "seed " + text + " is out of range")
                ->notes.push_back({{}, "allowed: 0 to 18446744073709551615"});
        }
    }
    read_setting(set, "rate traffic", Dim::frequency, 1, 1000, false, sc.traffic_rate);
    read_setting(set, "rate planning", Dim::frequency, 0.1, 100, false, sc.planning_rate);
    read_setting(set, "rate latency", Dim::time, 0, 10, false, sc.planning_latency);
    read_setting(set, "rate sensor_range", Dim::length, 1, 10000, true, sc.sensor_range);
    if (ctx.road != nullptr && ctx.road->ok) {
        auto it = std::find_if(program.roads.begin(), program.roads.end(),
                               [&](const ir::Road& r) { return r.name == ctx.road->name; });
        if (it == program.roads.end()) {
            sc.road = static_cast<int32_t>(program.roads.size());
            program.roads.push_back(ctx.road->road);
        } else {
            sc.road = static_cast<int32_t>(it - program.roads.begin());
        }
    }
    // Vehicle names first: trees and expectations refer to any of them.
    for (const auto& v : s.vehicles) {
        if (auto it = ctx.vehicle_index.find(v.name.text); it != ctx.vehicle_index.end()) {
            const ast::VehicleDecl& first = s.vehicles[static_cast<size_t>(it->second)];
            set_instance(&v);
            auto* d = error("E0108", v.name.range, "duplicate vehicle '" + v.name.text + "'");
            set_instance(nullptr);
            d->notes.push_back({first.name.range, first.instance ? "first declared here, as " + first.instance->label +
                                                                       " of '" + first.instance->of + "'"
                                                                 : std::string("first declared here")});
        }
        ctx.vehicle_index.emplace(v.name.text, static_cast<int32_t>(ctx.vehicle_names.size()));
        ctx.vehicle_names.push_back(v.name.text);
        if (v.is_ego) {
            if (ctx.ego >= 0) {
                auto* d = error("E0507", v.name.range, where + " has more than one ego");
                d->notes.push_back({s.vehicles[static_cast<size_t>(ctx.ego)].name.range,
                                    "the ego is declared here"});
            } else {
                ctx.ego = static_cast<int32_t>(ctx.vehicle_names.size() - 1);
            }
        }
    }
    ctx.ir = &sc;
    for (const auto& v : s.vehicles) {
        set_instance(&v);
        sc.vehicles.push_back(check_vehicle(v, ctx, program));
    }
    set_instance(nullptr);
    // `meet V`: V is another agent of the scenario (the runtime resolves it by name).
    for (const auto& v : s.vehicles) {
        set_instance(&v);
        for (size_t i = 1; i < v.meets.size(); ++i) error("E0504", v.meets[i].range, "duplicate 'meet' of '" + v.name.text + "'");
        if (v.meets.empty()) continue;
        const ast::Ident& m = v.meets[0];
        auto it = ctx.vehicle_index.find(m.text);
        if (it == ctx.vehicle_index.end()) {
            auto* d = error("E0105", m.range, "unknown vehicle '" + m.text + "' in scenario '" + ctx.name + "'");
            add_suggestion(*d, m.text, ctx.vehicle_names);
        } else if (m.text == v.name.text) {
            error("E0105", m.range, "'" + v.name.text + "' cannot meet itself");
        }
    }
    set_instance(nullptr);
    check_overlaps(s, sc);
    for (const auto& l : s.lights) check_light(l, ctx);
    for (const auto& e : s.expects) {
        sc.expect_roots.push_back(check_expr(*e, ctx));
        if (e->window) check_window(*e, sc.expect_roots.back(), ctx);
    }
    program.scenarios.push_back(std::move(sc));
    // A campaign is checked on a scenario that is valid as written: its probes are variants of it.
    if (!s.varies.empty() && diags_->error_count() == errors_before) {
        check_vary(s, program, program.scenarios.size() - 1, instances_before);
    }
}

ir::Position Checker::check_position(const ast::Position& p, const ScenarioCtx& ctx,
                                     const std::string& what) {
    ir::Position out;
    out.loc = loc(p.range);
    auto num = [&](const ast::Value& v, Dim dim, const std::string& w, double lo, double hi) -> double {
        ParamDef def;
        def.dim = dim;
        def.min = lo;
        def.max = hi;
        Eval e = eval(v, nullptr, {ParamType::quantity, dim}, w, &def);
        if (e.kind == Eval::Kind::number) {
            if (e.ranged) error("E0205", v.range, w + " cannot be a range");
            check_range(e, def, w);
            return e.num.value;
        }
        return 0.0;
    };
    if (p.xy) {
        out.xy = true;
        out.x = num(*p.x, Dim::length, "x", -1e7, 1e7);
        out.y = num(*p.y, Dim::length, "y", -1e7, 1e7);
        if (p.heading) {
            out.heading = num(*p.heading, Dim::angle, "the heading", -10, 10);
            out.has_heading = true;
        }
        return out;
    }
    out.s = num(*p.s, Dim::length, "the position along the lane", -1e6, 1e6);
    if (p.offset) out.offset = num(*p.offset, Dim::length, "the lateral offset", -20, 20);
    out.lane = resolve_lane(p.lane, ctx, what);
    if (ctx.road != nullptr && ctx.road->ok && ctx.road->road.kind == ir::RoadKind::road &&
        !out.lane.empty()) {
        if (out.s < 0 || out.s > ctx.road->length) {
            auto* d = error("E0503", p.s->range,
                            what + " is off the road: s = " + fmt(out.s) + " m");
            d->notes.push_back({ctx.road->range, "road '" + ctx.road->name + "' is " +
                                                     fmt(ctx.road->length) + " m long"});
        }
        // A pedestrian may stand beside the lane (on the kerb, a walkway): `what` names it.
        const bool pedestrian = what.find("pedestrian '") != std::string::npos;
        if (!pedestrian && std::fabs(out.offset) > ctx.road->road.lane_width * 0.5 + 1e-9 && p.offset) {
            error("E0503", p.offset->range, what + " is outside its lane: the offset exceeds "
                                                   "half the lane width");
        }
    }
    return out;
}

// Lane references: built-in roads use indices (1.. forward, -1.. backward) and are named
// "<road>.<index>"; junction and map lanes are named and checked when the road loads.
std::string Checker::resolve_lane(const ast::LaneRef& l, const ScenarioCtx& ctx,
                                  const std::string& what) {
    if (ctx.road == nullptr) return "";
    const ir::Road& r = ctx.road->road;
    if (r.kind == ir::RoadKind::road) {
        if (l.kind != ast::LaneRef::Kind::index) {
            auto* d = error("E0106", l.range, "unknown lane '" + l.str() + "' for " + what);
            d->notes.push_back({{}, "lanes of a built-in road are numbered: 1 is the "
                                    "right-most forward lane, -1 the first backward lane"});
            return "";
        }
        const bool ok = (l.index >= 1 && l.index <= r.lanes_forward) ||
                        (l.index <= -1 && -l.index <= r.lanes_backward);
        if (!ok) {
            auto* d = error("E0303", l.range, "lane " + std::to_string(l.index) +
                                                  " does not exist on road '" + r.name + "'");
            std::string lanes = r.lanes_forward > 0 ? "1.." + std::to_string(r.lanes_forward) : "";
            if (r.lanes_backward > 0) {
                lanes += (lanes.empty() ? "" : " and ") + std::string("-1..-") +
                         std::to_string(r.lanes_backward);
            }
            d->notes.push_back({ctx.road->range, "its lanes are " + lanes});
            return "";
        }
        return r.name + "." + std::to_string(l.index);
    }
    if (r.kind == ir::RoadKind::junction) {
        if (l.kind == ast::LaneRef::Kind::index) {
            auto* d = error("E0106", l.range, "junction lanes are named, not numbered");
            d->notes.push_back({{}, "e.g. 'lane south.in' or 'lane south_to_west'"});
            return "";
        }
        return r.name + "." + (l.kind == ast::LaneRef::Kind::name ? l.name.str() : l.string);
    }
    return l.kind == ast::LaneRef::Kind::string ? l.string
           : l.kind == ast::LaneRef::Kind::name ? l.name.str()
                                                : std::to_string(l.index);
}

ir::Vehicle Checker::check_vehicle(const ast::VehicleDecl& v, ScenarioCtx& ctx,
                                   ir::Program& program) {
    ir::Vehicle out;
    out.name = v.name.text;
    out.is_ego = v.is_ego;
    out.pedestrian = v.is_pedestrian;
    out.loc = loc(v.name.range);
    const std::string what = (v.is_pedestrian ? "pedestrian '" : "vehicle '") + v.name.text + "'";
    const std::vector<std::string> kinds =
        v.is_pedestrian ? std::vector<std::string>{"sdp", "path", "trajectory"}
        : v.is_ego      ? std::vector<std::string>{"sdv", "trajectory", "path", "external"}
                        : std::vector<std::string>{"sdv", "trajectory", "path", "external", "static"};
    const std::string kind = v.kind.text;
    if (kind == "sdv" || (kind == "sdp" && v.is_pedestrian)) out.kind = ir::VehicleKind::sdv;
    else if (kind == "trajectory") out.kind = ir::VehicleKind::trajectory;
    else if (kind == "path") out.kind = ir::VehicleKind::path;
    else if (kind == "static") out.kind = ir::VehicleKind::static_object;
    else if (kind == "external") out.kind = ir::VehicleKind::external;
    if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end()) {
        auto* d = error("E0113", v.kind.range, std::string("unknown ") + (v.is_pedestrian ? "pedestrian" : "vehicle") + " kind '" + kind + "'");
        add_suggestion(*d, kind, kinds);
        std::string list;
        for (const auto& k : kinds) list += (list.empty() ? "" : ", ") + k;
        d->notes.push_back({{}, std::string(v.is_pedestrian ? "a pedestrian" : v.is_ego ? "the ego" : "a vehicle") + " is one of: " + list});
        if (v.is_pedestrian && kind == "sdv") d->notes.push_back({{}, "a simulated pedestrian is an 'sdp' (its tree walks, docs/pedestrians.md)"});
    }
    if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end()) return out;
    auto set = settings_map(v.settings, {"speed", "length", "width"}, what);
    ParamDef def;
    auto num = [&](const ast::Setting* s, Dim dim, double lo, double hi, bool excl, double fallback) {
        if (s == nullptr) return fallback;
        auto r = setting_number(*s, 0, dim, lo, hi, excl);
        return r.value_or(fallback);
    };
    out.speed = num(set["speed"], Dim::speed, 0, v.is_pedestrian ? catalog::kMaxPedestrianSpeed : catalog::kMaxVehicleSpeed,
                    false, 0.0);
    // A pedestrian is a disc of the larger of its length and width (Euro NCAP's adult target is
    // 0.5 m × 0.6 m; the reference's pedestrian radius is 0.27 m).
    const catalog::AgentSize max = v.is_pedestrian ? catalog::kMaxPedestrianSize
                                   : v.is_object   ? catalog::kMaxObjectSize
                                                   : catalog::kMaxVehicleSize;
    out.length = num(set["length"], Dim::length, 0, max.length, true, v.is_pedestrian ? 0.5 : 4.5);
    out.width = num(set["width"], Dim::length, 0, max.width, true, v.is_pedestrian ? 0.5 : 1.8);
    if (v.is_object) out.object = true;
    for (size_t i = 1; i < v.starts.size(); ++i) {
        error("E0504", v.starts[i].range, "duplicate 'start' of " + what);
    }
    for (size_t i = 1; i < v.goals.size(); ++i) {
        error("E0504", v.goals[i].range, "duplicate 'goal' of " + what);
    }
    for (size_t i = 1; i < v.routes.size(); ++i) {
        error("E0504", v.routes[i].front().range, "duplicate 'route' of " + what);
    }
    for (size_t i = 1; i < v.trees.size(); ++i) {
        error("E0504", v.trees[i].range, "duplicate 'tree' of " + what);
    }
    if (!v.starts.empty()) {
        out.start = check_position(v.starts[0], ctx, "the start of " + what);
    } else if (out.kind != ir::VehicleKind::trajectory && out.kind != ir::VehicleKind::path) {
        auto* d = error("E0506", v.name.range, what + " has no start position");
        d->notes.push_back({{}, "add e.g. 'start lane 1 at 20 m'"});
    }
    if (!v.goals.empty()) out.goal = check_position(v.goals[0], ctx, "the goal of " + what);
    out.goal_ends_run = v.goal_ends_run && !v.goals.empty();
    if (!v.routes.empty() && v.is_pedestrian) {
        auto* d = error("E0113", v.routes[0].empty() ? v.name.range : v.routes[0].front().range, "a pedestrian has no route");
        d->notes.push_back({{}, "it walks to its goal, through the crosswalk its tree selects"});
    } else if (!v.routes.empty()) {
        for (const auto& l : v.routes[0]) out.route.push_back(resolve_lane(l, ctx, "the route of " + what));
    }
    if (out.kind == ir::VehicleKind::sdv) {
        if (v.trees.empty()) {
            auto* d = error("E0505", v.name.range, what + " is an " + kind + " but has no tree");
            d->notes.push_back({{}, v.is_pedestrian ? "add e.g. 'tree std.walk()' (import \"std/pedestrian.sdv\")"
                                                    : "add e.g. 'tree std.drive()' (import \"std/drive.sdv\")"});
        } else {
            out.tree = expand_vehicle_tree(v, ctx, program);
            if (out.tree >= 0) check_tree_agent(v.trees[0], out, program);
        }
    } else if (!v.trees.empty()) {
        error("E0113", v.trees[0].range, std::string("only ") + (v.is_pedestrian ? "sdp pedestrians" : "sdv vehicles") + " have trees; " + what + " is " + kind);
    }
    if (out.kind == ir::VehicleKind::path) {
        check_path(v, out, ctx, what);
        if (!v.meets.empty()) out.meet = v.meets[0].text;
    } else if (!v.paths.empty()) {
        error("E0113", v.paths[0].empty() ? v.name.range : v.paths[0].front().range, "only path agents have a path; " + what + " is " + kind);
    }
    if (out.kind != ir::VehicleKind::path && !v.meets.empty()) {
        error("E0113", v.meets[0].range, "only path agents meet another agent; " + what + " is " + kind);
    }
    if (out.kind == ir::VehicleKind::trajectory) {
        if (v.trajectories.empty() || v.trajectories[0].size() < 2) {
            auto* d = error("E0506", v.name.range, what + " needs a trajectory with at least two waypoints");
            d->notes.push_back({{}, "trajectory { 0 s: lane 1 at 10 m  5 s: lane 1 at 80 m }"});
        } else {
            double last = -1;
            for (const auto& w : v.trajectories[0]) {
                ir::Waypoint wp;
                ParamDef tdef;
                tdef.dim = Dim::time;
                tdef.min = 0;
                tdef.max = catalog::kMaxScenarioTime;
                Eval t = eval(w.time, nullptr, {ParamType::quantity, Dim::time}, "the waypoint time", &tdef);
                if (t.kind == Eval::Kind::number) {
                    check_range(t, tdef, "the waypoint time");
                    wp.time = t.num.value;
                    if (wp.time <= last) {
                        error("E0301", w.time.range, "waypoint times must increase");
                    }
                    last = wp.time;
                }
                wp.position = check_position(w.position, ctx, "a waypoint of " + what);
                if (w.speed) wp.speed = check_speed(*w.speed, "the waypoint speed").value_or(wp.speed);
                out.trajectory.push_back(wp);
            }
            if (v.starts.empty()) out.start = out.trajectory.front().position;
        }
    } else if (!v.trajectories.empty()) {
        error("E0113", v.name.range, "only trajectory vehicles have a trajectory");
    }
    return out;
}

// A pedestrian walks by pedestrian leaves, a vehicle drives by vehicle leaves: the first leaf of
// the other kind in the expanded tree is the error, at the tree reference.
void Checker::check_tree_agent(const ast::TreeRef& ref, const ir::Vehicle& v, const ir::Program& program) {
    const auto& nodes = program.instances.at(static_cast<size_t>(v.tree)).nodes;
    for (const auto& n : nodes) {
        catalog::Agent agent = catalog::Agent::any;
        std::string leaf;
        // A leaf the checker could not resolve (already reported) has no agent.
        const bool known = n.leaf >= 0 && static_cast<size_t>(n.leaf) < (n.kind == ir::NodeKind::maneuver ? catalog::maneuvers().size()
                                                                                                         : catalog::conditions().size());
        if (!known) continue;
        if (n.kind == ir::NodeKind::maneuver) {
            const auto& m = catalog::maneuvers()[static_cast<size_t>(n.leaf)];
            agent = m.agent;
            leaf = "maneuver '" + m.name + "'";
        } else if (n.kind == ir::NodeKind::condition) {
            const auto& c = catalog::conditions()[static_cast<size_t>(n.leaf)];
            agent = c.agent;
            leaf = "condition '" + c.name + "'";
        }
        if (agent == catalog::Agent::any || (agent == catalog::Agent::pedestrian) == v.pedestrian) continue;
        const std::string file = n.loc.file < program.files.size() ? program.files[n.loc.file] : "?";
        auto* d = error("E0411", ref.range, "tree '" + ref.name.str() + "' is not a " + (v.pedestrian ? "pedestrian" : "vehicle") +
                                                "'s tree: its " + leaf + " (" + file + ":" + std::to_string(n.loc.line) + ") is for " +
                                                (agent == catalog::Agent::pedestrian ? "pedestrians" : "vehicles"));
        d->notes.push_back({{}, v.pedestrian ? "a pedestrian's tree walks: e.g. 'tree std.walk()' (import \"std/pedestrian.sdv\"); `sdv catalog` lists the leaves for pedestrians"
                                             : "a vehicle's tree drives: e.g. 'tree std.drive()'; `sdv catalog` lists the leaves for vehicles"});
        return;
    }
}

// A waypoint's or path point's speed (0 to 100 m/s); nullopt when it is not one (reported).
std::optional<double> Checker::check_speed(const ast::Value& v, const std::string& what) {
    ParamDef def;
    def.dim = Dim::speed;
    def.min = 0;
    def.max = catalog::kMaxWaypointSpeed;
    Eval sp = eval(v, nullptr, {ParamType::quantity, Dim::speed}, what, &def);
    if (sp.kind == Eval::Kind::number && check_range(sp, def, what)) return sp.num.value;
    return std::nullopt;
}

// The points of a path, each with its speed from there on (speeds left out: the previous one's).
void Checker::check_path(const ast::VehicleDecl& v, ir::Vehicle& out, ScenarioCtx& ctx, const std::string& what) {
    if (v.paths.empty() || v.paths[0].size() < 2) {
        auto* d = error("E0506", v.name.range, what + " needs a path with at least two points");
        d->notes.push_back({{}, "path { at (0 m, -6 m) speed 1.4 m/s  at (0 m, 6 m) }"});
        return;
    }
    for (const auto& pp : v.paths[0]) {
        ir::Waypoint wp;
        wp.time = -1;
        wp.position = check_position(pp.position, ctx, "a point of the path of " + what);
        if (pp.speed) wp.speed = check_speed(*pp.speed, "the path speed").value_or(wp.speed);
        out.trajectory.push_back(wp);
    }
    if (v.starts.empty()) out.start = out.trajectory.front().position;
}

// Vehicles that start on top of each other: one E0502 at each vehicle that overlaps one behind
// it on its lane (find_overlaps: O(n log n) whatever the places, and at most n - 1 errors).
void Checker::check_overlaps(const ast::ScenarioDecl& s, const ir::Scenario& sc) {
    std::map<std::string, int32_t> lanes;
    std::vector<Footprint> footprints(sc.vehicles.size());
    for (size_t i = 0; i < sc.vehicles.size(); ++i) {
        const ir::Vehicle& v = sc.vehicles[i];
        // A vehicle placed by x and y has no lane; a trajectory whose first waypoint is after
        // 0 s is not there at the start.
        const bool enters_later =
            v.kind == ir::VehicleKind::trajectory && !v.trajectory.empty() && v.trajectory.front().time > 0;
        if (v.start.xy || v.start.lane.empty() || enters_later) continue;
        const int32_t group = lanes.emplace(v.start.lane, static_cast<int32_t>(lanes.size())).first->second;
        footprints[i] = {group, v.start.s - 0.5 * v.length, v.start.s + 0.5 * v.length,
                         v.start.offset - 0.5 * v.width, v.start.offset + 0.5 * v.width};
    }
    auto start_range = [&](size_t i) {
        return s.vehicles[i].starts.empty() ? s.vehicles[i].name.range : s.vehicles[i].starts[0].range;
    };
    for (const Overlap& o : find_overlaps(footprints)) {
        set_instance(&s.vehicles[o.ahead]);
        auto* d = error("E0502", start_range(o.ahead),
                        "vehicles '" + sc.vehicles[o.ahead].name + "' and '" + sc.vehicles[o.behind].name +
                            "' start overlapped");
        d->notes.push_back({start_range(o.behind), "'" + sc.vehicles[o.behind].name + "' starts here"});
        set_instance(nullptr);
    }
}

void Checker::check_light(const ast::LightDecl& l, ScenarioCtx& ctx) {
    ir::LightProgram out;
    out.name = l.name.str();
    out.loc = loc(l.range);
    if (ctx.road != nullptr && ctx.road->road.kind == ir::RoadKind::road) {
        // A road's lights are those of its signalised crosswalks.
        std::vector<std::string> names;
        for (const auto& c : ctx.road->road.crosswalks) {
            if (c.signalised) names.push_back(ctx.road->name + "." + c.name);
        }
        if (names.empty()) {
            auto* d = error("E0106", l.name.range, "road '" + ctx.road->name + "' has no traffic lights");
            d->notes.push_back({{}, "a road's lights are those of its signalised crosswalks ('crosswalk NAME at S signalised')"});
        } else if (std::find(names.begin(), names.end(), out.name) == names.end()) {
            auto* d = error("E0106", l.name.range, "unknown traffic light '" + out.name + "'");
            add_suggestion(*d, out.name, names);
            std::string list;
            for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
            d->notes.push_back({{}, "the road's lights are " + list});
        }
    } else if (ctx.road != nullptr && ctx.road->road.kind == ir::RoadKind::junction) {
        const std::vector<std::string> names = {ctx.road->name + ".ns", ctx.road->name + ".ew"};
        if (ctx.road->road.control != "traffic_lights") {
            error("E0106", l.name.range, "junction '" + ctx.road->name + "' has no traffic lights (control " +
                                              ctx.road->road.control + ")");
        } else if (std::find(names.begin(), names.end(), out.name) == names.end()) {
            auto* d = error("E0106", l.name.range, "unknown traffic light '" + out.name + "'");
            add_suggestion(*d, out.name, names);
            d->notes.push_back({{}, "the junction's lights are " + names[0] + " and " + names[1]});
        }
    }
    for (const auto& ph : l.phases) {
        const std::string st = ph.key.text;
        if (st != "red" && st != "yellow" && st != "green") {
            auto* d = error("E0206", ph.key.range, "unknown light state '" + st + "'");
            add_suggestion(*d, st, {"red", "yellow", "green"});
            continue;
        }
        if (auto v = setting_number(ph, 0, Dim::time, 0, catalog::kMaxScenarioTime, true)) out.phases.push_back({st, *v});
    }
    if (l.phases.empty()) error("E0401", l.name.range, "light program without phases");
    if (l.offset) {
        ParamDef def;
        def.dim = Dim::time;
        def.min = 0;
        def.max = catalog::kMaxScenarioTime;
        Eval e = eval(*l.offset, nullptr, {ParamType::quantity, Dim::time}, "the offset", &def);
        if (e.kind == Eval::Kind::number && check_range(e, def, "the offset")) out.offset = e.num.value;
    }
    ctx.ir->lights.push_back(std::move(out));
}

int32_t Checker::check_expr(const ast::Expr& e, ScenarioCtx& ctx) {
    ir::Expect out;
    out.loc = loc(e.range);
    out.text = std::string(sm_.contents(e.range.begin.file)
                               .substr(e.range.begin.offset, e.range.end.offset - e.range.begin.offset));
    switch (e.kind) {
        case ast::Expr::Kind::not_: out.kind = ir::Expect::Kind::not_; break;
        case ast::Expr::Kind::and_: out.kind = ir::Expect::Kind::and_; break;
        case ast::Expr::Kind::or_: out.kind = ir::Expect::Kind::or_; break;
        case ast::Expr::Kind::call: out.kind = ir::Expect::Kind::call; break;
    }
    if (e.lhs) out.lhs = check_expr(*e.lhs, ctx);
    if (e.rhs) out.rhs = check_expr(*e.rhs, ctx);
    if (e.kind == ast::Expr::Kind::call) {
        const auto* f = catalog::find_expectation(e.function.text);
        if (f == nullptr) {
            std::vector<std::string> names;
            for (const auto& x : catalog::expectations()) names.push_back(x.name);
            auto* d = error("E0111", e.function.range, "unknown expectation '" + e.function.text + "'");
            add_suggestion(*d, e.function.text, names);
        } else {
            out.function = static_cast<int32_t>(f->kind);
            const int n = static_cast<int>(e.args.size());
            if (n < f->min_vehicles || n > f->max_vehicles) {
                error("E0508", e.function.range,
                      "'" + f->name + "' takes " +
                          (f->min_vehicles == f->max_vehicles
                               ? std::to_string(f->min_vehicles)
                               : std::to_string(f->min_vehicles) + " to " + std::to_string(f->max_vehicles)) +
                          " vehicle(s), found " + std::to_string(n));
            }
            for (const auto& a : e.args) {
                auto it = ctx.vehicle_index.find(a.text);
                if (it == ctx.vehicle_index.end()) {
                    auto* d = error("E0105", a.range, "unknown vehicle '" + a.text + "' in scenario '" +
                                                          ctx.name + "'");
                    add_suggestion(*d, a.text, ctx.vehicle_names);
                } else {
                    out.vehicles.push_back(it->second);
                }
            }
            if (f->boolean && !e.cmp.empty()) {
                error("E0204", e.bound->range, "'" + f->name + "' is true or false; it takes no comparison");
            } else if (!f->boolean && e.cmp.empty()) {
                auto* d = error("E0204", e.function.range,
                                "'" + f->name + "' is " + dim_phrase(f->result) + "; compare it");
                d->notes.push_back({{}, "e.g. " + f->name + "(...) < " +
                                        (f->result == Dim::time ? "2 s" : f->result == Dim::length ? "1 m" : "5")});
            } else if (!f->boolean) {
                out.cmp = e.cmp;
                Eval b = eval(*e.bound, nullptr, {ParamType::quantity, f->result}, "the bound of '" + f->name + "'", nullptr);
                if (b.kind == Eval::Kind::number) {
                    if (b.ranged) error("E0205", e.bound->range, "the bound cannot be a range");
                    out.bound = b.num.value;
                }
            }
        }
    }
    ctx.ir->expects.push_back(std::move(out));
    return static_cast<int32_t>(ctx.ir->expects.size() - 1);
}

void Checker::check_window(const ast::Expr& e, int32_t root, ScenarioCtx& ctx) {
    using Kind = ast::Expr::Window::Kind;
    const ast::Expr::Window& w = *e.window;
    ir::Expect& out = ctx.ir->expects[static_cast<size_t>(root)];
    // The statement's text includes its window: reports and `sdv diff` show it.
    out.text = std::string(sm_.contents(e.range.begin.file)
                               .substr(e.range.begin.offset, w.range.end.offset - e.range.begin.offset));
    const std::string& word = w.keyword.text;
    const ast::Value& v = w.value;
    const bool interval = v.kind == ast::Value::Kind::interval;
    if (v.spread || v.samples) {
        error("E0509", v.range, "a window cannot be spread or sampled")
            ->notes.push_back({{}, "write plain times, e.g. during 5 s .. 20 s"});
        return;
    }
    if (v.kind == ast::Value::Kind::list || interval != (w.kind == Kind::during)) {
        auto* d = error("E0509", v.range,
                        w.kind == Kind::during ? "'during' takes an interval of times"
                                               : "'" + word + "' takes one time");
        d->notes.push_back({{}, w.kind == Kind::during ? "e.g. during 5 s .. 20 s" : "e.g. " + word + " 5 s"});
        return;
    }
    auto time = [&](const ast::Primary& p) -> std::optional<double> {
        auto t = to_si(p, Dim::time, "the window of an expectation");
        if (t && *t < 0) {
            error("E0509", p.range, "a window time cannot be negative")
                ->notes.push_back({{}, "times count from the start of the run, 0 s"});
            return std::nullopt;
        }
        return t;
    };
    std::optional<double> lo, hi;
    if (w.kind == Kind::during) {
        lo = time(v.lo);
        hi = time(*v.hi);
        if (!lo || !hi) return;
        if (*lo >= *hi) {
            error("E0509", v.range, "empty window: it ends before it starts")
                ->notes.push_back({{}, "write the earlier time first, e.g. during 5 s .. 20 s"});
            return;
        }
    } else {
        auto t = time(v.lo);
        if (!t) return;
        (w.kind == Kind::after ? lo : hi) = t;
    }
    if (lo && *lo >= ctx.ir->timeout) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "the window starts at %g s, at or after the scenario's timeout (%g s)", *lo,
                      ctx.ir->timeout);
        error("E0509", v.range, buf)->notes.push_back({{}, "nothing is measured after the run ends"});
        return;
    }
    // Whole-run counts cannot be restricted to a window.
    bool windowable = true;
    std::function<void(const ast::Expr&)> visit = [&](const ast::Expr& x) {
        if (x.lhs) visit(*x.lhs);
        if (x.rhs) visit(*x.rhs);
        if (x.kind != ast::Expr::Kind::call) return;
        const auto* f = catalog::find_expectation(x.function.text);
        if (f == nullptr || f->windowed) return;
        windowable = false;
        error("E0509", x.function.range, "'" + f->name + "' is counted over the whole run; it takes no window")
            ->notes.push_back({w.range, "the window is here"});
    };
    visit(e);
    if (!windowable) return;
    out.after = lo;
    out.before = hi;
    out.window = std::string(sm_.contents(w.range.begin.file)
                                 .substr(w.range.begin.offset, w.range.end.offset - w.range.begin.offset));
}

}  // namespace sdv::compiler::sema
