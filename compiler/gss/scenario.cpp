// GeoScenario 2.0 reading (pugixml; byte offsets of elements become diagnostic locations) and
// conversion to .sdv text.
#include "compiler/gss/scenario.h"

#include "compiler/gss/lower.h"
#include "compiler/syntax/format.h"
#include "runtime/catalog/catalog.h"
#include "runtime/road/lanelet2_reader.h"
#include "runtime/road/reader_text.h"
#include "runtime/road/routing.h"

#include <pugixml.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace sdv::compiler::gss {
namespace fs = std::filesystem;
using syntax::comment_text;
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    std::string s = buf;
    if (s.find('.') != std::string::npos) {
        while (s.back() == '0') s.pop_back();
        if (s.back() == '.') s.pop_back();
    }
    if (s == "-0") s = "0";
    return s;
}

// An identifier of the .sdv grammar from any text, in one pass: letters and digits lowered, every run
// of other characters one `_`, none at either end.
std::string ident(const std::string& raw, const std::string& fallback) {
    std::string s;
    s.reserve(raw.size());
    bool gap = false;
    for (char c : raw) {
        const auto u = static_cast<unsigned char>(c);
        if (!std::isalnum(u)) {
            gap = true;
            continue;
        }
        if (gap && !s.empty()) s += '_';
        gap = false;
        s += static_cast<char>(std::tolower(u));
    }
    if (s.empty()) s = fallback;
    if (std::isdigit(static_cast<unsigned char>(s[0]))) s = fallback + "_" + s;
    return s;
}

// A light's name as the .sdv grammar reads it: names of letters, digits and `_` joined by '.'.
bool is_qualified_name(const std::string& s) {
    if (s.empty() || s.front() == '.' || s.back() == '.' || s.find("..") != std::string::npos) return false;
    bool start = true;
    for (char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '.') {
            start = true;
        } else if (std::isalpha(u) || c == '_' || (!start && std::isdigit(u))) {
            start = false;
        } else {
            return false;
        }
    }
    return true;
}

// Reads one file's elements; every message names the element and points at it.
class Reader {
public:
    Reader(diag::FileId file, const diag::SourceManager& sm, diag::DiagnosticEngine& diags)
        : file_(file), text_(sm.contents(file)), diags_(diags) {}

