// Maneuver configurations as the planner consumes them: plain numbers in SI, the field names of
// the catalog (runtime/catalog), whose defaults `default_config` reads, so that the language,
// `sdv catalog` and the planner can never disagree on a default.
#pragma once

#include <optional>
#include <string>

#include "runtime/catalog/catalog.h"
#include "runtime/planner/sampling.h"

namespace sdv::planner {

using catalog::ManeuverKind;

enum class StopTarget { goal, stop_line, position, now, pedestrian };
enum class LaneTarget { left, right, route, current, target };

struct CommonConfig {
    double max_long_jerk = 10, max_lat_jerk = 10;
    double max_long_acc = 12, max_lat_acc = 4.9;
    bool collision = true, off_lane = true, direction = true;
    double w_time = 1, w_efficiency = 1, w_lane_offset = 1, w_long_jerk = 1, w_lat_jerk = 1,
           w_long_acc = 1, w_lat_acc = 1, w_proximity = 10;
    // The efficiency cost: the mean speed's deviation from the target speed (false), or
    // GeoScenario's, which falls as the mean speed rises (true; see planner.cpp).
    bool efficiency_reference = false;
    double expected_offset = 0.5, expected_acc = 1, expected_jerk = 2;
    Sampled lat_offset = Sampled::single(0.0);
    int eval_points = 10;
};

struct ManeuverConfig {
    ManeuverKind kind = ManeuverKind::keep_velocity;
    CommonConfig common;
    Sampled speed = Sampled::single(14);        // keep_velocity, reverse
    Sampled duration = Sampled::single(3);      // all but stop
    double max_speed_change = 8;                // keep_velocity
    double time_gap = 3, stop_distance = 3;     // follow
    double follow_speed = 0;                    // follow: the driver's own speed (0: none)
    LaneTarget lane = LaneTarget::left;         // lane_change, cut_in
    Sampled delta_s = Sampled::single(10);      // cut_in
    double delta_v = 5, delta_a = 0;            // cut_in
    bool gap_from_reference = false;            // cut_in: delta_s beyond 2 own lengths (GeoScenario)
    StopTarget stop_at = StopTarget::now;       // stop
    std::optional<double> stop_position;        // stop (at = position)
    double stop_before = 0;                     // stop
    double stop_decel = 3;                      // stop (at = now)
    Sampled duration_factor = Sampled::single(1);  // stop
};

// The one binding of maneuver parameters: sets the field a catalog parameter names
// (ParamDef::field) from its value (`number` for quantities, integers and booleans, `choice`
// for choices, as an index into the parameter's choices). Returns false for fields that are
// not part of the configuration (the vehicles `leader` and `target`, which the runtime
// resolves into the plan request) and for `none`.
bool set_field(ManeuverConfig& config, catalog::ConfigField field, const Sampled& number, int choice);

// The catalog's defaults for a maneuver kind (SPEC §3.6), applied through set_field.
ManeuverConfig default_config(ManeuverKind kind);

// Every field of a configuration as text, one `name=value` per field (for traces and tests).
std::string describe(const ManeuverConfig& config);

// Candidates a configuration produces: the product of its sample counts.
int candidate_count(const ManeuverConfig& config);

}  // namespace sdv::planner
