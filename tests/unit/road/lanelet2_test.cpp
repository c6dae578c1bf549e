// The Lanelet2 reader on the reference map and the GeoScenario maps, checked against facts
// read off the files (counted with an XML parser: 371 lanelet relations in mapping_example.osm,
// 345 of them road or highway lanelets, of which 17 are tagged for bicycles and pedestrians only
// and 60 one_way=no; 6 traffic-light regulatory elements), and on malformed variants.
#include <doctest/doctest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>

#include "runtime/road/commonroad_reader.h"
#include "runtime/road/lane_geometry.h"
#include "runtime/road/lanelet2_reader.h"
#include "runtime/road/routing.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace lanelet2_test {

using namespace sdv::road;

namespace {

const std::string kShared = SDV_SHARED_DIR;

LaneId id(const RoadNetwork& net, const std::string& name) {
    auto l = net.find(name);
    REQUIRE_MESSAGE(l.has_value(), "no lanelet " << name);
    return *l;
}

}  // namespace

TEST_CASE("mapping_example.osm: lanelets, traffic lights, stop lines") {
    auto r = load_lanelet2(kShared + "/data/lanelet2/mapping_example.osm");
    REQUIRE_MESSAGE(r.errors.empty(), r.errors.front());
    REQUIRE(r.network);
    CHECK(r.lanelets == 371);
    CHECK(r.drivable == 328);
    CHECK(r.both_ways == 60);
    CHECK(r.network->lanes().size() == 388);  // a second lane "<id>:inv" per two-way lanelet
    CHECK(r.network->lights.size() == 6);
    int controlled = 0, stop_lines = 0;
    for (const auto& l : r.network->lanes()) {
        controlled += !l.traffic_lights.empty();
        stop_lines += !l.stop_lines.empty();
    }
    CHECK(controlled > 0);
    CHECK(stop_lines >= controlled);
    for (const auto& tl : r.network->lights) CHECK(!tl.lanes.empty());
    CHECK(r.network->rights_of_way.size() == 2);
}

TEST_CASE("mapping_example.osm: routing and neighbours") {
    auto r = load_lanelet2(kShared + "/data/lanelet2/mapping_example.osm");
    REQUIRE(r.network);
    const RoadNetwork& net = *r.network;
    // A chain of successors found in the file: their bounds end where the next begin. (The three
    // are two-way lanelets drawn against the direction Lanelet2 gives them: the chain runs along
    // their inversions.)
    const LaneId a = id(net, "43672:inv"), b = id(net, "43685:inv"), c = id(net, "43694:inv");
    CHECK(net.lane(a).successors == std::vector<LaneId>{b});
    const Route route = shortest_route(net, a, c);
    REQUIRE(route.steps.size() == 3);
    CHECK(route.steps[1].lane == b);
    // Lanelet 44964's right bound is lanelet 44962's left bound, drawn the same way.
    const LaneId l = id(net, "44962"), n = id(net, "44964");
    CHECK(net.lane(l).left == n);
    CHECK(net.lane(l).left_same_direction);
    CHECK(net.lane(n).right == l);
    // 42440 and 45254 share their left way drawn the same way (a lane splitting): they overlap
    // and are not opposite neighbours.
    const LaneId s1 = id(net, "42440"), s2 = id(net, "45254");
    CHECK(net.lane(s1).left != s2);
    CHECK(net.lane(s2).left != s1);
    // Regulatory element 45230 makes 45014 and 45016 yield: they get its stop line.
    CHECK(net.lane(id(net, "45014")).stop_lines.size() == 1);
    CHECK(net.lane(id(net, "45016")).stop_lines.size() == 1);
}

TEST_CASE("the GeoScenario maps load") {
    for (const char* m : {"ll2_mapping_example.osm", "lanelet2_university_weber_alt.osm", "ll2_firetower_4waystop.osm"}) {
        auto r = load_lanelet2(kShared + "/data/geoscenario/maps/" + m);
        CHECK_MESSAGE(r.errors.empty(), m << ": " << (r.errors.empty() ? "" : r.errors.front()));
        CHECK(r.network.has_value());
    }
    auto fire = load_lanelet2(kShared + "/data/geoscenario/maps/ll2_firetower_4waystop.osm");
    REQUIRE(fire.network);
    CHECK(fire.drivable == 32);
    CHECK(std::any_of(fire.network->lanes().begin(), fire.network->lanes().end(),
                      [](const Lane& l) { return l.all_way_stop; }));
    auto weber = load_lanelet2(kShared + "/data/geoscenario/maps/lanelet2_university_weber_alt.osm");
    REQUIRE(weber.network);
    CHECK(weber.network->lights.size() == 8);
}

