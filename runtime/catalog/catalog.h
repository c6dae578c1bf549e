// The catalog: every maneuver, condition and expectation function of the language, with its
// parameters (type, dimension, default, allowed range) and a one-line meaning. This is the one
// registry that the checker validates against, the runtime reads its defaults from, and
// `sdv catalog` and docs/catalog.md print. Values are stored in SI units.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/catalog/units.h"

namespace sdv::catalog {

// What kind of value a parameter takes.
enum class ParamType {
    quantity,  // a number with a unit of `dim` (Dim::none: a plain number)
    integer,   // a whole number without unit
    boolean,   // true / false
    choice,    // one of `choices`
    vehicle,   // a vehicle: its name, `ego`, `self`, or a zone (front, front_left, ...)
};

std::string_view to_string(ParamType type);

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// The largest length and width of an agent, in metres (both must also be above 0): what the
// checker accepts for `length` and `width`, and what the readers of recorded traffic accept, so
// that every recorded agent can be written as a scenario (docs/catalog.md, Agent sizes).
struct AgentSize {
    double length;
    double width;
};
inline constexpr AgentSize kMaxVehicleSize{30, 5};     // a vehicle: up to a long articulated bus
inline constexpr AgentSize kMaxPedestrianSize{2, 2};   // a pedestrian: a disc of the larger of the two
inline constexpr AgentSize kMaxObjectSize{100, 5};     // a static object: a long barrier, a parked convoy

// An agent's speed, as a scenario may state it (a vehicle's or pedestrian's `speed`, a
// maneuver's target speed) and the readers of recorded traffic take a vehicle's.
inline constexpr double kMaxVehicleSpeed = 100;   // m/s: 360 km/h, beyond any road vehicle
inline constexpr double kMaxPedestrianSpeed = 10;  // m/s: a sprint

// Values a scenario states outside the parameters below, as the checker accepts them and the
// GeoScenario converter writes them: a time (a timeout, a light phase or offset, a waypoint's
// time) up to a day; a waypoint's or path point's speed, 0 to 100 m/s; a map origin's altitude.
inline constexpr double kMaxScenarioTime = 86400;  // s
inline constexpr double kMaxWaypointSpeed = 100;   // m/s
inline constexpr double kMinAltitude = -1000;      // m
inline constexpr double kMaxAltitude = 10000;      // m
// The points of one sampled value (`samples N`), as the checker accepts them and the GeoScenario
// converter writes an MP(...) or LT(...) spread.
inline constexpr int kMaxSamples = 100;

// A default that may itself be a sampled range: value ±spread_pct % with `samples` points.
struct DefaultValue {
    double value = 0.0;       // SI; for choices the index into `choices`; for booleans 0/1
    double spread_pct = 0.0;  // ± percentage of value (0: a single value)
    int samples = 1;
};

// The planner configuration field a maneuver parameter sets. runtime/planner binds each one
// (planner::set_field, an exhaustive switch); a maneuver parameter with `none` is a defect that
// tests/unit/planner catches. Vehicle parameters (`leader`, `target`) are resolved by the
// runtime into the plan request instead of the configuration.
enum class ConfigField {
    none,
    // common: feasibility
    max_long_jerk, max_lat_jerk, max_long_acc, max_lat_acc, collision, off_lane, direction,
    // common: cost
    w_time, w_efficiency, w_lane_offset, w_long_jerk, w_lat_jerk, w_long_acc, w_lat_acc,
    w_proximity, expected_offset, expected_acc, expected_jerk, efficiency,
    // common: lateral
    lat_offset, eval_points,
    // kind-specific
    speed, duration, max_speed_change, time_gap, stop_distance, follow_speed, lane, delta_s, delta_v, delta_a, gap_from,
    stop_at, stop_position, stop_before, stop_decel, duration_factor,
    // resolved by the runtime into the plan request
    leader, target,
};

struct ParamDef {
    std::string name;
    ParamType type = ParamType::quantity;
    Dim dim = Dim::none;
    std::optional<DefaultValue> def;  // nullopt: required, or optional-without-default (below)
    bool optional = false;            // may be left out even though it has no default
    double min = -kInf;               // allowed range (SI, inclusive)
    double max = kInf;
    bool min_exclusive = false;  // e.g. durations and jerk limits must be > 0
    bool sampleable = false;     // may be given as a range with samples
    std::vector<std::string> choices;
    std::string doc;
    std::string group;  // "" for kind-specific parameters; "feasibility", "cost", "lateral"
    ConfigField field = ConfigField::none;  // maneuver parameters: what it configures

    bool required() const { return !def.has_value() && !optional; }

    // Whether the SI value `x` is in the allowed range (finite, above min, at most max).
    bool accepts(double x) const { return std::isfinite(x) && (min_exclusive ? x > min : x >= min) && x <= max; }

