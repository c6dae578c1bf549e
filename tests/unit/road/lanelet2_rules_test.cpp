// The Lanelet2 reader against Lanelet2's own topology rules: for every Lanelet2 map in
// shared/data, the table of lanes the reader builds (orientation, successors, neighbours) equals
// the golden table that scripts/lanelet2-golden.py derives independently from the OSM file
// (tests/golden/lanelet2/<map>.txt); and routes on the GeoScenario copy of the Lanelet2 example
// map follow successors and permitted lane changes.
#include <doctest/doctest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <pugixml.hpp>
#include <sstream>

#include "runtime/road/lanelet2_reader.h"
#include "runtime/road/routing.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace lanelet2_rules_test {

using namespace sdv::road;

namespace {

const std::string kShared = SDV_SHARED_DIR;
const std::string kSource = SDV_SOURCE_DIR;

const char* const kMaps[] = {
    "lanelet2/mapping_example.osm",
    "geoscenario/maps/lanelet2_ringroad.osm",
    "geoscenario/maps/lanelet2_ringroad_pedestrians.osm",
    "geoscenario/maps/lanelet2_university_weber_alt.osm",
    "geoscenario/maps/lanelet2_university_weber_alt_walkways.osm",
    "geoscenario/maps/ll2_firetower_4waystop.osm",
    "geoscenario/maps/ll2_mapping_example.osm",
};

std::vector<std::string> read_lines(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
}

// The lanelet id and whether the lane drives it inverted, from a lane name.
std::pair<long long, bool> lanelet_of(const std::string& name) {
    const bool inv = name.size() > std::string(kInvertedSuffix).size() &&
                     name.compare(name.size() - std::string(kInvertedSuffix).size(),
                                  std::string::npos, kInvertedSuffix) == 0;
    return {std::stoll(name.substr(
                0, inv ? name.size() - std::string(kInvertedSuffix).size() : name.size())),
            inv};
}

// One line per lane, in the format of scripts/lanelet2-golden.py, from the RoadNetwork alone
// (bound end points are named by the nearest end node of the lanelet's two bound ways).
std::vector<std::string> table(const std::string& map_path, const LoadResult& r) {
    pugi::xml_document doc;
    REQUIRE(doc.load_file(map_path.c_str()));
    std::map<long long, Vec2> nodes;
    std::map<long long, std::vector<long long>> ways;
    std::map<long long, std::vector<long long>> bound_ends;  // lanelet -> end nodes of its bounds
    for (auto n : doc.child("osm").children("node")) {
        nodes[n.attribute("id").as_llong()] =
            project(r.origin, n.attribute("lat").as_double(), n.attribute("lon").as_double());
    }
    for (auto w : doc.child("osm").children("way")) {
        auto& v = ways[w.attribute("id").as_llong()];
        for (auto nd : w.children("nd")) v.push_back(nd.attribute("ref").as_llong());
    }
    for (auto rel : doc.child("osm").children("relation")) {
        for (auto m : rel.children("member")) {
            const std::string role = m.attribute("role").as_string();
            if (role != "left" && role != "right") continue;
            const auto& w = ways[m.attribute("ref").as_llong()];
            if (w.empty()) continue;
            auto& e = bound_ends[rel.attribute("id").as_llong()];
            e.push_back(w.front());
            e.push_back(w.back());
        }
    }
    const RoadNetwork& net = *r.network;
    auto node_at = [&](long long lanelet, Vec2 p) {
        long long best = 0;
        double bd = 1e300;
        for (long long id : bound_ends[lanelet]) {
            if (distance(nodes[id], p) < bd) {
                bd = distance(nodes[id], p);
                best = id;
            }
        }
        return std::to_string(best);
    };
    std::vector<std::pair<std::pair<long long, bool>, std::string>> rows;
    for (const Lane& l : net.lanes()) {
        const auto key = lanelet_of(l.name);
        std::vector<std::string> succ;
        for (LaneId s : l.successors) succ.push_back(net.lane(s).name);
        std::sort(succ.begin(), succ.end());
        std::string succ_text;
        for (const auto& s : succ) succ_text += (succ_text.empty() ? "" : ",") + s;
        auto nb = [&](LaneId id, bool same) {
            return id == kNoLane ? std::string("-")
                                 : net.lane(id).name + (same ? "/same" : "/opposite");
        };
        std::ostringstream line;
        line << l.name << " left=" << node_at(key.first, l.left_bound.front()) << ">"
             << node_at(key.first, l.left_bound.back())
             << " right=" << node_at(key.first, l.right_bound.front()) << ">"
             << node_at(key.first, l.right_bound.back())
             << " succ=" << (succ_text.empty() ? "-" : succ_text)
             << " lnb=" << nb(l.left, l.left_same_direction)
             << " rnb=" << nb(l.right, l.right_same_direction);
        rows.push_back({key, line.str()});
    }
    std::sort(rows.begin(), rows.end());
    std::vector<std::string> out;
    for (auto& row : rows) out.push_back(std::move(row.second));
    return out;
}

std::string field(const std::string& line, const std::string& name) {
    const auto at = line.find(" " + name + "=");
    if (at == std::string::npos) return "";
    const auto from = at + name.size() + 2;
    return line.substr(from, line.find(' ', from) - from);
}

std::string basename_txt(const std::string& map) {
    const auto slash = map.rfind('/');
    return map.substr(slash + 1, map.rfind('.') - slash - 1) + ".txt";
}

}  // namespace

