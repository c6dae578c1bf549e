// Expectations say what they mean (issue "Drivers that behave like drivers", finding 9): each
// metric measured on a constructed situation, compiled from text as a user writes it and run;
// the values as summary.json and the stdout report show them.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>
#include <string>

#include "compiler/sema/compile.h"
#include "runtime/io/outputs.h"
#include "runtime/sim/simulation.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace expectations_test {

using namespace sdv;

namespace {

struct Run {
    ir::Program program;
    sim::RunResult result;
    nlohmann::json summary;
    std::string report;
};

// Compiles `scenario` (a scenario body) on a straight two-lane road and runs it.
Run run(const std::string& scenario, const std::string& trees = "") {
    const std::string text = "road r {\n lanes 2 forward\n straight 600 m\n}\n" + trees +
                             "\nscenario s {\n road r\n" + scenario + "\n}\n";
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    auto c = compiler::compile_source("test.sdv", text, sm, diags);
    for (const auto& d : diags.sorted()) MESSAGE(d.message);
    REQUIRE(c.program);
    Run r{*c.program, {}, {}, {}};
    r.result = sim::simulate(r.program, 0, {});
    REQUIRE(r.result.error.empty());
    r.summary = nlohmann::json::parse(io::summary_json(r.program, 0, r.result, {}));
    r.report = io::report(r.program, 0, r.result);
    return r;
}

const nlohmann::json& pair(const Run& r) { return r.summary["metrics"]["pairs"][0]; }
const nlohmann::json& vehicle(const Run& r, size_t i) { return r.summary["metrics"]["vehicles"][i]; }

// b overtakes a in the next lane, at constant speeds: they pass alongside 1.7 m apart.
const char* kOvertake =
    " timeout 12 s\n"
    " vehicle a: trajectory { trajectory {\n 0 s: lane 1 at 60 m\n 12 s: lane 1 at 180 m\n } }\n"
    " vehicle b: trajectory { trajectory {\n 0 s: lane 2 at 10 m\n 12 s: lane 2 at 250 m\n } }\n";

// a follows b in the same lane, 2 m/s faster: 55.5 m apart at first, 31.5 m after 12 s.
const char* kFollow =
    " timeout 12 s\n"
    " vehicle a: trajectory { trajectory {\n 0 s: lane 1 at 0 m\n 12 s: lane 1 at 144 m\n } }\n"
    " vehicle b: trajectory { trajectory {\n 0 s: lane 1 at 60 m\n 12 s: lane 1 at 180 m\n } }\n";

}  // namespace

TEST_CASE("a vehicle passing alongside in the next lane gives a small clearance but no bumper gap") {
    const Run r = run(std::string(kOvertake) +
                      " expect min_gap(a, b) < 5 m\n"
                      " expect min_clearance(a, b) < 5 m\n"
                      " expect min_lateral(a, b) < 2 m\n");
    CHECK(pair(r)["min_clearance"].get<double>() == doctest::Approx(1.7).epsilon(0.01));
    CHECK(pair(r)["min_lateral"].get<double>() == doctest::Approx(1.7).epsilon(0.01));
    CHECK(pair(r)["min_gap"].is_null());      // never in the same lane
    CHECK(pair(r)["min_ttc"].is_null());      // never closing along a lane
    CHECK(pair(r)["min_headway"].is_null());  // never following
    REQUIRE(r.result.expectations.size() == 3);
    CHECK_FALSE(r.result.expectations[0].passed);
    CHECK(r.result.expectations[1].passed);
    CHECK(r.result.expectations[2].passed);
    const auto& gap = r.summary["expectations"][0]["parts"][0];
    CHECK(gap["metric"] == "min_gap");
    CHECK(gap["value"].is_null());
    CHECK(gap["none"] == "never in the same lane");
    CHECK(r.report.find("FAIL  expect min_gap(a, b) < 5 m  (same-lane bumper gap: never in the same lane)") != std::string::npos);
}

TEST_CASE("same-lane following: bumper gap, TTC and headway along the lane") {
    const Run r = run(std::string(kFollow) + " expect min_gap(a, b) > 30 m\n");
    // Rear bumper of b minus front bumper of a: 60 - 4.5 - 2 t m; closing at 2 m/s; a at 12 m/s.
    CHECK(pair(r)["min_gap"].get<double>() == doctest::Approx(31.5).epsilon(0.01));
    CHECK(pair(r)["min_ttc"].get<double>() == doctest::Approx(31.5 / 2).epsilon(0.01));
    CHECK(pair(r)["min_headway"].get<double>() == doctest::Approx(31.5 / 12).epsilon(0.01));
    CHECK(pair(r)["min_lateral"].is_null());  // never side by side
    // Outline clearance of two cars in line is their bumper gap.
    CHECK(pair(r)["min_clearance"].get<double>() == doctest::Approx(31.5).epsilon(0.01));
    CHECK(r.result.passed());
}

TEST_CASE("a pair that never closes in has no TTC (null), whatever its gap") {
    // b ahead, 0.05 m/s slower: a closing speed below 0.1 m/s is noise, not closing (no TTC of 500 s).
    const Run r = run(
        " timeout 12 s\n"
        " vehicle a: trajectory { trajectory {\n 0 s: lane 1 at 0 m\n 12 s: lane 1 at 120 m\n } }\n"
        " vehicle b: trajectory { trajectory {\n 0 s: lane 1 at 30 m\n 12 s: lane 1 at 149.4 m\n } }\n"
        " expect min_ttc(a, b) > 2 s\n"
        " expect min_ttc(a, b) < 10000 s\n");
    CHECK(pair(r)["min_ttc"].is_null());
    CHECK(pair(r)["min_headway"].get<double>() > 0);
    CHECK(r.result.expectations[0].passed);        // never closing: no TTC below any bound
    CHECK_FALSE(r.result.expectations[1].passed);  // and none above one either
    CHECK(r.summary["expectations"][1]["parts"][0]["none"] == "never closing");
}

