#include "compiler/diff/diff.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "runtime/catalog/catalog.h"

namespace sdv::diff {
namespace {

constexpr auto num = catalog::format_number;

std::string quantity(double si, catalog::Dim dim) {
    if (dim == catalog::Dim::angle) return num(si * 180 / M_PI) + " deg";
    const std::string u(catalog::si_unit(dim));
    return u.empty() ? num(si) : num(si) + " " + u;
}

std::string sampled(const ir::Sampled& s, catalog::Dim dim) {
    std::string out = quantity(s.value, dim);
    if (s.samples > 1 || s.lo != s.hi) {
        out = quantity(s.lo, dim) + " .. " + quantity(s.hi, dim) + " samples " + std::to_string(s.samples);
        if (s.method == ir::SampleMethod::uniform) out += " uniform";
        if (s.method == ir::SampleMethod::normal) out += " normal(" + quantity(s.sigma, dim) + ")";
    }
    return out;
}

std::string vehicle_ref(const ir::VehicleRef& r, const ir::Scenario& sc) {
    switch (r.kind) {
        case ir::VehicleRef::Kind::none: return "(default)";
        case ir::VehicleRef::Kind::self: return "self";
        case ir::VehicleRef::Kind::vehicle:
            return r.vehicle >= 0 && static_cast<size_t>(r.vehicle) < sc.vehicles.size() ? sc.vehicles[static_cast<size_t>(r.vehicle)].name : "?";
        case ir::VehicleRef::Kind::zone: return catalog::vehicle_zones()[static_cast<size_t>(r.zone)];
    }
    return "?";
}

std::string param_text(const ir::ParamValue& v, const catalog::ParamDef& d, const ir::Scenario& sc) {
    if (!v.given) return "(unset)";
    switch (d.type) {
        case catalog::ParamType::choice: return v.choice >= 0 ? d.choices[static_cast<size_t>(v.choice)] : "?";
        case catalog::ParamType::boolean: return v.number.value != 0 ? "true" : "false";
        case catalog::ParamType::vehicle: return vehicle_ref(v.vehicle, sc);
        case catalog::ParamType::integer: return num(v.number.value);
        case catalog::ParamType::quantity: return sampled(v.number, d.dim);
    }
    return "?";
}

const std::vector<catalog::ParamDef>& defs(const ir::Node& n) {
    return n.kind == ir::NodeKind::maneuver ? catalog::maneuvers()[static_cast<size_t>(n.leaf)].params
                                            : catalog::conditions()[static_cast<size_t>(n.leaf)].params;
}

const char* kind_name(ir::NodeKind k) {
    switch (k) {
        case ir::NodeKind::fallback: return "fallback";
        case ir::NodeKind::sequence: return "sequence";
        case ir::NodeKind::reactive_sequence: return "reactive_sequence";
        case ir::NodeKind::parallel: return "parallel";
        case ir::NodeKind::condition: return "condition";
        case ir::NodeKind::maneuver: return "maneuver";
        case ir::NodeKind::not_: return "not";
        case ir::NodeKind::once: return "once";
        case ir::NodeKind::latch: return "latch";
    }
    return "?";
}

std::string node_text(const ir::Node& n) {
    std::string s = kind_name(n.kind);
    if (n.kind == ir::NodeKind::maneuver) s += " " + catalog::maneuvers()[static_cast<size_t>(n.leaf)].name;
    if (n.kind == ir::NodeKind::condition) s += " " + catalog::conditions()[static_cast<size_t>(n.leaf)].name;
    return s;
}

std::string parent_of(const std::string& path) {
    const auto p = path.rfind('/');
    return p == std::string::npos ? "" : path.substr(0, p);
}

void diff_trees(const ir::Program& pa, const ir::TreeInstance& a, const ir::Scenario& sa, const ir::Program& pb,
                const ir::TreeInstance& b, const ir::Scenario& sb, const std::string& who, std::vector<Change>& out) {
    std::map<std::string, const ir::Node*> ma, mb;
    for (const auto& n : a.nodes) ma[n.path] = &n;
    for (const auto& n : b.nodes) mb[n.path] = &n;
    // Identity of a node independent of its place: declaring tree + name.
    auto identity = [](const ir::Program& p, const ir::Node& n) {
        const std::string tree = n.tree >= 0 && static_cast<size_t>(n.tree) < p.trees.size() ? p.trees[static_cast<size_t>(n.tree)].name : "";
        return tree + ":" + n.name + ":" + kind_name(n.kind);
    };
    std::map<std::string, std::vector<const ir::Node*>> removed_by_id;
    for (const auto& [path, n] : ma) {
        if (!mb.count(path)) removed_by_id[identity(pa, *n)].push_back(n);
    }
    for (const auto& [path, n] : mb) {
        if (ma.count(path)) continue;
        auto it = removed_by_id.find(identity(pb, *n));
        if (it != removed_by_id.end() && !it->second.empty()) {
            const ir::Node* old = it->second.front();
            it->second.erase(it->second.begin());
            out.push_back({who + ": node " + n->name, "moved from " + parent_of(old->path) + " to " + parent_of(path)});
            continue;
        }
        out.push_back({who + ": node " + path, "added (" + node_text(*n) + ")"});
    }
    for (const auto& [id, nodes] : removed_by_id) {
        for (const ir::Node* n : nodes) out.push_back({who + ": node " + n->path, "removed (" + node_text(*n) + ")"});
    }
    for (const auto& [path, na] : ma) {
        auto it = mb.find(path);
        if (it == mb.end()) continue;
        const ir::Node& nb = *it->second;
        if (na->kind != nb.kind || na->leaf != nb.leaf) {
            out.push_back({who + ": node " + path, node_text(*na) + " → " + node_text(nb)});
            continue;
        }
        if (na->kind == ir::NodeKind::parallel && na->success_threshold != nb.success_threshold) {
            out.push_back({who + ": node " + path, "success threshold " + std::to_string(na->success_threshold) + " → " +
                                                       std::to_string(nb.success_threshold)});
        }
        if (na->kind != ir::NodeKind::maneuver && na->kind != ir::NodeKind::condition) continue;
        const auto& d = defs(*na);
        for (size_t i = 0; i < d.size() && i < na->params.size() && i < nb.params.size(); ++i) {
            const std::string ta = param_text(na->params[i], d[i], sa), tb = param_text(nb.params[i], d[i], sb);
            if (ta != tb) out.push_back({who + ": node " + path, d[i].name + " " + ta + " → " + tb});
        }
    }
}

std::string position(const ir::Position& p) {
    if (p.xy) return "(" + num(p.x) + " m, " + num(p.y) + " m)";
    std::string s = "lane " + p.lane + " at " + num(p.s) + " m";
    if (p.offset != 0) s += " offset " + num(p.offset) + " m";
    return s;
}

void field(std::vector<Change>& out, const std::string& where, const std::string& name, const std::string& a,
           const std::string& b) {
    if (a != b) out.push_back({where, name + " " + a + " → " + b});
}

std::string road_text(const ir::Program& p, int32_t r) {
    if (r < 0) return "(none)";
    const ir::Road& road = p.roads[static_cast<size_t>(r)];
    std::ostringstream o;
    o << road.name;
    if (road.kind == ir::RoadKind::road) {
        o << " (" << road.lanes_forward << " forward, " << road.lanes_backward << " backward, width " << num(road.lane_width)
          << " m, limit " << num(road.speed_limit) << " m/s, segments";
        for (const auto& s : road.segments) o << " " << (s.arc ? "arc " : "straight ") << num(s.length) << (s.arc ? "/r" + num(s.radius) : "");
        o << ")";
    } else if (road.kind == ir::RoadKind::junction) {
        o << " (junction " << road.lanes_forward << " lanes, " << road.control << ", arms " << num(road.arm_length) << " m)";
    } else {
        o << " (map " << road.map_file << ")";
    }
    return o.str();
}

}  // namespace

std::vector<Change> diff_programs(const ir::Program& a, const ir::Program& b) {
    std::vector<Change> out;
    std::map<std::string, const ir::Scenario*> sa, sb;
    for (const auto& s : a.scenarios) sa[s.name] = &s;
    for (const auto& s : b.scenarios) sb[s.name] = &s;
    for (const auto& [name, s] : sa) {
        if (!sb.count(name)) out.push_back({"scenario " + name, "removed"});
    }
    for (const auto& [name, s] : sb) {
        if (!sa.count(name)) out.push_back({"scenario " + name, "added"});
    }
    for (const auto& [name, x] : sa) {
        auto it = sb.find(name);
        if (it == sb.end()) continue;
        const ir::Scenario& y = *it->second;
        const std::string where = "scenario " + name;
        field(out, where, "road", road_text(a, x->road), road_text(b, y.road));
        field(out, where, "timeout", num(x->timeout) + " s", num(y.timeout) + " s");
        field(out, where, "seed", std::to_string(x->seed), std::to_string(y.seed));
        field(out, where, "traffic rate", num(x->traffic_rate) + " Hz", num(y.traffic_rate) + " Hz");
        field(out, where, "planning rate", num(x->planning_rate) + " Hz", num(y.planning_rate) + " Hz");
        field(out, where, "planning latency", num(x->planning_latency) + " s", num(y.planning_latency) + " s");
        std::map<std::string, const ir::Vehicle*> va, vb;
        for (const auto& v : x->vehicles) va[v.name] = &v;
        for (const auto& v : y.vehicles) vb[v.name] = &v;
        for (const auto& [vn, v] : va) {
            if (!vb.count(vn)) out.push_back({"vehicle " + vn, "removed"});
        }
        for (const auto& [vn, v] : vb) {
            if (!va.count(vn)) out.push_back({"vehicle " + vn, "added"});
        }
        for (const auto& [vn, v] : va) {
            auto jt = vb.find(vn);
            if (jt == vb.end()) continue;
            const ir::Vehicle& w = *jt->second;
            const std::string who = "vehicle " + vn;
            static const char* kinds[] = {"sdv", "trajectory", "static", "external"};
            field(out, who, "kind", kinds[static_cast<int>(v->kind)], kinds[static_cast<int>(w.kind)]);
            field(out, who, "ego", v->is_ego ? "yes" : "no", w.is_ego ? "yes" : "no");
            field(out, who, "start", position(v->start), position(w.start));
            if (!v->start.xy && !w.start.xy && v->start.lane == w.start.lane && v->start.s != w.start.s) {
                out.back().what += " (" + num(std::fabs(w.start.s - v->start.s)) + " m " + (w.start.s > v->start.s ? "later" : "earlier") + ")";
            }
            field(out, who, "goal", v->goal ? position(*v->goal) : "(none)", w.goal ? position(*w.goal) : "(none)");
            field(out, who, "goal ends run", v->goal_ends_run ? "yes" : "no", w.goal_ends_run ? "yes" : "no");
            field(out, who, "speed", num(v->speed) + " m/s", num(w.speed) + " m/s");
            field(out, who, "length", num(v->length) + " m", num(w.length) + " m");
            field(out, who, "width", num(v->width) + " m", num(w.width) + " m");
            if (v->tree >= 0 && w.tree >= 0) {
                diff_trees(a, a.instances[static_cast<size_t>(v->tree)], *x, b, b.instances[static_cast<size_t>(w.tree)], y, who, out);
            }
        }
        std::vector<std::string> ea, eb;
        for (int32_t r : x->expect_roots) ea.push_back(x->expects[static_cast<size_t>(r)].text);
        for (int32_t r : y.expect_roots) eb.push_back(y.expects[static_cast<size_t>(r)].text);
        for (const auto& e : ea) {
            if (std::find(eb.begin(), eb.end(), e) == eb.end()) out.push_back({where, "expectation removed: " + e});
        }
        for (const auto& e : eb) {
            if (std::find(ea.begin(), ea.end(), e) == ea.end()) out.push_back({where, "expectation added: " + e});
        }
        std::map<std::string, std::string> la, lb;
        auto light = [](const ir::LightProgram& l) {
            std::string s;
            for (const auto& p : l.phases) s += p.state + " " + num(p.duration) + " s  ";
            return s + "offset " + num(l.offset) + " s";
        };
        for (const auto& l : x->lights) la[l.name] = light(l);
        for (const auto& l : y.lights) lb[l.name] = light(l);
        for (const auto& [ln, t] : la) field(out, where, "light " + ln, t, lb.count(ln) ? lb[ln] : "(none)");
        for (const auto& [ln, t] : lb) {
            if (!la.count(ln)) field(out, where, "light " + ln, "(none)", t);
        }
    }
    return out;
}

std::string render_text(const std::vector<Change>& changes) {
    if (changes.empty()) return "no difference\n";
    std::string out;
    for (const auto& c : changes) out += c.where + ": " + c.what + "\n";
    out += std::to_string(changes.size()) + (changes.size() == 1 ? " difference\n" : " differences\n");
    return out;
}

nlohmann::ordered_json to_json(const std::vector<Change>& changes) {
    nlohmann::ordered_json j;
    j["equal"] = changes.empty();
    j["changes"] = nlohmann::ordered_json::array();
    for (const auto& c : changes) j["changes"].push_back({{"where", c.where}, {"what", c.what}});
    return j;
}

std::string render_json(const std::vector<Change>& changes) {
    return to_json(changes).dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace sdv::diff