namespace {

std::string osm(const std::string& body) {
    return "<?xml version='1.0'?><osm version='0.6'>"
           "<node id='1' lat='49.0' lon='8.0'/><node id='2' lat='49.0' lon='8.001'/>"
           "<node id='3' lat='49.00003' lon='8.0'/><node id='4' lat='49.00003' lon='8.001'/>"
           "<way id='10'><nd ref='3'/><nd ref='4'/></way><way id='11'><nd ref='1'/><nd ref='2'/></way>" +
           body + "</osm>";
}

}  // namespace

TEST_CASE("malformed maps give errors naming the element") {
    auto ok = parse_lanelet2(osm("<relation id='100'><member type='way' ref='10' role='left'/>"
                                 "<member type='way' ref='11' role='right'/><tag k='type' v='lanelet'/></relation>"));
    CHECK(ok.errors.empty());
    REQUIRE(ok.network);
    CHECK(ok.network->lane(0).length == doctest::Approx(73).epsilon(0.02));  // 0.001° of longitude at 49° N
    CHECK(ok.network->lane(0).width == doctest::Approx(3.34).epsilon(0.02));

    auto missing_node = parse_lanelet2(osm("<way id='12'><nd ref='99'/></way>"));
    REQUIRE(!missing_node.errors.empty());
    CHECK(missing_node.errors[0] == "way 12: refers to missing node 99");

    auto missing_way = parse_lanelet2(osm("<relation id='101'><member type='way' ref='10' role='left'/>"
                                          "<member type='way' ref='77' role='right'/><tag k='type' v='lanelet'/></relation>"));
    REQUIRE(!missing_way.errors.empty());
    CHECK(missing_way.errors[0] == "lanelet 101: refers to missing way 77");

    auto degenerate = parse_lanelet2(osm("<way id='13'><nd ref='1'/></way><relation id='102'>"
                                         "<member type='way' ref='10' role='left'/><member type='way' ref='13' role='right'/>"
                                         "<tag k='type' v='lanelet'/></relation>"));
    REQUIRE(!degenerate.errors.empty());
    CHECK(degenerate.errors[0].rfind("lanelet 102: degenerate right bound", 0) == 0);

    auto bad_role = parse_lanelet2(osm("<relation id='103'><member type='way' ref='10' role='sideways'/>"
                                       "<tag k='type' v='regulatory_element'/><tag k='subtype' v='traffic_light'/></relation>"));
    REQUIRE(!bad_role.errors.empty());
    CHECK(bad_role.errors[0] == "regulatory element 103: unknown member role 'sideways'");

    CHECK(!parse_lanelet2("<osm><node").errors.empty());
    CHECK(!parse_lanelet2("").errors.empty());
    CHECK(load_lanelet2("/no/such/map.osm").errors[0] == "cannot read map file '/no/such/map.osm'");
}

