// The readers of recorded traffic on the committed CommonRoad recordings (counts as in
// ../shared/data/recorded/README.md), properties of the networks they build (every recorded
// position on a lane, projections round-trip on every lane, successors continue their
// predecessors), the INTERACTION reader on text, and the comparison metrics.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "runtime/realism/metrics.h"
#include "runtime/realism/recording.h"
#include "runtime/realism/route.h"
#include "runtime/road/commonroad_reader.h"
#include "runtime/road/routing.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace recording_test {

using namespace sdv;

namespace {

std::string recorded(const std::string& name) { return std::string(SDV_SHARED_DIR) + "/data/recorded/commonroad/" + name; }

struct Expected {
    const char* file;
    size_t vehicles;
    size_t states;
    int lanelets;
    size_t lights;
    double duration;
};

// ../shared/data/recorded/README.md, "Files".
const Expected kFiles[] = {
    {"USA_US101-3_3_T-1.xml", 12, 384, 12, 0, 3.1},
    {"USA_US101-4_1_T-1.xml", 22, 1271, 12, 0, 10.0},
    {"USA_Lanker-1_1_T-1.xml", 24, 938, 91, 0, 4.0},
    {"test_reading_complex_tl.xml", 19, 323, 95, 8, 1.6},
    {"USA_Peach-4_8_T-1.xml", 9, 368, 79, 4, 6.0},
};

}  // namespace

TEST_CASE("CommonRoad recordings: agents, states, lanelets and lights as the README counts them") {
    for (const auto& e : kFiles) {
        CAPTURE(e.file);
        const auto rec = realism::read_commonroad(recorded(e.file));
        REQUIRE(rec.errors.empty());
        CHECK(rec.tracks.size() == e.vehicles);
        size_t states = 0;
        for (const auto& t : rec.tracks) {
            states += t.states.size();
            CHECK(t.type == "car");
            CHECK(t.start() == doctest::Approx(0));
            for (size_t i = 1; i < t.states.size(); ++i) CHECK(t.states[i].t - t.states[i - 1].t == doctest::Approx(0.1));
        }
        CHECK(states == e.states);
        CHECK(rec.duration() == doctest::Approx(e.duration).epsilon(0.02));
        CHECK(rec.lights.size() == e.lights);
        const auto net = road::load_commonroad(recorded(e.file));
        REQUIRE(net.errors.empty());
        CHECK(net.lanelets == e.lanelets);
        CHECK(net.network->lights.size() == e.lights);
    }
}

TEST_CASE("every recorded position lies on a lane of its network") {
    for (const auto& e : kFiles) {
        CAPTURE(e.file);
        const auto rec = realism::read_commonroad(recorded(e.file));
        auto net = road::load_commonroad(recorded(e.file)).network;
        REQUIRE(net);
        net->prepare();
        size_t off = 0, all = 0;
        for (const auto& t : rec.tracks) {
            for (const auto& s : t.states) {
                // Any lane: a vehicle turning across a junction may face none of the lanes it is on.
                const auto at = net->locate({s.x, s.y});
                ++all;
                if (at.lane == road::kNoLane || std::fabs(at.d) > 0.5 * net->lane(at.lane).width + 0.5) ++off;
            }
        }
        // The README: every recorded position lies inside some lanelet polygon.
        CHECK(off == 0);
        CHECK(all > 0);
    }
}

