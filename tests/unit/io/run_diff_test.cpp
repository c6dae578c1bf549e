// `sdv diff --runs` (runtime/io/run_diff.h): where two runs first differ, read from run
// directories as untrusted input. Properties: a run equals itself; any change beyond the
// tolerance to a row is found at its tick, with every agent changed there, whichever run comes
// first; an agent's rows cut short are missing from that run from the first tick cut; a file
// that is not what sdv run writes is refused with the file and the line, whichever run holds it;
// decision lines of any shape are compared without throwing; the JSON output parses whatever
// the names hold.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "runtime/io/run_diff.h"
#include "runtime/road/reader_text.h"
#include "tests/unit/io/csv_lines.h"
#include "tests/unit/io/temp_dir.h"
#include "tests/unit/io/traced_run.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace run_diff_test {

using namespace sdv;
using test::TempDir;
using test::cells_of;
using test::joined;
using test::lines_of;
using test::row_of;
using Json = nlohmann::json;

namespace {

// Two cars; the truck's speed is the parameter the runs differ in.
std::string two_cars(const std::string& truck_speed) {
    return R"(import "std/drive.sdv"
road r {
    lanes 2 forward
    straight 400 m
}
scenario two_cars {
    road r
    timeout 3 s
    ego car: sdv { start lane 1 at 20 m  speed 12 m/s  tree std.drive(speed = 12 m/s) }
    vehicle truck: sdv { start lane 2 at 60 m  speed 10 m/s  tree std.drive(speed = )" +
           truck_speed + R"( m/s) }
    expect no_collision()
}
)";
}

struct RunFiles {
    std::string trajectories, decisions;
};

// trajectories.csv and decisions.jsonl of a traced run of two_cars(truck_speed).
RunFiles run_files(const std::string& truck_speed) {
    TempDir dir("sdv_run_diff_test_real");
    test::write_traced_run(two_cars(truck_speed), dir.path.string());
    RunFiles out;
    REQUIRE(road::read_file((dir.path / "trajectories.csv").string(), out.trajectories));
    REQUIRE(road::read_file((dir.path / "decisions.jsonl").string(), out.decisions));
    return out;
}

const RunFiles& base_run() {
    static const RunFiles run = run_files("10");
    return run;
}

// Two run directories side by side.
struct Pair {
    TempDir a{"sdv_run_diff_test_a"}, b{"sdv_run_diff_test_b"};
    void write(const RunFiles& ra, const RunFiles& rb) const {
        a.write("trajectories.csv", ra.trajectories);
        b.write("trajectories.csv", rb.trajectories);
        if (!ra.decisions.empty()) a.write("decisions.jsonl", ra.decisions);
        if (!rb.decisions.empty()) b.write("decisions.jsonl", rb.decisions);
    }
    io::RunDiff forward() const { return io::diff_runs(a.path.string(), b.path.string()); }
    io::RunDiff backward() const { return io::diff_runs(b.path.string(), a.path.string()); }
};

std::string fixed4(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.4f", v);
    return buf;
}

// The JSON output parses, and says what the diff says.
void check_json(const io::RunDiff& d) {
    const Json j = Json::parse(io::render_json(d), nullptr, false);
    REQUIRE(j.is_object());
    CHECK(j["equal"] == d.equal);
    CHECK(j.contains("first_tick") == (d.first_tick >= 0));
    CHECK(j.contains("decision") == !d.decision_detail.empty());
}

}  // namespace

TEST_CASE("a run equals itself; a changed parameter diverges the same way whichever run comes first") {
    const RunFiles& a = base_run();
    const RunFiles b = run_files("10.5");
    Pair same;
    same.write(a, a);
    const io::RunDiff self = same.forward();
    CHECK_MESSAGE(self.error.empty(), self.error);
    CHECK(self.equal);
    CHECK(self.has_decisions);
    CHECK(io::render_text(self) == "runs are equal\n");
    check_json(self);

    Pair other;
    other.write(a, b);
    const io::RunDiff f = other.forward(), r = other.backward();
    REQUIRE(f.error.empty());
    REQUIRE(r.error.empty());
    CHECK_FALSE(f.equal);
    CHECK_FALSE(r.equal);
    CHECK(f.first_tick > 0);
    CHECK(f.first_tick == r.first_tick);
    CHECK(f.vehicles == r.vehicles);
    CHECK(std::find(f.vehicles.begin(), f.vehicles.end(), "truck") != f.vehicles.end());
    CHECK_FALSE(f.decision_detail.empty());
    CHECK(f.decision_time == r.decision_time);
    CHECK(f.decision_vehicle == r.decision_vehicle);
    check_json(f);
    check_json(r);
}

