#include "runtime/road/lanelet2_reader.h"

#include <GeographicLib/LocalCartesian.hpp>
#include <pugixml.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace sdv::road {
namespace {

using Id = long long;

struct Way {
    std::vector<Id> nodes;
    std::map<std::string, std::string> tags;
};

struct Member {
    std::string type, role;
    Id ref;
};

struct Relation {
    std::vector<Member> members;
    std::map<std::string, std::string> tags;
};

std::map<std::string, std::string> read_tags(const pugi::xml_node& e) {
    std::map<std::string, std::string> tags;
    for (auto t : e.children("tag")) tags[t.attribute("k").as_string()] = t.attribute("v").as_string();
    return tags;
}

bool parse_id(const char* text, Id& out) {
    char* end = nullptr;
    errno = 0;
    out = std::strtoll(text, &end, 10);
    return end != text && *end == '\0' && errno == 0;
}

// Speed limits as written in maps: "50", "50 km/h", "30 mph", "13.9 m/s" → m/s.
std::optional<double> parse_speed(const std::string& v) {
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (end == v.c_str() || !std::isfinite(x) || x <= 0) return std::nullopt;
    std::string unit(end);
    unit.erase(std::remove(unit.begin(), unit.end(), ' '), unit.end());
    if (unit.empty() || unit == "km/h" || unit == "kmh" || unit == "kph") return x / 3.6;
    if (unit == "mph") return x * 0.44704;
    if (unit == "m/s" || unit == "mps") return x;
    return std::nullopt;
}

const std::set<std::string> kDrivable = {"road", "highway", "play_street", "emergency_lane", "bus_lane", ""};
const std::set<std::string> kRoles = {"refers", "ref_line", "light_bulbs", "right_of_way", "yield", "cancels",
                                      "cancel_line"};
const std::set<std::string> kRegSubtypes = {"traffic_light", "right_of_way", "all_way_stop", "speed_limit",
                                            "traffic_sign"};

}  // namespace

LoadResult load_lanelet2(const std::string& path, std::optional<GeoOrigin> origin) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        LoadResult r;
        r.errors.push_back("cannot read map file '" + path + "'");
        return r;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_lanelet2(ss.str(), origin);
}