TEST_CASE("a coordinate is a number and nothing more, or the node is refused, naming it") {
    // Random coordinates of a real map, each spoilt in one way strtod (and pugixml, and
    // Lanelet2's loader) would have read a prefix of: the map is refused with an error naming
    // the node and the attribute. (A fuzz input read lon "8.:5461" as 8: its node moved 30 km
    // and its lanelets became 30 km long.) Spaces and a sign around a number are fine.
    std::ifstream in(kShared + "/data/geoscenario/maps/lanelet2_university_weber_alt.osm");
    REQUIRE(in);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    struct Attr {
        size_t at, size;  // the value
        std::string node, key;
    };
    std::vector<Attr> attrs;
    for (size_t n = text.find("<node "); n != std::string::npos; n = text.find("<node ", n + 1)) {
        const size_t id = text.find("id='", n) + 4, end = text.find('>', n);
        for (const char* key : {"lat", "lon"}) {
            const size_t v = text.find(std::string(" ") + key + "='", n) + std::string(key).size() + 3;
            REQUIRE(v < end);
            attrs.push_back({v, text.find('\'', v) - v, text.substr(id, text.find('\'', id) - id), key});
        }
    }
    REQUIRE(attrs.size() > 400);
    const auto base = parse_lanelet2(text);
    REQUIRE(base.errors.empty());
    REQUIRE(base.network);
    std::mt19937 rng(19);
    const std::vector<std::string> spoil_end = {":", "x", "mph", ",5", "e", "e+", "..1", "-", " 1"};
    for (int round = 0; round < 24; ++round) {
        const Attr& a = attrs[std::uniform_int_distribution<size_t>(0, attrs.size() - 1)(rng)];
        std::string value = text.substr(a.at, a.size);
        switch (round % 3) {
            case 0: value += spoil_end[static_cast<size_t>(round) % spoil_end.size()]; break;  // a tail
            case 1: value[std::uniform_int_distribution<size_t>(3, value.size() - 1)(rng)] = ':'; break;  // a byte
            default: value = round % 2 ? "" : "north"; break;  // no number at all
        }
        const std::string spoilt = text.substr(0, a.at) + value + text.substr(a.at + a.size);
        CAPTURE(value);
        const auto r = parse_lanelet2(spoilt);
        REQUIRE(!r.errors.empty());
        CHECK(r.errors[0] == "node " + a.node + ": " + a.key + " '" + value + "' is not a number");
    }
    // Spaces and a plus sign around every coordinate: the same map.
    std::string padded = text;
    for (auto a = attrs.rbegin(); a != attrs.rend(); ++a) {
        const std::string v = text.substr(a->at, a->size);
        padded.replace(a->at, a->size, " " + (v[0] == '-' ? v : "+" + v) + " ");
    }
    const auto same = parse_lanelet2(padded);
    CHECK(same.errors.empty());
    REQUIRE(same.network);
    REQUIRE(same.network->lanes().size() == base.network->lanes().size());
    for (size_t i = 0; i < base.network->lanes().size(); ++i)
        CHECK(same.network->lanes()[i].centre == base.network->lanes()[i].centre);
    // local_x / local_y and ele, on the small map.
    auto with_node = [](const std::string& tags) {
        return parse_lanelet2(osm("<node id='7' lat='0' lon='0'>" + tags + "</node>"
                                  "<relation id='100'><member type='way' ref='10' role='left'/><member type='way' "
                                  "ref='11' role='right'/><tag k='type' v='lanelet'/></relation>"));
    };
    const auto fine = with_node("<tag k='local_x' v='1.5'/><tag k='local_y' v=' 2 '/><tag k='ele' v='-3e1'/>");
    CHECK_MESSAGE(fine.errors.empty(), (fine.errors.empty() ? "" : fine.errors[0]));
    const auto x = with_node("<tag k='local_x' v='1.5m'/><tag k='local_y' v='2'/>");
    REQUIRE(!x.errors.empty());
    CHECK(x.errors[0] == "node 7: local_x / local_y are not numbers ('1.5m', '2')");
    const auto ele = with_node("<tag k='local_x' v='1'/><tag k='local_y' v='2'/><tag k='ele' v='298.0 m'/>");
    REQUIRE(!ele.errors.empty());
    CHECK(ele.errors[0] == "node 7: ele '298.0 m' is not a number");
}