TEST_CASE("Lanelet2 maps: orientation, successors and neighbours as Lanelet2 gives them") {
    for (const char* m : kMaps) {
        CAPTURE(m);
        const std::string path = kShared + "/data/" + m;
        const auto golden = read_lines(kSource + "/tests/golden/lanelet2/" + basename_txt(m));
        REQUIRE_MESSAGE(!golden.empty(),
                        "no golden file for " << m << ": run scripts/lanelet2-golden.py");
        const LoadResult r = load_lanelet2(path);
        REQUIRE_MESSAGE(r.errors.empty(), r.errors.front());
        REQUIRE(r.network);
        const auto ours = table(path, r);
        // Per lanelet: which columns differ, and the first differing lines in full.
        std::map<std::string, std::string> by_name;
        for (const auto& l : ours) by_name[l.substr(0, l.find(' '))] = l;
        int missing = 0, direction = 0, successors = 0, neighbours = 0;
        std::string first;
        for (const auto& g : golden) {
            auto it = by_name.find(g.substr(0, g.find(' ')));
            if (it == by_name.end()) {
                ++missing;
            } else {
                direction += field(g, "left") != field(it->second, "left") ||
                             field(g, "right") != field(it->second, "right");
                successors += field(g, "succ") != field(it->second, "succ");
                neighbours += field(g, "lnb") != field(it->second, "lnb") ||
                              field(g, "rnb") != field(it->second, "rnb");
            }
            if ((it == by_name.end() || it->second != g) && first.size() < 2000) {
                first += "\n  golden: " + g + "\n  sdv:    " +
                         (it == by_name.end() ? std::string("(no such lane)") : it->second);
            }
        }
        std::map<std::string, bool> in_golden;
        for (const auto& g : golden) in_golden[g.substr(0, g.find(' '))] = true;
        const auto extra = std::count_if(by_name.begin(), by_name.end(), [&](const auto& kv) {
            return !in_golden.count(kv.first);
        });
        CHECK_MESSAGE(ours == golden, std::string(m)
                                          << ": " << golden.size() << " golden lanes, "
                                          << ours.size() << " lanes; " << missing << " missing, "
                                          << extra << " not in the golden table, " << direction
                                          << " in another direction, " << successors
                                          << " with other successors, " << neighbours
                                          << " with other neighbours" << first);
    }
}

namespace {

LaneId lane(const RoadNetwork& net, const std::string& name) {
    auto l = net.find(name);
    REQUIRE_MESSAGE(l.has_value(), "no lane " << name);
    return *l;
}

// Each step of a route is a successor of the previous one or, when marked, its same-direction
// neighbour across a bound that permits the change.
void check_follows(const RoadNetwork& net, const Route& route) {
    for (size_t i = 1; i < route.steps.size(); ++i) {
        const Lane& prev = net.lane(route.steps[i - 1].lane);
        const LaneId next = route.steps[i].lane;
        CAPTURE(prev.name);
        CAPTURE(net.lane(next).name);
        if (route.steps[i].by_lane_change) {
            CHECK(((prev.left == next && prev.left_same_direction) ||
                   (prev.right == next && prev.right_same_direction)));
        } else {
            CHECK(std::find(prev.successors.begin(), prev.successors.end(), next) !=
                  prev.successors.end());
        }
    }
}

}  // namespace

