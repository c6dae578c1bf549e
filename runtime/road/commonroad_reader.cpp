#include "runtime/road/commonroad_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <pugixml.hpp>
#include <set>

#include "runtime/road/lane_geometry.h"
#include "runtime/road/reader_text.h"

namespace sdv::road {
namespace {

// The same limits as the Lanelet2 reader: coordinates within 1,000 km of the origin, lanelets
// at most 50 km long (sampled every 0.5 m) and 100 km of lanes in all, so that reading stays
// linear in the file's size.
constexpr double kMaxCoordinate = 1e6;
constexpr double kMaxLaneletLength = 50e3;
constexpr double kMaxTotalLength = 100e3;

using Lines = XmlLines;
constexpr auto number = parse_number;

struct Reader {
    const Lines& lines;
    LoadResult& r;

    std::string at(const pugi::xml_node& n, const std::string& what) const {
        return "line " + std::to_string(lines.line(n)) + ": " + what;
    }
    void error(const pugi::xml_node& n, const std::string& what, const std::string& msg) const {
        r.errors.push_back(at(n, what + ": " + msg));
    }
    void warning(const pugi::xml_node& n, const std::string& what, const std::string& msg) const {
        r.warnings.push_back(at(n, what + ": " + msg));
    }

    // The points of a bound or line (<point><x/><y/></point>...).
    std::optional<std::vector<Vec2>> points(const pugi::xml_node& e, const std::string& what) const {
        std::vector<Vec2> out;
        for (auto p : e.children("point")) {
            const auto x = number(p.child_value("x")), y = number(p.child_value("y"));
            if (!x || !y) {
                error(p, what, "a point without numeric <x> and <y>");
                return std::nullopt;
            }
            if (std::fabs(*x) > kMaxCoordinate || std::fabs(*y) > kMaxCoordinate) {
                error(p, what, "a point more than 1,000 km from the origin");
                return std::nullopt;
            }
            out.push_back({*x, *y});
        }
        return out;
    }
};

struct LaneletEntry {
    std::string id;
    pugi::xml_node node;
    LaneId lane = kNoLane;
};

// Speed-limit signs: MUTCD R2-1 (value in m/s, as CommonRoad converts it) and German 274.
std::optional<double> sign_speed_limit(const pugi::xml_node& sign) {
    for (auto el : sign.children("trafficSignElement")) {
        const std::string code = el.child_value("trafficSignID");
        if (code != "R2-1" && code != "274" && code != "274.1") continue;
        if (auto v = number(el.child_value("additionalValue")); v && *v > 0 && *v < 150) return *v;
    }
    return std::nullopt;
}

}  // namespace

std::string commonroad_light_name(const std::string& id) {
    // A name scenarios can write (letters, digits, '_'): the id comes from the file.
    std::string out = "tl";
    for (char c : id) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return out;
}

bool is_commonroad(const std::string& xml) {
    // The root element's name, skipping the declaration, comments and whitespace.
    size_t i = 0;
    while (i < xml.size()) {
        i = xml.find('<', i);
        if (i == std::string::npos || i + 1 >= xml.size()) return false;
        if (xml[i + 1] == '?' || xml[i + 1] == '!') {
            ++i;
            continue;
        }
        return xml.compare(i + 1, 10, "commonRoad") == 0;
    }
    return false;
}

LoadResult load_commonroad(const std::string& path) {
    std::string text;
    if (!read_file(path, text)) {
        LoadResult r;
        r.errors.push_back("cannot read map file '" + path + "'");
        return r;
    }
    return parse_commonroad(text);
}

LoadResult load_map(const std::string& path, std::optional<GeoOrigin> origin) {
    std::string text;
    if (!read_file(path, text)) {
        LoadResult r;
        r.errors.push_back("cannot read map file '" + path + "'");
        return r;
    }
    return is_commonroad(text) ? parse_commonroad(text) : parse_lanelet2(text, origin);
}

LoadResult parse_commonroad(const std::string& xml) {
    LoadResult r;
    pugi::xml_document doc;
    const auto parsed = doc.load_buffer(xml.data(), xml.size());
    if (!parsed) {
        r.errors.push_back(std::string("not a valid XML file: ") + parsed.description() + " at byte " +
                           std::to_string(parsed.offset));
        return r;
    }
    const auto root = doc.child("commonRoad");
    if (!root) {
        r.errors.push_back("not a CommonRoad file: no <commonRoad> element");
        return r;
    }
    const Lines lines(xml);
    const Reader rd{lines, r};
    RoadNetwork net;
    // Lanelets (2020a may wrap them in <laneletNetwork>? No: both formats put them at the root).
    std::vector<LaneletEntry> entries;
    std::map<std::string, size_t> by_id;
    double total_length = 0;
    for (auto e : root.children("lanelet")) {
        const std::string id = e.attribute("id").as_string();
        const std::string where = "lanelet " + (id.empty() ? std::string("(no id)") : id);
        if (id.empty() || !number(id.c_str())) {
            rd.error(e, where, "needs a numeric id");
            continue;
        }
        if (by_id.count(id)) {
            rd.error(e, where, "the id is used twice");
            continue;
        }
        const auto left = rd.points(e.child("leftBound"), where + " leftBound");
        const auto right = rd.points(e.child("rightBound"), where + " rightBound");
        if (!left || !right) continue;
        if (left->size() < 2 || right->size() < 2) {
            rd.error(e, where, "each bound needs at least two points");
            continue;
        }
        const double length = std::max(polyline_length(*left), polyline_length(*right));
        if (!(length <= kMaxLaneletLength)) {
            rd.error(e, where, "a bound is " + std::to_string(static_cast<long long>(length / 1000)) +
                                   " km long; sdv reads lanelets up to 50 km");
            return r;
        }
        if (length < 1e-3) {
            rd.error(e, where, "its bounds have no length");
            continue;
        }
        total_length += length;
        if (total_length > kMaxTotalLength) {
            rd.error(e, where, "the map's lanes are more than 100 km long together; sdv reads maps of up to 100 km of "
                               "lanes (cut the map to the scenario's area)");
            return r;
        }
        auto between = centre_between(*left, *right);
        Lane lane;
        lane.name = id;
        lane.centre = std::move(between.centre);
        lane.left_bound = *left;
        lane.right_bound = *right;
        lane.width = between.width;
        lane.speed_limit = 50 / 3.6;
        if (auto v = number(e.child_value("speedLimit")); v && *v > 0 && *v < 150) lane.speed_limit = *v;
        if (polyline_length(lane.centre) < 1e-3) {
            rd.error(e, where, "its centre line has no length");
            continue;
        }
        by_id[id] = entries.size();
        entries.push_back({id, e, net.add_lane(std::move(lane))});
    }
    r.lanelets = static_cast<int>(entries.size());
    r.drivable = r.lanelets;
    auto lane_of = [&](const pugi::xml_node& ref_node, const std::string& where, const char* what) -> LaneId {
        const std::string ref = ref_node.attribute("ref").as_string();
        auto it = by_id.find(ref);
        if (it == by_id.end()) {
            rd.warning(ref_node, where, std::string(what) + " " + (ref.empty() ? "(no ref)" : ref) + " is not a lanelet; ignored");
            return kNoLane;
        }
        return entries[it->second].lane;
    };
    // Successors (predecessors follow from them; a predecessor named without the matching
    // successor is connected too).
    std::set<std::pair<LaneId, LaneId>> links;
    for (const auto& en : entries) {
        const std::string where = "lanelet " + en.id;
        for (auto s : en.node.children("successor"))
            if (LaneId to = lane_of(s, where, "successor"); to != kNoLane) links.insert({en.lane, to});
        for (auto p : en.node.children("predecessor"))
            if (LaneId from = lane_of(p, where, "predecessor"); from != kNoLane) links.insert({from, en.lane});
    }
    for (const auto& [from, to] : links) net.connect(from, to);
    // Neighbours.
    for (const auto& en : entries) {
        const std::string where = "lanelet " + en.id;
        Lane& lane = net.lane_mut(en.lane);
        for (const bool left_side : {true, false}) {
            const auto adj = en.node.child(left_side ? "adjacentLeft" : "adjacentRight");
            if (!adj) continue;
            const LaneId other = lane_of(adj, where, left_side ? "adjacentLeft" : "adjacentRight");
            if (other == kNoLane || other == en.lane) continue;
            const std::string dir = adj.attribute("drivingDir").as_string();
            if (dir != "same" && dir != "opposite") {
                rd.warning(adj, where, "drivingDir '" + dir + "' is neither same nor opposite; ignored");
                continue;
            }
            (left_side ? lane.left : lane.right) = other;
            (left_side ? lane.left_same_direction : lane.right_same_direction) = dir == "same";
        }
    }
    // Signs: speed limits.
    std::map<std::string, double> sign_limits;
    for (auto s : root.children("trafficSign"))
        if (auto v = sign_speed_limit(s)) sign_limits[s.attribute("id").as_string()] = *v;
    for (const auto& en : entries) {
        for (auto ref : en.node.children("trafficSignRef")) {
            auto it = sign_limits.find(ref.attribute("ref").as_string());
            if (it != sign_limits.end()) net.lane_mut(en.lane).speed_limit = it->second;
        }
    }
    // Traffic lights.
    std::map<std::string, int32_t> light_index;
    for (auto l : root.children("trafficLight")) {
        const std::string id = l.attribute("id").as_string();
        if (id.empty() || light_index.count(id)) {
            rd.error(l, "trafficLight " + id, id.empty() ? "needs an id" : "the id is used twice");
            continue;
        }
        TrafficLight tl;
        tl.id = static_cast<int32_t>(net.lights.size());
        tl.name = commonroad_light_name(id);
        if (auto pts = rd.points(l.child("position"), "trafficLight " + id); pts && !pts->empty()) tl.position = pts->front();
        light_index[id] = tl.id;
        net.lights.push_back(std::move(tl));
    }
    for (const auto& en : entries) {
        const std::string where = "lanelet " + en.id;
        Lane& lane = net.lane_mut(en.lane);
        std::set<int32_t> lights;
        auto add_light = [&](const pugi::xml_node& ref) {
            auto it = light_index.find(ref.attribute("ref").as_string());
            if (it == light_index.end()) {
                rd.warning(ref, where, std::string("traffic light ") + ref.attribute("ref").as_string() + " does not exist; ignored");
                return;
            }
            lights.insert(it->second);
        };
        for (auto ref : en.node.children("trafficLightRef")) add_light(ref);
        const auto stop = en.node.child("stopLine");
        if (stop) {
            for (auto ref : stop.children("trafficLightRef")) add_light(ref);
            const auto pts = rd.points(stop, where + " stopLine");
            const auto& ref = net.reference(en.lane);
            if (pts && pts->size() >= 2) {
                const Vec2 mid = 0.5 * (pts->front() + pts->back());
                const FrenetState f = ref.project(mid);
                if (f.s >= -2 && f.s <= ref.length() + 2 && std::fabs(f.d) < 0.5 * lane.width + 3)
                    lane.stop_lines.assign(1, StopLine{std::clamp(f.s, 0.0, ref.length()), {}});
                else
                    rd.warning(stop, where, "the stop line does not lie across the lanelet; ignored");
            } else if (pts) {
                lane.stop_lines.assign(1, StopLine{ref.length(), {}});  // no points: the lanelet's end
            }
        }
        for (int32_t l : lights) {
            lane.traffic_lights.push_back(l);
            net.lights[static_cast<size_t>(l)].lanes.push_back(en.lane);
        }
        for (StopLine& line : lane.stop_lines) line.traffic_lights = lane.traffic_lights;
    }
    // Intersections: the lanelets an incoming leads into are junction lanes with their turn.
    for (auto in : root.children("intersection")) {
        const std::string where = "intersection " + std::string(in.attribute("id").as_string());
        for (auto inc : in.children("incoming")) {
            const std::pair<const char*, Turn> kinds[] = {
                {"successorsRight", Turn::right}, {"successorsStraight", Turn::straight}, {"successorsLeft", Turn::left}};
            for (const auto& [tag, turn] : kinds) {
                for (auto s : inc.children(tag)) {
                    const LaneId l = lane_of(s, where, tag);
                    if (l == kNoLane) continue;
                    net.lane_mut(l).in_junction = true;
                    net.lane_mut(l).turn = turn;
                }
            }
        }
    }
    if (auto crowded = crowded_place(net); crowded && r.errors.empty()) r.errors.push_back(*crowded);
    if (r.errors.empty()) {
        mark_junctions(net);
        find_crossings(net);
    }
    if (entries.empty() && r.errors.empty()) r.errors.push_back("the file has no lanelet");
    if (r.errors.empty()) r.network = std::move(net);
    return r;
}

}  // namespace sdv::road