    std::optional<GsScenario> read() {
        pugi::xml_document doc;
        const auto parsed = doc.load_buffer(text_.data(), text_.size(), pugi::parse_default);
        if (!parsed) {
            // pugixml reports an input that ends too early one byte past its end.
            const auto at = static_cast<uint32_t>(std::clamp<ptrdiff_t>(parsed.offset, 0, static_cast<ptrdiff_t>(text_.size())));
            diags_.error("E0910", {{file_, at}, {file_, at}}, std::string("not a valid XML file: ") + parsed.description());
            return std::nullopt;
        }
        const auto osm = doc.child("osm");
        if (!osm) {
            diags_.error("E0910", {{file_, 0}, {file_, 0}}, "not a GeoScenario file: no <osm> element");
            return std::nullopt;
        }
        GsScenario sc;
        std::map<long long, GeoPoint> nodes;
        bool have_config = false;
        for (auto n : osm.children("node")) {
            GeoPoint p;
            p.range = range(n);
            // A number and nothing more: pugixml's as_double reads "8.:5461" as 8 (the node
            // moves tens of kilometres without a word).
            const auto lat = road::parse_number(n.attribute("lat").as_string());
            const auto lon = road::parse_number(n.attribute("lon").as_string());
            p.lat = lat.value_or(NAN);
            p.lon = lon.value_or(NAN);
            const long long id = n.attribute("id").as_llong(0);
            node_elems_.emplace(id, n);  // the first node of an id, as node_tags found it
            if (!lat || !lon) {
                const char* key = !lat ? "lat" : "lon";
                diags_.error("E0911", p.range, "node " + std::to_string(id) + ": " + key + " '" +
                                                   n.attribute(key).as_string() + "' is not a number");
                continue;
            }
            if (std::fabs(p.lat) > 90 || std::fabs(p.lon) > 180) {
                diags_.error("E0911", p.range, "node " + std::to_string(id) + ": invalid lat/lon");
                continue;
            }
            nodes[id] = p;
            const auto tags = read_tags(n);
            auto gs = tags.find("gs");
            if (gs == tags.end()) continue;
            const std::string what = gs->second.value;
            if (what == "globalconfig") {
                have_config = true;
                read_config(n, tags, sc);
            } else if (what == "origin") {
                sc.origin = p;
                sc.has_origin = true;
                if (auto a = tags.find("altitude"); a != tags.end()) {
                    const auto alt = number(a->second, "origin", "altitude");
                    if (alt && (*alt < catalog::kMinAltitude || *alt > catalog::kMaxAltitude)) {
                        diags_.error("E0911", a->second.range, "origin: tag 'altitude' must be in [" + catalog::format_number(catalog::kMinAltitude) +
                                                                    ", " + catalog::format_number(catalog::kMaxAltitude) + "] m (" + a->second.value + ")");
                    }
                    sc.origin_alt = alt.value_or(0);
                }
            } else if (what == "vehicle") {
                read_vehicle(n, tags, p, sc);
            } else if (what == "pedestrian") {
                read_pedestrian(n, tags, p, sc);
            } else if (what == "location") {
                // A named point (an SP's destination). The reference reads node locations only.
                if (auto name = text(tags, "name")) {
                    sc.locations[*name] = p;
                } else {
                    diags_.error("E0911", p.range, "location node " + std::to_string(id) + " without a 'name' tag");
                }
            } else if (what == "trafficlight") {
                read_light(n, tags, sc);
            } else if (what == "staticobject") {
                GsObject o;
                o.name = text(tags, "name").value_or("object" + std::to_string(sc.objects.size() + 1));
                o.at = p;
                o.range = p.range;
                const std::string who = "static object '" + o.name + "'";
                if (auto l = tags.find("length"); l != tags.end()) o.length = size(l->second, who, "length", catalog::kMaxObjectSize.length, "an object").value_or(0.5);
                if (auto w = tags.find("width"); w != tags.end()) o.width = size(w->second, who, "width", catalog::kMaxObjectSize.width, "an object").value_or(0.5);
                sc.objects.push_back(o);
            } else if (what == "egostart") {
                // The reference adds an external vehicle 99, 'Ego', for a client to drive.
                sc.egostart = p;
                if (auto o = tags.find("orientation"); o != tags.end()) sc.ego_orientation = number(o->second, "egostart", "orientation");
            } else if (what == "egogoal" || what == "metric" || what == "trigger") {
                diags_.warning("W0904", "gss-ignored-element", gs->second.range,
                               "node " + std::to_string(id) + ": GeoScenario element '" + what +
                                   "' is ignored, as by the reference (its ScenarioSetup does not read it)");
            } else if (what != "tnode") {
                diags_.error("E0913", gs->second.range, "node " + std::to_string(id) + ": GeoScenario element '" + what +
                                                            "' is not supported by sdv")
                    .notes.push_back({{}, "supported: globalconfig, origin, vehicle (SDV, TV, PV, EV, neutral), pedestrian (SP, TP, PP), "
                                          "location, trafficlight, staticobject, egostart, route, trajectory, path; ignored: "
                                          "egogoal, metric, trigger"});
            }
        }
        for (auto w : osm.children("way")) {
            const auto tags = read_tags(w);
            auto gs = tags.find("gs");
            if (gs == tags.end()) continue;
            const std::string what = gs->second.value;
            const auto name = text(tags, "name");
            if (what != "route" && what != "trajectory" && what != "path" && what != "staticobject" && what != "location") {
                diags_.error("E0913", gs->second.range, "way: GeoScenario element '" + what + "' is not supported by sdv")
                    .notes.push_back({{}, "supported ways: route, trajectory, path, staticobject and location (areas)"});
                continue;
            }
            if (!name) {
                diags_.error("E0911", range(w), what + " way without a 'name' tag");
                continue;
            }
            std::vector<GeoPoint> pts;
            std::vector<GsTnode> tnodes;
            std::vector<GsPathNode> pnodes;
            for (auto nd : w.children("nd")) {
                const long long ref = nd.attribute("ref").as_llong(0);
                auto f = nodes.find(ref);
                if (f == nodes.end()) {
                    diags_.error("E0912", range(nd), what + " '" + *name + "': node " + std::to_string(ref) + " does not exist");
                    continue;
                }
                pts.push_back(f->second);
                if (what == "path") {
                    // The reference's speed profile: agentspeed (km/h) at the node, and
                    // agentacceleration / timetoacceleration (usespeedprofile).
                    GsPathNode pn;
                    pn.at = f->second;
                    const auto ntags = node_tags(ref);
                    const std::string who = "path '" + *name + "', node " + std::to_string(ref);
                    if (auto sp = ntags.find("agentspeed"); sp != ntags.end()) {
                        pn.speed = number(sp->second, who, "agentspeed");
                        // km/h, as the .sdv path point speed writes it (at most 100 m/s).
                        if (pn.speed && (*pn.speed < 0 || *pn.speed > catalog::kMaxWaypointSpeed * 3.6)) {
                            diags_.error("E0911", sp->second.range,
                                         who + ": tag 'agentspeed' must be in [0, " + catalog::format_number(catalog::kMaxWaypointSpeed * 3.6) +
                                             "] km/h (" + sp->second.value + ")");
                            pn.speed.reset();
                        }
                    }
                    pn.accel = ntags.count("agentacceleration") > 0 || ntags.count("timetoacceleration") > 0;
                    pnodes.push_back(pn);
                }
                if (what == "trajectory") {
                    GsTnode t;
                    t.at = f->second;
                    const auto ntags = node_tags(ref);
                    auto time = ntags.find("time");
                    if (time == ntags.end()) {
                        diags_.error("E0911", f->second.range, "trajectory '" + *name + "': node " + std::to_string(ref) +
                                                                   " has no 'time' tag");
                        continue;
                    }
                    // Times as the .sdv trajectory has them: 0 to a day, increasing along the
                    // way (in the milliseconds the converted text writes).
                    const std::string who = "trajectory '" + *name + "', node " + std::to_string(ref);
                    const auto when = number(time->second, who, "time");
                    if (!when) continue;
                    if (*when < 0 || *when > catalog::kMaxScenarioTime) {
                        diags_.error("E0911", time->second.range, who + ": tag 'time' must be in [0, " +
                                                                      catalog::format_number(catalog::kMaxScenarioTime) + "] s (" + time->second.value + ")");
                        continue;
                    }
                    t.time = *when;
                    if (!tnodes.empty() && std::round(t.time * 1000) <= std::round(tnodes.back().time * 1000)) {
                        auto& e = diags_.error("E0911", time->second.range,
                                               who + ": its time (" + catalog::format_number(t.time) + " s) is not after the node before it (" +
                                                   catalog::format_number(tnodes.back().time) + " s)");
                        e.notes.push_back({{}, "a trajectory's times increase along its way, by at least 1 ms"});
                        continue;
                    }
                    if (auto sp = ntags.find("speed"); sp != ntags.end()) {
                        t.speed = number(sp->second, who, "speed");
                        if (t.speed && (*t.speed < 0 || *t.speed > catalog::kMaxWaypointSpeed)) {
                            diags_.error("E0911", sp->second.range, who + ": tag 'speed' must be in [0, " +
                                                                          catalog::format_number(catalog::kMaxWaypointSpeed) + "] m/s (" + sp->second.value + ")");
                            t.speed.reset();
                        }
                    }
                    tnodes.push_back(t);
                }
            }
            if (pts.empty()) {
                diags_.error("E0911", range(w), what + " '" + *name + "' has no nodes");
                continue;
            }
            if (what == "route") sc.routes[*name] = pts;
            else if (what == "path") sc.paths[*name] = pnodes;
            else if (what == "trajectory") sc.trajectories[*name] = tnodes;
            else add_area(what, *name, pts, range(w), sc);
        }
        if (!have_config) diags_.error("E0911", {{file_, 0}, {file_, 0}}, "the scenario has no globalconfig node");
        if (!sc.has_origin) {
            diags_.error("E0911", {{file_, 0}, {file_, 0}}, "the scenario has no origin node")
                .notes.push_back({{}, "GeoScenario places the map frame at a node tagged gs=origin"});
        }
        // References between elements.
        std::set<int> vids;
        for (const auto& v : sc.vehicles) {
            if (!vids.insert(v.vid).second) diags_.error("E0911", v.range, "vehicle id " + std::to_string(v.vid) + " is used twice");
            const std::string who = "vehicle " + std::to_string(v.vid) + (v.name.empty() ? std::string() : " ('" + v.name + "')");
            if (v.btype == "SDV" && !v.route.empty() && !sc.routes.count(v.route)) {
                diags_.error("E0912", v.range, who + ": route '" + v.route + "' is not defined in the scenario");
            }
            if (v.btype == "TV") check_trajectory(sc, v.trajectory, v.range, who);
            if (v.btype == "PV") check_path(sc, v.path, v.has_speed, v.range, who);
        }
        for (const auto& [vid, at] : meet_ranges_) {
            if (!vids.count(vid)) diags_.error("E0912", at, "collision_vehicle_vid: vehicle " + std::to_string(vid) + " is not in the scenario");
        }
        if (sc.egostart && vids.count(99)) {
            diags_.error("E0911", sc.egostart->range, "egostart: the reference makes it vehicle 99, and vehicle 99 exists");
        }
        assign_pids(sc);
        for (const auto& d : sc.pedestrians) {
            const std::string who = "pedestrian " + std::to_string(d.pid) + (d.name.empty() ? std::string() : " ('" + d.name + "')");
            if (d.btype == "TP") check_trajectory(sc, d.trajectory, d.range, who);
            if (d.btype == "PP") check_path(sc, d.path, d.speed.has_value(), d.range, who);
            if (d.btype == "SP") {
                if (!d.route.empty() && !sc.routes.count(d.route)) {
                    diags_.error("E0912", d.range, who + ": route '" + d.route + "' is not defined in the scenario");
                } else if (d.route.empty() && !d.destination.empty() && !sc.locations.count(d.destination)) {
                    diags_.error("E0912", d.range, who + ": location '" + d.destination + "' is not defined in the scenario")
                        .notes.push_back({{}, "a destination is the name of a node tagged gs=location"});
                }
            }
        }
        return sc;
    }

private:
    struct Tag {
        std::string value;
        diag::SourceRange range;
    };
    using Tags = std::map<std::string, Tag>;