TEST_CASE("every change beyond the tolerance is found at its tick, with every agent changed there") {
    const std::vector<std::string> lines = lines_of(base_run().trajectories);
    REQUIRE(lines.size() > 100);
    std::mt19937 rng(20261129);
    for (int trial = 0; trial < 200; ++trial) {
        CAPTURE(trial);
        std::vector<std::string> changed = lines;
        const bool within = trial % 5 == 0;  // every fifth trial changes less than the tolerance
        std::map<long, std::set<std::string>> at;  // the agents changed, by tick
        std::map<std::pair<long, std::string>, bool> moved;  // a position changed, else the speed
        std::set<size_t> rows;  // one change per row: two on one cell could cancel out
        while (rows.size() < 1 + rng() % 3) rows.insert(1 + rng() % (lines.size() - 1));
        for (const size_t row : rows) {
            auto cells = cells_of(changed[row]);
            const size_t column = std::vector<size_t>{4, 5, 7}[rng() % 3];  // x, y, speed
            const double size = within ? 0.0001 * static_cast<double>(1 + rng() % 4) : 0.002 + static_cast<double>(rng() % 100000) / 1000;
            const double delta = rng() % 2 ? size : -size;
            cells[column] = fixed4(std::strtod(cells[column].c_str(), nullptr) + delta);
            changed[row] = row_of(cells);
            at[std::stol(cells[1])].insert(cells[2]);
            moved[{std::stol(cells[1]), cells[2]}] = column != 7;
        }
        Pair pair;
        pair.write({joined(lines), ""}, {joined(changed), ""});
        for (const io::RunDiff& d : {pair.forward(), pair.backward()}) {
            REQUIRE_MESSAGE(d.error.empty(), d.error);
            CHECK_FALSE(d.has_decisions);
            if (within) {
                CHECK(d.equal);
                continue;
            }
            CHECK_FALSE(d.equal);
            CHECK(d.first_tick == at.begin()->first);
            CHECK(std::set<std::string>(d.vehicles.begin(), d.vehicles.end()) == at.begin()->second);
            // The detail is of the first agent (by name) there, and names what differs only.
            const std::string& first = *at.begin()->second.begin();
            const bool position = moved.at({at.begin()->first, first});
            CHECK(d.detail.rfind(first + ":", 0) == 0);
            CHECK((d.detail.find("position differs") != std::string::npos) == position);
            CHECK((d.detail.find("speed") != std::string::npos) == !position);
            check_json(d);
        }
    }
}

TEST_CASE("an agent's rows cut short are missing from that run from the first tick cut") {
    const std::vector<std::string> lines = lines_of(base_run().trajectories);
    std::mt19937 rng(7);
    for (int trial = 0; trial < 40; ++trial) {
        CAPTURE(trial);
        const std::string agent = trial % 2 ? "truck" : "car";
        const long from = static_cast<long>(rng() % 90);
        std::vector<std::string> cut{lines[0]};
        for (size_t i = 1; i < lines.size(); ++i) {
            const auto cells = cells_of(lines[i]);
            if (cells[2] != agent || std::stol(cells[1]) < from) cut.push_back(lines[i]);
        }
        Pair pair;
        pair.write({joined(lines), ""}, {joined(cut), ""});
        const io::RunDiff f = pair.forward(), r = pair.backward();
        REQUIRE_MESSAGE(f.error.empty(), f.error);
        REQUIRE_MESSAGE(r.error.empty(), r.error);
        CHECK(f.first_tick == from);
        CHECK(r.first_tick == from);
        CHECK(f.vehicles == std::vector<std::string>{agent});
        CHECK(f.detail == agent + " is missing from the second run");
        CHECK(r.detail == agent + " is missing from the first run");
    }
}

