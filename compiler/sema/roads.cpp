// Roads: `key value...` settings (duplicates, unknown keys, numbers with units and ranges, also
// used by scenarios and vehicles), and the checks of built-in roads (lanes, segments, arc radii),
// junctions (lanes, arms, control) and Lanelet2 maps (file, origin), each into an IR road.
#include <algorithm>
#include <set>

#include "compiler/sema/checker_internal.h"

namespace sdv::compiler::sema {

std::optional<double> Checker::setting_number(const ast::Setting& s, size_t i, Dim dim, double lo,
                                              double hi, bool lo_exclusive) {
    if (i >= s.values.size()) return std::nullopt;
    ParamDef def;
    def.dim = dim;
    def.min = lo;
    def.max = hi;
    def.min_exclusive = lo_exclusive;
    Eval e = eval(s.values[i], nullptr, {ParamType::quantity, dim}, "'" + s.key.text + "'", &def);
    if (e.kind != Eval::Kind::number) return std::nullopt;
    if (e.ranged) {
        error("E0205", s.values[i].range, "'" + s.key.text + "' cannot be a range");
        return std::nullopt;
    }
    if (!check_range(e, def, "'" + s.key.text + "'")) return std::nullopt;
    return e.num.value;
}

// Reads an optional numeric setting into `out`; false when it is present but invalid.
bool Checker::read_setting(std::map<std::string, const ast::Setting*>& set, const char* key,
                           Dim dim, double lo, double hi, bool lo_exclusive, double& out) {
    const ast::Setting* s = set[key];
    if (s == nullptr) return true;
    if (auto v = setting_number(*s, 0, dim, lo, hi, lo_exclusive)) {
        out = *v;
        return true;
    }
    return false;
}

// Reports duplicate settings and returns the first occurrence of each key.
std::map<std::string, const ast::Setting*> Checker::settings_map(
    const std::vector<ast::Setting>& ss, const std::vector<std::string>& known,
    const std::string& where) {
    std::map<std::string, const ast::Setting*> out;
    for (const auto& s : ss) {
        if (!known.empty() && std::find(known.begin(), known.end(), s.key.text) == known.end()) {
            auto* d = error("E0113", s.key.range, "unknown setting '" + s.key.text + "' in " + where);
            add_suggestion(*d, s.key.text, known);
            continue;
        }
        if (auto it = out.find(s.key.text); it != out.end()) {
            auto* d = error("E0504", s.key.range, "duplicate '" + s.key.text + "' in " + where);
            d->notes.push_back({it->second->range, "first given here"});
            continue;
        }
        out[s.key.text] = &s;
    }
    return out;
}

void Checker::check_roads() {
    for (const auto& r : road_decls_) {
        RoadSym sym;
        sym.unit = r.unit;
        if (r.road != nullptr) {
            sym.name = r.road->name.text;
            sym.range = r.road->name.range;
            check_builtin_road(*r.road, sym);
        } else if (r.junction != nullptr) {
            sym.name = r.junction->name.text;
            sym.range = r.junction->name.range;
            check_junction(*r.junction, sym);
        } else {
            sym.name = r.map->name.text;
            sym.range = r.map->name.range;
            check_map(*r.map, sym);
        }
        sym.road.name = sym.name;
        sym.road.loc = loc(sym.range);
        roads_.push_back(std::move(sym));
    }
}

void Checker::check_builtin_road(const ast::RoadDecl& r, RoadSym& sym) {
    ir::Road& road = sym.road;
    road.kind = ir::RoadKind::road;
    const std::string where = "road '" + r.name.text + "'";
    if (r.lanes.empty()) {
        auto* d = error("E0401", r.name.range, where + " does not say its lanes");
        d->notes.push_back({{}, "add e.g. 'lanes 2 forward, 1 backward'"});
        sym.ok = false;
    }
    road.lanes_forward = 0;
    road.lanes_backward = 0;
    std::set<std::string> dirs;
    for (const auto& l : r.lanes) {
        if (l.direction.text != "forward" && l.direction.text != "backward") {
            auto* d = error("E0206", l.direction.range,
                            "lane direction must be 'forward' or 'backward'");
            add_suggestion(*d, l.direction.text, {"forward", "backward"});
            sym.ok = false;
            continue;
        }
        if (!dirs.insert(l.direction.text).second) {
            error("E0504", l.direction.range, "'" + l.direction.text + "' lanes given twice");
            sym.ok = false;
            continue;
        }
        if (l.count < 0 || l.count > 8) {
            auto* d = error("E0301", l.count_range, "lane count " + std::to_string(l.count) +
                                                        " is out of range");
            d->notes.push_back({{}, "allowed: 0 to 8 lanes per direction"});
            sym.ok = false;
            continue;
        }
        (l.direction.text == "forward" ? road.lanes_forward : road.lanes_backward) =
            static_cast<int32_t>(l.count);
    }
    if (!r.lanes.empty() && road.lanes_forward + road.lanes_backward == 0 && sym.ok) {
        error("E0301", r.lanes_range, where + " has no lanes");
        sym.ok = false;
    }
    auto set = settings_map(r.settings, {"lane_width", "speed_limit", "origin", "heading"}, where);
    sym.ok = read_setting(set, "lane_width", Dim::length, 1.0, 10.0, false, road.lane_width) && sym.ok;
    sym.ok = read_setting(set, "speed_limit", Dim::speed, 0.0, 100.0, true, road.speed_limit) && sym.ok;
    if (auto* s = set["origin"]) {
        auto x = setting_number(*s, 0, Dim::length, -1e7, 1e7, false);
        auto y = setting_number(*s, 1, Dim::length, -1e7, 1e7, false);
        if (x && y) {
            road.origin_x = *x;
            road.origin_y = *y;
        } else {
            sym.ok = false;
        }
    }
    sym.ok = read_setting(set, "heading", Dim::angle, -10.0, 10.0, false, road.heading) && sym.ok;
    if (r.segments.empty()) {
        auto* d = error("E0401", r.name.range, where + " has no segments");
        d->notes.push_back({{}, "add e.g. 'straight 300 m'"});
        sym.ok = false;
    }
    // The reference line runs between the directions: a left arc has the backward lanes on
    // its inside, a right arc the forward lanes; the radius must exceed what lies inside.
    const double inside_left = road.lane_width * road.lanes_backward + 0.5;
    const double inside_right = road.lane_width * road.lanes_forward + 0.5;
    for (const auto& seg : r.segments) {
        ParamDef def;
        def.dim = Dim::length;
        def.min = 0;
        def.min_exclusive = true;
        def.max = 100000;
        Eval len = eval(seg.length, nullptr, {ParamType::quantity, Dim::length},
                        "the segment length", &def);
        if (len.kind != Eval::Kind::number || !check_range(len, def, "the segment length")) {
            sym.ok = false;
            continue;
        }
        ir::Segment out;
        out.arc = seg.arc;
        out.length = len.num.value;
        if (seg.arc) {
            ParamDef rdef = def;
            const bool right = seg.side && seg.side->text == "right";
            rdef.min = right ? inside_right : inside_left;
            rdef.min_exclusive = false;
            rdef.max = 1e6;
            Eval rad = eval(*seg.radius, nullptr, {ParamType::quantity, Dim::length},
                            "the arc radius", &rdef);
            if (rad.kind != Eval::Kind::number) {
                sym.ok = false;
                continue;
            }
            if (!check_range(rad, rdef, "the arc radius (it must exceed the width of the lanes on the inside of the turn)")) {
                sym.ok = false;
                continue;
            }
            out.radius = (seg.side && seg.side->text == "right") ? -rad.num.value : rad.num.value;
        }
        sym.length += out.length;
        road.segments.push_back(out);
    }
    // The work of building a road grows with its length (reference lines sampled along it).
    if (sym.ok && sym.length > ir::kMaxRoadLength) {
        auto* d = error("E0301", r.name.range, where + " is " + fmt(sym.length / 1000) + " km long");
        d->notes.push_back({{}, "a road is at most " + fmt(ir::kMaxRoadLength / 1000) + " km long, its segments together"});
        sym.ok = false;
    }
    check_crosswalks(r.crosswalks, sym, false);
}

// Crosswalks: on a road `at` a position along it (required) and `signalised` allowed; on a
// junction `on` an arm (required) with `at` the gap from the junction box (default 1 m); width
// 1..20 m (default 3 m).
void Checker::check_crosswalks(const std::vector<ast::CrosswalkDecl>& xs, RoadSym& sym, bool junction) {
    ir::Road& road = sym.road;
    std::map<std::string, const ast::CrosswalkDecl*> seen;
    for (const auto& x : xs) {
        const std::string what = "crosswalk '" + x.name.text + "'";
        if (auto [it, fresh] = seen.emplace(x.name.text, &x); !fresh) {
            auto* d = error("E0504", x.name.range, "duplicate " + what + " of '" + road.name + "'");
            d->notes.push_back({it->second->name.range, "first declared here"});
            sym.ok = false;
            continue;
        }
        ir::Crosswalk c;
        c.name = x.name.text;
        c.loc = loc(x.name.range);
        c.signalised = x.signalised.has_value();
        auto number = [&](const ast::Value& v, Dim dim, double lo, double hi, const std::string& label) -> std::optional<double> {
            ParamDef def;
            def.dim = dim;
            def.min = lo;
            def.max = hi;
            Eval e = eval(v, nullptr, {ParamType::quantity, dim}, label, &def);
            if (e.kind != Eval::Kind::number) return std::nullopt;
            if (e.ranged) {
                error("E0205", v.range, label + " cannot be a range");
                return std::nullopt;
            }
            if (!check_range(e, def, label)) return std::nullopt;
            return e.num.value;
        };
        bool ok = true;
        if (x.width) {
            auto w = number(*x.width, Dim::length, 1, 20, "the width of " + what);
            ok = ok && w.has_value();
            if (w) c.width = *w;
        }
        if (junction) {
            static const std::vector<std::string> arms = {"north", "east", "south", "west"};
            if (!x.arm) {
                auto* d = error("E0301", x.name.range, what + " of junction '" + road.name + "' has no arm");
                d->notes.push_back({{}, "e.g. 'crosswalk " + x.name.text + " on north'"});
                ok = false;
            } else if (std::find(arms.begin(), arms.end(), x.arm->text) == arms.end()) {
                auto* d = error("E0206", x.arm->range, "unknown junction arm '" + x.arm->text + "'");
                add_suggestion(*d, x.arm->text, arms);
                d->notes.push_back({{}, "a junction's arms are north, east, south and west"});
                ok = false;
            } else {
                c.arm = x.arm->text;
            }
            c.at = 1.0;
            if (x.at) {
                auto a = number(*x.at, Dim::length, 0, std::max(0.0, road.arm_length - c.width - 1), "the gap of " + what + " from the junction");
                ok = ok && a.has_value();
                if (a) c.at = *a;
            }
            if (x.signalised) {
                auto* d = error("E0301", *x.signalised, what + ": a junction's crosswalks follow its control");
                d->notes.push_back({{}, "with 'control traffic_lights' each crosswalk follows the light of the traffic parallel to it"});
                ok = false;
            }
        } else {
            if (x.arm) {
                auto* d = error("E0301", x.arm->range, what + ": a road has no arms");
                d->notes.push_back({{}, "place it along the road: 'crosswalk " + x.name.text + " at 100 m'"});
                ok = false;
            }
            if (!x.at) {
                auto* d = error("E0301", x.name.range, what + " of road '" + road.name + "' has no position");
                d->notes.push_back({{}, "e.g. 'crosswalk " + x.name.text + " at 100 m'"});
                ok = false;
            } else if (auto a = number(*x.at, Dim::length, 0.5 * c.width, std::max(0.5 * c.width, sym.length - 0.5 * c.width),
                                       "the position of " + what)) {
                c.at = *a;
            } else {
                ok = false;
            }
        }
        sym.ok = sym.ok && ok;
        if (ok) road.crosswalks.push_back(std::move(c));
    }
}

void Checker::check_junction(const ast::JunctionDecl& j, RoadSym& sym) {
    ir::Road& road = sym.road;
    road.kind = ir::RoadKind::junction;
    road.control = "stop_signs";
    const std::string where = "junction '" + j.name.text + "'";
    auto set = settings_map(j.settings, {"lanes", "lane_width", "speed_limit", "arm_length", "control"},
                            where);
    if (auto* s = set["lanes"]) {
        if (auto v = setting_number(*s, 0, Dim::none, 1, 4, false)) {
            road.lanes_forward = static_cast<int32_t>(*v);
        } else {
            sym.ok = false;
        }
    }
    sym.ok = read_setting(set, "lane_width", Dim::length, 1.0, 10.0, false, road.lane_width) && sym.ok;
    sym.ok = read_setting(set, "speed_limit", Dim::speed, 0.0, 100.0, true, road.speed_limit) && sym.ok;
    sym.ok = read_setting(set, "arm_length", Dim::length, 20.0, 10000.0, false, road.arm_length) && sym.ok;
    if (auto* s = set["control"]) {
        const std::string c = s->values[0].lo.name.str();
        const std::vector<std::string> choices = {"stop_signs", "two_way_stops", "traffic_lights", "none"};
        if (std::find(choices.begin(), choices.end(), c) == choices.end()) {
            auto* d = error("E0206", s->values[0].range, "unknown junction control '" + c + "'");
            add_suggestion(*d, c, choices);
            d->notes.push_back({{}, "expected stop_signs, two_way_stops, traffic_lights or none"});
            sym.ok = false;
        } else {
            road.control = c;
        }
    }
    sym.length = road.arm_length;
    check_crosswalks(j.crosswalks, sym, true);
}

void Checker::check_map(const ast::MapDecl& m, RoadSym& sym) {
    ir::Road& road = sym.road;
    road.kind = ir::RoadKind::lanelet2;
    const std::string where = "map '" + m.name.text + "'";
    auto set = settings_map(m.settings, {"file", "origin"}, where);
    if (auto* s = set["file"]) {
        fs::path p = s->values[0].lo.string;
        if (p.is_relative() && !sym.unit->dir.empty()) p = sym.unit->dir / p;
        std::error_code ec;
        if (!fs::is_regular_file(p, ec)) {
            error("E0510", s->values[0].range, "map file '" + s->values[0].lo.string +
                                                   "' not found (looked at " + p.string() + ")");
            sym.ok = false;
        }
        road.map_file = p.lexically_normal().string();
    } else {
        error("E0401", m.name.range, where + " needs a 'file \"path.osm\"'");
        sym.ok = false;
    }
    if (auto* s = set["origin"]) {
        if (s->values.size() < 2) {
            error("E0401", s->range, "origin needs latitude and longitude");
            sym.ok = false;
        } else {
            auto lat = setting_number(*s, 0, Dim::none, -90, 90, false);
            auto lon = setting_number(*s, 1, Dim::none, -180, 180, false);
            auto alt = s->values.size() > 2 ? setting_number(*s, 2, Dim::length, catalog::kMinAltitude, catalog::kMaxAltitude, false)
                                            : std::optional<double>(0.0);
            if (lat && lon && alt) {
                road.origin_lat = *lat;
                road.origin_lon = *lon;
                road.origin_alt = *alt;
                road.has_origin = true;
            } else {
                sym.ok = false;
            }
        }
    }
}

}  // namespace sdv::compiler::sema