    diag::SourceRange range(const pugi::xml_node& n) const {
        const auto at = static_cast<uint32_t>(std::max<ptrdiff_t>(0, n.offset_debug()));
        // offset_debug points at the element name; step back to its '<' and forward to the '>'.
        uint32_t begin = at > 0 && text_[at - 1] == '<' ? at - 1 : at;
        size_t end = text_.find('>', at);
        if (end == std::string_view::npos) end = at;
        return {{file_, begin}, {file_, static_cast<uint32_t>(end + 1)}};
    }

    Tags read_tags(const pugi::xml_node& e) const {
        Tags tags;
        for (auto t : e.children("tag")) tags[t.attribute("k").as_string()] = {t.attribute("v").as_string(), range(t)};
        return tags;
    }

    // The tags of the first node of this id: looked up, not searched for (a search per path
    // node was quadratic in a scenario's nodes).
    Tags node_tags(long long id) const {
        auto f = node_elems_.find(id);
        return f == node_elems_.end() ? Tags{} : read_tags(f->second);
    }

    static std::optional<std::string> text(const Tags& tags, const char* key) {
        auto f = tags.find(key);
        if (f == tags.end() || f->second.value.empty()) return std::nullopt;
        return f->second.value;
    }

    std::optional<double> number(const Tag& t, const std::string& who, const char* key) {
        char* end = nullptr;
        const double v = std::strtod(t.value.c_str(), &end);
        if (end == t.value.c_str() || *end != '\0' || !std::isfinite(v)) {
            diags_.error("E0911", t.range, who + ": tag '" + key + "' is not a number ('" + t.value + "')");
            return std::nullopt;
        }
        return v;
    }

    // An area (a way): a location is its centre (an SP's destination); a static object covers
    // it, as the box of its extent in latitude and longitude (GeoScenario objects are upright
    // boxes). The reference reads node locations and objects only.
    void add_area(const std::string& what, const std::string& name, const std::vector<GeoPoint>& pts, diag::SourceRange at,
                  GsScenario& sc) {
        std::vector<GeoPoint> corners = pts;
        if (corners.size() > 1 && corners.front().lat == corners.back().lat && corners.front().lon == corners.back().lon) corners.pop_back();
        double lat0 = 90, lat1 = -90, lon0 = 180, lon1 = -180;
        for (const auto& p : corners) {
            lat0 = std::min(lat0, p.lat), lat1 = std::max(lat1, p.lat);
            lon0 = std::min(lon0, p.lon), lon1 = std::max(lon1, p.lon);
        }
        GeoPoint c;
        c.lat = 0.5 * (lat0 + lat1);
        c.lon = 0.5 * (lon0 + lon1);
        c.range = at;
        if (what == "location") {
            sc.locations[name] = c;
            return;
        }
        GsObject o;
        o.name = name;
        o.at = c;
        o.range = at;
        o.area = {lat0, lon0, lat1, lon1};
        sc.objects.push_back(o);
    }

    // A comma-separated list of exactly n numbers (start_cartesian, start_frenet).
    std::optional<std::vector<double>> numbers(const Tag& t, const std::string& who, const char* key, size_t n, const char* what) {
        std::vector<double> out;
        std::stringstream ss(t.value);
        std::string item;
        while (std::getline(ss, item, ',')) {
            char* end = nullptr;
            const double v = std::strtod(item.c_str(), &end);
            while (end && (*end == ' ' || *end == '\t')) ++end;
            if (end == item.c_str() || *end != '\0' || !std::isfinite(v)) break;
            out.push_back(v);
        }
        if (out.size() != n || ss.good()) {
            diags_.error("E0911", t.range, who + ": tag '" + key + "' must be " + std::to_string(n) + " numbers: " + what + " ('" +
                                               t.value + "')");
            return std::nullopt;
        }
        return out;
    }

    std::optional<double> positive(const Tag& t, const std::string& who, const char* key) {
        auto v = number(t, who, key);
        if (v && *v <= 0) {
            diags_.error("E0911", t.range, who + ": tag '" + key + "' must be positive");
            return std::nullopt;
        }
        return v;
    }

    // A time the converted text writes in milliseconds: at least 1 ms, at most a day.
    static bool is_duration(double v) { return std::round(v * 1000) >= 1 && v <= catalog::kMaxScenarioTime; }
    std::optional<double> duration(const Tag& t, const std::string& who, const char* key) {
        auto v = number(t, who, key);
        if (v && !is_duration(*v)) {
            diags_.error("E0911", t.range, who + ": tag '" + key + "' must be in [0.001, " + catalog::format_number(catalog::kMaxScenarioTime) +
                                               "] s (" + t.value + ")");
            return std::nullopt;
        }
        return v;
    }

    // A length or width: positive, and at most what the agent may measure (catalog::AgentSize).
    std::optional<double> size(const Tag& t, const std::string& who, const char* key, double max, const char* agent) {
        auto v = positive(t, who, key);
        if (v && *v > max) {
            diags_.error("E0911", t.range, who + ": tag '" + key + "' is " + fixed(*v, 3) + " m, more than " + agent + "'s " +
                                               fixed(max, 3) + " m")
                .notes.push_back({{}, "the sizes an agent may have: docs/catalog.md, Agent sizes"});
            return std::nullopt;
        }
        return v;
    }

    std::optional<bool> yes_no(const Tag& t, const std::string& who, const char* key) {
        if (t.value == "yes" || t.value == "true" || t.value == "1") return true;
        if (t.value == "no" || t.value == "false" || t.value == "0") return false;
        diags_.error("E0911", t.range, who + ": tag '" + key + "' must be yes or no ('" + t.value + "')");
        return std::nullopt;
    }

    void read_config(const pugi::xml_node& n, const Tags& tags, GsScenario& sc) {
        sc.name = text(tags, "name").value_or("");
        if (auto v = tags.find("version"); v != tags.end() && v->second.value.rfind('2', 0) != 0) {
            diags_.error("E0910", v->second.range, "GeoScenario version " + v->second.value + " is not supported (only 2.x)");
        }
        if (auto t = tags.find("timeout"); t != tags.end()) sc.timeout = duration(t->second, "globalconfig", "timeout").value_or(60);
        if (auto c = tags.find("collision"); c != tags.end()) sc.collision = yes_no(c->second, "globalconfig", "collision").value_or(true);
        auto map = tags.find("lanelet");
        if (map == tags.end() || map->second.value.empty()) {
            diags_.error("E0911", range(n), "globalconfig: missing tag 'lanelet' (the map file)");
        } else {
            sc.map = map->second.value;
            sc.map_range = map->second.range;
        }
    }

