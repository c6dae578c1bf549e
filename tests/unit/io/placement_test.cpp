// Properties of runs on every road shape (issue "exact roads"): a vehicle started at
// `lane L at X m` stands on that lane's centre at arc length X; a vehicle driving round a
// circle or along a long road has continuous, monotone s; the `lane` column names the lane the
// vehicle's centre is in. Scenarios are compiled from text, as a user writes them.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "tests/unit/io/compile_text.h"
#include "runtime/io/recorder.h"
#include "runtime/sim/agents.h"
#include "runtime/sim/world.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace placement_test {

using namespace sdv;

namespace {

// Records where every agent stands at the first tick.
struct FirstTick : sim::RunObserver {
    std::vector<std::array<double, 4>> at;  // x, y, lane s, lane d
    std::vector<std::string> lanes;
    std::vector<road::Vec2> centre;  // the lane centre at the requested s
    std::vector<double> requested;
    void tick(const sim::World& w, int tick, double) override {
        if (tick != 0) return;
        for (const auto& a : w.agents) {
            at.push_back({a.x, a.y, a.lane_s, a.lane_d});
            lanes.push_back(w.net.lane(a.lane).name);
            const double s = a.v->trajectory.empty() ? a.v->start.s : a.v->trajectory.front().position.s;
            centre.push_back(w.net.reference(a.lane).point(s));
        }
    }
};

// The rows of trajectories.csv after its header, as fields (the lane is field 11, s field 9).
std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream csv(text);
    std::string line;
    std::getline(csv, line);
    while (std::getline(csv, line)) {
        std::vector<std::string>& f = rows.emplace_back();
        std::stringstream ls(line);
        for (std::string c; std::getline(ls, c, ',');) f.push_back(c);
    }
    return rows;
}

struct Road {
    const char* name;
    const char* body;
    std::vector<int> lanes;
};

const std::vector<Road>& roads() {
    static const std::vector<Road> r = {
        {"straight", "lanes 2 forward, 1 backward\n straight 400 m", {1, 2}},
        {"arc left", "lanes 1 forward\n arc 200 m radius 150 m left", {1}},
        {"arc right", "lanes 2 forward, 1 backward\n arc 220 m radius 90 m right", {1, 2}},
        {"beyond 180 degrees", "lanes 2 forward\n straight 20 m\n arc 190 m radius 45 m left\n straight 20 m", {1, 2}},
        {"S bend", "lanes 3 forward, 2 backward\n arc 120 m radius 70 m left\n arc 120 m radius 70 m right", {1, 2, 3}},
    };
    return r;
}

}  // namespace

TEST_CASE("a vehicle started at lane L at X m stands on that lane's centre at arc length X") {
    for (const Road& road : roads()) {
        for (int lane : road.lanes) {
            for (double x : {5.0, 60.0, 150.0, 190.0}) {
              for (const char* kind : {"sdv", "trajectory", "static"}) {
                std::ostringstream src;
                src << "import \"std/drive.sdv\"\nroad r {\n " << road.body << "\n}\nscenario s {\n road r\n timeout 0.1 s\n";
                if (std::string(kind) == "sdv") {
                    src << " vehicle a: sdv { start lane " << lane << " at " << x << " m speed 10 m/s tree std.drive() }\n";
                } else if (std::string(kind) == "trajectory") {
                    src << " vehicle a: trajectory { trajectory {\n 0 s: lane " << lane << " at " << x << " m\n 10 s: lane " << lane
                        << " at " << x + 1 << " m\n } }\n";
                } else {
                    src << " object a { start lane " << lane << " at " << x << " m }\n";
                }
                src << " expect timeout()\n}\n";
                auto p = test::compile_text(src.str());
                INFO(std::string(road.name) << " lane " << lane << " at " << x << " m");
                REQUIRE(p);
                FirstTick seen;
                auto r = sim::simulate(*p, 0, {}, &seen);
                if (!r.error.empty()) {
                    // Only beyond the lane's end (a right lane of a left arc is shorter).
                    CHECK(r.error.find("is off lane") != std::string::npos);
                    continue;
                }
                REQUIRE(seen.at.size() == 1);
                CHECK(std::hypot(seen.at[0][0] - seen.centre[0].x, seen.at[0][1] - seen.centre[0].y) < 0.01);
                CHECK(std::fabs(seen.at[0][2] - x) < 0.01);
                CHECK(std::fabs(seen.at[0][3]) < 0.01);
              }
            }
        }
    }
}

