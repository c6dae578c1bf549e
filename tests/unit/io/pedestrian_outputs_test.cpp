// The outputs of runs with pedestrians (issue 18): road.json lists the crosswalks (centre,
// bounds, width, the pedestrians' light) and walkways of the road, with the numbers written like
// the rest of road.json, and only when the road has them (road.json of other runs is unchanged);
// `sdv plot` labels pedestrians and draws the pedestrian areas; `sdv view` sizes a pedestrian
// without a summary entry at 0.5 m x 0.5 m.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "runtime/io/plot.h"
#include "runtime/io/recorder.h"
#include "runtime/io/view.h"
#include "tests/unit/io/compile_text.h"
#include "tests/unit/io/temp_dir.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace pedestrian_outputs_test {

using namespace sdv;
using test::TempDir;

namespace {

const char* kZebra = R"(import "std/drive.sdv"
import "std/pedestrian.sdv"
road main {
    lanes 1 forward, 1 backward
    straight 300 m
    crosswalk zebra at 150 m width 4 m
    crosswalk lit at 60 m signalised
}
scenario zebra_crossing {
    road main
    timeout 12 s
    light main.lit { green 10 s  yellow 3 s  red 12 s }
    ego car: sdv { start lane 1 at 20 m  speed 12 m/s  goal lane 1 at 280 m  tree std.drive(speed = 12 m/s) }
    pedestrian anna: sdp { start lane 1 at 130 m offset -5 m  goal lane -1 at 170 m offset -5 m  speed 1.4 m/s  tree std.walk() }
    expect no_collision()
}
)";

io::Recording run(const std::string& text) {
    auto p = test::compile_text(text);
    REQUIRE(p);
    io::Recorder rec;
    auto r = sim::simulate(*p, 0, {}, &rec);
    REQUIRE_MESSAGE(r.error.empty(), r.error);
    return rec.take();
}

double x_of(const nlohmann::json& pt) { return pt.at(0).get<double>(); }
double y_of(const nlohmann::json& pt) { return pt.at(1).get<double>(); }

}  // namespace

TEST_CASE("road.json lists a built-in road's crosswalks with their light, in road.json's number format") {
    const auto rec = run(kZebra);
    const auto road = nlohmann::json::parse(rec.road_json);
    REQUIRE(road.contains("crosswalks"));
    CHECK_FALSE(road.contains("walkways"));
    const auto& cws = road["crosswalks"];
    REQUIRE(cws.size() == 2);
    // In the road's order (as declared).
    CHECK(cws[0]["name"] == "main.zebra");
    CHECK(cws[1]["name"] == "main.lit");
    // An unsignalised crosswalk has no light keys; a signalised road crosswalk's pedestrian
    // signal is the vehicles' light, inverted.
    CHECK_FALSE(cws[0].contains("light"));
    CHECK_FALSE(cws[0].contains("light_inverse"));
    CHECK(cws[1]["light"] == "main.lit");
    CHECK(cws[1]["light_inverse"] == true);
    CHECK(road["lights"][0]["name"] == "main.lit");
    CHECK(cws[0]["width"].get<double>() == 4.0);
    CHECK(cws[1]["width"].get<double>() == 3.0);
    // Across the road at 150 m (the road runs along x): the centre at x = 150 from kerb to kerb,
    // the bounds half the width to either side, parallel to it.
    for (const auto& [c, at, w] : {std::tuple{cws[0], 150.0, 4.0}, std::tuple{cws[1], 60.0, 3.0}}) {
        const std::string name = c["name"].get<std::string>();  // clang 14 cannot capture a binding
        CAPTURE(name);
        const auto& centre = c["centre"];
        REQUIRE(centre.size() >= 2);
        for (const auto& p : centre) CHECK(x_of(p) == doctest::Approx(at));
        CHECK(std::fabs(y_of(centre.front()) - y_of(centre.back())) > 7.0);  // both lanes and the kerbs
        REQUIRE(c["left"].size() == centre.size());
        REQUIRE(c["right"].size() == centre.size());
        for (size_t i = 0; i < centre.size(); ++i) {
            CHECK(std::fabs(x_of(c["left"][i]) - x_of(c["right"][i])) == doctest::Approx(w));
            CHECK((x_of(c["left"][i]) + x_of(c["right"][i])) / 2 == doctest::Approx(at));
        }
    }
    // Numbers as in the lanes: two decimals, points every ~1 m.
    CHECK(rec.road_json.find("],\"crosswalks\":[{\"name\":\"main.zebra\",\"centre\":[[150.00,-5.50],[150.00,-4.50],") != std::string::npos);
    CHECK(rec.road_json.find("\"width\":4.00}") != std::string::npos);
    CHECK(rec.road_json.find("\"width\":3.00,\"light\":\"main.lit\",\"light_inverse\":true}]}\n") != std::string::npos);
    // Deterministic.
    CHECK(run(kZebra).road_json == rec.road_json);
}

