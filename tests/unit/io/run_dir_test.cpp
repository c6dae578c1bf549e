// Reading a run directory back (`sdv view`, `sdv plot`; runtime/io/run_dir.h): every file is
// untrusted input. Properties: a real run's directory makes a report and a plot; a cell that is
// not a number, a tick beyond the limit or an agent skipping ticks is refused with the file, the
// row and the reason, by both; whatever the names hold, the report's data is JSON that keeps
// them and the plot is XML whose labels are them; wrongly typed JSON fields never throw.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>
#include <pugixml.hpp>

#include <cmath>
#include <cstdio>
#include <random>
#include <regex>
#include <string>
#include <vector>

#include "runtime/io/plot.h"
#include "runtime/io/run_dir.h"
#include "runtime/io/view.h"
#include "runtime/road/reader_text.h"
#include "tests/unit/io/csv_lines.h"
#include "tests/unit/io/temp_dir.h"
#include "tests/unit/io/traced_run.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace run_dir_test {

using namespace sdv;
using test::TempDir;
using test::cells_of;
using test::joined;
using test::lines_of;
using test::row_of;
using Json = nlohmann::json;

namespace {

const char* kTwoCars = R"(import "std/drive.sdv"
road r {
    lanes 2 forward
    straight 400 m
}
scenario two_cars {
    road r
    timeout 3 s
    ego car: sdv { start lane 1 at 20 m  speed 12 m/s  tree std.drive(speed = 12 m/s) }
    vehicle truck: sdv { start lane 2 at 60 m  speed 10 m/s  tree std.drive(speed = 10 m/s) }
    expect no_collision()
}
)";

// The files of a real run directory of kTwoCars with its decision trace (written once).
struct RealRun {
    std::string trajectories, summary, road, decisions;
};

const RealRun& real_run() {
    static const RealRun run = [] {
        TempDir dir("sdv_run_dir_test_real");
        test::write_traced_run(kTwoCars, dir.path.string());
        RealRun out;
        REQUIRE(road::read_file((dir.path / "trajectories.csv").string(), out.trajectories));
        REQUIRE(road::read_file((dir.path / "summary.json").string(), out.summary));
        REQUIRE(road::read_file((dir.path / "road.json").string(), out.road));
        REQUIRE(road::read_file((dir.path / "decisions.jsonl").string(), out.decisions));
        return out;
    }();
    return run;
}

struct Reports {
    std::string html, view_error, svg, plot_error;
};

Reports reports(const TempDir& dir) {
    Reports r;
    r.html = io::view_report(dir.path.string(), r.view_error);
    r.svg = io::plot_run(dir.path.string(), r.plot_error);
    return r;
}

// The JSON the page reads (between the template's text before and after its placeholder).
Json view_data(const std::string& html) {
    const std::string_view page = io::viewer_template();
    const size_t at = page.find("__SDV_DATA__");
    REQUIRE(at != std::string_view::npos);
    const size_t tail = page.size() - at - std::string_view("__SDV_DATA__").size();
    REQUIRE(html.size() >= at + tail);
    return Json::parse(html.substr(at, html.size() - at - tail), nullptr, false);
}

}  // namespace

TEST_CASE("is_plain_number accepts exactly the numbers the outputs write, which are JSON numbers") {
    const std::regex plain("-?(0|[1-9][0-9]*)(\\.[0-9]+)?");
    std::mt19937 rng(7);
    const std::string alphabet = "-0123456789.e+ ,xn";
    for (int k = 0; k < 20000; ++k) {
        std::string t(rng() % 8, ' ');
        for (auto& c : t) c = alphabet[rng() % alphabet.size()];
        CAPTURE(t);
        const bool ok = io::is_plain_number(t);
        CHECK(ok == std::regex_match(t, plain));
        if (ok) CHECK(Json::parse(t, nullptr, false).is_number());
    }
    // Whatever sim::fmt writes of a finite value.
    for (int k = 0; k < 20000; ++k) {
        const double v = std::ldexp(static_cast<double>(rng()) / 4294967296.0 - 0.5, static_cast<int>(rng() % 80) - 40);
        CAPTURE(v);
        CHECK(io::is_plain_number(sim::fmt(v)));
        CHECK(io::is_plain_number(sim::fmt(v, 2)));
    }
    for (const char* t : {"nan", "-nan", "inf", "-inf", "1e5", "1.", ".5", "-", "", "01", "-01.5", "1.5.5", " 1", "1 "}) {
        CAPTURE(t);
        CHECK_FALSE(io::is_plain_number(t));
    }
}

