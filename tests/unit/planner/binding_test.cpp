// The one binding of maneuver parameters (catalog ParamDef::field → planner::set_field): every
// parameter of every maneuver binds to something, and setting it changes exactly what it names.
#include <doctest/doctest.h>

#include "runtime/catalog/catalog.h"
#include "runtime/planner/maneuver.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace binding_test {

using namespace sdv;

namespace {

// A value unlike any default, valid for the parameter's kind.
planner::Sampled probe_value(const catalog::ParamDef& p) {
    double v = 7.25;
    if (p.type == catalog::ParamType::boolean) v = p.def && p.def->value != 0 ? 0.0 : 1.0;
    if (p.type == catalog::ParamType::integer) v = 37;
    return {v, v - 1, v + 1, 3, planner::SampleMethod::linear, 0.0};
}

int probe_choice(const catalog::ParamDef& p) {
    const int def = p.def ? static_cast<int>(p.def->value) : -1;
    for (int c = 0; c < static_cast<int>(p.choices.size()); ++c) {
        if (c != def) return c;
    }
    return 0;
}

}  // namespace

TEST_CASE("every vehicle maneuver parameter of the catalog binds to a configuration field or the request") {
    for (const auto& m : catalog::maneuvers()) {
        if (m.agent != catalog::Agent::vehicle) continue;
        for (const auto& p : m.params) {
            CAPTURE(m.name);
            CAPTURE(p.name);
            REQUIRE(p.field != catalog::ConfigField::none);
            planner::ManeuverConfig c = planner::default_config(m.kind);
            const std::string before = planner::describe(c);
            const bool bound = planner::set_field(c, p.field, probe_value(p), probe_choice(p));
            if (p.type == catalog::ParamType::vehicle) {
                // Vehicles are resolved by the runtime into the plan request.
                CHECK_FALSE(bound);
                CHECK(describe(c) == before);
            } else {
                CHECK(bound);
                CHECK(planner::describe(c) != before);
            }
        }
    }
}

TEST_CASE("two parameters of one maneuver never bind the same field") {
    for (const auto& m : catalog::maneuvers()) {
        if (m.agent != catalog::Agent::vehicle) continue;
        for (size_t i = 0; i < m.params.size(); ++i) {
            for (size_t j = i + 1; j < m.params.size(); ++j) {
                CAPTURE(m.name);
                CAPTURE(m.params[i].name);
                CHECK(m.params[i].field != m.params[j].field);
            }
        }
    }
}

TEST_CASE("pedestrian maneuvers bind no planner field: they set the walker's intent") {
    int n = 0;
    for (const auto& m : catalog::maneuvers()) {
        if (m.agent != catalog::Agent::pedestrian) continue;
        ++n;
        CHECK(static_cast<int>(m.kind) >= static_cast<int>(catalog::kFirstPedestrianManeuver));
        CHECK(planner::candidate_count(planner::default_config(m.kind)) == 0);
        for (const auto& p : m.params) {
            CAPTURE(m.name);
            CHECK(p.field == catalog::ConfigField::none);
        }
    }
    CHECK(n == 8);
}

TEST_CASE("conditions bind no configuration field") {
    for (const auto& c : catalog::conditions()) {
        for (const auto& p : c.params) {
            CAPTURE(c.name);
            CHECK(p.field == catalog::ConfigField::none);
        }
    }
}

TEST_CASE("default_config is the catalog's defaults through the binding") {
    const auto kv = planner::default_config(catalog::ManeuverKind::keep_velocity);
    CHECK(kv.speed.value == doctest::Approx(14));
    CHECK(kv.speed.samples == 3);
    CHECK(kv.common.w_proximity == doctest::Approx(10));
    const auto rev = planner::default_config(catalog::ManeuverKind::reverse);
    CHECK_FALSE(rev.common.direction);
    const auto cut = planner::default_config(catalog::ManeuverKind::cut_in);
    CHECK(cut.lane == planner::LaneTarget::target);
    CHECK(cut.delta_s.lo < cut.delta_s.value);
    const auto stop = planner::default_config(catalog::ManeuverKind::stop);
    CHECK(stop.stop_at == planner::StopTarget::now);
    CHECK_FALSE(stop.stop_position.has_value());
}

}  // namespace binding_test
