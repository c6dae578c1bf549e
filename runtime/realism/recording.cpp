#include "runtime/realism/recording.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <pugixml.hpp>
#include <set>
#include <sstream>

#include "runtime/catalog/catalog.h"
#include "runtime/road/commonroad_reader.h"
#include "runtime/road/reader_text.h"

namespace sdv::realism {
namespace {

constexpr double kMaxCoordinate = 1e6;  // m from the origin, as the map readers
constexpr double kMaxTime = 1e6;        // s

constexpr auto number = road::parse_number;
using road::read_file;
using catalog::format_number;
using Lines = road::XmlLines;

// The value of a CommonRoad state field: <field><exact>v</exact></field>; an interval or a
// missing value is nullopt (`why` says which).
std::optional<double> exact(const pugi::xml_node& state, const char* field, std::string& why) {
    const auto f = state.child(field);
    if (!f) {
        why = std::string("no <") + field + ">";
        return std::nullopt;
    }
    const auto e = f.child("exact");
    if (!e) {
        why = std::string("<") + field + "> is not exact (sdv reads recorded states, not intervals)";
        return std::nullopt;
    }
    auto v = number(e.child_value());
    if (!v) why = std::string("<") + field + "> is not a number";
    return v;
}

Recording unreadable(const std::string& path) {
    Recording r;
    r.path = path;
    r.errors.push_back(path + ": cannot read the file");
    return r;
}

}  // namespace

double Recording::duration() const {
    double t0 = INFINITY, t1 = -INFINITY;
    for (const auto& tr : tracks) {
        t0 = std::min(t0, tr.start());
        t1 = std::max(t1, tr.end());
    }
    return tracks.empty() ? 0 : t1 - t0;
}

const Track* Recording::find(const std::string& id) const {
    for (const auto& t : tracks)
        if (t.id == id) return &t;
    return nullptr;
}

Recording read_commonroad(const std::string& path) {
    std::string text;
    if (!read_file(path, text)) return unreadable(path);
    return parse_commonroad(text, path);
}

Recording parse_commonroad(const std::string& xml, const std::string& path) {
    Recording r;
    r.path = path;
    r.map_path = path;
    pugi::xml_document doc;
    const auto parsed = doc.load_buffer(xml.data(), xml.size());
    if (!parsed) {
        r.errors.push_back(path + ": not a valid XML file: " + parsed.description() + " at byte " +
                           std::to_string(parsed.offset));
        return r;
    }
    const auto root = doc.child("commonRoad");
    if (!root) {
        r.errors.push_back(path + ": not a CommonRoad file (no <commonRoad> element)");
        return r;
    }
    const Lines lines(xml);
    auto at = [&](const pugi::xml_node& n) { return path + ":" + std::to_string(lines.line(n)) + ": "; };
    const std::string version = root.attribute("commonRoadVersion").as_string();
    r.format = "commonroad" + (version.empty() ? std::string() : " " + version);
    const auto dt = number(root.attribute("timeStepSize").as_string());
    if (!dt || *dt <= 0 || *dt > 10) {
        r.errors.push_back(at(root) + "commonRoad: timeStepSize must be a number of seconds in (0, 10]");
        return r;
    }
    r.dt = *dt;
    std::set<std::string> ids;
    for (auto o : root.children()) {
        const std::string tag = o.name();
        const bool dynamic = tag == "dynamicObstacle" ||
                             (tag == "obstacle" && std::string(o.child_value("role")) == "dynamic");
        if (!dynamic) continue;
        Track tr;
        tr.id = o.attribute("id").as_string();
        const std::string where = at(o) + "obstacle " + (tr.id.empty() ? "(no id)" : tr.id) + ": ";
        if (tr.id.empty() || !ids.insert(tr.id).second) {
            r.errors.push_back(where + (tr.id.empty() ? "needs an id" : "the id is used twice"));
            continue;
        }
        if (r.tracks.size() >= kMaxTracks) {
            r.errors.push_back(where + "more than " + std::to_string(kMaxTracks) + " recorded agents");
            return r;
        }
        tr.type = o.child_value("type");
        if (tr.type.empty()) tr.type = "unknown";
        const auto shape = o.child("shape");
        // Sizes the scenario of a replay can declare (catalog::AgentSize).
        const catalog::AgentSize max = tr.pedestrian() ? catalog::kMaxPedestrianSize : catalog::kMaxVehicleSize;
        const std::string kind = tr.pedestrian() ? "a pedestrian" : "a vehicle";
        if (const auto rect = shape.child("rectangle")) {
            const auto l = number(rect.child_value("length")), w = number(rect.child_value("width"));
            if (!l || !w || !(*l > 0) || !(*w > 0) || *l > max.length || *w > max.width) {
                r.errors.push_back(where + "its rectangle needs a length in (0, " + format_number(max.length) + "] m and a width in (0, " +
                                   format_number(max.width) + "] m, the size of " + kind + " (" + tr.type + ")");
                continue;
            }
            tr.length = *l;
            tr.width = *w;
        } else if (const auto circle = shape.child("circle")) {
            const auto rad = number(circle.child_value("radius"));
            const double max_radius = std::min(max.length, max.width) / 2;
            if (!rad || !(*rad > 0) || *rad > max_radius) {
                r.errors.push_back(where + "its circle needs a radius in (0, " + format_number(max_radius) + "] m, the size of " + kind +
                                   " (" + tr.type + ")");
                continue;
            }
            tr.length = tr.width = 2 * *rad;
        } else {
            r.errors.push_back(where + "its shape must be a rectangle or a circle");
            continue;
        }
        bool ok = true;
        auto add_state = [&](const pugi::xml_node& s) {
            std::string why;
            const auto p = s.child("position").child("point");
            const auto x = number(p.child_value("x")), y = number(p.child_value("y"));
            const auto step = exact(s, "time", why);
            const auto heading = step ? exact(s, "orientation", why) : std::nullopt;
            const auto speed = heading ? exact(s, "velocity", why) : std::nullopt;
            if (!p) why = "its position is not a point";
            if (!p || !x || !y || !step || !heading || !speed) {
                r.errors.push_back(at(s) + "obstacle " + tr.id + ": a state " +
                                   (why.empty() ? std::string("without numeric <x> and <y>") : why));
                ok = false;
                return;
            }
            const double t = *step * r.dt, v = speed.value_or(0);
            if (std::fabs(*x) > kMaxCoordinate || std::fabs(*y) > kMaxCoordinate || t < 0 || t > kMaxTime) {
                r.errors.push_back(at(s) + "obstacle " + tr.id + ": a state beyond the limits (1,000 km, 10^6 s)");
                ok = false;
                return;
            }
            if (!tr.states.empty() && t <= tr.states.back().t) {
                r.errors.push_back(at(s) + "obstacle " + tr.id + ": states must be in increasing time");
                ok = false;
                return;
            }
            // A replay starts its SDV at the recorded speed, so a vehicle's is a speed a scenario's
            // vehicle may have (sdv replays vehicles driving forwards).
            if (!tr.pedestrian() && !(v >= 0 && v <= catalog::kMaxVehicleSpeed)) {
                r.errors.push_back(at(s) + "obstacle " + tr.id + ": velocity " + format_number(v) +
                                   " m/s is not a vehicle's speed, 0 to " + format_number(catalog::kMaxVehicleSpeed) + " m/s");
                ok = false;
                return;
            }
            if (tr.states.size() >= kMaxStates) {
                r.errors.push_back(at(s) + "obstacle " + tr.id + ": more than " + std::to_string(kMaxStates) + " states");
                ok = false;
                return;
            }
            tr.states.push_back({t, *x, *y, *heading, v});
        };
        const auto init = o.child("initialState");
        if (!init) {
            r.errors.push_back(where + "no <initialState>");
            continue;
        }
        add_state(init);
        for (auto s : o.child("trajectory").children("state")) {
            if (!ok) break;
            add_state(s);
        }
        if (ok) r.tracks.push_back(std::move(tr));
    }
    // Traffic-light cycles (durations and offsets in time steps).
    for (auto l : root.children("trafficLight")) {
        const std::string id = l.attribute("id").as_string();
        const std::string where = at(l) + "trafficLight " + id + ": ";
        LightCycle c;
        c.light = road::commonroad_light_name(id);
        const auto cycle = l.child("cycle");
        double total = 0;
        bool ok = true;
        for (auto e : cycle.children("cycleElement")) {
            const auto steps = number(e.child_value("duration"));
            std::string color = e.child_value("color");
            if (!steps || *steps <= 0 || *steps > kMaxTime) {
                r.errors.push_back(at(e) + "trafficLight " + id + ": a cycle element needs a positive duration");
                ok = false;
                break;
            }
            // sdv's lights are red, yellow or green: red-yellow (about to turn green) still
            // means stop; an inactive light controls nothing.
            if (color == "redYellow" || color == "red_yellow") color = "red";
            if (color == "inactive") color = "green";
            if (color != "red" && color != "yellow" && color != "green") {
                r.errors.push_back(at(e) + "trafficLight " + id + ": unknown color '" + color + "'");
                ok = false;
                break;
            }
            c.phases.push_back({color, *steps * r.dt});
            total += *steps * r.dt;
        }
        if (!ok) continue;
        if (c.phases.empty()) {
            r.warnings.push_back(where + "no cycle: the light stays green");
            continue;
        }
        // CommonRoad's cycle starts at timeOffset; sdv's offset is how far into the cycle the
        // light is at time 0.
        const double start = number(cycle.child_value("timeOffset")).value_or(0) * r.dt;
        c.offset = std::fmod(std::fmod(-start, total) + total, total);
        if (std::string(l.child_value("active")) == "false") continue;
        r.lights.push_back(std::move(c));
    }
    if (r.tracks.empty() && r.errors.empty()) r.errors.push_back(path + ": the file records no dynamic obstacle");
    return r;
}

Recording read_interaction(const std::string& csv_path, const std::string& map_path) {
    std::string text;
    if (!read_file(csv_path, text)) return unreadable(csv_path);
    Recording r = parse_interaction(text, csv_path);
    r.map_path = map_path;
    if (map_path.empty()) r.errors.push_back(csv_path + ": an INTERACTION track file needs its Lanelet2 map (--map)");
    return r;
}

Recording parse_interaction(const std::string& csv, const std::string& path) {
    Recording r;
    r.path = path;
    r.format = "interaction";
    std::istringstream in(csv);
    std::string line;
    int lineno = 0;
    std::vector<std::string> header;
    std::map<std::string, size_t> col;
    auto split = [](const std::string& s) {
        std::vector<std::string> out;
        std::string cell;
        for (char ch : s) {
            if (ch == ',') {
                out.push_back(cell);
                cell.clear();
            } else if (ch != '\r' && ch != '"') {
                cell += ch;
            }
        }
        out.push_back(cell);
        return out;
    };
    std::map<std::string, size_t> index;  // track id → r.tracks
    double t0 = NAN;
    size_t states = 0;
    while (std::getline(in, line)) {
        ++lineno;
        const std::string where = path + ":" + std::to_string(lineno) + ": ";
        if (line.empty() || line == "\r") continue;
        auto cells = split(line);
        if (header.empty()) {
            header = cells;
            for (size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
            for (const char* need : {"track_id", "timestamp_ms", "x", "y", "vx", "vy"}) {
                if (!col.count(need)) {
                    r.errors.push_back(where + "the header has no column '" + need +
                                       "' (expected track_id,frame_id,timestamp_ms,agent_type,x,y,vx,vy,psi_rad,length,width)");
                    return r;
                }
            }
            continue;
        }
        if (cells.size() != header.size()) {
            r.errors.push_back(where + "expected " + std::to_string(header.size()) + " cells, found " + std::to_string(cells.size()));
            if (r.errors.size() >= 20) return r;
            continue;
        }
        auto num = [&](const char* name) -> std::optional<double> {
            auto it = col.find(name);
            if (it == col.end()) return std::nullopt;
            return number(cells[it->second].c_str());
        };
        const std::string id = cells[col["track_id"]];
        const auto ms = num("timestamp_ms"), x = num("x"), y = num("y"), vx = num("vx"), vy = num("vy");
        if (id.empty() || !ms || !x || !y || !vx || !vy) {
            r.errors.push_back(where + "track_id, timestamp_ms, x, y, vx and vy must be given and numeric");
            if (r.errors.size() >= 20) return r;
            continue;
        }
        if (std::fabs(*x) > kMaxCoordinate || std::fabs(*y) > kMaxCoordinate || std::fabs(*ms) > kMaxTime * 1000 ||
            std::fabs(*vx) > 1000 || std::fabs(*vy) > 1000) {
            r.errors.push_back(where + "a value beyond the limits (1,000 km, 10^6 s, 1,000 m/s)");
            if (r.errors.size() >= 20) return r;
            continue;
        }
        if (std::isnan(t0)) t0 = *ms;
        // A track is kept with its first state that is read: a row refused for its values adds
        // no track (a track always has states).
        auto it = index.find(id);
        Track added;
        if (it == index.end()) {
            if (r.tracks.size() >= kMaxTracks) {
                r.errors.push_back(where + "more than " + std::to_string(kMaxTracks) + " tracks");
                return r;
            }
            added.id = id;
            added.type = col.count("agent_type") ? cells[col["agent_type"]] : "car";
            if (added.type.empty()) added.type = "car";
            if (added.pedestrian()) added.length = added.width = 0.5;
            // INTERACTION leaves length and width empty for pedestrians and bicycles: the defaults.
            const catalog::AgentSize max = added.pedestrian() ? catalog::kMaxPedestrianSize : catalog::kMaxVehicleSize;
            const auto l = num("length"), w = num("width");
            if ((l && !(*l > 0 && *l <= max.length)) || (w && !(*w > 0 && *w <= max.width))) {
                r.errors.push_back(where + "track " + id + ": length and width must be in (0, " + format_number(max.length) + "] m and (0, " +
                                   format_number(max.width) + "] m, the size of " + (added.pedestrian() ? "a pedestrian" : "a vehicle") +
                                   " (" + added.type + ")");
                if (r.errors.size() >= 20) return r;
                continue;
            }
            if (l) added.length = *l;
            if (w) added.width = *w;
        }
        const Track& tr = it == index.end() ? added : r.tracks[it->second];
        State s;
        s.t = (*ms - t0) / 1000.0;
        s.x = *x;
        s.y = *y;
        s.speed = std::hypot(*vx, *vy);
        if (!tr.pedestrian() && s.speed > catalog::kMaxVehicleSpeed) {
            r.errors.push_back(where + "track " + id + ": speed " + format_number(s.speed) + " m/s (vx, vy) is not a vehicle's, 0 to " +
                               format_number(catalog::kMaxVehicleSpeed) + " m/s");
            if (r.errors.size() >= 20) return r;
            continue;
        }
        const auto psi = num("psi_rad");
        s.heading = psi ? *psi : (s.speed > 0.1 ? std::atan2(*vy, *vx) : tr.states.empty() ? 0 : tr.states.back().heading);
        if (!tr.states.empty() && s.t <= tr.states.back().t) {
            r.errors.push_back(where + "track " + id + ": timestamps must increase along a track");
            if (r.errors.size() >= 20) return r;
            continue;
        }
        if (++states > kMaxStates * 10) {
            r.errors.push_back(where + "more than " + std::to_string(kMaxStates * 10) + " states");
            return r;
        }
        if (it == index.end()) {
            it = index.emplace(id, r.tracks.size()).first;
            r.tracks.push_back(std::move(added));
        }
        r.tracks[it->second].states.push_back(s);
    }
    // Time steps: the most common difference between consecutive states.
    std::map<long long, int> steps;
    for (const auto& tr : r.tracks)
        for (size_t i = 1; i < tr.states.size(); ++i)
            ++steps[std::llround((tr.states[i].t - tr.states[i - 1].t) * 1000)];
    if (!steps.empty()) {
        const auto best = std::max_element(steps.begin(), steps.end(), [](auto& a, auto& b) { return a.second < b.second; });
        if (best->first > 0) r.dt = static_cast<double>(best->first) / 1000.0;
    }
    if (header.empty()) r.errors.push_back(path + ": the file is empty");
    else if (r.tracks.empty() && r.errors.empty()) r.errors.push_back(path + ": the file has no track");
    return r;
}

Recording read_recording(const std::string& path, const std::string& map_path) {
    std::string text;
    if (!read_file(path, text)) return unreadable(path);
    if (road::is_commonroad(text)) {
        Recording r = parse_commonroad(text, path);
        if (!map_path.empty()) r.map_path = map_path;
        return r;
    }
    Recording r = parse_interaction(text, path);
    r.map_path = map_path;
    if (map_path.empty()) r.errors.push_back(path + ": an INTERACTION track file needs its Lanelet2 map (--map)");
    return r;
}

}  // namespace sdv::realism