TEST_CASE("a real run's directory makes a report and a plot") {
    const RealRun& run = real_run();
    TempDir dir("sdv_run_dir_test_real_reports");
    dir.write("trajectories.csv", run.trajectories);
    dir.write("summary.json", run.summary);
    dir.write("road.json", run.road);
    dir.write("decisions.jsonl", run.decisions);
    const Reports r = reports(dir);
    REQUIRE_MESSAGE(r.view_error.empty(), r.view_error);
    REQUIRE_MESSAGE(r.plot_error.empty(), r.plot_error);
    const Json data = view_data(r.html);
    REQUIRE(data.is_object());
    CHECK(data["scenario"] == "two_cars");
    REQUIRE(data["vehicles"].size() == 2);
    CHECK(data["vehicles"][0]["name"] == "car");
    CHECK(data["vehicles"][0]["x"].size() == data["times"].size());
    CHECK(data["decisions"].size() == lines_of(run.decisions).size());
    pugi::xml_document svg;
    REQUIRE(svg.load_string(r.svg.c_str()));
}

TEST_CASE("a cell that is not a number is refused with its file, row and column, by view and plot") {
    const RealRun& run = real_run();
    const auto lines = lines_of(run.trajectories);
    REQUIRE(lines.size() > 20);
    const char* names[] = {"time", "tick", "vehicle", "kind", "x", "y", "yaw", "speed", "accel", "s", "d"};
    const char* bad[] = {"nan", "inf", "abc", "1e3", "", "01", "1.", "-", "1]}", "\"1\"", "0x10", "1,5"};
    std::mt19937 rng(11);
    TempDir dir("sdv_run_dir_test_cells");
    dir.write("summary.json", run.summary);
    dir.write("road.json", run.road);
    for (int k = 0; k < 200; ++k) {
        auto mutated = lines;
        const size_t row = 1 + rng() % (lines.size() - 1);
        const size_t numeric[] = {0, 4, 5, 6, 7, 8, 9, 10};
        const size_t col = numeric[rng() % 8];
        auto cells = cells_of(mutated[row]);
        const std::string value = bad[rng() % std::size(bad)];
        cells[col] = value;
        mutated[row] = row_of(cells);
        dir.write("trajectories.csv", joined(mutated));
        CAPTURE(mutated[row]);
        const Reports r = reports(dir);
        CHECK(r.html.empty());
        CHECK(r.svg.empty());
        const std::string where = "trajectories.csv:" + std::to_string(row + 1) + ": ";
        // A comma in the value adds a column: the row has 14.
        const std::string what = value.find(',') != std::string::npos
                                     ? std::string("expected 13 columns, found more")
                                     : std::string("column '") + names[col] + "' is not a number: '" + value + "'";
        CHECK_MESSAGE(r.view_error.find(where + what) != std::string::npos, r.view_error);
        CHECK_MESSAGE(r.plot_error.find(where + what) != std::string::npos, r.plot_error);
    }
}