TEST_CASE("driving round a circle and along a long S-bend road, s grows continuously") {
    const char* kRoads[] = {
        "lanes 1 forward\n arc 370 m radius 60 m left",          // almost a full circle
        "lanes 1 forward\n arc 310 m radius 50 m right",         // 355 degrees of a tight circle
        "lanes 2 forward, 1 backward\n straight 100 m\n arc 250 m radius 80 m left\n arc 250 m radius 80 m right\n straight 400 m",
    };
    for (const char* body : kRoads) {
        std::ostringstream src;
        src << "import \"std/drive.sdv\"\nroad r {\n " << body << "\n}\nscenario s {\n road r\n timeout 28 s\n"
            << " vehicle a: sdv { start lane 1 at 3 m speed 10 m/s tree std.drive(speed = 10 m/s) }\n"
            << " expect timeout()\n}\n";
        auto p = test::compile_text(src.str());
        INFO(std::string(body));
        REQUIRE(p);
        io::Recorder rec;
        auto r = sim::simulate(*p, 0, {}, &rec);
        REQUIRE(r.error.empty());
        double prev_s = -1;
        std::string prev_lane;
        int rows = 0, jumps = 0;
        double worst = 0;
        for (const auto& f : csv_rows(rec.take().trajectories_csv)) {
            REQUIRE(f.size() >= 12);
            const double s = std::stod(f[9]);
            if (!prev_lane.empty() && f[11] == prev_lane) {
                const double ds = s - prev_s;
                // 10 m/s at 30 Hz: 0.33 m per tick.
                if (ds < -1e-6 || ds > 0.5) {
                    ++jumps;
                    worst = std::max(worst, std::fabs(ds));
                }
            }
            prev_s = s;
            prev_lane = f[11];
            ++rows;
        }
        CHECK(rows > 800);
        INFO("worst step " << worst);
        CHECK(jumps == 0);
    }
}

TEST_CASE("round a loop of 21 lanelets of a Lanelet2 ring road, s grows continuously in every lanelet") {
    // The ring of shared/data/geoscenario/maps/lanelet2_ringroad.osm (found in the golden
    // successor table of tests/golden/lanelet2): one lap by a route through it, then on.
    const std::string map = std::string(SDV_SHARED_DIR) + "/data/geoscenario/maps/lanelet2_ringroad.osm";
    std::ostringstream src;
    src << "import \"std/drive.sdv\"\nmap ring {\n file \"" << map << "\"\n origin (43.47110803016, -80.53879884742, 320 m)\n}\n"
        << "scenario loop {\n road ring\n timeout 300 s\n"
        << " vehicle a: sdv {\n  start lane \"-7226\" at 1 m\n  speed 15 m/s\n"
        << "  route lane \"-7036\", lane \"-7020\", lane \"-7008\", lane \"-6996\", lane \"-7094\", lane \"-7226\"\n"
        << "  tree std.drive(speed = 15 m/s)\n }\n expect timeout()\n}\n";
    auto p = test::compile_text(src.str());
    REQUIRE(p);
    io::Recorder rec;
    auto r = sim::simulate(*p, 0, {}, &rec);
    REQUIRE(r.error.empty());
    for (const auto& e : r.events) CHECK_MESSAGE(e.kind != "left_road", "left the road at " << e.time << " s");
    double prev_s = -1;
    std::string prev_lane;
    std::vector<std::string> lanes;
    int jumps = 0;
    for (const auto& f : csv_rows(rec.take().trajectories_csv)) {
        REQUIRE(f.size() >= 12);
        const double s = std::stod(f[9]);
        if (f[11] == prev_lane && (s - prev_s < -1e-6 || s - prev_s > 1.0)) ++jumps;  // 0.5 m a tick at 15 m/s
        if (f[11] != prev_lane && !f[11].empty()) lanes.push_back(f[11]);
        prev_s = s;
        prev_lane = f[11];
    }
    CHECK(jumps == 0);
    // More than a lap (about 2.6 km): the start lanelet comes round again.
    CHECK(std::count(lanes.begin(), lanes.end(), "-7226") >= 2);
}

}  // namespace placement_test