TEST_CASE("braking then accelerating: min_acc < 0 while max_acc > 0, each in its own window") {
    const char* tree =
        "tree slow_then_fast() {\n fallback {\n  sequence {\n   condition sim_time(before = 6 s)\n"
        "   maneuver keep_velocity(speed = 5 m/s)\n  }\n  maneuver keep_velocity(speed = 15 m/s)\n }\n}\n";
    const Run r = run(
        " timeout 20 s\n"
        " vehicle v: sdv { start lane 1 at 10 m  speed 15 m/s  tree slow_then_fast() }\n"
        " expect min_acc(v) < -1 m/s^2 and max_acc(v) > 1 m/s^2\n"
        " expect max_acc(v) > 1 m/s^2 before 5 s\n"      // braking only: re-accelerating later does not count
        " expect min_acc(v) < -1 m/s^2 after 8 s\n"      // accelerating only
        " expect min_speed(v) < 6 m/s and max_speed(v) > 14 m/s\n",
        tree);
    CHECK(vehicle(r, 0)["min_acc"].get<double>() < -1);
    CHECK(vehicle(r, 0)["max_acc"].get<double>() > 1);
    REQUIRE(r.result.expectations.size() == 4);
    CHECK(r.result.expectations[0].passed);
    CHECK_FALSE(r.result.expectations[1].passed);
    CHECK(*r.result.expectations[1].value <= 0.01);
    CHECK_FALSE(r.result.expectations[2].passed);
    CHECK(*r.result.expectations[2].value >= -0.1);
    CHECK(r.result.expectations[3].passed);
    CHECK(r.summary["expectations"][1]["window"]["before"] == 5.0);
    CHECK(r.summary["expectations"][1]["window"]["after"].is_null());
}

TEST_CASE("compound expectations carry the value of every part") {
    const Run r = run(std::string(kFollow) +
                      " expect collision(a, b) or min_gap(a, b) < 40 m and not min_ttc(a, b) < 1 s\n");
    const auto& e = r.summary["expectations"][0];
    CHECK(e["passed"] == true);
    CHECK_FALSE(e.contains("value"));  // not a single comparison
    REQUIRE(e["parts"].size() == 3);
    CHECK(e["parts"][0]["call"] == "collision(a, b)");
    CHECK(e["parts"][0]["metric"] == "collision");
    CHECK(e["parts"][0]["holds"] == false);
    CHECK(e["parts"][0]["time"].is_null());
    CHECK(e["parts"][1]["call"] == "min_gap(a, b) < 40 m");
    CHECK(e["parts"][1]["value"].get<double>() == doctest::Approx(31.5).epsilon(0.01));
    CHECK(e["parts"][1]["unit"] == "m");
    CHECK(e["parts"][2]["metric"] == "min_ttc");
    CHECK(e["parts"][2]["holds"] == false);
    CHECK(e["parts"][2]["value"].get<double>() == doctest::Approx(15.75).epsilon(0.01));
    // The report prints each part below the statement.
    CHECK(r.report.find("          collision(a, b) is false  (no collision)") != std::string::npos);
    CHECK(r.report.find("          min_gap(a, b) < 40 m is true  (same-lane bumper gap 31.5") != std::string::npos);
    CHECK(r.report.find("          min_ttc(a, b) < 1 s is false  (same-lane time to collision 15.7") != std::string::npos);
}

TEST_CASE("a window measures only its own ticks and events") {
    const Run r = run(std::string(kFollow) +
                      " expect min_gap(a, b) > 40 m during 1 s .. 5 s\n"
                      " expect min_gap(a, b) < 35 m after 10 s\n"
                      " expect min_gap(a, b) < 35 m before 8 s\n"
                      " expect no_collision() after 2 s\n");
    REQUIRE(r.result.expectations.size() == 4);
    // 60 - 4.5 - 2 t: 45.5 m at 5 s, 31.5 m at 12 s, 39.5 m at 8 s.
    CHECK(*r.result.expectations[0].value == doctest::Approx(45.5).epsilon(0.01));
    CHECK(r.result.expectations[0].passed);
    CHECK(*r.result.expectations[1].value == doctest::Approx(31.5).epsilon(0.01));
    CHECK(r.result.expectations[1].passed);
    CHECK(*r.result.expectations[2].value == doctest::Approx(39.5).epsilon(0.01));
    CHECK_FALSE(r.result.expectations[2].passed);
    CHECK(r.result.expectations[3].passed);
    // The part is the call without its window; the statement keeps it.
    CHECK(r.summary["expectations"][0]["expect"] == "min_gap(a, b) > 40 m during 1 s .. 5 s");
    CHECK(r.summary["expectations"][0]["parts"][0]["call"] == "min_gap(a, b) > 40 m");
}

TEST_CASE("summary.json gives every vehicle its fallback share and longest stall") {
    const Run r = run(std::string(kFollow) + " expect no_collision()\n");
    for (size_t i = 0; i < 2; ++i) {
        CHECK(vehicle(r, i).contains("fallback_plans"));
        CHECK(vehicle(r, i)["fallback_share"] == 0.0);  // no plans: nothing fell back
        CHECK(vehicle(r, i).contains("longest_stall_s"));
    }
}

}  // namespace expectations_test
