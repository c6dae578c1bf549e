#include "runtime/planner/maneuver.h"

namespace sdv::planner {
namespace {

Sampled from_default(const catalog::ParamDef& p) {
    const auto& d = *p.def;
    return Sampled::spread(d.value, d.spread_pct, d.samples, p.min >= 0);
}

}  // namespace

ManeuverConfig default_config(ManeuverKind kind) {
    ManeuverConfig c;
    c.kind = kind;
    const auto& def = catalog::maneuver(kind);
    auto num = [&](const char* name) { return def.find_param(name)->def->value; };
    auto smp = [&](const char* name) { return from_default(*def.find_param(name)); };
    CommonConfig& k = c.common;
    k.max_long_jerk = num("max_long_jerk");
    k.max_lat_jerk = num("max_lat_jerk");
    k.max_long_acc = num("max_long_acc");
    k.max_lat_acc = num("max_lat_acc");
    k.collision = num("collision") != 0;
    k.off_lane = num("off_lane") != 0;
    k.direction = num("direction") != 0;
    k.w_time = num("w_time");
    k.w_efficiency = num("w_efficiency");
    k.w_lane_offset = num("w_lane_offset");
    k.w_long_jerk = num("w_long_jerk");
    k.w_lat_jerk = num("w_lat_jerk");
    k.w_long_acc = num("w_long_acc");
    k.w_lat_acc = num("w_lat_acc");
    k.w_proximity = num("w_proximity");
    k.expected_offset = num("expected_offset");
    k.expected_acc = num("expected_acc");
    k.expected_jerk = num("expected_jerk");
    k.lat_offset = Sampled::single(num("lat_offset"));
    k.eval_points = static_cast<int>(num("eval_points"));
    switch (kind) {
        case ManeuverKind::keep_velocity:
            c.speed = smp("speed");
            c.duration = smp("duration");
            c.max_speed_change = num("max_speed_change");
            break;
        case ManeuverKind::follow:
            c.duration = smp("duration");
            c.time_gap = num("time_gap");
            c.stop_distance = num("stop_distance");
            break;
        case ManeuverKind::lane_change:
            c.duration = smp("duration");
            c.lane = LaneTarget::left;
            break;
        case ManeuverKind::cut_in:
            c.duration = smp("duration");
            c.delta_s = Sampled::spread(num("delta_s"), def.find_param("delta_s")->def->spread_pct,
                                        def.find_param("delta_s")->def->samples, false);
            c.delta_v = num("delta_v");
            c.delta_a = num("delta_a");
            c.lane = LaneTarget::target;
            break;
        case ManeuverKind::stop:
            c.duration_factor = smp("duration_factor");
            c.stop_before = num("distance");
            c.stop_at = StopTarget::now;
            break;
        case ManeuverKind::reverse:
            c.speed = smp("speed");
            c.duration = smp("duration");
            break;
    }
    return c;
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
    }
    return 0;
}

}  // namespace sdv::planner