    void read_vehicle(const pugi::xml_node& n, const Tags& tags, const GeoPoint& p, GsScenario& sc) {
        GsVehicle v;
        v.at = p;
        v.range = range(n);
        v.name = text(tags, "name").value_or("");
        const std::string who0 = "vehicle" + (v.name.empty() ? std::string() : " '" + v.name + "'");
        auto vid = tags.find("vid");
        if (vid == tags.end()) {
            diags_.error("E0911", v.range, who0 + ": missing tag 'vid'");
            return;
        }
        const auto id = number(vid->second, who0, "vid");
        if (!id || *id != std::floor(*id) || *id < 0 || *id > 1e6) {
            if (id) diags_.error("E0911", vid->second.range, who0 + ": 'vid' must be a whole number");
            return;
        }
        v.vid = static_cast<int>(*id);
        const std::string who = "vehicle " + std::to_string(v.vid) + (v.name.empty() ? std::string() : " ('" + v.name + "')");
        v.btype = text(tags, "btype").value_or("");
        for (char& c : v.btype) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        if (v.btype != "SDV" && v.btype != "TV" && v.btype != "PV" && v.btype != "EV") {
            // The reference (ScenarioSetup.py) makes a vehicle of any other type, or none, a
            // neutral one: motionless where it stands, and traffic to everyone else.
            if (!v.btype.empty()) {
                diags_.warning("W0903", "gss-unknown-type", tags.at("btype").range,
                               who + ": vehicle type '" + v.btype + "' is not one GeoScenario knows; as the reference "
                                     "does, sdv makes it a neutral (motionless) vehicle")
                    .notes.push_back({{}, "GeoScenario's vehicle types: SDV, TV, PV, EV; a vehicle without btype is neutral"});
            }
            v.btype = "NV";
        }
        if (auto y = tags.find("yaw"); y != tags.end()) v.yaw = number(y->second, who, "yaw");
        if (auto s = tags.find("speed"); s != tags.end()) {
            v.speed = number(s->second, who, "speed").value_or(0);
            v.has_speed = true;
        }
        if (v.speed < 0) diags_.error("E0911", tags.at("speed").range, who + ": 'speed' must not be negative");
        if (auto l = tags.find("length"); l != tags.end()) v.length = size(l->second, who, "length", catalog::kMaxVehicleSize.length, "a vehicle").value_or(4.5);
        if (auto w = tags.find("width"); w != tags.end()) v.width = size(w->second, who, "width", catalog::kMaxVehicleSize.width, "a vehicle").value_or(1.8);
        if (auto g = tags.find("goal_ends_simulation"); g != tags.end()) {
            v.goal_ends_simulation = yes_no(g->second, who, "goal_ends_simulation").value_or(false);
        }
        if (v.btype == "SDV") {
            // An SDV starts at rest (its speed tag is not read), unless its start state is given
            // in Cartesian (x_vel, x_acc, y_vel, y_acc) or Frenet coordinates (s, s_vel, s_acc,
            // d, d_vel, d_acc, along the first lanelet of its route).
            if (auto c = tags.find("start_cartesian"); c != tags.end()) {
                const auto xs = numbers(c->second, who, "start_cartesian", 4, "x_vel, x_acc, y_vel, y_acc");
                if (xs) v.start_speed = std::hypot((*xs)[0], (*xs)[2]);
            }
            if (auto f = tags.find("start_frenet"); f != tags.end()) {
                if (auto xs = numbers(f->second, who, "start_frenet", 6, "s, s_vel, s_acc, d, d_vel, d_acc")) {
                    v.frenet_s = (*xs)[0];
                    v.frenet_d = (*xs)[3];
                    v.start_speed = (*xs)[1];
                    v.start_frenet = true;
                }
            }
            auto bt = text(tags, "btree");
            auto route = text(tags, "route");
            if (!route) diags_.error("E0911", v.range, who + ": an SDV needs a 'route' tag");
            // Without a btree tag, the reference's standard driver (ScenarioSetup.py).
            v.btree = bt.value_or("st_standard_driver.btree");
            v.btconfig = text(tags, "btconfig").value_or("");
            v.default_btree = !bt;
            v.route = route.value_or("");
            btree_ranges_[v.vid] = bt ? tags.at("btree").range : v.range;
        } else if (v.btype == "TV") {
            auto tr = text(tags, "trajectory");
            if (!tr) diags_.error("E0911", v.range, who + ": a trajectory vehicle (TV) needs a 'trajectory' tag");
            v.trajectory = tr.value_or("");
        } else if (v.btype == "PV") {
            read_path_agent(tags, v.range, who, "path vehicle (PV)", v.path, v.use_speed_profile, v.meet);
        }
        sc.vehicles.push_back(v);
    }

    // (An empty name: the missing tag is reported already.)
    void check_trajectory(const GsScenario& sc, const std::string& name, diag::SourceRange at, const std::string& who) {
        if (name.empty()) return;
        auto t = sc.trajectories.find(name);
        if (t == sc.trajectories.end()) {
            diags_.error("E0912", at, who + ": trajectory '" + name + "' is not defined in the scenario");
        } else if (t->second.size() < 2) {
            diags_.error("E0911", at, who + ": trajectory '" + name + "' needs at least two nodes");
        }
    }

    // A path (PV, PP): at least two distinct nodes, and a speed to start with, the first node's
    // agentspeed or the agent's speed tag (the reference skips the agent without either).
    void check_path(const GsScenario& sc, const std::string& name, bool has_speed, diag::SourceRange at,
                    const std::string& who) {
        if (name.empty()) return;
        auto p = sc.paths.find(name);
        if (p == sc.paths.end()) {
            diags_.error("E0912", at, who + ": path '" + name + "' is not defined in the scenario");
            return;
        }
        double length = 0;
        for (size_t i = 1; i < p->second.size(); ++i) {
            length += std::hypot(p->second[i].at.lat - p->second[i - 1].at.lat, p->second[i].at.lon - p->second[i - 1].at.lon);
        }
        if (p->second.size() < 2 || !(length > 0)) {
            diags_.error("E0911", at, who + ": path '" + name + "' needs at least two distinct nodes");
        }
        if (!p->second.empty() && !p->second.front().speed && !has_speed) {
            diags_.error("E0911", at, who + ": no speed to start with")
                .notes.push_back({{}, "give the agent a 'speed' tag (km/h) or the first node of path '" + name +
                                          "' an 'agentspeed' tag"});
        }
    }

    // Pedestrians without a pid get the smallest ids not taken, in the order of the file (the
    // reference's GSParser).
    void assign_pids(GsScenario& sc) {
        std::set<int> taken;
        for (const auto& d : sc.pedestrians) {
            if (d.pid > 0 && !taken.insert(d.pid).second) {
                diags_.error("E0911", d.range, "pedestrian id " + std::to_string(d.pid) + " is used twice");
            }
        }
        int next = 1;
        for (auto& d : sc.pedestrians) {
            if (d.pid > 0) continue;
            while (taken.count(next)) ++next;
            d.pid = next;
            taken.insert(next);
        }
    }