TEST_CASE("ll2_mapping_example: routes over successors and permitted lane changes") {
    auto r = load_lanelet2(kShared + "/data/geoscenario/maps/ll2_mapping_example.osm");
    REQUIRE(r.network);
    const RoadNetwork& net = *r.network;
    CHECK(r.lanelets == 372);  // one more walkway than mapping_example.osm
    CHECK(r.drivable ==
          328);  // 337 road + 8 highway, less 17 roads for bicycles and pedestrians only
    CHECK(r.both_ways == 60);  // the roads tagged one_way=no
    CHECK(net.lanes().size() == 388);
    CHECK(!net.find("45202").has_value());  // a road tagged participant:bicycle/pedestrian only

    SUBCASE("a two-way lanelet is two lanes") {
        // Lanelet 43672 (one_way=no) is drawn against the direction Lanelet2 gives it (both
        // bounds are inverted on load); its inversion drives the other way over the same ground.
        const Lane& l = net.lane(lane(net, "43672"));
        const Lane& inv = net.lane(lane(net, "43672:inv"));
        CHECK(distance(l.centre.front(), inv.centre.back()) < 1e-6);
        CHECK(distance(l.centre.back(), inv.centre.front()) < 1e-6);
        CHECK(l.left != inv.id);
        CHECK(l.right != inv.id);
        const Route route = shortest_route(net, lane(net, "43672:inv"), lane(net, "43694:inv"));
        REQUIRE_MESSAGE(!route.steps.empty(), route.error);
        CHECK(route.steps.size() == 3);
        CHECK(net.lane(route.steps[1].lane).name == "43685:inv");
        check_follows(net, route);
        CHECK(shortest_route(net, lane(net, "43672"), lane(net, "43694")).steps.empty());
        CHECK(!shortest_route(net, lane(net, "43694"), lane(net, "43672")).steps.empty());
    }

    SUBCASE("the highway of GeoScenario's lanechange scenario") {
        // The reference's vehicle starts in 45394, changes to the right lane 45396 and drives on
        // to its goal in 45404 (lanechange.gs.osm). Under the old reader 45404 pointed the other
        // way, so the goal was only reachable in 45402.
        const Route route = shortest_route(net, lane(net, "45394"), lane(net, "45404"));
        REQUIRE_MESSAGE(!route.steps.empty(), route.error);
        CHECK(route.steps.size() == 3);
        CHECK(std::count_if(route.steps.begin(), route.steps.end(),
                            [](const RouteStep& s) { return s.by_lane_change; }) == 1);
        check_follows(net, route);
        // Two lane changes from the leftmost lane.
        const Route two = shortest_route(net, lane(net, "45392"), lane(net, "45404"));
        REQUIRE_MESSAGE(!two.steps.empty(), two.error);
        CHECK(std::count_if(two.steps.begin(), two.steps.end(),
                            [](const RouteStep& s) { return s.by_lane_change; }) == 2);
        check_follows(net, two);
        // 45406 shares 45404's right bound, a solid line: no lane change across it.
        CHECK(net.lane(lane(net, "45404")).right == kNoLane);
        CHECK(shortest_route(net, lane(net, "45404"), lane(net, "45406")).steps.empty());
    }

    SUBCASE("an urban route over five successors and one lane change") {
        const LaneId from = lane(net, "45010"), to = lane(net, "45028");
        const Route route = shortest_route(net, from, to);
        REQUIRE_MESSAGE(!route.steps.empty(), route.error);
        CHECK(route.steps.front().lane == from);
        CHECK(route.steps.back().lane == to);
        CHECK(route.steps.size() >= 6);
        CHECK(std::count_if(route.steps.begin(), route.steps.end(),
                            [](const RouteStep& s) { return s.by_lane_change; }) == 1);
        check_follows(net, route);
        // The lane change is needed: without lane changes the goal is unreachable.
        RoadNetwork no_changes = net;
        for (const Lane& l : net.lanes()) {
            if (l.left_same_direction) no_changes.lane_mut(l.id).left = kNoLane;
            if (l.right_same_direction) no_changes.lane_mut(l.id).right = kNoLane;
        }
        CHECK(shortest_route(no_changes, from, to).steps.empty());
    }

    SUBCASE("solid_dashed: a lane change one way only") {
        // Way between 5499728065004547155 (left) and 6012398680329441872 (right): line_thick
        // solid_dashed, drawn in their direction: changing to the left is allowed, to the right
        // not.
        const LaneId left = lane(net, "5499728065004547155"),
                     right = lane(net, "6012398680329441872");
        CHECK(net.lane(right).left == left);
        CHECK(net.lane(right).left_same_direction);
        CHECK(net.lane(left).right == kNoLane);
    }
}

}  // namespace lanelet2_rules_test