    // The allowed range in words, for the note under an out-of-range error: "0 m to 100 m",
    // "more than 0 s to 60 s", "at least 0 m/s", "at most 5"; `write` writes a bound (an SI value)
    // with its unit as the reader of the message wrote it.
    std::string allowed(const std::function<std::string(double)>& write) const;
};

// Who a leaf is for: a vehicle's tree (SDV), a pedestrian's tree (SDP), or either.
enum class Agent { vehicle, pedestrian, any };
std::string_view to_string(Agent agent);

// The runtime's maneuver kinds: the vehicle maneuvers in the order of SPEC §3.6 (planned by the
// Frenet planner), then the pedestrian maneuvers (they set where and how fast the pedestrian
// walks; the social force model moves it: docs/pedestrians.md).
enum class ManeuverKind {
    keep_velocity, follow, lane_change, cut_in, stop, reverse,
    walk, stand, wait_at_crosswalk, enter_crosswalk, exit_crosswalk, turn_back, select_crosswalk, speed_up,
};
inline constexpr ManeuverKind kFirstPedestrianManeuver = ManeuverKind::walk;

struct ManeuverDef {
    std::string name;
    ManeuverKind kind;
    std::string doc;
    std::string status;  // what the leaf returns, in words
    std::vector<ParamDef> params;  // kind-specific first, then the common ones
    int default_candidates = 0;    // candidates with all defaults (product of samples)
    Agent agent = Agent::vehicle;  // vehicle or pedestrian

    const ParamDef* find_param(std::string_view name) const;
    // Whether the leaf never returns FAILURE (keep_velocity, stop, reverse: RUNNING, then
    // SUCCESS): a fallback never gets past it (the checker's E0403; the GeoScenario converter
    // leaves out what follows it).
    bool never_fails() const;
};

enum class ConditionKind {
    sim_time,
    vehicle_state,
    delta_state,
    gap,
    ttc,
    distance,
    lane_occupied,
    can_lane_change,
    vehicle_moving,
    vehicle_stopped,
    vehicle_parked,
    reached_goal,
    at_lane_change_segment,
    approaching_stop,
    traffic_light,
    stop_for_light,
    intersection_type,
    yield_role,
    intersection_occupied,
    all_way_stop_turn,
    out_of_route,
    wait,
    stopped_at_line,
    time_to_arrival,
    pedestrian_crossing,
    // pedestrians
    has_target_crosswalk,
    approaching_crosswalk,
    at_crosswalk_entrance,
    on_crosswalk,
    crosswalk_exit_reached,
    crosswalk_has_light,
    pedestrian_light,
    can_cross_before_red,
    accept_gap,
};

struct ConditionDef {
    std::string name;
    ConditionKind kind;
    std::string doc;
    std::vector<ParamDef> params;
    // Groups of parameters of which at least one must be given (e.g. sim_time: after/before).
    std::vector<std::string> at_least_one_of;
    // Parameters that exclude each other (e.g. gap: vehicle / lane).
    std::vector<std::string> exclusive;
    Agent agent = Agent::vehicle;  // whose trees may use it

    const ParamDef* find_param(std::string_view name) const;
};

// Functions usable in `expect` statements. The order is that of expectations(): the IR stores
// a function as its index there.
enum class ExpectKind {
    collision,       // collision(a, b) / collision(a) / collision(): bool
    no_collision,    // no_collision(): bool
    reached_goal,    // reached_goal(v): bool
    min_clearance,   // min_clearance(a, b): length, outline clearance in any direction
    min_gap,         // min_gap(a, b): length, same-lane bumper gap along the lane
    min_lateral,     // min_lateral(a, b): length, lateral clearance while side by side
    min_ttc,         // min_ttc(a, b): time, same lane, closing along the lane
    min_headway,     // min_headway(a, b): time, same lane
    max_jerk,        // max_jerk(v): jerk, largest |jerk|
    min_acc,         // min_acc(v): acceleration, most negative (hardest braking)
    max_acc,         // max_acc(v): acceleration, largest positive
    min_speed,       // min_speed(v): speed, signed (reverse is negative)
    max_speed,       // max_speed(v): speed, signed
    fallback_used,   // fallback_used(v): bool
    fallback_share,  // fallback_share(v): ratio of plans without a feasible candidate
    timeout,         // timeout(): bool
};

struct ExpectDef {
    std::string name;
    ExpectKind kind;
    int min_vehicles = 0;  // number of vehicle arguments
    int max_vehicles = 0;
    Dim result = Dim::none;  // none with boolean = true
    bool boolean = false;
    // Measured per tick or from timed events, so it can be restricted to a time window
    // (`after`, `before`, `during`); false: a whole-run count.
    bool windowed = true;
    // The metric in a few words, for reports: a quantity ("same-lane bumper gap") or, for a
    // boolean, the event it looks for ("collision").
    std::string label;
    std::string none;  // what a quantity without value means ("never closing")
    std::string doc;
};

std::span<const ManeuverDef> maneuvers();
std::span<const ConditionDef> conditions();
std::span<const ExpectDef> expectations();

const ManeuverDef* find_maneuver(std::string_view name);
const ConditionDef* find_condition(std::string_view name);
const ExpectDef* find_expectation(std::string_view name);
const ManeuverDef& maneuver(ManeuverKind kind);
const ConditionDef& condition(ConditionKind kind);

// The vehicle zones of SPEC §3.5 and the other words a `vehicle` parameter accepts.
std::span<const std::string> vehicle_zones();

// Rendering, shared by `sdv catalog` and docs/catalog.md.
std::string render_text();
std::string render_markdown();
nlohmann::ordered_json to_json();
// Formats an SI value in the parameter's display unit ("14 m/s ±10 % × 3").
std::string format_default(const ParamDef& p);
// A number as the catalog and the messages about its limits print it: six significant
// digits, no trailing zeros ("30", "2.5", "1e+06", "inf").
std::string format_number(double v);

}  // namespace sdv::catalog