TEST_CASE("CommonRoad networks: projections round-trip on every lane; successors continue their lane") {
    for (const auto& e : kFiles) {
        CAPTURE(e.file);
        auto net = road::load_commonroad(recorded(e.file)).network;
        REQUIRE(net);
        for (const auto& lane : net->lanes()) {
            CAPTURE(lane.name);
            const auto& ref = net->reference(lane.id);
            for (double s = 0; s <= ref.length(); s += std::max(0.5, ref.length() / 20)) {
                for (double d : {-1.0, 0.0, 1.0}) {
                    // Within the radius of curvature, where the Frenet frame is one-to-one
                    // (CommonRoad bounds have corners: the smoothed centre line bends sharply).
                    if (std::fabs(d * ref.curvature(s)) > 0.5) continue;
                    const auto c = ref.to_cartesian({s, 0, 0, d, 0, 0});
                    const auto f = ref.project({c.x, c.y}, s);
                    CHECK(f.s == doctest::Approx(s).epsilon(0).scale(1).epsilon(1e-3));
                    CHECK(f.d == doctest::Approx(d).epsilon(1e-3));
                }
            }
            for (road::LaneId next : lane.successors) {
                const double gap = road::distance(lane.centre.back(), net->lane(next).centre.front());
                CHECK_MESSAGE(gap < 1.0, lane.name << " -> " << net->lane(next).name);
            }
            if (lane.left != road::kNoLane) {
                // A neighbour lies beside the lane, about a lane width away.
                const auto mid = lane.centre[lane.centre.size() / 2];
                const auto f = net->reference(lane.left).project(mid);
                CHECK(std::fabs(f.d) < 2.0 * std::max(lane.width, net->lane(lane.left).width));
            }
        }
    }
}

TEST_CASE("traffic-light cycles: CommonRoad's offset becomes how far into the cycle the light is at 0 s") {
    const auto rec = realism::parse_commonroad(R"(<?xml version="1.0"?>
<commonRoad timeStepSize="0.1" commonRoadVersion="2020a">
  <trafficLight id="7">
    <cycle>
      <cycleElement><duration>50</duration><color>red</color></cycleElement>
      <cycleElement><duration>10</duration><color>redYellow</color></cycleElement>
      <cycleElement><duration>100</duration><color>green</color></cycleElement>
      <cycleElement><duration>40</duration><color>yellow</color></cycleElement>
      <timeOffset>30</timeOffset>
    </cycle>
  </trafficLight>
  <dynamicObstacle id="1">
    <type>car</type>
    <shape><rectangle><length>4</length><width>2</width></rectangle></shape>
    <initialState><position><point><x>0</x><y>0</y></point></position><orientation><exact>0</exact></orientation>
      <time><exact>0</exact></time><velocity><exact>1</exact></velocity></initialState>
  </dynamicObstacle>
</commonRoad>)");
    REQUIRE(rec.errors.empty());
    REQUIRE(rec.lights.size() == 1);
    const auto& c = rec.lights[0];
    CHECK(c.light == "tl7");
    REQUIRE(c.phases.size() == 4);
    CHECK(c.phases[1].first == "red");  // red-yellow still means stop
    CHECK(c.phases[2].second == doctest::Approx(10.0));
    CHECK(c.offset == doctest::Approx(20.0 - 3.0));  // the cycle (20 s) starts at 3 s
    CHECK(rec.tracks.size() == 1);
}

TEST_CASE("CommonRoad reader errors name the line and the element") {
    const auto rec = realism::parse_commonroad(R"(<commonRoad timeStepSize="0.1">
  <dynamicObstacle id="5">
    <type>car</type>
    <shape><rectangle><length>4</length><width>2</width></rectangle></shape>
    <initialState><position><point><x>nan</x><y>0</y></point></position></initialState>
  </dynamicObstacle>
</commonRoad>)", "x.xml");
    REQUIRE(rec.errors.size() == 1);
    CHECK(rec.errors[0].rfind("x.xml:5: obstacle 5:", 0) == 0);
    const auto bad = road::parse_commonroad("<commonRoad><lanelet id=\"1\"><leftBound><point><x>0</x><y>0</y></point></leftBound></lanelet></commonRoad>");
    REQUIRE(!bad.errors.empty());
    CHECK(bad.errors[0].rfind("line 1: lanelet 1:", 0) == 0);
}

