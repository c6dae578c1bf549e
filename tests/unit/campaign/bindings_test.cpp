// The contract of a campaign's IR: a variant is the compiled scenario plus bindings. For every
// varied path (vehicle settings, positions, tree arguments with spreads, overrides of labelled
// nodes, scenario settings) and values drawn across the domain, the IR made by applying the
// bindings equals, number for number, the IR compiled from the source with those values
// written in (compiler::concretize).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>

#include "compiler/sema/compile.h"
#include "runtime/campaign/variants.h"
#include "runtime/ir/bindings.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace bindings_test {

using namespace sdv;

namespace {

const char* kScenario = R"(import "std/drive.sdv"
import "std/lane_change.sdv"

road r {
    lanes 2 forward
    straight 300 m
    arc 100 m radius 150 m left
    straight 300 m
}

tree cutter(accept_gap: length = 5 m, dv: speed = -3 m/s, cruise: speed = 16 m/s) {
    fallback {
        subtree std.cut_in(target = ego, lane = right, accept_gap = accept_gap, gap = 4 m, dv = dv)
        subtree std.drive(speed = cruise, keep.speed = cruise ±10% samples 5)
    }
}

scenario s {
    road r
    timeout 20 s
    ego a: sdv {
        start lane 1 at 40 m
        speed 12 m/s
        tree std.drive(speed = 14 m/s)
    }
    vehicle b: sdv {
        start lane 2 at 10 m offset 0.2 m
        speed 13 m/s
        tree cutter(dv = -4 m/s)
    }
    expect min_gap(a, b) > 2 m
    vary {
        a.speed in 8 m/s .. 16 m/s
        a.length in [4 m, 4.5 m, 5 m]
        b.start in 0 m .. 25 m
        b.start.offset in -0.5 m .. 0.5 m
        b.tree.accept_gap in 2 m .. 9 m
        b.tree.dv in -6 m/s .. -1 m/s
        b.tree.cruise in 14 m/s .. 20 m/s
        a.tree.follow.time_gap in 0.8 s .. 2.5 s
        timeout in 15 s .. 30 s
        seed in 1 .. 1000
        sample random 12
        seed 3
    }
}
)";

std::optional<ir::Program> compile(const std::string& text) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    auto c = compiler::compile_source("bindings.sdv", text, sm, diags);
    for (const auto& d : diags.sorted()) {
        if (d.severity == diag::Severity::error) MESSAGE(d.code << " " << d.message);
    }
    return std::move(c.program);
}

std::string text_of(double v, const std::string& unit, bool integer) {
    char buf[40];
    if (integer) return std::to_string(std::llround(v));
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return unit.empty() ? buf : std::string(buf) + " " + unit;
}

}  // namespace

TEST_CASE("a variant's IR is the compiled IR plus bindings, on every kind of varied path") {
    auto base = compile(kScenario);
    REQUIRE(base);
    const ir::Scenario& sc = base->scenarios[0];
    REQUIRE(sc.vary.params.size() == 10);
    const campaign::VariantSpace space(sc.vary);
    const auto base_numbers = ir::scenario_number_values(*base, 0);
    for (int64_t i = 0; i < space.size(); ++i) {
        const auto values = space.values(i);
        ir::Program applied = *base;
        REQUIRE(ir::apply_variant(applied, 0, base_numbers, values).empty());
        std::vector<std::pair<std::string, std::string>> placed;
        for (size_t k = 0; k < values.size(); ++k) {
            const auto& p = sc.vary.params[k];
            placed.emplace_back(p.name, text_of(values[k], p.unit, p.integer));
        }
        std::string error;
        auto text = compiler::concretize("bindings.sdv", kScenario, "s", placed, "variant", error);
        REQUIRE_MESSAGE(text, error);
        auto direct = compile(*text);
        REQUIRE(direct);
        CHECK(direct->scenarios[0].vary.empty());
        CHECK(direct->scenarios[0].seed == applied.scenarios[0].seed);
        const auto want = ir::scenario_number_values(*direct, 0);
        const auto got = ir::scenario_number_values(applied, 0);
        REQUIRE(want.size() == got.size());
        CHECK(got != base_numbers);  // the variant is not the compiled scenario
        CHECK(applied.scenarios[0].seed == static_cast<uint64_t>(values[9]));
        for (size_t j = 0; j < want.size(); ++j) {
            INFO("variant " << i << ", number " << j);
            CHECK(got[j] == doctest::Approx(want[j]).epsilon(1e-9));
        }
        // Resetting restores the compiled numbers exactly.
        ir::reset_variant(applied, 0, *base);
        CHECK(ir::scenario_number_values(applied, 0) == base_numbers);
    }
}

}  // namespace bindings_test