    void read_pedestrian(const pugi::xml_node& n, const Tags& tags, const GeoPoint& p, GsScenario& sc) {
        GsPedestrian d;
        d.at = p;
        d.range = range(n);
        d.name = text(tags, "name").value_or("");
        const std::string who0 = "pedestrian" + (d.name.empty() ? std::string() : " '" + d.name + "'");
        if (auto pid = tags.find("pid"); pid != tags.end()) {
            const auto id = number(pid->second, who0, "pid");
            if (!id || *id != std::floor(*id) || *id < 1 || *id > 1e6) {
                if (id) diags_.error("E0911", pid->second.range, who0 + ": 'pid' must be a positive whole number");
                return;
            }
            d.pid = static_cast<int>(*id);
        }
        const std::string who = d.pid == 0 ? who0
                                           : "pedestrian " + std::to_string(d.pid) +
                                                 (d.name.empty() ? std::string() : " ('" + d.name + "')");
        d.btype = text(tags, "btype").value_or("PP");
        for (char& c : d.btype) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        if (d.btype != "SP" && d.btype != "TP" && d.btype != "PP") {
            // The reference (ScenarioSetup.py) takes any other type as a path pedestrian.
            auto& e = diags_.warning("W0903", "gss-unknown-type", tags.at("btype").range,
                                     who + ": pedestrian type '" + d.btype + "' is not one GeoScenario knows; "
                                           "as the reference does, sdv makes it a path pedestrian (PP)");
            e.notes.push_back({{}, "GeoScenario's pedestrian types: SP (simulated), TP (trajectory), PP (path)"});
            d.btype = "PP";
        }
        if (auto l = tags.find("length"); l != tags.end()) d.length = size(l->second, who, "length", catalog::kMaxPedestrianSize.length, "a pedestrian").value_or(d.length);
        if (auto w = tags.find("width"); w != tags.end()) d.width = size(w->second, who, "width", catalog::kMaxPedestrianSize.width, "a pedestrian").value_or(d.width);
        d.has_speed = tags.count("speed") > 0;
        if (d.btype == "SP") {
            // The reference's SP walks to the last node of its route, else to its destination;
            // its speed tag is not read (it walks at its desired speed).
            d.route = text(tags, "route").value_or("");
            d.destination = text(tags, "destination").value_or("");
            if (d.route.empty() && d.destination.empty()) {
                diags_.error("E0911", d.range, who + ": a simulated pedestrian (SP) needs a 'destination' or a 'route' tag");
            }
            d.btree = text(tags, "btree").value_or("");
            d.btree_range = tags.count("btree") ? tags.at("btree").range : d.range;
        } else if (d.btype == "TP") {
            d.trajectory = text(tags, "trajectory").value_or("");
            if (d.trajectory.empty()) diags_.error("E0911", d.range, who + ": a trajectory pedestrian (TP) needs a 'trajectory' tag");
        } else {
            read_path_agent(tags, d.range, who, "path pedestrian (PP, without btype)", d.path, d.use_speed_profile, d.meet);
            if (auto s = tags.find("speed"); s != tags.end()) {
                d.speed = number(s->second, who, "speed");
                if (d.speed && (*d.speed < 0 || *d.speed > 36)) {
                    diags_.error("E0911", s->second.range, who + ": 'speed' must be 0 to 36 (km/h)");
                    d.speed.reset();
                }
            }
        }
        sc.pedestrians.push_back(d);
    }

    // The tags of a path agent (PV, PP) besides its speed.
    void read_path_agent(const Tags& tags, diag::SourceRange at, const std::string& who, const std::string& kind,
                         std::string& path, bool& use_speed_profile, std::optional<int>& meet) {
        path = text(tags, "path").value_or("");
        if (path.empty()) diags_.error("E0911", at, who + ": a " + kind + " needs a 'path' tag");
        if (auto u = tags.find("usespeedprofile"); u != tags.end()) {
            use_speed_profile = yes_no(u->second, who, "usespeedprofile").value_or(false);
        }
        if (auto c = tags.find("collision_vehicle_vid"); c != tags.end()) {
            // The reference's ensured collision: timed to meet that vehicle (`meet v<vid>`).
            const auto id = number(c->second, who, "collision_vehicle_vid");
            if (id && *id == -1) {
                // -1: none (the default of the reference's MKeepInLaneConfig)
            } else if (id && (*id != std::floor(*id) || *id < 0 || *id > 1e6)) {
                diags_.error("E0911", c->second.range, who + ": 'collision_vehicle_vid' must be a vehicle id");
            } else if (id) {
                meet = static_cast<int>(*id);
                meet_ranges_.push_back({*meet, c->second.range});
            }
        }
    }

    void read_light(const pugi::xml_node& n, const Tags& tags, GsScenario& sc) {
        GsLight l;
        l.range = range(n);
        l.name = text(tags, "name").value_or("");
        if (l.name.empty()) {
            diags_.error("E0911", l.range, "trafficlight without a 'name' tag (it must match a light of the map)");
            return;
        }
        if (!is_qualified_name(l.name)) {
            diags_.error("E0911", l.range, "trafficlight name '" + comment_text(l.name) + "' is not a name a scenario can refer to")
                .notes.push_back({{}, "a light's name is letters, digits and '_' (not first), parts joined by '.', as in the map"});
            return;
        }
        const std::string who = "trafficlight '" + l.name + "'";
        auto states = tags.find("states");
        auto durations = tags.find("duration");
        if (states == tags.end() || durations == tags.end()) {
            diags_.error("E0911", l.range, who + ": needs 'states' and 'duration' tags");
            return;
        }
        std::stringstream ss(states->second.value);
        for (std::string s; std::getline(ss, s, ',');) {
            s.erase(0, s.find_first_not_of(' '));
            s.erase(s.find_last_not_of(' ') + 1);
            if (s != "G" && s != "Y" && s != "R" && s != "g" && s != "y" && s != "r") {
                diags_.error("E0911", states->second.range, who + ": unknown light state '" + s + "'")
                    .notes.push_back({{}, "states are G, Y or R, separated by commas"});
                return;
            }
            l.states.push_back(std::string(1, static_cast<char>(std::toupper(static_cast<unsigned char>(s[0])))));
        }
        std::stringstream ds(durations->second.value);
        for (std::string s; std::getline(ds, s, ',');) {
            char* end = nullptr;
            const double d = std::strtod(s.c_str(), &end);
            if (end == s.c_str() || !std::isfinite(d) || !is_duration(d)) {
                diags_.error("E0911", durations->second.range,
                             who + ": duration '" + s + "' is not a number of seconds in [0.001, " + catalog::format_number(catalog::kMaxScenarioTime) + "]");
                return;
            }
            l.durations.push_back(d);
        }
        if (l.states.size() != l.durations.size() || l.states.empty()) {
            diags_.error("E0911", durations->second.range,
                         who + ": " + std::to_string(l.states.size()) + " states but " + std::to_string(l.durations.size()) + " durations");
            return;
        }
        sc.lights.push_back(l);
    }

public:
    std::map<int, diag::SourceRange> btree_ranges_;
    std::vector<std::pair<int, diag::SourceRange>> meet_ranges_;  // collision_vehicle_vid tags

private:
    diag::FileId file_;
    std::string_view text_;
    diag::DiagnosticEngine& diags_;
    std::map<long long, pugi::xml_node> node_elems_;
};

// A GeoScenario yaw (degrees, clockwise: follow.gs.osm's 310 faces north-east) as a heading
// (degrees, counter-clockwise from east) in (-180, 180].
double heading_of_yaw(double yaw) {
    double h = std::fmod(-yaw, 360.0);
    if (h <= -180) h += 360;
    if (h > 180) h -= 360;
    return h;
}

std::string relative_to(const fs::path& p, const std::string& dir) {
    std::error_code ec;
    const fs::path abs = fs::weakly_canonical(p, ec);
    if (dir.empty()) return abs.string();
    const fs::path base = fs::weakly_canonical(dir, ec);
    fs::path rel = abs.lexically_relative(base);
    return rel.empty() ? abs.string() : rel.string();
}

// A name or path as a .sdv string literal.
std::string quoted(const std::string& s) { return syntax::string_literal(s); }

}  // namespace

bool is_btree_path(const std::string& path) { return fs::path(path).extension() == ".btree"; }

bool is_geoscenario_path(const std::string& path) { return fs::path(path).extension() == ".osm"; }

std::optional<GsScenario> read_geoscenario(diag::FileId file, const diag::SourceManager& sm, diag::DiagnosticEngine& diags) {
    const size_t before = diags.error_count();
    Reader r(file, sm, diags);
    auto sc = r.read();
    if (!sc || diags.error_count() > before) return std::nullopt;
    return sc;
}