TEST_CASE("ticks: from 0 to the limit, each agent at every tick from its first to its last") {
    TempDir dir("sdv_run_dir_test_ticks");
    dir.write("summary.json", R"({"scenario":"t"})");
    dir.write("road.json", R"({"lanes":[]})");
    const std::string header = std::string(io::kTrajectoriesHeader) + "\n";
    auto row = [](long tick, const std::string& name) {
        return "0.0000," + std::to_string(tick) + "," + name + ",sdv,1.0000,2.0000,0.0000,3.0000,0.0000,1.0000,0.0000,a.1,keep\n";
    };
    // An agent that enters later (its first tick after the others'): placed from its first tick.
    dir.write("trajectories.csv", header + row(0, "a") + row(1, "a") + row(2, "a") + row(2, "b") + row(3, "b"));
    Reports r = reports(dir);
    REQUIRE_MESSAGE(r.view_error.empty(), r.view_error);
    CHECK(r.plot_error.empty());
    Json data = view_data(r.html);
    CHECK(data["times"].size() == 4);
    CHECK(data["vehicles"][1]["first"] == 2);
    CHECK(data["vehicles"][1]["x"].size() == 2);

    dir.write("trajectories.csv", header + row(0, "a") + row(1, "a") + row(3, "a"));
    r = reports(dir);
    CHECK(r.html.empty());
    CHECK_MESSAGE(r.view_error.find("trajectories.csv:4: agent \"a\" at tick 3 after tick 1") != std::string::npos, r.view_error);
    dir.write("trajectories.csv", header + row(0, "a") + row(0, "a"));
    r = reports(dir);
    CHECK_MESSAGE(r.view_error.find("trajectories.csv:3: agent \"a\" at tick 0 after tick 0") != std::string::npos, r.view_error);

    // At most 100,000 ticks without a row before a row (one row at tick 99,999,999, 166 bytes,
    // asked for 2.2 GB of report data); a plot has no such limit, its data being the rows.
    for (const long tick : {io::kMaxEmptyTicks, io::kMaxEmptyTicks + 1, 3 * io::kMaxEmptyTicks}) {
        CAPTURE(tick);
        dir.write("trajectories.csv", header + row(0, "a") + row(tick, "b") + row(tick + 1, "b"));
        r = reports(dir);
        CHECK_MESSAGE(r.plot_error.empty(), r.plot_error);
        if (tick - 1 <= io::kMaxEmptyTicks) {
            REQUIRE_MESSAGE(r.view_error.empty(), r.view_error);
            CHECK(view_data(r.html)["times"].size() == static_cast<size_t>(tick) + 2);
        } else {
            CHECK(r.html.empty());
            const std::string what = "trajectories.csv:3: tick " + std::to_string(tick) + " leaves " + std::to_string(tick - 1) +
                                     " ticks without a row before it";
            CHECK_MESSAGE(r.view_error.find(what) != std::string::npos, r.view_error);
        }
    }
    // Ticks beyond any run's, or not whole numbers.
    for (const std::string& tick : {std::to_string(io::kMaxRunTicks + 1), std::string("99999999999999999999"), std::string("-1"),
                                   std::string("1.5"), std::string("")}) {
        std::string line = row(0, "a");
        line.replace(line.find(",0,"), 3, "," + tick + ",");
        dir.write("trajectories.csv", header + line);
        r = reports(dir);
        CAPTURE(tick);
        CHECK(r.html.empty());
        CHECK(r.svg.empty());
        const std::string what = "trajectories.csv:2: tick '" + tick + "' is not a whole number from 0 to 86400000";
        CHECK_MESSAGE(r.view_error.find(what) != std::string::npos, r.view_error);
        CHECK_MESSAGE(r.plot_error.find(what) != std::string::npos, r.plot_error);
    }
}

TEST_CASE("names keep their text in the report's JSON and the plot's labels, whatever they hold") {
    TempDir dir("sdv_run_dir_test_names");
    dir.write("summary.json", R"({"scenario":"n","metrics":{"vehicles":[{"vehicle":"a","length":5,"width":2}]}})");
    dir.write("road.json", R"({"lanes":[]})");
    const std::string header = std::string(io::kTrajectoriesHeader) + "\n";
    const std::vector<std::string> names = {
        "</text><script>alert(1)</script><text>", "a&b", "\"quoted\"", "<!--", "</script>", "tab\there",
        "caf\xC3\xA9", "\xFF\xFE", "ctrl\x01", "{\"x\":1}", "]}", "pedestrian"};
    for (const auto& name : names) {
        CAPTURE(name);
        const bool pedestrian = name == "pedestrian";
        dir.write("trajectories.csv", header + "0.0000,0," + name + "," + (pedestrian ? "pedestrian" : "sdv") +
                                          ",1.0000,2.0000,0.0000,3.0000,0.0000,1.0000,0.0000," + name + "," + name + "\n");
        const Reports r = reports(dir);
        REQUIRE_MESSAGE(r.view_error.empty(), r.view_error);
        REQUIRE_MESSAGE(r.plot_error.empty(), r.plot_error);
        CHECK(r.html.find("</script><script>alert") == std::string::npos);
        const Json data = view_data(r.html);
        REQUIRE(data.is_object());
        // Bytes that are not UTF-8 become U+FFFD; everything else is kept.
        const std::string kept = name == "\xFF\xFE" ? "\xEF\xBF\xBD\xEF\xBF\xBD" : name;
        CHECK(data["vehicles"][0]["name"] == kept);
        CHECK(data["lanes"][0] == kept);
        CHECK(data["maneuvers"][0] == kept);
        pugi::xml_document svg;
        REQUIRE(svg.load_string(r.svg.c_str()));
        // The elements of a plot, and one label per agent in each panel, whose text is the name
        // (control characters, which XML 1.0 does not allow, left out).
        for (auto node : svg.select_nodes("//*")) {
            const std::string element = node.node().name();
            CHECK_MESSAGE(std::string(" svg rect g polyline circle text tspan defs pattern ").find(" " + element + " ") != std::string::npos,
                          element);
        }
        const std::string label = name == "ctrl\x01" ? "ctrl" : kept;
        auto labels = svg.select_nodes("//g[@id='paths']/text");
        REQUIRE(labels.size() == 1);
        CHECK(std::string(labels.first().node().first_child().value()) == label);
        if (pedestrian) CHECK(std::string(labels.first().node().child("tspan").text().get()) == " (pedestrian)");
    }
}

