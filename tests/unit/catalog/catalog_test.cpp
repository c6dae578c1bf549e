// The catalog holds SPEC §3.6's defaults and candidate counts, and is internally consistent.
#include <doctest/doctest.h>

#include <cmath>
#include <set>

#include "runtime/catalog/catalog.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace catalog_test {

using namespace sdv::catalog;

TEST_CASE("default candidate counts match SPEC 3.6") {
    CHECK(maneuver(ManeuverKind::keep_velocity).default_candidates == 18);
    CHECK(maneuver(ManeuverKind::follow).default_candidates == 10);
    CHECK(maneuver(ManeuverKind::lane_change).default_candidates == 6);
    CHECK(maneuver(ManeuverKind::cut_in).default_candidates == 30);
    CHECK(maneuver(ManeuverKind::stop).default_candidates == 6);
    CHECK(maneuver(ManeuverKind::reverse).default_candidates == 18);
}

TEST_CASE("maneuver kinds index the table in order") {
    for (size_t i = 0; i < maneuvers().size(); ++i) {
        CHECK(static_cast<size_t>(maneuvers()[i].kind) == i);
    }
    for (size_t i = 0; i < conditions().size(); ++i) {
        CHECK(static_cast<size_t>(conditions()[i].kind) == i);
    }
}

TEST_CASE("common defaults follow the reference") {
    const auto& kv = maneuver(ManeuverKind::keep_velocity);
    CHECK(kv.find_param("max_long_jerk")->def->value == 10);
    CHECK(kv.find_param("max_lat_acc")->def->value == doctest::Approx(4.9));
    CHECK(kv.find_param("w_proximity")->def->value == 10);
    CHECK(kv.find_param("speed")->def->spread_pct == 10);
    CHECK(maneuver(ManeuverKind::stop).find_param("max_long_acc")->def->value == 30);
    CHECK(maneuver(ManeuverKind::reverse).find_param("direction")->def->value == 0);
    CHECK(kv.find_param("direction")->def->value == 1);
    CHECK(kv.find_param("nonexistent") == nullptr);
}

TEST_CASE("names are unique and defaults lie in their allowed range") {
    std::set<std::string> names;
    for (const auto& m : maneuvers()) {
        CHECK(names.insert(m.name).second);
        std::set<std::string> pnames;
        for (const auto& p : m.params) {
            CHECK(pnames.insert(p.name).second);
            if (p.def && (p.type == ParamType::quantity || p.type == ParamType::integer)) {
                CHECK(p.def->value >= p.min);
                CHECK(p.def->value <= p.max);
            }
            CHECK(!p.doc.empty());
        }
    }
    for (const auto& c : conditions()) {
        CHECK(names.insert(c.name).second);
        for (const auto& g : c.at_least_one_of) CHECK(c.find_param(g) != nullptr);
        for (const auto& g : c.exclusive) CHECK(c.find_param(g) != nullptr);
    }
}

TEST_CASE("units normalise to SI") {
    CHECK(find_unit("km/h")->to_si == doctest::Approx(1 / 3.6));
    CHECK(find_unit("m/s^2")->dim == Dim::accel);
    CHECK(find_unit("deg")->to_si == doctest::Approx(M_PI / 180));
    CHECK(!find_unit("furlong"));
    CHECK(is_unit_atom("km"));
    CHECK(!is_unit_atom("speed"));
}

TEST_CASE("renderings mention every entry") {
    const std::string text = render_text();
    const std::string md = render_markdown();
    for (const auto& m : maneuvers()) {
        CHECK(text.find(m.name) != std::string::npos);
        CHECK(md.find("`" + m.name + "`") != std::string::npos);
    }
    CHECK(format_default(*maneuver(ManeuverKind::keep_velocity).find_param("speed")) ==
          "14 m/s ±10% samples 3");
}

TEST_CASE("every maneuver and condition sits at the index of its kind (the IR stores indices)") {
    for (size_t i = 0; i < maneuvers().size(); ++i) CHECK(static_cast<size_t>(maneuvers()[i].kind) == i);
    for (size_t i = 0; i < conditions().size(); ++i) {
        INFO(conditions()[i].name);
        CHECK(static_cast<size_t>(conditions()[i].kind) == i);
    }
}

TEST_CASE("a parameter's allowed range in words says what accepts() takes") {
    const auto write = [](double v) { return format_number(v) + " u"; };
    ParamDef p;
    CHECK(p.allowed(write) == "any finite number");
    p.min = 0;
    CHECK(p.allowed(write) == "at least 0 u");
    p.min_exclusive = true;
    CHECK(p.allowed(write) == "more than 0 u");
    p.max = 40;
    CHECK(p.allowed(write) == "more than 0 u to 40 u");
    p.min_exclusive = false;
    CHECK(p.allowed(write) == "0 u to 40 u");
    p.min = -kInf;
    CHECK(p.allowed(write) == "at most 40 u");
    // Every range of the catalog: the words name each finite bound, "more than" exactly when the
    // lower bound itself is refused.
    const auto check = [&](const ParamDef& q) {
        INFO(q.name);
        const std::string words = q.allowed(write);
        if (std::isfinite(q.min)) {
            CHECK(words.find(write(q.min)) != std::string::npos);
            CHECK((words.rfind("more than ", 0) == 0) == !q.accepts(q.min));
        }
        if (std::isfinite(q.max)) {
            CHECK(words.find(write(q.max)) != std::string::npos);
            CHECK(q.accepts(q.max));
        }
    };
    for (const auto& m : maneuvers()) {
        for (const auto& q : m.params) check(q);
    }
    for (const auto& c : conditions()) {
        for (const auto& q : c.params) check(q);
    }
}

}  // namespace catalog_test