std::optional<Converted> convert_btrees(const std::vector<std::string>& paths, const ConvertOptions& options,
                                        diag::SourceManager& sm, diag::DiagnosticEngine& diags) {
    std::vector<std::string> search = options.btree_path;
    for (const auto& p : paths) search.push_back(fs::path(p).parent_path().empty() ? "." : fs::path(p).parent_path().string());
    BtreeLibrary lib(search, sm, diags);
    bool ok = true;
    for (const auto& p : paths) ok = lib.add_file(p).has_value() && ok;
    if (!ok) return std::nullopt;
    return Converted{lib.text(), lib.files()};
}

std::optional<Converted> convert_geoscenario(const std::string& path, const ConvertOptions& options,
                                             diag::SourceManager& sm, diag::DiagnosticEngine& diags) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        diags.error("E0006", {}, "cannot read file '" + path + "'");
        return std::nullopt;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    const diag::FileId file = sm.add_file(path, ss.str());
    const size_t before = diags.error_count();
    Reader reader(file, sm, diags);
    auto sc = reader.read();
    if (!sc || diags.error_count() > before) return std::nullopt;

    // The map: --map-dir directories first, then the scenario's directory and its parents
    // (GeoScenario writes it relative to the scenario collection's root).
    std::vector<fs::path> tried;
    std::optional<fs::path> map;
    std::error_code ec;
    std::vector<fs::path> bases;
    for (const auto& d : options.map_dirs) bases.emplace_back(d);
    for (fs::path d = fs::absolute(path, ec).parent_path(); !d.empty(); d = d.parent_path()) {
        bases.push_back(d);
        if (d == d.parent_path()) break;
    }
    for (const auto& b : bases) {
        for (const fs::path& cand : {b / sc->map, b / fs::path(sc->map).filename()}) {
            tried.push_back(cand);
            if (fs::is_regular_file(cand, ec)) {
                map = cand;
                break;
            }
        }
        if (map) break;
    }
    if (!map) {
        auto& d = diags.error("E0912", sc->map_range, "map '" + sc->map + "' not found");
        d.notes.push_back({{}, "looked in the --map-dir directories, then beside the scenario and in its parent directories"});
        d.notes.push_back({{}, "give the directory holding it with --map-dir DIR"});
        return std::nullopt;
    }
    if (!syntax::fits_string_literal(relative_to(*map, options.out_dir))) {
        diags.error("E0911", sc->map_range, "map '" + comment_text(map->string()) + "': its path is not valid UTF-8 or has a line break, so .sdv text cannot name it")
            .notes.push_back({{}, "rename the map file, or the directories of its path"});
        return std::nullopt;
    }

    // Trees: --btree-path directories first, then the scenario's directory, then the
    // reference's layout (its trees in btrees/sdv and btrees/sp of the collection's root, which
    // holds scenarios/ and maps/): each btrees/ directory in the scenario's directory and its
    // parents.
    std::vector<std::string> search = options.btree_path;
    search.push_back(fs::absolute(path, ec).parent_path().string());
    for (size_t k = options.map_dirs.size(); k < bases.size(); ++k) {
        if (fs::is_directory(bases[k] / "btrees", ec)) search.push_back((bases[k] / "btrees").string());
    }
    BtreeLibrary lib(search, sm, diags);
    std::map<int, std::string> tree_of, ped_tree_of, call_of;
    for (const auto& v : sc->vehicles) {
        if (v.btype != "SDV") continue;
        auto name = lib.add_named(v.btree, reader.btree_ranges_[v.vid], BtAgent::vehicle);
        if (name && !v.btconfig.empty()) {
            // btconfig: the reference reconfigures the tree's nodes (BTreeInterpreter.reconfigure_nodes).
            auto call = lib.call_with_config(v.btree, v.btconfig, path + ": vehicle " + std::to_string(v.vid) + " btconfig",
                                             reader.btree_ranges_[v.vid], BtAgent::vehicle);
            if (call) call_of[v.vid] = *call;
        }
        if (name && lib.agent(*name) == BtAgent::pedestrian) {
            diags.error("E0911", reader.btree_ranges_[v.vid], "vehicle " + std::to_string(v.vid) + ": '" + v.btree +
                                                                  "' is a pedestrian's behavior tree")
                .notes.push_back({{}, "its maneuvers and conditions are the reference's pedestrian ones (btrees/sp)"});
        }
        if (name) tree_of[v.vid] = *name;
    }
    for (const auto& d : sc->pedestrians) {
        if (d.btype != "SP") continue;
        // Without a btree tag, the reference's default pedestrian tree (ScenarioSetup.py).
        const std::string tree_file = d.btree.empty() ? "walk.btree" : d.btree;
        auto name = lib.add_named(tree_file, d.btree_range, BtAgent::pedestrian);
        if (name && lib.agent(*name) == BtAgent::vehicle) {
            diags.error("E0911", d.btree_range, "pedestrian " + std::to_string(d.pid) + ": '" + tree_file +
                                                    "' is a vehicle's behavior tree")
                .notes.push_back({{}, "its maneuvers and conditions are the reference's vehicle ones (btrees/sdv); "
                                      "pedestrian trees are in btrees/sp"});
        }
        if (name) ped_tree_of[d.pid] = *name;
    }
    if (diags.error_count() > before) return std::nullopt;

    const road::GeoOrigin origin{sc->origin.lat, sc->origin.lon, sc->origin_alt};
    auto xy = [&](const GeoPoint& p) {
        const road::Vec2 q = road::project(origin, p.lat, p.lon);
        return "(" + fixed(q.x, 3) + " m, " + fixed(q.y, 3) + " m)";
    };
    auto heading = [&](const GeoPoint& a, const GeoPoint& b) {
        const road::Vec2 p = road::project(origin, a.lat, a.lon), q = road::project(origin, b.lat, b.lon);
        return fixed(std::atan2(q.y - p.y, q.x - p.x) * 180.0 / kPi, 2) + " deg";
    };

    // The route's intermediate nodes, as the lanelets they lie in (direction from the node before
    // to the node after): the route passes through them in order, as the reference's does. The
    // map is read here only for that; a map that fails to load is reported when the scenario runs.
    std::optional<road::LoadResult> map_net;
    auto via_lanes = [&](const std::vector<GeoPoint>& route) {
        std::vector<std::string> lanes;
        if (route.size() < 3) return lanes;
        if (!map_net) map_net = road::load_lanelet2(*map, origin);
        if (!map_net->errors.empty() || !map_net->network) return lanes;
        for (size_t i = 1; i + 1 < route.size(); ++i) {
            const road::Vec2 p = road::project(origin, route[i].lat, route[i].lon);
            const road::Vec2 a = road::project(origin, route[i - 1].lat, route[i - 1].lon);
            const road::Vec2 b = road::project(origin, route[i + 1].lat, route[i + 1].lon);
            const auto loc = map_net->network->locate(p, std::atan2(b.y - a.y, b.x - a.x));
            if (loc.lane == road::kNoLane) continue;
            const std::string& name = map_net->network->lane(loc.lane).name;
            if (lanes.empty() || lanes.back() != name) lanes.push_back(name);
        }
        return lanes;
    };

    // start_frenet: s along the route's first lanelet (the one the vehicle's node is on), and
    // on along the route past its end; d across it (left positive). nullopt: reported.
    auto frenet_start = [&](const GsVehicle& v, const std::vector<GeoPoint>& route) -> std::optional<std::string> {
        if (!map_net) map_net = road::load_lanelet2(*map, origin);
        if (!map_net->errors.empty() || !map_net->network) return std::nullopt;  // reported when the scenario runs
        const road::RoadNetwork& net = *map_net->network;
        const road::Vec2 p = road::project(origin, v.at.lat, v.at.lon);
        const road::Vec2 q = road::project(origin, route.front().lat, route.front().lon);
        const road::Vec2 g = road::project(origin, route.back().lat, route.back().lon);
        const road::Vec2 prev = road::project(origin, (route.size() >= 2 ? route[route.size() - 2] : v.at).lat,
                                                (route.size() >= 2 ? route[route.size() - 2] : v.at).lon);
        const auto loc = net.locate(p, std::atan2(q.y - p.y, q.x - p.x));
        const auto goal = net.locate(g, std::atan2(g.y - prev.y, g.x - prev.x));
        if (loc.lane == road::kNoLane) {
            diags.error("E0911", reader.btree_ranges_[v.vid], "vehicle " + std::to_string(v.vid) +
                                                                  ": start_frenet is along the lanelet of the vehicle's node, and it is on none");
            return std::nullopt;
        }
        road::LaneId lane = loc.lane;
        double s = v.frenet_s;
        const auto steps = goal.lane != road::kNoLane ? road::shortest_route(net, lane, goal.lane).steps : std::vector<road::RouteStep>{};
        for (size_t i = 1; s > net.reference(lane).length() && i < steps.size(); ++i) {
            s -= net.reference(lane).length();
            lane = steps[i].lane;
        }
        return "lane " + quoted(net.lane(lane).name) + " at " + fixed(s, 3) + " m offset " + fixed(v.frenet_d, 3) + " m";
    };

    const std::string stem = fs::path(path).filename().string().substr(0, fs::path(path).filename().string().find('.'));
    const std::string scen = ident(stem, "scenario");
    std::ostringstream out;
    out << "# Converted by `sdv convert` from " << comment_text(fs::path(path).filename().string()) << " (GeoScenario "
        << "2.0): \"" << comment_text(sc->name) << "\".\n"
        << "# Vehicles are named v<vid>, the ids the behavior trees use.\n"
        << (sc->pedestrians.empty() ? "" : "# Pedestrians are named p<pid>.\n") << "\n";
    out << lib.text();
    out << "map gs_map {\n    file " << quoted(relative_to(*map, options.out_dir)) << "\n    origin (" << fixed(sc->origin.lat, 11)
        << ", " << fixed(sc->origin.lon, 11) << ", " << fixed(sc->origin_alt, 3) << " m)\n}\n\n";
    out << "scenario " << scen << " {\n    road gs_map\n    timeout " << fixed(sc->timeout, 3) << " s\n";
    // The reference's rates (SimConfig.py: TRAFFIC_RATE, PLANNER_RATE, PLANNING_TIME): outcomes
    // near a threshold, and the tick keys of violations.json, depend on them.
    out << "    rate traffic 40 Hz\n    rate planning 5 Hz\n    rate latency 200 ms\n";
    // A path agent (PV, PP) moves along its path at the speed of its nodes (agentspeed, km/h),
    // interpolated in the distance travelled, from the first node on (Actor.follow_path); a node
    // without one keeps the speed before it; the first, the agent's speed tag.
    auto write_path = [&](const std::vector<GsPathNode>& nodes, bool use_speed_profile, std::optional<int> meet) {
        bool accel = false, speeds = false;
        for (const auto& n : nodes) {
            accel = accel || n.accel;
            speeds = speeds || n.speed.has_value();
        }
        if (meet) {
            // collision_vehicle_vid: timed to meet the vehicle, unless its nodes give speeds,
            // which the reference's follow_path applies after the timing (so they win).
            if (speeds) {
                out << "        # collision_vehicle_vid " << *meet << ": its nodes' speeds win over the timing, as in the reference\n";
            } else {
                out << "        meet v" << *meet << "\n";
            }
        }
        if (use_speed_profile && accel) {
            out << "        # usespeedprofile: the speeds at the nodes (agentspeed) are interpolated along the path;\n"
                << "        # agentacceleration and timetoacceleration are not read\n";
        }
        out << "        path {\n";
        for (const auto& n : nodes) {
            out << "            at " << xy(n.at);
            if (n.speed) out << " speed " << fixed(*n.speed, 3) << " km/h";
            out << "\n";
        }
        out << "        }\n";
    };
    // Time-stamped positions (TV, TP), linear between them, at rest after the last.
    auto write_trajectory = [&](const std::vector<GsTnode>& tn) {
        out << "        trajectory {\n";
        for (size_t i = 0; i < tn.size(); ++i) {
            const GeoPoint& next = i + 1 < tn.size() ? tn[i + 1].at : tn[i].at;
            const GeoPoint& prev = i + 1 < tn.size() ? tn[i].at : (i > 0 ? tn[i - 1].at : tn[i].at);
            out << "            " << fixed(tn[i].time, 3) << " s: at " << xy(tn[i].at) << " heading " << heading(prev, next);
            if (tn[i].speed) out << " speed " << fixed(*tn[i].speed, 3) << " m/s";
            out << "\n";
        }
        out << "        }\n";
    };
    std::vector<std::string> goal_vehicles, all_sdv_goals;
    for (const auto& v : sc->vehicles) {
        const std::string name = "v" + std::to_string(v.vid);
        out << "    # " << name << (v.name.empty() ? "" : " '" + comment_text(v.name) + "'") << "\n";
        if (v.btype == "SDV") {
            const auto& route = sc->routes.at(v.route);
            const GeoPoint& goal = route.back();
            const GeoPoint& from = route.size() >= 2 ? route[route.size() - 2] : v.at;
            out << "    vehicle " << name << ": sdv {\n";
            if (v.default_btree) out << "        # no btree tag: the reference's default, st_standard_driver.btree\n";
            if (v.has_speed && !v.start_speed) out << "        # its speed tag is not read: the reference's SDV starts at rest\n";
            std::optional<std::string> frenet;
            if (v.start_frenet) frenet = frenet_start(v, route);
            if (frenet) {
                out << "        # start_frenet: along the first lanelet of its route\n        start " << *frenet << "\n";
            } else {
                out << "        start at " << xy(v.at) << " heading " << heading(route.size() >= 2 ? route[0] : v.at, route.size() >= 2 ? route[1] : goal) << "\n";
            }
            out << "        speed " << fixed(v.start_speed.value_or(0), 3) << " m/s\n";
            if (v.length != 4.5) out << "        length " << fixed(v.length, 3) << " m\n";
            if (v.width != 1.8) out << "        width " << fixed(v.width, 3) << " m\n";
            if (const auto via = via_lanes(route); !via.empty()) {
                out << "        route ";
                for (size_t i = 0; i < via.size(); ++i) out << (i ? ", " : "") << "lane " << quoted(via[i]);
                out << "\n";
            }
            out << "        goal at " << xy(goal) << " heading " << heading(from, goal) << (v.goal_ends_simulation ? " ends run" : "") << "\n";
            if (call_of.count(v.vid)) out << "        # btconfig: " << comment_text(v.btconfig) << "\n";
            out << "        tree " << (call_of.count(v.vid) ? call_of.at(v.vid) : tree_of.at(v.vid) + "()") << "\n    }\n";
            all_sdv_goals.push_back(name);
            if (v.goal_ends_simulation) goal_vehicles.push_back(name);
        } else if (v.btype == "PV") {
            out << "    vehicle " << name << ": path {\n";
            if (v.goal_ends_simulation) out << "        # goal_ends_simulation: the reference reads it for SDVs only\n";
            if (v.has_speed) out << "        speed " << fixed(v.speed, 3) << " km/h\n";
            if (v.length != 4.5) out << "        length " << fixed(v.length, 3) << " m\n";
            if (v.width != 1.8) out << "        width " << fixed(v.width, 3) << " m\n";
            write_path(sc->paths.at(v.path), v.use_speed_profile, v.meet);
            out << "    }\n";
        } else if (v.btype == "NV") {
            // Neutral: where it stands, facing -yaw (else along its lane), for good.
            out << "    vehicle " << name << ": static {\n";
            out << "        start at " << xy(v.at);
            if (v.yaw) out << " heading " << fixed(heading_of_yaw(*v.yaw), 2) << " deg";
            out << "\n";
            if (v.length != 4.5) out << "        length " << fixed(v.length, 3) << " m\n";
            if (v.width != 1.8) out << "        width " << fixed(v.width, 3) << " m\n";
            out << "    }\n";
        } else if (v.btype == "EV") {
            // Where it starts; from then on its co-simulation client sets its state.
            out << "    vehicle " << name << ": external {\n";
            out << "        start at " << xy(v.at) << "\n";
            out << "        speed " << fixed(v.speed, 3) << " m/s\n";
            if (v.length != 4.5) out << "        length " << fixed(v.length, 3) << " m\n";
            if (v.width != 1.8) out << "        width " << fixed(v.width, 3) << " m\n";
            out << "    }\n";
        } else {
            const auto& tn = sc->trajectories.at(v.trajectory);
            out << "    vehicle " << name << ": trajectory {\n";
            if (v.length != 4.5) out << "        length " << fixed(v.length, 3) << " m\n";
            if (v.width != 1.8) out << "        width " << fixed(v.width, 3) << " m\n";
            write_trajectory(tn);
            out << "    }\n";
        }
    }
    if (sc->egostart) {
        // The reference's external vehicle for a client to drive (vid 99, 'Ego'); sdv starts it
        // at the egostart node, where the reference's waits at the origin for its client.
        out << "    # egostart: the ego, driven by a co-simulation client (sdv run --cosim ...)\n";
        out << "    ego v99: external {\n        start at " << xy(*sc->egostart);
        if (sc->ego_orientation) out << " heading " << fixed(heading_of_yaw(*sc->ego_orientation), 2) << " deg";
        out << "\n    }\n";
    }
    // Pedestrians are p<pid>, as the reference names them in its outputs.
    for (const auto& d : sc->pedestrians) {
        const std::string name = "p" + std::to_string(d.pid);
        out << "    # " << name << (d.name.empty() ? "" : " '" + comment_text(d.name) + "'") << "\n";
        const std::string kind = d.btype == "SP" ? "sdp" : d.btype == "TP" ? "trajectory" : "path";
        out << "    pedestrian " << name << ": " << kind << " {\n";
        if (d.btype == "SP") {
            // It starts at rest and walks to its goal: the last node of its route, else its
            // destination (the nodes of the route before are not used by the reference either).
            const GeoPoint& goal = d.route.empty() ? sc->locations.at(d.destination) : sc->routes.at(d.route).back();
            if (d.has_speed) out << "        # its speed tag is not read: the reference's SP walks at its desired speed, 2 m/s\n";
            out << "        start at " << xy(d.at) << "\n";
            out << "        goal at " << xy(goal) << "\n";
        } else if (d.btype == "PP" && d.speed) {
            out << "        speed " << fixed(*d.speed, 3) << " km/h\n";
        }
        out << "        length " << fixed(d.length, 3) << " m\n";
        out << "        width " << fixed(d.width, 3) << " m\n";
        if (d.btype == "SP") out << "        tree " << ped_tree_of.at(d.pid) << "()\n";
        if (d.btype == "TP") write_trajectory(sc->trajectories.at(d.trajectory));
        if (d.btype == "PP") write_path(sc->paths.at(d.path), d.use_speed_profile, d.meet);
        out << "    }\n";
    }
    std::set<std::string> object_names;
    std::map<std::string, int> copies;  // a name -> the number its next copy tries first
    for (const auto& o : sc->objects) {
        std::string name = ident(o.name, "object");
        // Vehicles are v<vid>, pedestrians p<pid>: keep objects out of those name spaces.
        const bool vehicle_like = name.size() > 1 && (name[0] == 'v' || name[0] == 'p') &&
                                  name.find_first_not_of("0123456789", 1) == std::string::npos;
        if (vehicle_like) name = "o_" + name;
        // Copies of one name are numbered from 2 (`cone`, `cone_2`, ...), past names taken
        // otherwise; each copy starts where the last one stopped, so many copies cost linear time.
        if (object_names.count(name)) {
            const std::string base = name;
            int& n = copies.try_emplace(base, 2).first->second;
            do {
                name = base + "_" + std::to_string(n++);
            } while (object_names.count(name));
        }
        object_names.insert(name);
        double length = o.length, width = o.width;
        std::string facing;
        if (o.area) {
            // An area: the box of its extent, east-west by north-south.
            const auto& a = *o.area;
            const road::Vec2 p0 = road::project(origin, a[0], a[1]), p1 = road::project(origin, a[2], a[3]);
            length = std::max(0.1, std::fabs(p1.x - p0.x));
            width = std::max(0.1, std::fabs(p1.y - p0.y));
            facing = " heading 0 deg";
            const catalog::AgentSize max = catalog::kMaxObjectSize;
            if (length > max.length || width > max.width) {
                diags.error("E0911", o.range, "static object '" + o.name + "': its area is " + fixed(length, 3) + " m east-west by " +
                                                   fixed(width, 3) + " m north-south, more than an object's " + fixed(max.length, 3) +
                                                   " m by " + fixed(max.width, 3) + " m")
                    .notes.push_back({{}, "the sizes an agent may have: docs/catalog.md, Agent sizes; draw a larger area as several objects"});
            }
        }
        out << "    object " << name << " {\n        start at " << xy(o.at) << facing << "\n        length " << fixed(length, 3)
            << " m\n        width " << fixed(width, 3) << " m\n    }\n";
    }
    for (const auto& l : sc->lights) {
        out << "    light " << l.name << " {";
        for (size_t i = 0; i < l.states.size(); ++i) {
            out << " " << (l.states[i] == "G" ? "green" : l.states[i] == "Y" ? "yellow" : "red") << " " << fixed(l.durations[i], 3) << " s";
        }
        out << " }\n";
    }
    // The reference's success: no collision, and the run ends by a goal before the timeout.
    if (sc->collision) out << "    expect no_collision()\n";
    for (const auto& g : goal_vehicles.empty() ? all_sdv_goals : goal_vehicles) out << "    expect reached_goal(" << g << ")\n";
    if (!goal_vehicles.empty()) out << "    expect not timeout()\n";
    out << "}\n";
    if (diags.error_count() > before) return std::nullopt;
    std::vector<std::string> files = lib.files();
    return Converted{out.str(), files};
}

}  // namespace sdv::compiler::gss
