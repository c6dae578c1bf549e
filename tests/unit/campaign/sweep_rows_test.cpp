// The rows a sweep appends to DIR/rows are read back strictly: a line is a row only when it is
// the very text sdv writes for a variant of the campaign, with that variant's values. Whatever
// else is in the files (a hand edit, a damaged disk block, a row of another tool) is reported,
// and on a resume its variant runs again, so results.csv is the same bytes as an undamaged sweep.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "runtime/campaign/sweep.h"
#include "tests/unit/io/compile_text.h"
#include "tests/unit/io/csv_lines.h"
#include "tests/unit/io/temp_dir.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace sweep_rows_test {

using namespace sdv;

namespace {

// Two expectations (one with a value, one boolean), a seed (a whole number) and a continuous
// speed drawn at random: every kind of cell a row has.
const char* kScenario = R"(
import "std/drive.sdv"
road r {
    lanes 1 forward
    straight 200 m
}
scenario s {
    road r
    timeout 1 s
    seed 3
    vehicle v: sdv {
        start lane 1 at 10 m
        speed 5 m/s
        tree std.drive(speed = 5 m/s)
    }
    vehicle w: sdv {
        start lane 1 at 60 m
        speed 5 m/s
        tree std.drive(speed = 5 m/s)
    }
    expect min_gap(v, w) > 2 m
    expect not collision(v, w)
    vary {
        seed in 1 .. 1000
        v.speed in 2 m/s .. 9 m/s
        sample random 12
    }
}
)";

std::string slurp(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// A random row of a random variant, with that variant's parameter values.
campaign::Row random_row(const ir::Scenario& s, const campaign::VariantSpace& space, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    auto magnitude = [&]() {
        const double m = std::pow(10.0, std::floor(u(rng) * 12) - 6);
        return (u(rng) < 0.2 ? -1 : 1) * u(rng) * m;
    };
    campaign::Row r;
    r.variant = static_cast<int64_t>(rng() % static_cast<uint64_t>(space.size()));
    r.values = space.values(r.variant);
    r.passed = u(rng) < 0.5;
    r.expect_values.assign(s.expect_roots.size(), std::nullopt);
    r.expect_passed.assign(s.expect_roots.size(), false);
    if (u(rng) < 0.2) {
        const char* errors[] = {"no lane at 10 m", "a \"quoted\" word, and a comma", "x"};
        r.error = errors[rng() % 3];
        r.passed = false;
        return r;
    }
    r.collisions = static_cast<int>(rng() % 4);
    for (auto* m : {&r.min_ttc, &r.min_gap, &r.min_clearance}) {
        if (u(rng) < 0.7) *m = magnitude();
    }
    r.fallback_share = u(rng);
    r.duration = u(rng) * 60;
    for (size_t k = 0; k < s.expect_roots.size(); ++k) {
        if (u(rng) < 0.6) r.expect_values[k] = magnitude();
        r.expect_passed[k] = u(rng) < 0.5;
    }
    return r;
}

}  // namespace

TEST_CASE("a row sdv writes reads back, and writes back to the same bytes") {
    const auto program = test::compile_text(kScenario);
    REQUIRE(program);
    const ir::Scenario& s = program->scenarios[0];
    const campaign::VariantSpace space(s.vary);
    std::mt19937_64 rng(7);
    for (int i = 0; i < 2000; ++i) {
        const campaign::Row r = random_row(s, space, rng);
        const std::string line = campaign::row_text(s, r);
        campaign::Row back;
        std::string why;
        REQUIRE_MESSAGE(campaign::read_row(s, space, line, back, why), line << ": " << why);
        CHECK(campaign::row_text(s, back) == line);
        CHECK(back.variant == r.variant);
        CHECK(back.passed == r.passed);
        CHECK(back.error == r.error);
        CHECK(back.collisions == r.collisions);
        CHECK(back.min_ttc.has_value() == r.min_ttc.has_value());
        CHECK(back.expect_values.size() == s.expect_roots.size());
        CHECK(back.expect_passed == r.expect_passed);
        if (r.min_gap) CHECK(*back.min_gap == doctest::Approx(*r.min_gap).epsilon(1e-5));
    }
}

