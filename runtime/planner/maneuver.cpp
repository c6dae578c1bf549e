#include "runtime/planner/maneuver.h"

#include <cstdio>

namespace sdv::planner {
namespace {

Sampled from_default(const catalog::ParamDef& p) {
    const auto& d = *p.def;
    return Sampled::spread(d.value, d.spread_pct, d.samples, p.min >= 0);
}

}  // namespace

bool set_field(ManeuverConfig& c, catalog::ConfigField field, const Sampled& number, int choice) {
    using F = catalog::ConfigField;
    CommonConfig& k = c.common;
    const double v = number.value;
    switch (field) {
        case F::max_long_jerk: k.max_long_jerk = v; return true;
        case F::max_lat_jerk: k.max_lat_jerk = v; return true;
        case F::max_long_acc: k.max_long_acc = v; return true;
        case F::max_lat_acc: k.max_lat_acc = v; return true;
        case F::collision: k.collision = v != 0; return true;
        case F::off_lane: k.off_lane = v != 0; return true;
        case F::direction: k.direction = v != 0; return true;
        case F::w_time: k.w_time = v; return true;
        case F::w_efficiency: k.w_efficiency = v; return true;
        case F::efficiency:
            if (choice < 0 || choice > 1) return false;
            k.efficiency_reference = choice == 1;
            return true;
        case F::w_lane_offset: k.w_lane_offset = v; return true;
        case F::w_long_jerk: k.w_long_jerk = v; return true;
        case F::w_lat_jerk: k.w_lat_jerk = v; return true;
        case F::w_long_acc: k.w_long_acc = v; return true;
        case F::w_lat_acc: k.w_lat_acc = v; return true;
        case F::w_proximity: k.w_proximity = v; return true;
        case F::expected_offset: k.expected_offset = v; return true;
        case F::expected_acc: k.expected_acc = v; return true;
        case F::expected_jerk: k.expected_jerk = v; return true;
        case F::lat_offset: k.lat_offset = number; return true;
        case F::eval_points: k.eval_points = static_cast<int>(v); return true;
        case F::speed: c.speed = number; return true;
        case F::duration: c.duration = number; return true;
        case F::max_speed_change: c.max_speed_change = v; return true;
        case F::time_gap: c.time_gap = v; return true;
        case F::follow_speed: c.follow_speed = v; return true;
        case F::stop_distance: c.stop_distance = v; return true;
        case F::lane: {
            // The choice's word names the target (the choices differ between maneuvers).
            const auto* p = catalog::maneuver(c.kind).find_param("lane");
            if (p == nullptr || choice < 0 || static_cast<size_t>(choice) >= p->choices.size()) return false;
            const std::string& w = p->choices[static_cast<size_t>(choice)];
            c.lane = w == "left"    ? LaneTarget::left
                     : w == "right" ? LaneTarget::right
                     : w == "route" ? LaneTarget::route
                     : w == "target" ? LaneTarget::target
                                     : LaneTarget::current;
            return true;
        }
        case F::delta_s: c.delta_s = number; return true;
        case F::delta_v: c.delta_v = v; return true;
        case F::delta_a: c.delta_a = v; return true;
        case F::gap_from:
            if (choice < 0 || choice > 1) return false;
            c.gap_from_reference = choice == 1;
            return true;
        case F::stop_at:
            if (choice < 0 || choice > static_cast<int>(StopTarget::pedestrian)) return false;
            c.stop_at = static_cast<StopTarget>(choice);
            return true;
        case F::stop_position: c.stop_position = v; return true;
        case F::stop_before: c.stop_before = v; return true;
        case F::stop_decel: c.stop_decel = v; return true;
        case F::duration_factor: c.duration_factor = number; return true;
        case F::leader:
        case F::target:
        case F::none: return false;
    }
    return false;
}

ManeuverConfig default_config(ManeuverKind kind) {
    ManeuverConfig c;
    c.kind = kind;
    for (const catalog::ParamDef& p : catalog::maneuver(kind).params) {
        if (!p.def) continue;
        set_field(c, p.field, from_default(p), static_cast<int>(p.def->value));
    }
    return c;
}

std::string describe(const ManeuverConfig& c) {
    std::string out;
    auto num = [&](const char* name, double v) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%s=%.17g\n", name, v);
        out += buf;
    };
    auto smp = [&](const char* name, const Sampled& s) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s=%.17g[%.17g,%.17g]x%d/%d/%.17g\n", name, s.value, s.lo, s.hi, s.samples,
                      static_cast<int>(s.method), s.sigma);
        out += buf;
    };
    const CommonConfig& k = c.common;
    num("kind", static_cast<int>(c.kind));
    num("max_long_jerk", k.max_long_jerk);
    num("max_lat_jerk", k.max_lat_jerk);
    num("max_long_acc", k.max_long_acc);
    num("max_lat_acc", k.max_lat_acc);
    num("collision", k.collision);
    num("off_lane", k.off_lane);
    num("direction", k.direction);
    num("w_time", k.w_time);
    num("w_efficiency", k.w_efficiency);
    if (k.efficiency_reference) num("efficiency_reference", 1);
    num("w_lane_offset", k.w_lane_offset);
    num("w_long_jerk", k.w_long_jerk);
    num("w_lat_jerk", k.w_lat_jerk);
    num("w_long_acc", k.w_long_acc);
    num("w_lat_acc", k.w_lat_acc);
    num("w_proximity", k.w_proximity);
    num("expected_offset", k.expected_offset);
    num("expected_acc", k.expected_acc);
    num("expected_jerk", k.expected_jerk);
    smp("lat_offset", k.lat_offset);
    num("eval_points", k.eval_points);
    smp("speed", c.speed);
    smp("duration", c.duration);
    num("max_speed_change", c.max_speed_change);
    num("time_gap", c.time_gap);
    num("follow_speed", c.follow_speed);
    num("stop_distance", c.stop_distance);
    num("lane", static_cast<int>(c.lane));
    smp("delta_s", c.delta_s);
    num("delta_v", c.delta_v);
    num("delta_a", c.delta_a);
    num("gap_from_reference", c.gap_from_reference);
    num("stop_at", static_cast<int>(c.stop_at));
    if (c.stop_position) num("stop_position", *c.stop_position);
    num("stop_before", c.stop_before);
    num("stop_decel", c.stop_decel);
    smp("duration_factor", c.duration_factor);
    return out;
}

int candidate_count(const ManeuverConfig& c) {
    auto n = [](const Sampled& s) { return s.samples < 1 ? 1 : s.samples; };
    const int lat = n(c.common.lat_offset);
    switch (c.kind) {
        case ManeuverKind::keep_velocity:
        case ManeuverKind::reverse: return n(c.speed) * n(c.duration) * lat;
        case ManeuverKind::follow:
        case ManeuverKind::lane_change: return n(c.duration) * lat;
        case ManeuverKind::cut_in: return n(c.duration) * n(c.delta_s) * lat;
        case ManeuverKind::stop: return n(c.duration_factor) * lat;
        case ManeuverKind::walk:
        case ManeuverKind::stand:
        case ManeuverKind::wait_at_crosswalk:
        case ManeuverKind::enter_crosswalk:
        case ManeuverKind::exit_crosswalk:
        case ManeuverKind::turn_back:
        case ManeuverKind::select_crosswalk:
        case ManeuverKind::speed_up: return 0;  // pedestrians: no planner candidates
    }
    return 0;
}

}  // namespace sdv::planner