TEST_CASE("INTERACTION tracks: one track per id, speeds from vx and vy, the time step found") {
    const auto rec = realism::parse_interaction(
        "track_id,frame_id,timestamp_ms,agent_type,x,y,vx,vy,psi_rad,length,width\n"
        "1,1,100,car,10,20,3,4,0.9,4.5,1.9\n"
        "1,2,200,car,10.3,20.4,3,4,0.9,4.5,1.9\n"
        "2,2,200,car,0,0,0,0,0,5,2\n"
        "1,3,300,car,10.6,20.8,3,4,0.9,4.5,1.9\n",
        "t.csv");
    REQUIRE(rec.errors.empty());
    REQUIRE(rec.tracks.size() == 2);
    CHECK(rec.tracks[0].states.size() == 3);
    CHECK(rec.tracks[0].states[0].speed == doctest::Approx(5));
    CHECK(rec.tracks[1].start() == doctest::Approx(0.1));
    CHECK(rec.tracks[1].length == doctest::Approx(5));
    CHECK(rec.dt == doctest::Approx(0.1));
    const auto bad = realism::parse_interaction("track_id,frame_id,timestamp_ms,agent_type,x,y,vx,vy\n1,1,x,car,0,0,0,0\n", "b.csv");
    REQUIRE(bad.errors.size() == 1);
    CHECK(bad.errors[0].rfind("b.csv:2:", 0) == 0);
}

TEST_CASE("STED: 0 for the same path, the offset for a shifted one, only over the common span") {
    std::vector<realism::State> a, b, late;
    for (int i = 0; i <= 30; ++i) {
        const double t = i * 0.1;
        a.push_back({t, 10 * t, 0, 0, 10});
        b.push_back({t, 10 * t, 1.5, 0, 9});
        if (t >= 1.0) late.push_back({t, 10 * t + 2, 0, 0, 10});
    }
    auto same = realism::compare(a, a);
    REQUIRE(same);
    CHECK(same->sted == doctest::Approx(0));
    auto shifted = realism::compare(a, b);
    REQUIRE(shifted);
    CHECK(shifted->sted == doctest::Approx(1.5));
    CHECK(shifted->speed_rmse == doctest::Approx(1));
    CHECK(shifted->samples == 31);
    auto part = realism::compare(a, late);
    REQUIRE(part);
    CHECK(part->span == doctest::Approx(2.0));
    CHECK(part->sted == doctest::Approx(2));
    // A simulated path sampled at 30 Hz against a 10 Hz recording: interpolated.
    std::vector<realism::State> fine;
    for (int i = 0; i <= 90; ++i) fine.push_back({i / 30.0, 10 * i / 30.0, 0, 0, 10});
    CHECK(realism::compare(fine, a)->sted == doctest::Approx(0).epsilon(1e-9));
    CHECK_FALSE(realism::compare(a, {{5.0, 0, 0, 0, 0}}));
}

TEST_CASE("the route of every recorded vehicle is a chain of lanes a vehicle can drive, ending at its goal") {
    for (const auto& e : kFiles) {
        CAPTURE(e.file);
        const auto rec = realism::read_commonroad(recorded(e.file));
        auto net = road::load_commonroad(recorded(e.file)).network;
        REQUIRE(net);
        net->prepare();
        for (const auto& t : rec.tracks) {
            CAPTURE(t.id);
            const auto route = realism::recorded_route(*net, t, 30);
            REQUIRE(route.error.empty());
            REQUIRE(!route.lanes.empty());
            CHECK(route.lanes.back() == route.goal_lane);
            for (size_t i = 1; i < route.lanes.size(); ++i) {
                const auto r = road::shortest_route(*net, route.lanes[i - 1], route.lanes[i]);
                CHECK_MESSAGE(!r.steps.empty(), net->lane(route.lanes[i - 1]).name << " -> " << net->lane(route.lanes[i]).name);
            }
            CHECK(route.goal_s >= 0);
            CHECK(route.goal_s <= net->lane(route.goal_lane).length);
        }
    }
}

}  // namespace recording_test