TEST_CASE("a line that is not the text sdv writes for a variant is refused, naming the cell") {
    const auto program = test::compile_text(kScenario);
    REQUIRE(program);
    const ir::Scenario& s = program->scenarios[0];
    const campaign::VariantSpace space(s.vary);
    const auto cols = campaign::columns(s);
    // Text no cell of a row can hold as sdv writes it, by column.
    const std::vector<std::string> never_a_number = {"", "x", "1.0", "+1", " 1", "1 ", "nan", "inf", "1e999",
                                                     "0x1", "1,5", "\"1\""};
    std::mt19937_64 rng(11);
    int refused = 0;
    for (int i = 0; i < 600; ++i) {
        campaign::Row r = random_row(s, space, rng);
        if (!r.error.empty()) continue;  // the error's comma would shift the cells below
        r.min_ttc = 1.5;                 // every measure present: an empty one would be valid
        r.min_gap = 2.5;
        r.min_clearance = 0.5;
        for (auto& v : r.expect_values) v = 4.25;
        const std::string line = campaign::row_text(s, r);
        auto cells = test::cells_of(line);
        REQUIRE(cells.size() == cols.size());
        const size_t c = rng() % cells.size();
        std::string bad;
        const std::string& name = cols[c];
        if (name == "variant") {
            const std::string v[] = {"-1", "01", std::to_string(space.size()), "x", ""};
            bad = v[rng() % 5];
        } else if (name == "error") {
            bad = "unquoted";
        } else if (name == "passed" || name.find("_passed") != std::string::npos) {
            const std::string v[] = {"", "2", "true", "01"};
            bad = v[rng() % 4];
        } else if (name == "collisions") {
            const std::string v[] = {"", "-1", "1.5", "01", "x"};
            bad = v[rng() % 5];
        } else if (c <= s.vary.params.size()) {
            // A parameter: another variant's value is as wrong as text that is no number.
            campaign::Row other = r;
            other.values = space.values((r.variant + 1) % space.size());
            bad = rng() % 2 ? never_a_number[rng() % never_a_number.size()]
                            : test::cells_of(campaign::row_text(s, other))[c];
        } else {
            bad = never_a_number[1 + rng() % (never_a_number.size() - 1)];
        }
        if (bad == cells[c]) continue;
        cells[c] = bad;
        const std::string damaged = test::row_of(cells);
        campaign::Row back;
        std::string why;
        CHECK_MESSAGE(!campaign::read_row(s, space, damaged, back, why), damaged);
        CHECK_MESSAGE(!why.empty(), damaged);
        // A cell that splits in two ("1,5") shifts the count; every other message names the cell
        // or says the row is not as sdv writes it (an unquoted error is an error, so the next
        // cell, a measure, is the one named).
        const bool named = why.find("'" + (name == "error" ? std::string("collisions") : name) + "'") !=
                               std::string::npos ||
                           why.find("cells, not the campaign's") != std::string::npos ||
                           why.find("not the text sdv writes") != std::string::npos ||
                           why.find("quote is not closed") != std::string::npos;
        CHECK_MESSAGE(named, damaged << " -> " << why);
        ++refused;
    }
    CHECK(refused > 400);
    // Whole-line damage.
    campaign::Row back;
    std::string why;
    const std::string good = campaign::row_text(s, random_row(s, space, rng));
    for (const std::string& bad : {std::string("variant,seed"), good + ",", good.substr(0, good.size() / 2),
                                   std::string("\"") + good, good + "\r", std::string(1000, ',')}) {
        CHECK_MESSAGE(!campaign::read_row(s, space, bad, back, why), bad);
        CHECK(!why.empty());
    }
}

TEST_CASE("damaged rows are named by gather, run again on a resume, and leave results.csv as if undamaged") {
    const auto program = test::compile_text(kScenario);
    REQUIRE(program);
    const test::TempDir clean("sdv-sweep-rows-clean"), damaged("sdv-sweep-rows-damaged");
    const std::string dir = damaged.path.string();
    campaign::SweepOptions o;
    o.dir = clean.path.string();
    REQUIRE(campaign::run_sweep(*program, 0, o).error == "");
    campaign::Results want;
    REQUIRE(campaign::gather(*program, 0, o.dir, want) == "");
    REQUIRE(want.lines.size() == 12);
    const std::string slice = "/rows/slice-0-of-1.csv";
    const std::string rows_text = slurp(o.dir + slice);

    std::mt19937_64 rng(5);
    for (int round = 0; round < 6; ++round) {
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir + "/rows");
        damaged.write("rows/manifest.json", slurp(o.dir + "/rows/manifest.json"));
        // Damage 1-3 distinct rows (a cell replaced by text that is no number), add a line of
        // garbage, and duplicate an undamaged row (a duplicate is harmless).
        auto lines = test::lines_of(rows_text);
        std::vector<size_t> hit;
        const size_t k = 1 + rng() % 3;
        while (hit.size() < k) {
            const size_t at = rng() % lines.size();
            if (std::find(hit.begin(), hit.end(), at) == hit.end()) hit.push_back(at);
        }
        std::set<int64_t> damaged_variants;
        for (const size_t at : hit) {
            auto cells = test::cells_of(lines[at]);
            damaged_variants.insert(std::stoll(cells[0]));
            const size_t c = 1 + rng() % (cells.size() - 1);
            cells[c] = cells[c] == "x" ? "y" : "x";
            lines[at] = test::row_of(cells);
        }
        size_t spare = 0;
        while (std::find(hit.begin(), hit.end(), spare) != hit.end()) ++spare;
        damaged.write(slice.substr(1), test::joined(lines) + "garbage\n" + lines[spare] + "\n");

        // gather names the first damaged line, with its file and line number.
        campaign::Results got;
        const std::string e = campaign::gather(*program, 0, dir, got);
        const size_t first = *std::min_element(hit.begin(), hit.end()) + 1;
        CHECK_MESSAGE(e.find("is incomplete: " + std::to_string(damaged_variants.size()) + " of 12") !=
                          std::string::npos,
                      e);
        CHECK_MESSAGE(e.find(std::to_string(k + 1) + " lines are not rows as sdv writes them (first: " + dir + slice +
                             ":" + std::to_string(first) + ": ") != std::string::npos,
                      e);

        // A resume runs exactly the damaged variants; then the rows gather to the clean ones.
        campaign::SweepOptions r;
        r.dir = dir;
        r.resume = true;
        const auto out = campaign::run_sweep(*program, 0, r);
        REQUIRE(out.error == "");
        CHECK(out.ran == static_cast<int64_t>(damaged_variants.size()));
        CHECK(out.skipped == 12 - static_cast<int64_t>(damaged_variants.size()));
        CHECK(out.damaged == static_cast<int64_t>(k + 1));
        CHECK(out.damage.rfind(dir + slice + ":" + std::to_string(first) + ": ", 0) == 0);
        got = {};
        REQUIRE(campaign::gather(*program, 0, dir, got) == "");
        CHECK(got.lines == want.lines);
    }
}

}  // namespace sweep_rows_test