TEST_CASE("JSON fields of the wrong type are left aside, never thrown on") {
    TempDir dir("sdv_run_dir_test_types");
    const std::string header = std::string(io::kTrajectoriesHeader) + "\n";
    dir.write("trajectories.csv", header + "0.0000,0,a,sdv,1.0000,2.0000,0.0000,3.0000,0.0000,1.0000,0.0000,l,m\n");
    const std::vector<std::pair<std::string, std::string>> summaries_roads = {
        {R"({"scenario":5})", R"({"lanes":[[1,2],5,"x",null]})"},
        {R"({"metrics":{"vehicles":[{"vehicle":1,"length":"5","width":[]}, 7, "x"]}})", R"({"lanes":[{"left":5,"right":"x","centre":[[1,"a"],[2]]}]})"},
        {R"({"metrics":{"vehicles":{"vehicle":"a"}}})", R"({"lanes":[],"walkways":[5,{"left":[[0,0],[1,1]],"right":"x"}],"crosswalks":{"a":1}})"},
        {R"({"metrics":[]})", R"({"lanes":[{"left":[[0,0],[1e308,1e308]]}]})"},
    };
    for (const auto& summary_road : summaries_roads) {
        // Named copies: clang 14 cannot capture structured bindings in CAPTURE's lambda.
        const std::string& summary = summary_road.first;
        const std::string& road = summary_road.second;
        CAPTURE(summary);
        CAPTURE(road);
        dir.write("summary.json", summary);
        dir.write("road.json", road);
        dir.write("decisions.jsonl", R"({"nodes":[{"node":5,"status":[]},3],"paths":[{"status":1,"xy":[1,2,3,4,5,6,7,8,9,10,11,"x"]}],"rejected":[]})"
                                     "\n" R"({"nodes":5,"cost":{"a":"b"},"start":{"x":1}})" "\n");
        Reports r;
        CHECK_NOTHROW(r = reports(dir));
        REQUIRE_MESSAGE(r.view_error.empty(), r.view_error);
        CHECK(view_data(r.html).is_object());
        CHECK_MESSAGE(r.plot_error.empty(), r.plot_error);
    }
    // A road without an array of lanes: the plot says so, the report shows the run anyway.
    dir.write("summary.json", "{}");
    for (const char* road : {R"({"lanes":5})", R"([1,2])", R"({})"}) {
        dir.write("road.json", road);
        const Reports r = reports(dir);
        CHECK(r.view_error.empty());
        CHECK(r.svg.empty());
        CHECK(r.plot_error.find("road.json") != std::string::npos);
    }
}