TEST_CASE("a map loads when its lanes total at most 100 km, and is refused with a located error above") {
    // Stacked straight lanelets of random lengths (each within the 50 km of one lanelet), in
    // Lanelet2 (local_x/local_y) and CommonRoad: the same verdict from both readers, and an
    // error naming the lanelet at which the total passes 100 km.
    std::mt19937 rng(16);
    std::uniform_real_distribution<double> km(0.5, 12.0);
    std::uniform_int_distribution<int> count(2, 24);
    int loaded = 0, refused = 0;
    for (int round = 0; round < 40; ++round) {
        const int n = count(rng);
        std::vector<double> lengths;
        for (int i = 0; i < n; ++i) lengths.push_back(1000 * km(rng));
        std::ostringstream ll2, cr;
        ll2 << "<osm>";
        cr << "<commonRoad>";
        double total = 0;
        int over = -1;
        for (int i = 0; i < n; ++i) {
            const int b = 10 * i;
            auto node = [&](int id, double x, double y) {
                ll2 << "<node id='" << id << "' lat='0' lon='0'><tag k='local_x' v='" << x
                    << "'/><tag k='local_y' v='" << y << "'/></node>";
            };
            node(b + 1, 0, 3.5 * i);
            node(b + 2, lengths[static_cast<size_t>(i)], 3.5 * i);
            node(b + 3, 0, 3.5 * i + 3.5);
            node(b + 4, lengths[static_cast<size_t>(i)], 3.5 * i + 3.5);
            ll2 << "<way id='" << b + 5 << "'><nd ref='" << b + 1 << "'/><nd ref='" << b + 2 << "'/></way>"
                << "<way id='" << b + 6 << "'><nd ref='" << b + 3 << "'/><nd ref='" << b + 4 << "'/></way>"
                << "<relation id='" << b + 7 << "'><member type='way' ref='" << b + 6
                << "' role='left'/><member type='way' ref='" << b + 5
                << "' role='right'/><tag k='type' v='lanelet'/><tag k='subtype' v='road'/></relation>";
            auto point = [&](double x, double y) { cr << "<point><x>" << x << "</x><y>" << y << "</y></point>"; };
            cr << "<lanelet id='" << b + 7 << "'><leftBound>";
            point(0, 3.5 * i + 3.5);
            point(lengths[static_cast<size_t>(i)], 3.5 * i + 3.5);
            cr << "</leftBound><rightBound>";
            point(0, 3.5 * i);
            point(lengths[static_cast<size_t>(i)], 3.5 * i);
            cr << "</rightBound></lanelet>";
            total += lengths[static_cast<size_t>(i)];
            if (over < 0 && total > 100e3) over = b + 7;
        }
        ll2 << "</osm>";
        cr << "</commonRoad>";
        CAPTURE(total);
        const auto a = parse_lanelet2(ll2.str());
        const auto c = parse_commonroad(cr.str());
        if (over < 0) {
            CHECK(a.errors.empty());
            CHECK(c.errors.empty());
            REQUIRE(a.network);
            CHECK(a.network->lanes().size() == static_cast<size_t>(n));
            ++loaded;
        } else {
            REQUIRE(a.errors.size() == 1);
            CHECK(a.errors[0].rfind("lanelet " + std::to_string(over) + ": the map's lanes are more than 100 km", 0) == 0);
            REQUIRE(!c.errors.empty());
            CHECK(c.errors[0].find("lanelet " + std::to_string(over) + ": the map's lanes are more than 100 km") !=
                  std::string::npos);
            ++refused;
        }
    }
    CHECK(loaded > 5);
    CHECK(refused > 5);
}

TEST_CASE("a map's crosswalks and walkways total at most 100 km, and the map is refused with a located error above") {
    // One short road and crosswalk and walkway lanelets of random lengths, some sharing the ways of
    // the one before (areas cost what their bounds measure, not what the file weighs: fuzz
    // finding 17 read 40 km crosswalks that shared two ways, 100 of them in 18 KB).
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> km(0.5, 12.0);
    std::uniform_int_distribution<int> count(2, 24);
    int loaded = 0, refused = 0;
    for (int round = 0; round < 30; ++round) {
        const int n = count(rng);
        std::ostringstream ll2;
        ll2 << "<osm>";
        auto node = [&](int id, double x, double y) {
            ll2 << "<node id='" << id << "' lat='0' lon='0'><tag k='local_x' v='" << x << "'/><tag k='local_y' v='" << y
                << "'/></node>";
        };
        auto lanelet = [&](int id, int left, int right, const char* subtype) {
            ll2 << "<relation id='" << id << "'><member type='way' ref='" << left << "' role='left'/><member type='way' ref='"
                << right << "' role='right'/><tag k='type' v='lanelet'/><tag k='subtype' v='" << subtype << "'/></relation>";
        };
        auto way = [&](int id, int a, int b) { ll2 << "<way id='" << id << "'><nd ref='" << a << "'/><nd ref='" << b << "'/></way>"; };
        node(1, 0, 0), node(2, 50, 0), node(3, 0, 3.5), node(4, 50, 3.5);
        way(5, 1, 2), way(6, 3, 4);
        lanelet(7, 6, 5, "road");
        double total = 0, length = 0;
        int over = -1, left = 0, right = 0;
        for (int i = 0; i < n; ++i) {
            const int b = 100 + 10 * i;
            if (i == 0 || rng() % 3 != 0) {  // new ways across the road, else the previous area's again
                length = 1000 * km(rng);
                node(b + 1, 20 + 3 * i, -length / 2), node(b + 2, 20 + 3 * i, length / 2);
                node(b + 3, 22 + 3 * i, -length / 2), node(b + 4, 22 + 3 * i, length / 2);
                way(b + 5, b + 1, b + 2), way(b + 6, b + 3, b + 4);
                left = b + 5, right = b + 6;
            }
            lanelet(b + 7, left, right, rng() % 2 ? "crosswalk" : "walkway");
            total += length;
            if (over < 0 && total > 100e3) over = b + 7;
        }
        ll2 << "</osm>";
        CAPTURE(total);
        const auto a = parse_lanelet2(ll2.str());
        if (over < 0) {
            CHECK(a.errors.empty());
            REQUIRE(a.network);
            CHECK(a.network->crosswalks.size() + a.network->walkways.size() == static_cast<size_t>(n));
            ++loaded;
        } else {
            REQUIRE(a.errors.size() == 1);
            CHECK(a.errors[0].rfind("lanelet " + std::to_string(over) + ": the map's crosswalks and walkways are more than 100 km", 0) == 0);
            CHECK(!a.network);
            ++refused;
        }
    }
    CHECK(loaded > 5);
    CHECK(refused > 5);
}

