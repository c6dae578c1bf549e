// Every agent the readers of recorded traffic accept can be written as a scenario: the sizes they
// accept are the sizes the checker accepts (catalog::AgentSize), so a replay of a recording
// compiles whatever its agents measure. Fuzz finding 24: a CommonRoad car 55 m long was read,
// and its replay did not compile (E0301). Property: the first car of a real recording, resized
// to lengths and widths around the limits, as a rectangle or a circle, is either refused with a
// message naming it, or replays (as the SDV and as a recorded trajectory) to a scenario that
// compiles without errors. The same for INTERACTION tracks on a built road, and for a vehicle's
// recorded speed (finding 31, the last test).
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/recorded/replay.h"
#include "compiler/sema/compile.h"
#include "runtime/catalog/catalog.h"
#include "runtime/realism/recording.h"
#include "runtime/road/commonroad_reader.h"
#include "runtime/road/builtin_road.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace replay_sizes_test {

using namespace sdv;

namespace {

const std::string kFile = std::string(SDV_SHARED_DIR) + "/data/recorded/commonroad/USA_US101-3_3_T-1.xml";
constexpr const char* kShape = "<rectangle>\n        <length>4.1148</length>\n        <width>2.4079</width>\n      </rectangle>";

std::string read(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// The first error of compiling `text`, or "" when it compiles.
std::string compile_error(const std::string& text) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    const auto c = compiler::compile_source("replay.sdv", text, sm, diags);
    for (const auto& d : diags.sorted()) {
        if (d.severity == diag::Severity::error) return d.code + " " + d.message;
    }
    return c.program ? "" : "no program";
}

// Replays `id` as the SDV, and every agent as recorded: both must compile.
void check_replays(const realism::Recording& rec, const road::RoadNetwork& net, const std::string& id) {
    compiler::recorded::ReplaySpec as_sdv;
    as_sdv.sdv = id;
    for (const auto& spec : {as_sdv, compiler::recorded::ReplaySpec{}}) {
        const auto src = compiler::recorded::replay_source(rec, net, spec);
        REQUIRE_MESSAGE(src.error.empty(), src.error);
        CHECK_MESSAGE(compile_error(src.text).empty(), compile_error(src.text));
    }
}

struct Size {
    double length, width;
};

// Sizes within, on and just past each limit, and nonsense.
std::vector<Size> sizes(const catalog::AgentSize& max) {
    std::vector<Size> out;
    const double ls[] = {0.3, 4.5, max.length, max.length + 1e-3, 55.097, 0, -1};
    const double ws[] = {0.3, 1.8, max.width, max.width + 1e-3, 0};
    for (double l : ls)
        for (double w : ws) out.push_back({l, w});
    return out;
}

// A straight road of 200 m, for INTERACTION tracks (their map is not read).
road::BuildResult straight_road() {
    road::RoadSpec spec;
    spec.name = "r";
    spec.segments.push_back({road::Segment::straight, 200, 0});
    auto built = road::build_road(spec);
    REQUIRE(built.errors.empty());
    built.network.prepare();
    return built;
}

}  // namespace

TEST_CASE("a CommonRoad agent the reader accepts replays to a scenario that compiles, at every size") {
    const std::string text = read(kFile);
    REQUIRE(text.find(kShape) != std::string::npos);
    auto net = road::parse_commonroad(text);
    REQUIRE(net.network);
    net.network->prepare();
    const catalog::AgentSize max = catalog::kMaxVehicleSize;
    for (const Size s : sizes(max)) {
        CAPTURE(s.length);
        CAPTURE(s.width);
        std::string t = text;
        t.replace(t.find(kShape), std::string(kShape).size(),
                  "<rectangle><length>" + std::to_string(s.length) + "</length><width>" + std::to_string(s.width) + "</width></rectangle>");
        auto rec = realism::parse_commonroad(t, kFile);
        rec.map_path = kFile;
        const bool fits = s.length > 0 && s.width > 0 && s.length <= max.length && s.width <= max.width;
        if (!fits) {
            REQUIRE(rec.errors.size() == 1);
            CHECK(rec.errors[0].find("obstacle 363: its rectangle needs a length in (0, 30] m and a width in (0, 5] m") !=
                  std::string::npos);
            continue;
        }
        REQUIRE(rec.errors.empty());
        check_replays(rec, *net.network, "363");
    }
    // A circle: its diameter is both length and width.
    for (const double r : {0.2, max.width / 2, max.width / 2 + 1e-3, 20.0}) {
        CAPTURE(r);
        std::string t = text;
        t.replace(t.find(kShape), std::string(kShape).size(), "<circle><radius>" + std::to_string(r) + "</radius></circle>");
        auto rec = realism::parse_commonroad(t, kFile);
        rec.map_path = kFile;
        if (2 * r > max.width) {
            REQUIRE(rec.errors.size() == 1);
            CHECK(rec.errors[0].find("its circle needs a radius in (0, 2.5] m") != std::string::npos);
            continue;
        }
        REQUIRE(rec.errors.empty());
        check_replays(rec, *net.network, "363");
    }
}