TEST_CASE("road.json of a road without pedestrian areas has no crosswalk or walkway keys") {
    const auto rec = run(R"(import "std/drive.sdv"
road r {
    lanes 2 forward
    straight 200 m
}
scenario s {
    road r
    timeout 1 s
    vehicle a: sdv { start lane 1 at 10 m speed 10 m/s tree std.drive() }
    expect timeout()
}
)");
    CHECK(rec.road_json.find("crosswalks") == std::string::npos);
    CHECK(rec.road_json.find("walkways") == std::string::npos);
    // It ends with the lights, as before crosswalks existed.
    const std::string end = "],\"lights\":[]}\n";
    REQUIRE(rec.road_json.size() > end.size());
    CHECK(rec.road_json.substr(rec.road_json.size() - end.size()) == end);
}

TEST_CASE("road.json lists a Lanelet2 map's crosswalk and walkways") {
    const std::string map = std::string(SDV_SHARED_DIR) + "/data/geoscenario/maps/lanelet2_ringroad_pedestrians.osm";
    const auto rec = run(std::string("import \"std/drive.sdv\"\nmap ring {\n file \"") + map +
                         "\"\n origin (43.47110803016, -80.53879884742, 320 m)\n}\n"
                         "scenario s {\n road ring\n timeout 1 s\n"
                         " vehicle a: sdv { start lane \"-5001866\" at 1 m speed 10 m/s tree std.drive() }\n"
                         " expect timeout()\n}\n");
    const auto road = nlohmann::json::parse(rec.road_json);
    // As tests/unit/road/crosswalk_test.cpp counts them: one unsignalised crosswalk, 8 walkways.
    REQUIRE(road["crosswalks"].size() == 1);
    CHECK(road["crosswalks"][0]["name"] == "-5001877");
    CHECK_FALSE(road["crosswalks"][0].contains("light"));
    CHECK(road["crosswalks"][0]["width"].get<double>() > 0.5);
    REQUIRE(road["walkways"].size() == 8);
    for (const auto& w : road["walkways"]) {
        CAPTURE(w.dump().substr(0, 60));
        CHECK_FALSE(w["name"].get<std::string>().empty());
        CHECK(w["left"].size() >= 2);
        CHECK(w["right"].size() >= 2);
        CHECK_FALSE(w.contains("centre"));
        for (const auto& p : w["left"]) CHECK(std::isfinite(x_of(p)));
    }
}

TEST_CASE("sdv plot labels pedestrians and draws crosswalks; sdv view sizes pedestrians") {
    const auto rec = run(kZebra);
    TempDir dir("sdv_pedestrian_outputs_test");
    dir.write("road.json", rec.road_json);
    dir.write("trajectories.csv", rec.trajectories_csv);
    std::string error;
    const std::string svg = io::plot_run(dir.path.string(), error);
    REQUIRE_MESSAGE(error.empty(), error);
    // Both in the map panel and the speed plot's legend, dashed.
    size_t labels = 0;
    const std::string label = ">anna<tspan font-style=\"italic\"> (pedestrian)</tspan></text>";
    for (size_t at = svg.find(label); at != std::string::npos; at = svg.find(label, at + 1)) ++labels;
    CHECK(labels == 2);
    CHECK(svg.find(">car<") != std::string::npos);
    CHECK(svg.find("stroke-dasharray=\"5 3\"") != std::string::npos);
    CHECK(svg.find("fill=\"url(#zebra)\"") != std::string::npos);

    // A view without sizes in summary.json: a pedestrian is 0.5 m x 0.5 m, a vehicle 4.5 m x 1.8 m.
    dir.write("summary.json", "{\"scenario\":\"zebra_crossing\"}");
    const std::string html = io::view_report(dir.path.string(), error);
    REQUIRE_MESSAGE(error.empty(), error);
    CHECK(html.find("\"name\":\"anna\",\"kind\":\"pedestrian\",\"length\":0.5,\"width\":0.5,") != std::string::npos);
    CHECK(html.find("\"name\":\"car\",\"kind\":\"ego\",\"length\":4.5,\"width\":1.8,") != std::string::npos);
    CHECK(html.find("\"crosswalks\":[{") != std::string::npos);
}

}  // namespace pedestrian_outputs_test
