// Vehicles that start overlapped (E0502): find_overlaps against every pair on random placements
// (ties, touching edges, lanes, unusable sizes), its work bounded by n log n on the placements
// that made the pairwise check quadratic (finding 39 of docs/reliability.md), and the checker's
// errors on scenarios.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "compiler/sema/compile.h"
#include "compiler/sema/overlaps.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace overlaps_test {

namespace {

using sdv::compiler::sema::find_overlaps;
using sdv::compiler::sema::Footprint;
using sdv::compiler::sema::footprints_overlap;
using sdv::compiler::sema::Overlap;
using sdv::compiler::sema::OverlapWork;

// `a` is behind `b`: its back is behind b's, or at the same place and a comes first.
bool behind(const std::vector<Footprint>& f, size_t a, size_t b) {
    return f[a].s_lo < f[b].s_lo || (f[a].s_lo == f[b].s_lo && a < b);
}

// Footprints on a coarse grid (a quarter metre), so that backs tie and edges touch often.
std::vector<Footprint> random_footprints(std::mt19937_64& rng, size_t n, double spread) {
    std::uniform_int_distribution<int> group(-1, 3), cell(0, static_cast<int>(spread * 4)), size(0, 24),
        odd(0, 40);
    std::vector<Footprint> out;
    for (size_t i = 0; i < n; ++i) {
        const double s = cell(rng) / 4.0, lat = (cell(rng) % 32) / 4.0 - 4;
        double len = size(rng) / 4.0, wid = (size(rng) % 12) / 4.0;
        if (odd(rng) == 0) len = std::numeric_limits<double>::quiet_NaN();
        if (odd(rng) == 0) wid = std::numeric_limits<double>::infinity();
        out.push_back({group(rng), s - len / 2, s + len / 2, lat - wid / 2, lat + wid / 2});
    }
    return out;
}

size_t log2_ceil(size_t n) {
    size_t k = 0;
    while ((size_t{1} << k) < n) ++k;
    return k;
}

// A bound on the segment tree's work for n footprints: each takes part in a query and two
// updates of one path from a leaf to the root.
size_t work_bound(size_t n) { return 4 * n * (log2_ceil(n) + 1); }

std::vector<std::string> errors_of(const std::string& text) {
    sdv::diag::SourceManager sm;
    sdv::diag::DiagnosticEngine diags;
    (void)sdv::compiler::compile_source("test.sdv", text, sm, diags);
    std::vector<std::string> out;
    for (const auto& d : diags.sorted()) {
        if (d.severity != sdv::diag::Severity::error) continue;
        const auto line_no = d.range.valid() ? sm.line_col(d.range.begin).line : 0;
        std::string line = d.code + " " + std::to_string(line_no) + " " + d.message;
        for (const auto& n : d.notes) line += " | " + n.message;
        out.push_back(line);
    }
    return out;
}

std::string scenario(const std::string& vehicles) {
    return "import \"std/drive.sdv\"\n"
           "road r {\n    lanes 2 forward\n    straight 3000 m\n}\n"
           "scenario s {\n    road r\n" +
           vehicles + "    expect no_collision()\n}\n";
}

}  // namespace

TEST_CASE("find_overlaps names, for each footprint overlapping one behind it, one of those") {
    std::mt19937_64 rng(39);
    size_t with_overlaps = 0, without = 0, pairs = 0;
    for (int round = 0; round < 400; ++round) {
        const size_t n = static_cast<size_t>(round % 60);
        const auto f = random_footprints(rng, n, round % 3 == 0 ? 5.0 : 60.0);
        std::vector<bool> expected(n, false);
        for (size_t b = 0; b < n; ++b) {
            for (size_t a = 0; a < n; ++a) {
                if (a != b && behind(f, a, b) && footprints_overlap(f[a], f[b])) expected[b] = true;
            }
        }
        const auto found = find_overlaps(f);
        std::vector<bool> named(n, false);
        for (size_t k = 0; k < found.size(); ++k) {
            const Overlap& o = found[k];
            REQUIRE(o.ahead < n);
            REQUIRE(o.behind < n);
            CHECK(footprints_overlap(f[o.ahead], f[o.behind]));
            CHECK(behind(f, o.behind, o.ahead));
            CHECK_FALSE(named[o.ahead]);  // once each
            if (k > 0) CHECK(found[k - 1].ahead < o.ahead);
            named[o.ahead] = true;
        }
        CHECK(named == expected);
        CHECK(found.size() + (n > 0 ? 1 : 0) <= std::max<size_t>(n, 1));
        pairs += found.size();
        (found.empty() ? without : with_overlaps) += 1;
    }
    // The placements exercise both outcomes, not one.
    CHECK(with_overlaps > 100);
    CHECK(without > 20);
    CHECK(pairs > 1000);
}

TEST_CASE("footprints overlap by area: touching, other lanes and unusable sizes are no overlap") {
    const Footprint a{0, 0, 4.5, -0.9, 0.9};
    CHECK(footprints_overlap(a, {0, 4.4, 8.9, -0.9, 0.9}));
    CHECK_FALSE(footprints_overlap(a, {0, 4.5, 9.0, -0.9, 0.9}));  // nose to tail
    CHECK_FALSE(footprints_overlap(a, {0, 1, 5.5, 0.9, 2.7}));     // side by side
    CHECK_FALSE(footprints_overlap(a, {1, 0, 4.5, -0.9, 0.9}));    // another lane
    CHECK_FALSE(footprints_overlap(a, {-1, 0, 4.5, -0.9, 0.9}));   // no lane
    CHECK_FALSE(footprints_overlap(a, {0, 2, 2, -0.9, 0.9}));      // no length
    CHECK_FALSE(footprints_overlap(a, {0, 0, std::nan(""), -0.9, 0.9}));
    CHECK(find_overlaps({a, {0, 2, 2, -0.9, 0.9}}).empty());
}