TEST_CASE("a file that is not what sdv run writes is refused with the file and the line, whichever run holds it") {
    const RunFiles& good = base_run();
    const std::vector<std::string> lines = lines_of(good.trajectories);
    std::mt19937 rng(3);
    const std::vector<std::string> not_numbers = {"", "abc", "nan", "inf", "1e5", "0x10", "1.", ".5", "--1", "1 ", "1234567890123.5"};
    for (int trial = 0; trial < 60; ++trial) {
        CAPTURE(trial);
        std::vector<std::string> bad = lines;
        const size_t row = 1 + rng() % (lines.size() - 1);
        auto cells = cells_of(bad[row]);
        const size_t column = std::vector<size_t>{0, 4, 5, 6, 7, 8, 9, 10}[rng() % 8];
        cells[column] = not_numbers[rng() % not_numbers.size()];
        bad[row] = row_of(cells);
        Pair pair;
        pair.write({joined(bad), ""}, good);
        const std::string where = "trajectories.csv:" + std::to_string(row + 1) + ": column";
        for (const io::RunDiff& d : {pair.forward(), pair.backward()}) {
            CHECK_MESSAGE(d.error.find(where) != std::string::npos, d.error);
        }
    }
    // An agent skipping a tick, a wrong header.
    {
        std::vector<std::string> bad = lines;
        bad.erase(bad.begin() + 10);
        Pair pair;
        pair.write(good, {joined(bad), ""});
        CHECK(pair.forward().error.find("(an agent has a row at every tick from its first to its last)") != std::string::npos);
        bad = lines;
        bad[0] = "t,x";
        pair.write(good, {joined(bad), ""});
        CHECK(pair.forward().error.find("trajectories.csv:1: unexpected header") != std::string::npos);
    }
    // Decision lines: nested over 64 levels, or not JSON (text that is not UTF-8 is not, nor a
    // number beyond a double), or not an object.
    const std::string deep = std::string(65, '[') + std::string(65, ']');
    for (const std::string& line : {deep, std::string("{\"time\":"), std::string("{\"time\":0,\"vehicle\":\"\xff\"}"),
                                    std::string("{\"time\":1e400}"),
                                    std::string("[1,2]"), std::string("17")}) {
        CAPTURE(line);
        Pair pair;
        pair.write(good, {good.trajectories, good.decisions + line + "\n"});
        const std::string where = "decisions.jsonl:" + std::to_string(lines_of(good.decisions).size() + 1) + ": ";
        CHECK_MESSAGE(pair.forward().error.find(where) != std::string::npos, pair.forward().error);
        CHECK(pair.backward().error.find(where) != std::string::npos);
    }
    // 64 levels are read.
    Pair pair;
    pair.write(good, {good.trajectories, good.decisions + "{\"x\":" + std::string(63, '[') + std::string(63, ']') + "}\n"});
    CHECK(pair.forward().error.empty());
}

TEST_CASE("decision lines of any shape are compared without throwing") {
    const RunFiles& good = base_run();
    const std::vector<std::string> odd = {
        R"({"time":"0","vehicle":"ego","maneuver":"keep"})",          // a time that is no number: no decision
        R"({"time":0,"vehicle":7})",                                  // a vehicle that is no string
        R"({"time":0.5,"vehicle":"ego","maneuver":5,"winner":[1],"cost":"high"})",
        R"({"time":0.5,"vehicle":"ego","maneuver":{"a":[{}]},"cost":{"total":"x"}})",
        R"({"time":0.5,"vehicle":"ego","cost":{"total":{"nested":[1,2,3]}},"winner":null})",
        R"({"time":0.5,"vehicle":"</script>\u0001","maneuver":"\u00e9"})",
        R"({})",
    };
    for (size_t i = 0; i < odd.size(); ++i) {
        for (size_t j = 0; j < odd.size(); ++j) {
            CAPTURE(i);
            CAPTURE(j);
            Pair pair;
            pair.write({good.trajectories, odd[i] + "\n"}, {good.trajectories, odd[j] + "\n"});
            const io::RunDiff f = pair.forward(), r = pair.backward();
            REQUIRE_MESSAGE(f.error.empty(), f.error);
            CHECK(f.equal == r.equal);
            if (i == j) CHECK(f.equal);
            check_json(f);
            check_json(r);
            (void)io::render_text(f);
        }
    }
}

TEST_CASE("the JSON output parses whatever the names hold") {
    const std::vector<std::string> lines = lines_of(base_run().trajectories);
    for (const std::string name : {"\xff\xfe", "<b>\"quoted\"</b>", "tab\there", "\xc3", "ok"}) {
        CAPTURE(name);
        std::vector<std::string> a = lines, b = lines;
        for (size_t i = 1; i < lines.size(); ++i) {
            auto cells = cells_of(lines[i]);
            if (cells[2] != "truck") continue;
            cells[2] = name;
            a[i] = row_of(cells);
            cells[4] = fixed4(std::strtod(cells[4].c_str(), nullptr) + 1);
            b[i] = row_of(cells);
        }
        Pair pair;
        pair.write({joined(a), ""}, {joined(b), ""});
        const io::RunDiff d = pair.forward();
        REQUIRE_MESSAGE(d.error.empty(), d.error);
        CHECK(d.vehicles == std::vector<std::string>{name});
        check_json(d);
    }
}

}  // namespace run_diff_test