TEST_CASE("a map loads when at most 16 lanes and crosswalks pass through one place, and is refused above") {
    // N lanelets stacked on each other (the same two ways, or ways of their own a little apart)
    // and C crosswalks along them: loaded up to 16 lines at one place, else a located error
    // naming the first lanelet there (fuzz finding 18: 500 stacked lanelets took 21 s).
    std::mt19937 rng(18);
    int loaded = 0, refused = 0;
    for (int round = 0; round < 40; ++round) {
        const int n = 1 + static_cast<int>(rng() % 24), c = static_cast<int>(rng() % 4);
        const bool shared = rng() % 2 == 0;
        const double length = 20 + static_cast<double>(rng() % 400);
        std::ostringstream ll2;
        ll2 << "<osm>";
        auto node = [&](int id, double x, double y) {
            ll2 << "<node id='" << id << "' lat='0' lon='0'><tag k='local_x' v='" << x << "'/><tag k='local_y' v='" << y
                << "'/></node>";
        };
        auto way = [&](int id, int a, int b) { ll2 << "<way id='" << id << "'><nd ref='" << a << "'/><nd ref='" << b << "'/></way>"; };
        auto lanelet = [&](int id, int left, int right, const char* subtype) {
            ll2 << "<relation id='" << id << "'><member type='way' ref='" << left << "' role='left'/><member type='way' ref='"
                << right << "' role='right'/><tag k='type' v='lanelet'/><tag k='subtype' v='" << subtype << "'/></relation>";
        };
        for (int i = 0; i < n + c; ++i) {
            const int b = 100 + 10 * i;
            const double dy = shared ? 0 : 0.01 * i;
            if (i == 0 || !shared) {
                node(b + 1, 0, dy), node(b + 2, length, dy), node(b + 3, 0, 3.5 + dy), node(b + 4, length, 3.5 + dy);
                way(b + 5, b + 1, b + 2), way(b + 6, b + 3, b + 4);
            }
            const int ways = shared ? 100 : b;
            lanelet(b + 7, ways + 6, ways + 5, i < n ? "road" : "crosswalk");
        }
        ll2 << "</osm>";
        CAPTURE(n);
        CAPTURE(c);
        CAPTURE(shared);
        const auto a = parse_lanelet2(ll2.str());
        if (n + c <= 16) {
            CHECK(a.errors.empty());
            REQUIRE(a.network);
            CHECK(a.network->lanes().size() == static_cast<size_t>(n));
            ++loaded;
        } else {
            REQUIRE(a.errors.size() == 1);
            CHECK(a.errors[0].rfind("lanelet 107: more than 16 lanes and crosswalks pass through the 2 m square at (", 0) == 0);
            CHECK(!a.network);
            ++refused;
        }
    }
    CHECK(loaded > 5);
    CHECK(refused > 5);
}