TEST_CASE("an INTERACTION track the reader accepts replays to a scenario that compiles, at every size") {
    const road::BuildResult built = straight_road();
    for (const bool pedestrian : {false, true}) {
        const catalog::AgentSize max = pedestrian ? catalog::kMaxPedestrianSize : catalog::kMaxVehicleSize;
        for (const Size s : sizes(max)) {
            CAPTURE(pedestrian);
            CAPTURE(s.length);
            CAPTURE(s.width);
            const std::string type = pedestrian ? "pedestrian/bicycle" : "car";
            std::string csv = "track_id,frame_id,timestamp_ms,agent_type,x,y,vx,vy,psi_rad,length,width\n";
            for (int k = 0; k < 10; ++k) {
                csv += "1," + std::to_string(k) + "," + std::to_string(100 * k) + "," + type + "," + std::to_string(20 + k) +
                       ",-1.75,10,0,0," + std::to_string(s.length) + "," + std::to_string(s.width) + "\n";
            }
            auto rec = realism::parse_interaction(csv, "t.csv");
            rec.map_path = kFile;  // the checker requires the map file to exist, and does not read it
            const bool fits = s.length > 0 && s.width > 0 && s.length <= max.length && s.width <= max.width;
            if (!fits) {
                REQUIRE(!rec.errors.empty());
                CHECK(rec.errors[0].find("t.csv:2: track 1: length and width must be in") == 0);
                continue;
            }
            REQUIRE(rec.errors.empty());
            REQUIRE(rec.tracks.size() == 1);
            CHECK(rec.tracks[0].length == doctest::Approx(s.length));
            if (pedestrian) {
                // A pedestrian is never the SDV: only the recorded replay.
                const auto src = compiler::recorded::replay_source(rec, built.network, {});
                REQUIRE_MESSAGE(src.error.empty(), src.error);
                CHECK_MESSAGE(compile_error(src.text).empty(), compile_error(src.text));
            } else {
                check_replays(rec, built.network, "1");
            }
        }
    }
}

