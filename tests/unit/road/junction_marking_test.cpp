// mark_junctions: a Lanelet2 map does not say which lanelets form a junction; sdv finds them
// (lanes whose centre lines cross, merge or diverge with an unrelated lane). Pinned by
// properties: on built-in junctions of every size and control, where the builder knows the
// answer, it finds exactly the builder's junction lanes; on the real maps, a lane with a stop
// line (an approach) is never in a junction while the lanes it leads into at a junction are;
// lanes of a plain road are in none.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "runtime/road/builtin_road.h"
#include "runtime/road/lanelet2_reader.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace junction_marking_test {

using namespace sdv::road;

namespace {

const std::string kShared = SDV_SHARED_DIR;

std::vector<char> flags(const RoadNetwork& net) {
    std::vector<char> out;
    for (const auto& l : net.lanes()) out.push_back(l.in_junction ? 1 : 0);
    return out;
}

}  // namespace

TEST_CASE("on built-in junctions, the lanes found are exactly the builder's junction lanes") {
    for (int lanes = 1; lanes <= 3; ++lanes) {
        for (double arm : {30.0, 100.0}) {
            for (auto control : {JunctionSpec::stop_signs, JunctionSpec::traffic_lights, JunctionSpec::two_way_stops,
                                 JunctionSpec::none}) {
                JunctionSpec j;
                j.name = "x";
                j.lanes_per_direction = lanes;
                j.arm_length_m = arm;
                j.control = control;
                auto r = build_junction(j);
                REQUIRE(r.errors.empty());
                RoadNetwork& net = r.network;
                const auto built = flags(net);
                int in = 0;
                for (char f : built) in += f;
                REQUIRE(in > 0);
                for (const auto& l : net.lanes()) net.lane_mut(l.id).in_junction = false;
                mark_junctions(net);
                const auto found = flags(net);
                for (size_t i = 0; i < built.size(); ++i) {
                    CHECK_MESSAGE(found[i] == built[i], "lanes " << lanes << ", arm " << arm << ": lane "
                                                                 << net.lane(static_cast<LaneId>(i)).name
                                                                 << (built[i] ? " is" : " is not") << " in the junction");
                }
            }
        }
    }
}

TEST_CASE("on a plain road no lane is in a junction") {
    for (int forward = 1; forward <= 3; ++forward) {
        RoadSpec spec;
        spec.name = "r";
        spec.lanes_forward = forward;
        spec.lanes_backward = 1;
        spec.segments.push_back({Segment::straight, 100, 0});
        spec.segments.push_back({Segment::arc, 80, 60});
        spec.segments.push_back({Segment::arc, 80, -40});
        auto r = build_road(spec);
        REQUIRE(r.errors.empty());
        mark_junctions(r.network);
        for (const auto& l : r.network.lanes()) CHECK_MESSAGE(!l.in_junction, l.name);
    }
}

TEST_CASE("on the real maps, approaches are never in a junction and what they lead into at one is") {
    const std::string g = kShared + "/data/geoscenario/maps/";
    for (const std::string& file : {g + "ll2_firetower_4waystop.osm", g + "lanelet2_university_weber_alt.osm",
                                    g + "ll2_mapping_example.osm", kShared + "/data/lanelet2/mapping_example.osm"}) {
        CAPTURE(file);
        auto r = load_lanelet2(file);
        REQUIRE(r.network);
        const RoadNetwork& net = *r.network;
        int approaches = 0, junction = 0;
        for (const auto& l : net.lanes()) {
            junction += l.in_junction;
            // An approach: a stop line at its end, leading into two or more lanes (a junction,
            // not a stop line mid-road before a crosswalk).
            if (l.stop_lines.empty() || l.length - l.stop_lines.back().s > 3 || l.successors.size() < 2) continue;
            ++approaches;
            CHECK_MESSAGE(!l.in_junction, "approach " << l.name);
            for (LaneId s : l.successors) CHECK_MESSAGE(net.lane(s).in_junction, l.name << " -> " << net.lane(s).name);
        }
        CHECK(junction > 0);
        MESSAGE(file << ": " << approaches << " approaches, " << junction << " of " << net.lanes().size() << " lanes in junctions");
    }
    // The 4-way stop: its four approaches (the all-way-stop lanelets) lead into junction lanes only.
    auto r = load_lanelet2(g + "ll2_firetower_4waystop.osm");
    REQUIRE(r.network);
    int aws = 0;
    for (const auto& l : r.network->lanes()) {
        if (!l.all_way_stop) continue;
        ++aws;
        CHECK(!l.in_junction);
        REQUIRE(!l.successors.empty());
        for (LaneId s : l.successors) CHECK(r.network->lane(s).in_junction);
    }
    CHECK(aws == 4);
}

}  // namespace junction_marking_test