TEST_CASE("find_overlaps does work in n log n, however the footprints lie") {
    const size_t n = 100000;  // the checker's limit of agents in a scenario
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> along(0, 3000), tiny(0, 0.5);
    struct Case {
        const char* name;
        std::vector<Footprint> f;
        std::optional<size_t> overlapping;  // the footprints named as ahead, where known
    };
    std::vector<Case> cases;
    // Every one at one place (the finding: d[102..2000] at 70 m), each overlapping all the others.
    cases.push_back({"all at one place", std::vector<Footprint>(n, Footprint{0, 67.75, 72.25, -0.9, 0.9}), n - 1});
    // Nose to tail along the lane: none overlaps.
    std::vector<Footprint> queue;
    for (size_t i = 0; i < n; ++i) queue.push_back({0, 5.0 * static_cast<double>(i), 5.0 * static_cast<double>(i) + 4.5, -0.9, 0.9});
    cases.push_back({"nose to tail", queue, 0});
    // Short ones side by side in one place: each is under the s-interval of all the others but
    // overlaps none of them (the pairwise check's worst case without any error).
    std::vector<Footprint> side;
    for (size_t i = 0; i < n; ++i) {
        const double lat = 0.125 * static_cast<double>(i);  // exact: edges touch, never cross
        side.push_back({0, 0, 1, lat, lat + 0.125});
    }
    cases.push_back({"side by side", side, 0});
    // At random along three lanes.
    std::vector<Footprint> spread;
    for (size_t i = 0; i < n; ++i) {
        const double s = along(rng), w = tiny(rng);
        spread.push_back({static_cast<int32_t>(i % 3), s - 2.25, s + 2.25, -w - 0.9, -w + 0.9});
    }
    cases.push_back({"at random", spread, std::nullopt});
    for (const auto& c : cases) {
        CAPTURE(c.name);
        OverlapWork work;
        const auto found = find_overlaps(c.f, &work);
        CHECK(work.tree_steps <= work_bound(n));
        CHECK(work.tree_steps >= n);  // the count counts
        if (c.overlapping) CHECK(found.size() == *c.overlapping);
        for (const auto& o : found) CHECK(footprints_overlap(c.f[o.ahead], c.f[o.behind]));
    }
}

TEST_CASE("E0502 at each vehicle that starts on one behind it, naming one") {
    // Two on top of each other: the error at the one ahead, whichever is declared first.
    CHECK(errors_of(scenario("    vehicle a: sdv { start lane 1 at 10 m tree std.drive(speed = 10 m/s) }\n"
                             "    vehicle b: sdv { start lane 1 at 12 m tree std.drive(speed = 10 m/s) }\n")) ==
          std::vector<std::string>{"E0502 9 vehicles 'b' and 'a' start overlapped | 'a' starts here"});
    CHECK(errors_of(scenario("    vehicle b: sdv { start lane 1 at 12 m tree std.drive(speed = 10 m/s) }\n"
                             "    vehicle a: sdv { start lane 1 at 10 m tree std.drive(speed = 10 m/s) }\n")) ==
          std::vector<std::string>{"E0502 8 vehicles 'b' and 'a' start overlapped | 'a' starts here"});
    // Nose to tail (4.5 m apart), in other lanes, or one side of a lane each: none.
    CHECK(errors_of(scenario("    vehicle a: sdv { start lane 1 at 10 m tree std.drive(speed = 10 m/s) }\n"
                             "    vehicle b: sdv { start lane 1 at 14.5 m tree std.drive(speed = 10 m/s) }\n"
                             "    vehicle c: sdv { start lane 2 at 12 m tree std.drive(speed = 10 m/s) }\n"))
              .empty());
    CHECK(errors_of(scenario("    vehicle a: sdv { start lane 1 at 10 m offset -0.9 m width 1.5 m tree std.drive(speed = 10 m/s) }\n"
                             "    vehicle b: sdv { start lane 1 at 10 m offset 0.9 m width 1.5 m tree std.drive(speed = 10 m/s) }\n"))
              .empty());
    // The finding's shape: 1,899 vehicles of one template at one place, an error at each but the
    // first, reported once for the template with the instances it is for.
    const auto many = errors_of(scenario("    vehicle d[102..2000]: sdv { start lane 1 at 70 m tree std.drive(speed = 10 m/s) }\n"));
    CHECK(many == std::vector<std::string>{"E0502 8 vehicles 'd103' and 'd102' start overlapped | 'd102' starts here | "
                                           "for d103 (i = 103), d104 (i = 104), d105 (i = 105) and 1895 more of "
                                           "'d[102..2000]'"});
    // Two templates at one place: the second's instances overlap the first's.
    const auto two = errors_of(scenario("    vehicle p[1..3]: sdv { start lane 1 at (100 + 10 * i) m tree std.drive(speed = 10 m/s) }\n"
                                        "    vehicle q[1..3]: sdv { start lane 1 at (101 + 10 * i) m tree std.drive(speed = 10 m/s) }\n"));
    CHECK(two == std::vector<std::string>{"E0502 9 vehicles 'q1' and 'p1' start overlapped | 'p1' starts here | "
                                          "for q1 (i = 1), q2 (i = 2) and q3 (i = 3) of 'q[1..3]'"});
}

}  // namespace overlaps_test