// Finding 31: a CommonRoad car whose initial velocity read 1660.21 m/s (a real recording with a
// few bytes mutated) was accepted, and its replay as the SDV started at that speed, which the
// checker refuses (E0301: a vehicle's speed is 0 to 100 m/s). A vehicle's recorded speed is one
// a scenario's vehicle may have (catalog::kMaxVehicleSpeed), or the reader refuses it, naming
// the obstacle; INTERACTION's (vx, vy) alike.
TEST_CASE("a recorded vehicle's speed is one a scenario's vehicle may start with, or the reader refuses it") {
    const std::string text = read(kFile);
    auto net = road::parse_commonroad(text);
    REQUIRE(net.network);
    net.network->prepare();
    const size_t obstacle = text.find("<obstacle id=\"363\">");
    REQUIRE(obstacle != std::string::npos);
    const size_t begin = text.find("<exact>", text.find("<velocity>", obstacle)) + 7;
    const size_t end = text.find("</exact>", begin);
    const double max = catalog::kMaxVehicleSpeed;
    for (const double v : {0.0, 12.5, max - 1e-3, max, max + 1e-3, 1660.21, -0.5, 1e9}) {
        CAPTURE(v);
        std::string t = text;
        t.replace(begin, end - begin, std::to_string(v));
        auto rec = realism::parse_commonroad(t, kFile);
        rec.map_path = kFile;
        if (!(v >= 0 && v <= max)) {
            REQUIRE(rec.errors.size() == 1);
            CHECK(rec.errors[0].find("obstacle 363: velocity ") != std::string::npos);
            CHECK(rec.errors[0].find(" m/s is not a vehicle's speed, 0 to 100 m/s") != std::string::npos);
            continue;
        }
        REQUIRE(rec.errors.empty());
        check_replays(rec, *net.network, "363");
    }

    const road::BuildResult built = straight_road();
    for (const double vx : {10.0, 70.0, max - 1e-3, max + 1e-3, 141.0, 999.0}) {
        for (const double vy : {0.0, 70.0}) {
            CAPTURE(vx);
            CAPTURE(vy);
            std::string csv = "track_id,frame_id,timestamp_ms,agent_type,x,y,vx,vy,psi_rad,length,width\n";
            for (int k = 0; k < 10; ++k) {
                csv += "1," + std::to_string(k) + "," + std::to_string(100 * k) + ",car," + std::to_string(20 + k) + ",-1.75," +
                       std::to_string(vx) + "," + std::to_string(vy) + ",0,4.5,1.8\n";
            }
            auto rec = realism::parse_interaction(csv, "t.csv");
            rec.map_path = kFile;
            if (std::hypot(vx, vy) > max) {
                REQUIRE(!rec.errors.empty());
                CHECK(rec.errors[0].find("t.csv:2: track 1: speed ") == 0);
                CHECK(rec.errors[0].find(" m/s (vx, vy) is not a vehicle's, 0 to 100 m/s") != std::string::npos);
                continue;
            }
            REQUIRE(rec.errors.empty());
            check_replays(rec, built.network, "1");
        }
    }
}

// Finding 32: the check of finding 31 came after the track was added, so a track whose only row
// was refused for its speed was kept without a state (the campaign of 770002a without sanitizers,
// at about a million executions). A refused row adds no state and no track, wherever it is.
TEST_CASE("an INTERACTION row the reader refuses adds no state and no track, at every position") {
    const double max = catalog::kMaxVehicleSpeed;
    for (int rows = 1; rows <= 4; ++rows) {
        for (int refused = 0; refused < rows; ++refused) {
            for (const std::string why : {"speed", "size", "time"}) {
                CAPTURE(rows);
                CAPTURE(refused);
                CAPTURE(why);
                std::string csv = "track_id,frame_id,timestamp_ms,agent_type,x,y,vx,vy,psi_rad,length,width\n";
                for (int k = 0; k < rows; ++k) {
                    const bool bad = k == refused;
                    const std::string vx = bad && why == "speed" ? std::to_string(max + 1) : "10";
                    const std::string length = bad && why == "size" ? "40" : "4.5";
                    const int ms = bad && why == "time" && k > 0 ? 0 : 100 * k;
                    csv += "7," + std::to_string(k) + "," + std::to_string(ms) + ",car," + std::to_string(20 + k) + ",-1.75," +
                           vx + ",0,0," + length + ",1.8\n";
                }
                // Another track after it, read whatever happened to the first.
                csv += "8,0,0,car,60,-1.75,10,0,0,4.5,1.8\n8,1,100,car,61,-1.75,10,0,0,4.5,1.8\n";
                const auto rec = realism::parse_interaction(csv, "t.csv");
                // A length is read from a track's first row only, and the first row has no time
                // before it: a later row of another size, or a first row at time 0, is no error.
                const bool refuses = why == "speed" || (why == "size" && refused == 0) || (why == "time" && refused > 0);
                CHECK(rec.errors.size() == (refuses ? 1u : 0u));
                size_t states7 = 0;
                for (const auto& t : rec.tracks) {
                    CHECK(!t.states.empty());
                    if (t.id == "7") states7 = t.states.size();
                }
                const size_t kept = static_cast<size_t>(refuses ? rows - 1 : rows);
                CHECK(states7 == kept);
                CHECK(rec.tracks.size() == (kept > 0 ? 2u : 1u));
            }
        }
    }
}

}  // namespace replay_sizes_test