LoadResult parse_lanelet2(const std::string& xml, std::optional<GeoOrigin> origin) {
    LoadResult r;
    pugi::xml_document doc;
    const auto parsed = doc.load_buffer(xml.data(), xml.size());
    if (!parsed) {
        r.errors.push_back(std::string("not a valid OSM XML file: ") + parsed.description() + " at byte " +
                           std::to_string(parsed.offset));
        return r;
    }
    const auto osm = doc.child("osm");
    if (!osm) {
        r.errors.push_back("not an OSM file: no <osm> element");
        return r;
    }
    // Nodes (projected), ways, relations.
    std::map<Id, Vec2> nodes;
    std::map<Id, Way> ways;
    std::map<Id, Relation> rels;
    std::vector<Id> rel_order;
    bool have_origin = origin.has_value();
    GeographicLib::LocalCartesian proj;
    for (auto n : osm.children("node")) {
        Id id;
        if (!parse_id(n.attribute("id").as_string(), id)) {
            r.errors.push_back("node with an invalid id '" + std::string(n.attribute("id").as_string()) + "'");
            continue;
        }
        const auto tags = read_tags(n);
        const double lat = n.attribute("lat").as_double(NAN), lon = n.attribute("lon").as_double(NAN);
        if (tags.count("local_x") && tags.count("local_y")) {
            nodes[id] = {std::strtod(tags.at("local_x").c_str(), nullptr), std::strtod(tags.at("local_y").c_str(), nullptr)};
            continue;
        }
        if (!std::isfinite(lat) || !std::isfinite(lon) || std::fabs(lat) > 90 || std::fabs(lon) > 180) {
            r.errors.push_back("node " + std::to_string(id) + ": invalid coordinates");
            continue;
        }
        if (!have_origin) {
            origin = GeoOrigin{lat, lon, 0};
            have_origin = true;
        }
        if (nodes.empty()) proj.Reset(origin->lat, origin->lon, origin->alt);
        double x, y, z;
        proj.Forward(lat, lon, origin->alt, x, y, z);
        nodes[id] = {x, y};
    }
    if (origin) r.origin = *origin;
    for (auto w : osm.children("way")) {
        Id id;
        if (!parse_id(w.attribute("id").as_string(), id)) continue;
        Way way;
        way.tags = read_tags(w);
        for (auto nd : w.children("nd")) {
            Id ref;
            if (!parse_id(nd.attribute("ref").as_string(), ref) || !nodes.count(ref)) {
                r.errors.push_back("way " + std::to_string(id) + ": refers to missing node " + nd.attribute("ref").as_string());
                continue;
            }
            way.nodes.push_back(ref);
        }
        ways[id] = std::move(way);
    }
    for (auto e : osm.children("relation")) {
        Id id;
        if (!parse_id(e.attribute("id").as_string(), id)) continue;
        Relation rel;
        rel.tags = read_tags(e);
        for (auto m : e.children("member")) {
            Member mem{m.attribute("type").as_string(), m.attribute("role").as_string(), 0};
            if (!parse_id(m.attribute("ref").as_string(), mem.ref)) {
                r.errors.push_back("relation " + std::to_string(id) + ": member with an invalid ref");
                continue;
            }
            rel.members.push_back(mem);
        }
        rels[id] = std::move(rel);
        rel_order.push_back(id);
    }
    auto points = [&](const Way& w) {
        std::vector<Vec2> pts;
        for (Id n : w.nodes) pts.push_back(nodes.at(n));
        return pts;
    };

    RoadNetwork net;
    struct LL {
        Id id;
        Id left_way, right_way;
        std::vector<Id> left, right;  // oriented node ids
        LaneId lane;
        std::vector<Id> regs;
        std::vector<Id> stop_ways;
    };
    std::vector<LL> lls;
    for (Id id : rel_order) {
        const Relation& rel = rels[id];
        auto type = rel.tags.find("type");
        if (type == rel.tags.end() || type->second != "lanelet") continue;
        ++r.lanelets;
        const std::string subtype = rel.tags.count("subtype") ? rel.tags.at("subtype") : "";
        const std::string where = "lanelet " + std::to_string(id);
        Id left = 0, right = 0;
        bool has_left = false, has_right = false;
        std::vector<Id> regs;
        std::vector<Id> stop_ways;  // GeoScenario maps name a lanelet's stop line directly
        for (const auto& m : rel.members) {
            if (m.role == "left") { left = m.ref; has_left = true; }
            else if (m.role == "right") { right = m.ref; has_right = true; }
            else if (m.role == "regulatory_element") {
                if (!rels.count(m.ref)) r.errors.push_back(where + ": refers to missing regulatory element " + std::to_string(m.ref));
                else regs.push_back(m.ref);
            } else if (m.role == "stop_line") {
                if (!ways.count(m.ref)) r.errors.push_back(where + ": refers to missing way " + std::to_string(m.ref));
                else stop_ways.push_back(m.ref);
            } else if (m.role.empty()) {
                r.warnings.push_back(where + ": member " + m.type + " " + std::to_string(m.ref) + " has no role; ignored");
            } else if (m.role != "centerline") {
                r.errors.push_back(where + ": unknown member role '" + m.role + "'");
            }
        }
        if (!has_left || !has_right) {
            r.errors.push_back(where + ": missing " + std::string(!has_left ? "left" : "right") + " bound");
            continue;
        }
        if (!ways.count(left) || !ways.count(right)) {
            r.errors.push_back(where + ": refers to missing way " + std::to_string(!ways.count(left) ? left : right));
            continue;
        }
        if (!kDrivable.count(subtype)) continue;
        std::vector<Id> ln = ways[left].nodes, rn = ways[right].nodes;
        if (ln.size() < 2 || rn.size() < 2) {
            r.errors.push_back(where + ": degenerate " + std::string(ln.size() < 2 ? "left" : "right") + " bound (way " +
                               std::to_string(ln.size() < 2 ? left : right) + " has fewer than 2 nodes)");
            continue;
        }
        std::vector<Vec2> lp = points(ways[left]), rp = points(ways[right]);
        if (polyline_length(lp) < 1e-3 || polyline_length(rp) < 1e-3) {
            r.errors.push_back(where + ": degenerate bound of zero length");
            continue;
        }
        // The right bound gives the direction; the left one is turned to match it. (Opposite
        // lanes share their middle way as both left bounds, so one of them must be turned;
        // outer bounds are drawn in the driving direction.)
        const double same = distance(lp.front(), rp.front()) + distance(lp.back(), rp.back());
        const double flipped = distance(lp.front(), rp.back()) + distance(lp.back(), rp.front());
        if (flipped < same) {
            std::reverse(ln.begin(), ln.end());
            std::reverse(lp.begin(), lp.end());
        }
        // Centre line: both bounds resampled at the same arc-length fractions and averaged.
        const int n = std::max(2, static_cast<int>(std::ceil(std::max(polyline_length(lp), polyline_length(rp)) / 0.5)) + 1);
        auto resample = [n](const std::vector<Vec2>& p) {
            std::vector<double> acc = {0};
            for (size_t i = 1; i < p.size(); ++i) acc.push_back(acc.back() + distance(p[i - 1], p[i]));
            std::vector<Vec2> out;
            size_t j = 0;
            for (int i = 0; i < n; ++i) {
                const double t = acc.back() * i / (n - 1);
                while (j + 2 < p.size() && acc[j + 1] < t) ++j;
                const double seg = acc[j + 1] - acc[j];
                const double f = seg > 0 ? std::clamp((t - acc[j]) / seg, 0.0, 1.0) : 0.0;
                out.push_back(p[j] + f * (p[j + 1] - p[j]));
            }
            return out;
        };
        const auto ls = resample(lp), rs = resample(rp);
        Lane lane;
        lane.name = std::to_string(id);
        for (int i = 0; i < n; ++i) lane.centre.push_back(0.5 * (ls[static_cast<size_t>(i)] + rs[static_cast<size_t>(i)]));
        lane.left_bound = lp;
        lane.right_bound = rp;
        lane.width = distance(ls[static_cast<size_t>(n / 2)], rs[static_cast<size_t>(n / 2)]);
        const std::string location = rel.tags.count("location") ? rel.tags.at("location") : "urban";
        lane.speed_limit = location == "nonurban" ? 100 / 3.6 : 50 / 3.6;
        if (rel.tags.count("speed_limit")) {
            if (auto v = parse_speed(rel.tags.at("speed_limit"))) lane.speed_limit = *v;
            else r.warnings.push_back(where + ": unreadable speed_limit '" + rel.tags.at("speed_limit") + "'");
        }
        const LaneId lid = net.add_lane(std::move(lane));
        lls.push_back({id, left, right, ln, rn, lid, regs, stop_ways});
        ++r.drivable;
    }
    // Successors: end nodes of both bounds are the start nodes of another lanelet's bounds.
    std::map<std::pair<Id, Id>, std::vector<size_t>> starts;
    for (size_t i = 0; i < lls.size(); ++i) starts[{lls[i].left.front(), lls[i].right.front()}].push_back(i);
    for (const auto& a : lls) {
        auto it = starts.find({a.left.back(), a.right.back()});
        if (it == starts.end()) continue;
        for (size_t b : it->second) net.connect(a.lane, lls[b].lane);
    }
    // Neighbours through shared bound ways.
    std::map<Id, std::vector<size_t>> by_way;
    for (size_t i = 0; i < lls.size(); ++i) {
        by_way[lls[i].left_way].push_back(i);
        by_way[lls[i].right_way].push_back(i);
    }
    for (size_t i = 0; i < lls.size(); ++i) {
        for (size_t j : by_way[lls[i].left_way]) {
            if (j == i) continue;
            const LL& a = lls[i];
            const LL& b = lls[j];
            if (b.right_way == a.left_way && b.right == a.left) {
                net.set_neighbours(a.lane, b.lane, true);
            } else if (b.left_way == a.left_way && !a.left.empty() && b.left.size() == a.left.size() &&
                       std::equal(a.left.begin(), a.left.end(), b.left.rbegin())) {
                // Opposite neighbours: the shared way runs against one of them. (Two lanelets
                // sharing a left bound drawn the same way overlap where a lane splits; they are
                // not neighbours.)
                net.lane_mut(a.lane).left = b.lane;
                net.lane_mut(a.lane).left_same_direction = false;
            }
        }
    }
    // Regulatory elements.
    std::map<Id, int32_t> light_index;
    for (Id id : rel_order) {
        const Relation& rel = rels[id];
        if (!rel.tags.count("type") || rel.tags.at("type") != "regulatory_element") continue;
        const std::string where = "regulatory element " + std::to_string(id);
        const std::string subtype = rel.tags.count("subtype") ? rel.tags.at("subtype") : "";
        if (!kRegSubtypes.count(subtype)) {
            r.warnings.push_back(where + ": subtype '" + subtype + "' is ignored");
            continue;
        }
        for (const auto& m : rel.members) {
            if (!kRoles.count(m.role)) r.errors.push_back(where + ": unknown member role '" + m.role + "'");
            const bool exists = m.type == "way" ? ways.count(m.ref) > 0 : m.type == "node" ? nodes.count(m.ref) > 0
                                                                                         : rels.count(m.ref) > 0;
            if (!exists) r.errors.push_back(where + ": member " + m.type + " " + std::to_string(m.ref) + " does not exist");
        }
        if (subtype == "traffic_light") {
            TrafficLight tl;
            tl.id = static_cast<int32_t>(net.lights.size());
            tl.name = std::to_string(id);
            Vec2 sum{};
            int count = 0;
            for (const auto& m : rel.members) {
                if (m.role == "refers" && m.type == "way" && ways.count(m.ref)) {
                    // GeoScenario scenarios bind their light programs by the light way's name.
                    if (auto nm = ways[m.ref].tags.find("name"); nm != ways[m.ref].tags.end() && !nm->second.empty()) {
                        tl.name = nm->second;
                    }
                    for (Id nd : ways[m.ref].nodes) {
                        sum = sum + nodes.at(nd);
                        ++count;
                    }
                }
            }
            if (count > 0) tl.position = (1.0 / count) * sum;
            light_index[id] = tl.id;
            net.lights.push_back(std::move(tl));
        }
    }
    // Attach regulatory elements and stop lines (ref_line) to the lanelets that refer to them.
    auto attach_stop_line = [&](const LL& a, Id way) {
        if (!ways.count(way) || ways[way].nodes.size() < 2) return;
        Lane& lane = net.lane_mut(a.lane);
        const auto pts = points(ways[way]);
        const Vec2 mid = 0.5 * (pts.front() + pts.back());
        const auto& ref = net.reference(a.lane);
        const FrenetState f = ref.project(mid);
        if (f.s >= -2 && f.s <= ref.length() + 2 && std::fabs(f.d) < 0.5 * lane.width + 3) {
            lane.stop_line_s = std::clamp(f.s, 0.0, ref.length());
        }
    };
    for (const LL& a : lls) {
        for (Id w : a.stop_ways) attach_stop_line(a, w);
        Lane& lane = net.lane_mut(a.lane);
        for (Id reg : a.regs) {
            const Relation& rel = rels[reg];
            const std::string subtype = rel.tags.count("subtype") ? rel.tags.at("subtype") : "";
            if (subtype == "traffic_light" && light_index.count(reg)) {
                lane.traffic_lights.push_back(light_index[reg]);
                net.lights[static_cast<size_t>(light_index[reg])].lanes.push_back(a.lane);
            }
            if (subtype == "all_way_stop") lane.all_way_stop = true;
            if (subtype == "speed_limit") {
                for (const auto& [k, v] : rel.tags) {
                    if (k == "speed_limit" || k == "sign_type") {
                        if (auto s = parse_speed(v)) lane.speed_limit = *s;
                    }
                }
            }
            // A right-of-way element's stop line belongs to its yielding lanelets only.
            bool yields = subtype != "right_of_way";
            for (const auto& m : rel.members) {
                if (m.role == "yield" && m.type == "relation" && m.ref == a.id) yields = true;
            }
            for (const auto& m : rel.members) {
                if (yields && m.role == "ref_line" && m.type == "way") attach_stop_line(a, m.ref);
            }
        }
    }
    // Right of way: yield and priority lanelets.
    for (Id id : rel_order) {
        const Relation& rel = rels[id];
        if (!rel.tags.count("subtype") || (rel.tags.at("subtype") != "right_of_way" && rel.tags.at("subtype") != "all_way_stop")) continue;
        RightOfWay row;
        for (const auto& m : rel.members) {
            if (m.type != "relation") continue;
            for (const LL& a : lls) {
                if (a.id != m.ref) continue;
                if (m.role == "yield") row.yield.push_back(a.lane);
                if (m.role == "right_of_way") row.priority.push_back(a.lane);
            }
        }
        const auto index = static_cast<int32_t>(net.rights_of_way.size());
        for (LaneId l : row.yield) net.lane_mut(l).right_of_way = index;
        for (LaneId l : row.priority) net.lane_mut(l).right_of_way = index;
        net.rights_of_way.push_back(std::move(row));
    }
    if (r.drivable == 0 && r.errors.empty()) r.errors.push_back("the map has no drivable lanelet");
    if (r.errors.empty()) r.network = std::move(net);
    return r;
}

Vec2 project(const GeoOrigin& origin, double lat, double lon) {
    GeographicLib::LocalCartesian proj(origin.lat, origin.lon, origin.alt);
    double x, y, z;
    proj.Forward(lat, lon, origin.alt, x, y, z);
    return {x, y};
}

}  // namespace sdv::road