TEST_CASE("a map loads when at most 96 pieces of centre line lie in any 2 m square, and a folded lanelet is refused") {
    // One to four lanelets side by side whose bounds zigzag up and down a 2 m square F times (each
    // stroke about 1.5 m, three pieces of centre line) before running on: the grid that finds
    // junctions tests the pieces that share a square pair by pair, so a lanelet folded into one
    // square (fuzz finding 20: 8 lanelets folded 500 times each, 560 KB, took 12 s under ASan)
    // must be refused. Oracle: the pieces of each centre line (computed as the reader does) whose
    // box, widened by a micrometre, meets each 2 m square, counted here independently.
    std::mt19937 rng(20);
    int loaded = 0, refused = 0;
    for (int round = 0; round < 40; ++round) {
        const int lanes = 1 + static_cast<int>(rng() % 4), folds = 1 + static_cast<int>(rng() % 40);
        std::ostringstream ll2;
        ll2 << "<osm>";
        int id = 1;
        std::vector<std::vector<Vec2>> bounds;
        for (int b = 0; b <= lanes; ++b) {
            // Bound b at x = 0.1 + 0.4 b: strokes between y = 0.2 and 1.7, then on along y to 100 m
            // through as many nodes again (so that the bounds' middle nodes, which orient them as
            // Lanelet2 does, lie on the straight part).
            std::vector<Vec2> pts;
            const double x = 0.1 + 0.4 * b;
            for (int f = 0; f <= folds; ++f) pts.push_back({x, f % 2 == 0 ? 0.2 : 1.7});
            for (int k = 0; k <= folds + 2; ++k) pts.push_back({x, 5 + 95.0 * k / (folds + 2)});
            const int first = id;
            for (const Vec2& q : pts)
                ll2 << "<node id='" << id++ << "' lat='0' lon='0'><tag k='local_x' v='" << q.x << "'/><tag k='local_y' v='"
                    << q.y << "'/></node>";
            ll2 << "<way id='" << 1000 + b << "'>";
            for (int n = first; n < id; ++n) ll2 << "<nd ref='" << n << "'/>";
            ll2 << "</way>";
            bounds.push_back(pts);
        }
        size_t most = 0;  // the most pieces of centre line in one square
        std::map<std::pair<long, long>, size_t> pieces;
        for (int l = 0; l < lanes; ++l) {
            // Driven up the y axis: the left bound is the one of smaller x.
            ll2 << "<relation id='" << 2000 + l << "'><member type='way' ref='" << 1000 + l
                << "' role='left'/><member type='way' ref='" << 1000 + l + 1
                << "' role='right'/><tag k='type' v='lanelet'/><tag k='subtype' v='road'/></relation>";
            const auto centre = centre_between(bounds[static_cast<size_t>(l)], bounds[static_cast<size_t>(l) + 1]).centre;
            for (size_t k = 0; k + 1 < centre.size(); ++k) {
                const Vec2 a = centre[k], b = centre[k + 1];
                const double w = 1e-6;
                for (long cx = static_cast<long>(std::floor((std::min(a.x, b.x) - w) / 2));
                     cx <= static_cast<long>(std::floor((std::max(a.x, b.x) + w) / 2)); ++cx)
                    for (long cy = static_cast<long>(std::floor((std::min(a.y, b.y) - w) / 2));
                         cy <= static_cast<long>(std::floor((std::max(a.y, b.y) + w) / 2)); ++cy)
                        most = std::max(most, ++pieces[{cx, cy}]);
            }
        }
        ll2 << "</osm>";
        CAPTURE(lanes);
        CAPTURE(folds);
        CAPTURE(most);
        const auto a = parse_lanelet2(ll2.str());
        if (most <= 96) {
            CHECK(a.errors.empty());
            CHECK(a.network);
            ++loaded;
        } else {
            REQUIRE(a.errors.size() == 1);
            // The square of the folds, and the lanelet with the most pieces there: the first of
            // equals, lanelet 2000.
            CHECK(most == pieces[{0, 0}]);
            CHECK(a.errors[0].rfind("lanelet 2000: " + std::to_string(most) + " pieces of lane and crosswalk centre lines lie in "
                                    "the 2 m square at (0, 0)", 0) == 0);
            CHECK(a.errors[0].find("does the lanelet fold back on itself?") != std::string::npos);
            CHECK(!a.network);
            ++refused;
        }
    }
    CHECK(loaded > 5);
    CHECK(refused > 5);
}

}  // namespace lanelet2_test