TEST_CASE("JSON nested deeper than 64 levels is refused before it is parsed (writing it back recurses per level)") {
    TempDir dir("sdv_run_dir_test_depth");
    const std::string header = std::string(io::kTrajectoriesHeader) + "\n";
    dir.write("trajectories.csv", header + "0.0000,0,a,sdv,1.0000,2.0000,0.0000,3.0000,0.0000,1.0000,0.0000,l,m\n");
    // {"lanes":[],"x":[[...]]} with `levels` levels in all ("[" inside a string does not count).
    auto nested = [](int levels) {
        return R"({"lanes":[],"s":"[[[[","x":)" + std::string(static_cast<size_t>(levels - 1), '[') +
               std::string(static_cast<size_t>(levels - 1), ']') + "}";
    };
    for (const char* file : {"summary.json", "road.json", "decisions.jsonl"}) {
        CAPTURE(file);
        dir.write("summary.json", "{}");
        dir.write("road.json", R"({"lanes":[]})");
        dir.write("decisions.jsonl", "{}\n");
        dir.write(file, nested(64));
        Reports r = reports(dir);
        CHECK_MESSAGE(r.view_error.empty(), r.view_error);
        CHECK_MESSAGE(r.plot_error.empty(), r.plot_error);
        dir.write(file, nested(65));
        r = reports(dir);
        CHECK(r.html.empty());
        const std::string what = std::string(file) + (std::string(file) == "decisions.jsonl" ? ":1" : "") +
                                 ": JSON nested more than 64 levels deep";
        CHECK_MESSAGE(r.view_error.find(what) != std::string::npos, r.view_error);
        if (std::string(file) == "road.json") CHECK_MESSAGE(r.plot_error.find(what) != std::string::npos, r.plot_error);
    }
}

TEST_CASE("recorded.csv: finite numbers or a located error") {
    TempDir dir("sdv_run_dir_test_recorded");
    const std::string header = std::string(io::kTrajectoriesHeader) + "\n";
    std::string csv = header;
    for (int k = 0; k < 10; ++k) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "%.4f,%d,a,sdv,%d.0000,0.0000,0.0000,3.0000,0.0000,1.0000,0.0000,l,m\n", k / 10.0, k, k);
        csv += buf;
    }
    dir.write("trajectories.csv", csv);
    dir.write("summary.json", "{}");
    dir.write("recorded.csv", "vehicle,t,x,y,heading,speed\nv1,0.000,0.0,0.0,0.0,1.0\nv1,1.000,1.0,0.0,0.0,1.0\n");
    std::string error;
    std::string html = io::view_report(dir.path.string(), error);
    REQUIRE_MESSAGE(error.empty(), error);
    Json data = view_data(html);
    REQUIRE(data["vehicles"].size() == 2);
    CHECK(data["vehicles"][1]["name"] == "v1 recorded");
    CHECK(data["vehicles"][1]["x"].size() == 10);
    for (const char* value : {"nan", "inf", "1e300", "x", ""}) {
        CAPTURE(value);
        dir.write("recorded.csv", std::string("vehicle,t,x,y,heading,speed\nv1,0.000,0.0,0.0,0.0,1.0\nv1,1.000,") + value + ",0.0,0.0,1.0\n");
        html = io::view_report(dir.path.string(), error);
        CHECK(html.empty());
        CHECK_MESSAGE(error.find("recorded.csv:3: expected vehicle,t,x,y,heading,speed") != std::string::npos, error);
        error.clear();
    }
}

TEST_CASE("a run longer than 100,000 ticks is reported and plotted") {
    TempDir dir("sdv_run_dir_test_long");
    // One car for 100,500 ticks (55.8 min at 30 Hz), a row at every tick as sdv run writes it.
    std::string csv(io::kTrajectoriesHeader);
    csv += "\n";
    char line[160];
    const long ticks = io::kMaxEmptyTicks + 500;
    for (long k = 0; k <= ticks; ++k) {
        std::snprintf(line, sizeof line, "%.4f,%ld,car,sdv,%.4f,0.0000,0.0000,10.0000,0.0000,%.4f,0.0000,a.1,keep\n",
                      static_cast<double>(k) / 30, k, static_cast<double>(k) / 3, static_cast<double>(k) / 3);
        csv += line;
    }
    dir.write("trajectories.csv", csv);
    dir.write("summary.json", R"({"scenario":"long"})");
    dir.write("road.json", R"({"lanes":[]})");
    const Reports r = reports(dir);
    REQUIRE_MESSAGE(r.view_error.empty(), r.view_error);
    REQUIRE_MESSAGE(r.plot_error.empty(), r.plot_error);
    const Json data = view_data(r.html);
    CHECK(data["times"].size() == static_cast<size_t>(ticks) + 1);
    CHECK(data["vehicles"][0]["x"].size() == static_cast<size_t>(ticks) + 1);
}

}  // namespace run_dir_test
