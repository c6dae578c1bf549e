// The catalog's contents. Defaults and candidate counts follow SPEC §3.6 (taken from the
// reference implementation); allowed ranges are physical plausibility limits that the checker
// enforces so that absurd values (negative durations, zero jerk limits, 1e308) never reach the
// runtime.
#include "runtime/catalog/catalog.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>

namespace sdv::catalog {
namespace {

// The agent sizes as `sdv catalog` prints them (markdown and JSON).
const std::pair<const char*, AgentSize> kAgentSizes[] = {
    {"vehicle", kMaxVehicleSize}, {"pedestrian", kMaxPedestrianSize}, {"object", kMaxObjectSize}};

// Small builders keep the tables below readable.
ParamDef qty(std::string name, Dim dim, std::optional<DefaultValue> def, double lo, double hi,
             std::string doc, bool lo_exclusive = false) {
    ParamDef p;
    p.name = std::move(name);
    p.type = ParamType::quantity;
    p.dim = dim;
    p.def = def;
    p.min = lo;
    p.max = hi;
    p.min_exclusive = lo_exclusive;
    p.doc = std::move(doc);
    return p;
}

ParamDef sampled(std::string name, Dim dim, double value, double pct, int n, double lo, double hi,
                 std::string doc, bool lo_exclusive = false) {
    ParamDef p = qty(std::move(name), dim, DefaultValue{value, pct, n}, lo, hi, std::move(doc),
                     lo_exclusive);
    p.sampleable = true;
    return p;
}

ParamDef opt_qty(std::string name, Dim dim, double lo, double hi, std::string doc) {
    ParamDef p = qty(std::move(name), dim, std::nullopt, lo, hi, std::move(doc));
    p.optional = true;
    return p;
}

ParamDef choice(std::string name, std::vector<std::string> choices, std::optional<int> def,
                std::string doc) {
    ParamDef p;
    p.name = std::move(name);
    p.type = ParamType::choice;
    p.choices = std::move(choices);
    if (def) p.def = DefaultValue{static_cast<double>(*def), 0, 1};
    p.doc = std::move(doc);
    return p;
}

ParamDef vehicle(std::string name, bool required, std::string doc) {
    ParamDef p;
    p.name = std::move(name);
    p.type = ParamType::vehicle;
    p.optional = !required;
    p.doc = std::move(doc);
    return p;
}

ParamDef boolean(std::string name, bool def, std::string doc) {
    ParamDef p;
    p.name = std::move(name);
    p.type = ParamType::boolean;
    p.def = DefaultValue{def ? 1.0 : 0.0, 0, 1};
    p.doc = std::move(doc);
    return p;
}

ParamDef integer(std::string name, int def, double lo, double hi, std::string doc) {
    ParamDef p;
    p.name = std::move(name);
    p.type = ParamType::integer;
    p.def = DefaultValue{static_cast<double>(def), 0, 1};
    p.min = lo;
    p.max = hi;
    p.doc = std::move(doc);
    return p;
}

ParamDef in_group(ParamDef p, std::string group) {
    p.group = std::move(group);
    return p;
}

// A maneuver parameter and the configuration field it sets.
ParamDef sets(ConfigField field, ParamDef p) {
    p.field = field;
    return p;
}

constexpr double kMaxSpeed = kMaxVehicleSpeed;
constexpr double kMaxDuration = 60.0;   // s: a single maneuver plan
constexpr double kMaxDistance = 10000;  // m
constexpr double kMaxAcc = 50.0;        // m/s²
constexpr double kMaxJerk = 100.0;      // m/s³

// The parameters every maneuver shares (SPEC §3.6 "Common parameters").
std::vector<ParamDef> common_params(double max_long_acc) {
    std::vector<ParamDef> ps = {
        sets(ConfigField::max_long_jerk, in_group(qty("max_long_jerk", Dim::jerk, DefaultValue{10}, 0, kMaxJerk,
                     "longitudinal jerk limit of a feasible trajectory", true),
                 "feasibility")),
        sets(ConfigField::max_lat_jerk, in_group(qty("max_lat_jerk", Dim::jerk, DefaultValue{10}, 0, kMaxJerk,
                     "lateral jerk limit of a feasible trajectory", true),
                 "feasibility")),
        sets(ConfigField::max_long_acc, in_group(qty("max_long_acc", Dim::accel, DefaultValue{max_long_acc}, 0, kMaxAcc,
                     "longitudinal acceleration limit (magnitude)", true),
                 "feasibility")),
        sets(ConfigField::max_lat_acc, in_group(qty("max_lat_acc", Dim::accel, DefaultValue{4.9}, 0, kMaxAcc,
                     "lateral acceleration limit (magnitude)", true),
                 "feasibility")),
        sets(ConfigField::collision, in_group(boolean("collision", true, "reject candidates that collide with a perceived "
                                            "vehicle or obstacle"),
                 "feasibility")),
        sets(ConfigField::off_lane, in_group(boolean("off_lane", true, "reject candidates that leave the current lane"),
                 "feasibility")),
        sets(ConfigField::direction, in_group(boolean("direction", true, "reject candidates whose s decreases"),
                 "feasibility")),
    };
    const struct {
        ConfigField field;
        const char* name;
        const char* doc;
    } weights[] = {
        {ConfigField::w_time, "w_time", "weight of the deviation from the target duration"},
        {ConfigField::w_efficiency, "w_efficiency", "weight of the mean-speed deviation from the target speed"},
        {ConfigField::w_lane_offset, "w_lane_offset", "weight of the offset from the lane centre"},
        {ConfigField::w_long_jerk, "w_long_jerk", "weight of the total longitudinal jerk"},
        {ConfigField::w_lat_jerk, "w_lat_jerk", "weight of the total lateral jerk"},
        {ConfigField::w_long_acc, "w_long_acc", "weight of the total longitudinal acceleration"},
        {ConfigField::w_lat_acc, "w_lat_acc", "weight of the total lateral acceleration"},
    };
    for (const auto& w : weights) {
        ps.push_back(sets(w.field, in_group(qty(w.name, Dim::none, DefaultValue{1}, 0, 1e6, w.doc), "cost")));
    }
    ps.push_back(sets(ConfigField::efficiency,
                      in_group(choice("efficiency", {"deviation", "reference"}, 0,
                                      "efficiency cost: deviation = of the mean speed from the target speed; reference = "
                                      "GeoScenario's effic_cost, logistic(2 (T - v) / v) of the mean speed v and the nominal "
                                      "duration T, which falls as the mean speed rises"),
                               "cost")));
    ps.push_back(sets(ConfigField::w_proximity, in_group(
        qty("w_proximity", Dim::none, DefaultValue{10}, 0, 1e6, "weight of the proximity to "
                                                                 "other vehicles and obstacles"),
        "cost")));
    ps.push_back(sets(ConfigField::expected_offset, in_group(qty("expected_offset", Dim::length, DefaultValue{0.5}, 0, 100,
                              "normaliser of the lane-offset cost", true),
                          "cost")));
    ps.push_back(sets(ConfigField::expected_acc, in_group(qty("expected_acc", Dim::accel, DefaultValue{1}, 0, kMaxAcc,
                              "normaliser of the acceleration costs", true),
                          "cost")));
    ps.push_back(sets(ConfigField::expected_jerk, in_group(qty("expected_jerk", Dim::jerk, DefaultValue{2}, 0, kMaxJerk,
                              "normaliser of the jerk costs", true),
                          "cost")));
    ps.push_back(sets(ConfigField::lat_offset, in_group(sampled("lat_offset", Dim::length, 0, 0, 1, -10, 10,
                                  "lateral target: offset from the target lane's centre (left "
                                  "positive)"),
                          "lateral")));
    ps.push_back(sets(ConfigField::eval_points, in_group(integer("eval_points", 10, 2, 1000,
                                  "points per trajectory at which feasibility is checked"),
                          "lateral")));
    return ps;
}

ManeuverDef make_maneuver(std::string name, ManeuverKind kind, std::string doc, std::string status,
                          std::vector<ParamDef> specific, double max_long_acc = 12) {
    ManeuverDef m{std::move(name), kind, std::move(doc), std::move(status), std::move(specific), 0};
    for (auto& p : common_params(max_long_acc)) m.params.push_back(std::move(p));
    int n = 1;
    for (const auto& p : m.params) {
        if (p.sampleable && p.def) n *= p.def->samples;
    }
    m.default_candidates = n;
    return m;
}

constexpr double kMaxWalkSpeed = kMaxPedestrianSpeed;

// Pedestrian maneuvers set the walker's intent (where to, how fast); they have no planner
// parameters. Each is SUCCESS when it could set its intent, FAILURE when it has nothing to act on.
void add_pedestrian_maneuvers(std::vector<ManeuverDef>& ms) {
    auto speed = [](double def, const char* doc) {
        return sampled("speed", Dim::speed, def, 0, 1, 0, kMaxWalkSpeed, doc);
    };
    auto add = [&](std::string name, ManeuverKind kind, std::string doc, std::string status,
                   std::vector<ParamDef> params) {
        ManeuverDef m{std::move(name), kind, std::move(doc), std::move(status), std::move(params), 1};
        m.agent = Agent::pedestrian;
        ms.push_back(std::move(m));
    };
    add("walk", ManeuverKind::walk,
        "walk its way: to the entrance of its target crosswalk (where it stops: `enter_crosswalk` "
        "steps onto it), along the crosswalk once on it, else straight to its goal (crossing any "
        "road on the way) and stand there; without a goal, straight ahead",
        "SUCCESS",
        {speed(1.4, "desired walking speed"),
         qty("arrive", Dim::length, DefaultValue{0.3}, 0.05, 10, "distance at which a point of the way counts as reached"),
         vehicle("meet", false,
                 "with a target crosswalk: walk at the speed that reaches the point where this vehicle's heading "
                 "crosses the crosswalk when the vehicle does, and stand while it heads for none "
                 "(GeoScenario's ensured collision)")});
    add("stand", ManeuverKind::stand, "stop walking and stand where it is (the social force model "
        "brings it to rest within about a second)", "SUCCESS", {});
    add("wait_at_crosswalk", ManeuverKind::wait_at_crosswalk,
        "walk to the entrance of its target crosswalk and wait there",
        "SUCCESS; FAILURE without a target crosswalk",
        {speed(1.4, "walking speed to the entrance")});
    add("enter_crosswalk", ManeuverKind::enter_crosswalk,
        "step onto its target crosswalk and walk across it to the far end",
        "SUCCESS; FAILURE without a target crosswalk",
        {speed(1.4, "walking speed on the crosswalk")});
    add("exit_crosswalk", ManeuverKind::exit_crosswalk,
        "leave the crosswalk at its far end and walk on to the goal (the crosswalk is done)",
        "SUCCESS; FAILURE without a target crosswalk",
        {speed(1.4, "walking speed after the crosswalk")});
    add("turn_back", ManeuverKind::turn_back,
        "on a crosswalk: walk back to the end it entered by, and wait there",
        "SUCCESS; FAILURE when not on a crosswalk",
        {speed(1.4, "walking speed back")});
    add("select_crosswalk", ManeuverKind::select_crosswalk,
        "choose the crosswalk to cross by: the nearest on its way, or (by = light) the nearest "
        "whose pedestrian signal is green, else the nearest",
        "SUCCESS; FAILURE when no crosswalk is on its way within max_detour",
        {choice("by", {"nearest", "light"}, 0, "how to choose"),
         qty("max_detour", Dim::length, DefaultValue{50}, 0, kMaxDistance,
             "longest detour over walking straight to the goal")});
    add("speed_up", ManeuverKind::speed_up,
        "walk on the same way, faster (hurrying across when the signal changes)",
        "SUCCESS",
        {qty("factor", Dim::none, DefaultValue{1.5}, 1, 5, "factor on the current desired speed"),
         qty("max_speed", Dim::speed, DefaultValue{2.5}, 0, kMaxWalkSpeed, "never faster than this", true)});
}

std::vector<ManeuverDef> build_maneuvers() {
    std::vector<ManeuverDef> ms;
    {
        auto speed = sets(ConfigField::speed, sampled("speed", Dim::speed, 14, 10, 3, 0, kMaxSpeed, "target speed"));
        ms.push_back(make_maneuver(
            "keep_velocity", ManeuverKind::keep_velocity,
            "drive in the lane at a target speed (quartic in s)", "SUCCESS",
            {speed,
             sets(ConfigField::duration, sampled("duration", Dim::time, 3, 20, 6, 0, kMaxDuration,
                     "time to reach the target speed", true)),
             sets(ConfigField::max_speed_change, qty("max_speed_change", Dim::speed, DefaultValue{8}, 0, kMaxSpeed,
                 "largest speed change planned in one cycle", true))}));
    }
    ms.push_back(make_maneuver(
        "follow", ManeuverKind::follow,
        "follow a leader at a time gap; stop behind it when it is (nearly) stopped (quintic)",
        "SUCCESS; FAILURE without a leader",
        {sets(ConfigField::leader, vehicle("leader", false, "the vehicle to follow (default: nearest ahead in the lane)")),
         sets(ConfigField::duration, sampled("duration", Dim::time, 4, 50, 10, 0, kMaxDuration, "time to settle behind the "
                                                                     "leader", true)),
         sets(ConfigField::time_gap, qty("time_gap", Dim::time, DefaultValue{3}, 0, 60, "time headway kept to the leader")),
         sets(ConfigField::stop_distance, qty("stop_distance", Dim::length, DefaultValue{3}, 0, 100,
             "bumper gap kept to a stopped leader")),
         sets(ConfigField::follow_speed, opt_qty("speed", Dim::speed, 0, kMaxSpeed,
             "the driver's own speed: never faster behind a faster leader, and the pace at which "
             "it closes in on a distant one (default: the leader's speed + 3 m/s)"))}));
    ms.push_back(make_maneuver(
        "lane_change", ManeuverKind::lane_change,
        "change to the neighbour lane (or swerve inside the lane with lat_offset) keeping the "
        "current speed (quartic)",
        "RUNNING until the footprint is in the target lane, then SUCCESS",
        {sets(ConfigField::lane, choice("lane", {"left", "right", "route", "current"}, 0,
                "target lane: left, right, the lane the route needs, or current (swerve)")),
         sets(ConfigField::duration, sampled("duration", Dim::time, 4.2, 10, 6, 0, kMaxDuration, "lane-change duration",
                 true))}));
    ms.push_back(make_maneuver(
        "cut_in", ManeuverKind::cut_in,
        "change lane into a gap relative to a target vehicle (quintic)",
        "RUNNING until in the target lane with the end state reached (gap within 2 m or 20 %, relative "
        "speed within 1 m/s), then SUCCESS; FAILURE without target, when already in the target lane, "
        "or when the end state is not reached within twice the longest duration",
        {sets(ConfigField::target, vehicle("target", true, "the vehicle to cut in front of")),
         sets(ConfigField::lane, choice("lane", {"left", "right", "target"}, 2,
                "target lane: left, right, or the target vehicle's lane")),
         sets(ConfigField::duration, sampled("duration", Dim::time, 4, 10, 6, 0, kMaxDuration, "cut-in duration", true)),
         sets(ConfigField::delta_s, sampled("delta_s", Dim::length, 10, 10, 5, -200, 200,
                 "bumper gap to the target at the end: its front to the own rear (negative: behind it)")),
         sets(ConfigField::gap_from, choice("gap_from", {"bumpers", "reference"}, 0,
                "what delta_s measures: the bumper gap, or (reference) the distance beyond two own "
                "lengths ahead of the target's centre, as GeoScenario Server does")),
         sets(ConfigField::delta_v, qty("delta_v", Dim::speed, DefaultValue{5}, -kMaxSpeed, kMaxSpeed,
             "speed relative to the target at the end")),
         sets(ConfigField::delta_a, qty("delta_a", Dim::accel, DefaultValue{0}, -kMaxAcc, kMaxAcc,
             "acceleration relative to the target at the end"))}));
    {
        auto m = make_maneuver(
            "stop", ManeuverKind::stop,
            "stop at the goal, the next stop line, a position, or now (quintic); behind the drivers "
            "queued in the own lane before the point (at a stop line or a pedestrian, those still "
            "moving too, as they will queue up to it), a standstill gap of 3 m apart",
            "SUCCESS",
            {sets(ConfigField::stop_at, choice("at", {"goal", "stop_line", "position", "now", "pedestrian"}, 3,
                 "where to stop (pedestrian: before the crosswalk of the nearest pedestrian that "
                 "`pedestrian_crossing` sees, or before the pedestrian itself off a crosswalk)")),
             sets(ConfigField::stop_position, opt_qty("position", Dim::length, 0, kMaxDistance,
                     "s along the lane to stop at (with at = position)")),
             sets(ConfigField::stop_before, qty("distance", Dim::length, DefaultValue{0}, 0, 100,
                 "stop this far before the target")),
             sets(ConfigField::stop_decel, qty("decel", Dim::accel, DefaultValue{3}, 0, kMaxAcc,
                 "peak deceleration of a stop `now` (with duration_factor 1); it stops "
                 "1.875·v²/(2·decel) ahead", true)),
             sets(ConfigField::duration_factor, sampled("duration_factor", Dim::none, 1, 40, 6, 0, 10,
                     "duration as a factor of 2·Δs/v", true))},
            30);
        ms.push_back(std::move(m));
    }
    {
        auto m = make_maneuver(
            "reverse", ManeuverKind::reverse, "drive backwards at a target speed (quartic)",
            "SUCCESS",
            {sets(ConfigField::speed, sampled("speed", Dim::speed, 5, 10, 6, 0, 30, "reverse speed (magnitude)")),
             sets(ConfigField::duration, sampled("duration", Dim::time, 3, 20, 3, 0, kMaxDuration,
                     "time to reach the speed", true))});
        for (auto& p : m.params) {
            if (p.name == "direction") p.def->value = 0.0;  // backwards is the point
        }
        ms.push_back(std::move(m));
    }
    add_pedestrian_maneuvers(ms);
    return ms;
}

const std::vector<std::string> kLanes3 = {"left", "current", "right"};

void add_pedestrian_conditions(std::vector<ConditionDef>& cs) {
    auto add = [&](std::string name, ConditionKind kind, std::string doc, std::vector<ParamDef> params) {
        cs.push_back(ConditionDef{std::move(name), kind, std::move(doc), std::move(params), {}, {}, Agent::pedestrian});
    };
    add("has_target_crosswalk", ConditionKind::has_target_crosswalk,
        "the pedestrian has chosen a crosswalk (select_crosswalk) and not yet left it", {});
    add("approaching_crosswalk", ConditionKind::approaching_crosswalk,
        "a crosswalk on its way to the goal (one across vehicle lanes whose far end is nearer to the goal than "
        "its near end, within max_detour) has an end within a distance",
        {qty("distance", Dim::length, DefaultValue{15}, 0, kMaxDistance, "distance to the crosswalk's near end"),
         qty("max_detour", Dim::length, DefaultValue{50}, 0, kMaxDistance,
             "longest detour over walking straight to the goal")});
    add("at_crosswalk_entrance", ConditionKind::at_crosswalk_entrance,
        "the pedestrian is off its target crosswalk, within a distance of the end it enters by",
        {qty("distance", Dim::length, DefaultValue{1.5}, 0, 100, "distance to the entrance")});
    add("on_crosswalk", ConditionKind::on_crosswalk,
        "the pedestrian has entered its target crosswalk and not yet left it", {});
    add("crosswalk_exit_reached", ConditionKind::crosswalk_exit_reached,
        "the pedestrian is on its target crosswalk within a distance of the far end",
        {qty("distance", Dim::length, DefaultValue{1.5}, 0, 100, "distance to the far end")});
    add("crosswalk_has_light", ConditionKind::crosswalk_has_light,
        "its target crosswalk has a pedestrian signal", {});
    add("pedestrian_light", ConditionKind::pedestrian_light,
        "the pedestrian signal of its target crosswalk shows a state (a crosswalk without signal "
        "shows none)",
        {choice("state", {"red", "yellow", "green"}, std::nullopt, "signal state")});
    add("can_cross_before_red", ConditionKind::can_cross_before_red,
        "walking the rest of its target crosswalk at its desired speed takes less than the time "
        "until its signal turns red, minus a margin (always true without a signal; false on red)",
        {qty("margin", Dim::time, DefaultValue{0}, 0, 60, "safety margin")});
    add("accept_gap", ConditionKind::accept_gap,
        "every vehicle that would cross the pedestrian's way ahead (its target crosswalk, or its "
        "straight way to the goal) within a distance arrives there later than a time gap, or is "
        "standing still: the pedestrian accepts the gap",
        {qty("time", Dim::time, DefaultValue{4}, 0, 60, "smallest accepted time gap"),
         qty("distance", Dim::length, DefaultValue{80}, 0, kMaxDistance, "vehicles farther than this along their lane are ignored")});
}

std::vector<ConditionDef> build_conditions() {
    std::vector<ConditionDef> cs;
    auto add = [&](std::string name, ConditionKind kind, std::string doc,
                   std::vector<ParamDef> params, std::vector<std::string> one_of = {},
                   std::vector<std::string> exclusive = {}) {
        cs.push_back(ConditionDef{std::move(name), kind, std::move(doc), std::move(params),
                                  std::move(one_of), std::move(exclusive)});
    };
    const auto self = [] {
        return vehicle("vehicle", false, "the vehicle observed (default: self)");
    };
    add("sim_time", ConditionKind::sim_time,
        "simulation time is after / before / inside a window",
        {opt_qty("after", Dim::time, 0, 1e6, "true from this time on"),
         opt_qty("before", Dim::time, 0, 1e6, "true until this time")},
        {"after", "before"});
    add("vehicle_state", ConditionKind::vehicle_state,
        "a vehicle's s, d, speed or acceleration is within bounds",
        {self(), opt_qty("s_min", Dim::length, -kMaxDistance, kMaxDistance, "lower bound of s"),
         opt_qty("s_max", Dim::length, -kMaxDistance, kMaxDistance, "upper bound of s"),
         opt_qty("d_min", Dim::length, -100, 100, "lower bound of d"),
         opt_qty("d_max", Dim::length, -100, 100, "upper bound of d"),
         opt_qty("speed_min", Dim::speed, -kMaxSpeed, kMaxSpeed, "lower bound of speed"),
         opt_qty("speed_max", Dim::speed, -kMaxSpeed, kMaxSpeed, "upper bound of speed"),
         opt_qty("acc_min", Dim::accel, -kMaxAcc, kMaxAcc, "lower bound of acceleration"),
         opt_qty("acc_max", Dim::accel, -kMaxAcc, kMaxAcc, "upper bound of acceleration")},
        {"s_min", "s_max", "d_min", "d_max", "speed_min", "speed_max", "acc_min", "acc_max"});
    add("delta_state", ConditionKind::delta_state,
        "another vehicle's state relative to self (other − self) is within bounds",
        {vehicle("vehicle", true, "the other vehicle"),
         opt_qty("ds_min", Dim::length, -kMaxDistance, kMaxDistance, "lower bound of Δs"),
         opt_qty("ds_max", Dim::length, -kMaxDistance, kMaxDistance, "upper bound of Δs"),
         opt_qty("dd_min", Dim::length, -100, 100, "lower bound of Δd"),
         opt_qty("dd_max", Dim::length, -100, 100, "upper bound of Δd"),
         opt_qty("dv_min", Dim::speed, -kMaxSpeed, kMaxSpeed, "lower bound of Δspeed"),
         opt_qty("dv_max", Dim::speed, -kMaxSpeed, kMaxSpeed, "upper bound of Δspeed")},
        {"ds_min", "ds_max", "dd_min", "dd_max", "dv_min", "dv_max"});
    {
        auto min = opt_qty("min", Dim::length, -kMaxDistance, kMaxDistance,
                           "true when the bumper gap is at least this");
        min.sampleable = true;
        add("gap", ConditionKind::gap,
            "bumper-to-bumper longitudinal gap to a vehicle, or to the nearest vehicle in a lane",
            {vehicle("vehicle", false, "the other vehicle"),
             choice("lane", kLanes3, std::nullopt, "or: the nearest vehicle in this lane"), min,
             opt_qty("max", Dim::length, -kMaxDistance, kMaxDistance,
                     "true when the bumper gap is at most this"),
             opt_qty("time_min", Dim::time, 0, 1e4,
                     "true when the time gap (the bumper gap over the driver's own speed; infinite below 0.1 m/s) is at least this"),
             opt_qty("time_max", Dim::time, 0, 1e4,
                     "true when the time gap (the bumper gap over the driver's own speed) is at most this")},
            {"min", "max", "time_min", "time_max"}, {"vehicle", "lane"});
        cs.back().params[1].optional = true;
    }
    add("ttc", ConditionKind::ttc, "time to collision with a vehicle is below a threshold",
        {vehicle("vehicle", false, "the other vehicle (default: the leader in the lane)"),
         qty("max", Dim::time, std::nullopt, 0, 1e4, "threshold", true)});
    add("distance", ConditionKind::distance,
        "Euclidean distance between the vehicles' centres is within bounds",
        {vehicle("vehicle", true, "the other vehicle"),
         opt_qty("min", Dim::length, 0, kMaxDistance, "lower bound"),
         opt_qty("max", Dim::length, 0, kMaxDistance, "upper bound")},
        {"min", "max"});
    add("lane_occupied", ConditionKind::lane_occupied,
        "a vehicle is ahead in a lane within a distance or time gap",
        {choice("lane", kLanes3, 1, "which lane"),
         qty("distance", Dim::length, DefaultValue{30}, 0, kMaxDistance, "look-ahead distance"),
         opt_qty("time_gap", Dim::time, 0, 1e4, "or: look-ahead time at own speed"),
         boolean("objects", true, "count objects (`object`) too; a static vehicle (a parked car) always counts, as in GeoScenario, whose lane occupancy holds vehicles only")});
    add("can_lane_change", ConditionKind::can_lane_change,
        "the target lane exists, runs the same way, and has no vehicle whose bumper gap to the driver (ahead or behind, along the lane) is under gap",
        {choice("lane", {"left", "right"}, std::nullopt, "target lane"),
         qty("gap", Dim::length, DefaultValue{10}, 0, kMaxDistance, "free bumper gap needed ahead and behind")});
    add("vehicle_moving", ConditionKind::vehicle_moving, "a vehicle moves faster than a threshold",
        {self(), qty("min_speed", Dim::speed, DefaultValue{0.5}, 0, kMaxSpeed, "threshold")});
    add("vehicle_stopped", ConditionKind::vehicle_stopped,
        "a vehicle moves slower than a threshold",
        {self(), qty("max_speed", Dim::speed, DefaultValue{0.1}, 0, kMaxSpeed, "threshold")});
    add("vehicle_parked", ConditionKind::vehicle_parked,
        "a vehicle has been stopped for at least a duration",
        {self(), qty("duration", Dim::time, DefaultValue{2}, 0, 1e4, "time stopped")});
    add("reached_goal", ConditionKind::reached_goal,
        "own route is complete and the goal is within a distance",
        {qty("distance", Dim::length, DefaultValue{4}, 0, 1000, "distance along the lane")});
    add("at_lane_change_segment", ConditionKind::at_lane_change_segment,
        "the route needs a lane change from the current lane",
        {choice("lane", {"left", "right", "any"}, 2, "direction of the needed change")});
    add("approaching_stop", ConditionKind::approaching_stop,
        "a stop line or intersection entry is ahead within a distance",
        {qty("distance", Dim::length, DefaultValue{30}, 0, kMaxDistance, "look-ahead distance"),
         choice("kind", {"stop_line", "intersection", "any"}, 2, "what to look for")});
    add("traffic_light", ConditionKind::traffic_light,
        "the light controlling own lane ahead shows a state",
        {choice("state", {"red", "yellow", "green"}, std::nullopt, "light state"),
         qty("distance", Dim::length, DefaultValue{100}, 0, kMaxDistance,
             "ignore lights farther than this")});
    add("stop_for_light", ConditionKind::stop_for_light,
        "the light ahead is red or yellow and the driver stops for it: it can bring its front "
        "bumper to rest at the stop line at no more than `decel`, or it decided so before (kept "
        "until green); a driver too close to stop goes on (the dilemma zone)",
        {qty("distance", Dim::length, DefaultValue{60}, 0, kMaxDistance, "ignore lights farther than this"),
         qty("decel", Dim::accel, DefaultValue{3}, 0, kMaxAcc,
             "the hardest constant deceleration the driver stops with")});
    add("intersection_type", ConditionKind::intersection_type,
        "the next intersection on the route is of a type",
        {choice("type", {"all_way_stop", "traffic_light", "yield", "none", "pedestrian_crossing"}, std::nullopt,
                "intersection type")});
    add("yield_role", ConditionKind::yield_role,
        "own lane's role at the next right-of-way element",
        {choice("role", {"yield", "priority"}, std::nullopt, "role")});
    add("intersection_occupied", ConditionKind::intersection_occupied,
        "another vehicle is inside the next intersection (or on a conflicting lane within "
        "distance)",
        {qty("distance", Dim::length, DefaultValue{0}, 0, 1000, "margin before the junction")});
    add("all_way_stop_turn", ConditionKind::all_way_stop_turn,
        "at an all-way stop, it is own turn (first come, first served; ties by vehicle order); an "
        "impatient driver, waiting at the line longer than `impatient_after`, takes the turn out of "
        "order with probability `impatient_chance` per planning cycle (never while another pulls away "
        "or the junction is occupied; GeoScenario's aws_yielding: 5 s, 0.05)",
        {qty("impatient_after", Dim::time, DefaultValue{0}, 0, 3600, "waiting this long makes it impatient (0: never)"),
         qty("impatient_chance", Dim::none, DefaultValue{0}, 0, 1,
             "then the chance per planning cycle that it goes out of turn (seeded: reproducible)")});
    add("out_of_route", ConditionKind::out_of_route,
        "own lane is not on the route to the goal (routes are re-planned as the vehicle moves, so "
        "this holds only while no route from the current lane exists)",
        {});
    add("wait", ConditionKind::wait,
        "a timer: SUCCESS once the node has been ticked on every planning cycle for a time, "
        "FAILURE before (a cycle that skips the node restarts it)",
        {qty("time", Dim::time, DefaultValue{1}, 0, 1e4, "time to wait")});
    add("stopped_at_line", ConditionKind::stopped_at_line,
        "the vehicle has come to a stop at the stop line of its current lane (within a distance "
        "before it): the latch of a stop sign, true until it leaves that lane",
        {qty("distance", Dim::length, DefaultValue{3}, 0, 100, "largest gap from the front bumper to the line")});
    add("time_to_arrival", ConditionKind::time_to_arrival,
        "time a vehicle needs at its current speed to reach the next junction (its conflict zone) "
        "or stop line along its lanes (along its route for the driver itself; along the shortest "
        "way for another vehicle) is within bounds; a vehicle inside the junction has 0, one "
        "standing still or with none within 300 m never arrives",
        {vehicle("vehicle", false, "whose arrival (default: the driver itself)"),
         choice("at", {"junction", "stop_line", "crossing"}, 0,
                "where to (crossing: in a pedestrian's tree, where the vehicle's lane meets the "
                "pedestrian's way; in a vehicle's tree, the next crosswalk)"),
         opt_qty("min", Dim::time, 0, 1e4, "lower bound"),
         opt_qty("max", Dim::time, 0, 1e4, "upper bound")},
        {"min", "max"});
    add("pedestrian_crossing", ConditionKind::pedestrian_crossing,
        "a pedestrian is on a crosswalk across the driver's lanes ahead within a distance, or at "
        "its entrance (within 2 m, not walking away), or inside the driver's lane ahead off any "
        "crosswalk",
        {qty("distance", Dim::length, DefaultValue{40}, 0, kMaxDistance, "look-ahead distance")});
    add_pedestrian_conditions(cs);
    // Conditions any agent may use: they read time, other agents, or its own goal.
    for (auto& c : cs) {
        if (c.kind == ConditionKind::sim_time || c.kind == ConditionKind::wait || c.kind == ConditionKind::distance ||
            c.kind == ConditionKind::reached_goal || c.kind == ConditionKind::time_to_arrival ||
            c.kind == ConditionKind::vehicle_moving || c.kind == ConditionKind::vehicle_stopped) {
            c.agent = Agent::any;
        }
    }
    return cs;
}

std::vector<ExpectDef> build_expectations() {
    // name, kind, vehicles min/max, result, boolean, windowed, label, none, meaning. Pair metrics
    // are symmetric; a minimum never measured (never in the same lane, never closing, never
    // side by side) is none: it compares as +infinity and is null in summary.json.
    return {
        {"collision", ExpectKind::collision, 0, 2, Dim::none, true, true, "collision", "",
         "a collision started (between the given vehicles, or involving one, or any); in a "
         "window: one that started in it"},
        {"no_collision", ExpectKind::no_collision, 0, 0, Dim::none, true, true, "collision", "",
         "no collision at all; in a window: none started in it"},
        {"reached_goal", ExpectKind::reached_goal, 1, 1, Dim::none, true, true, "goal reached",
         "",
         "the vehicle reached (or overshot) its goal; with a window: at a time in it "
         "(`before 20 s`: by 20 s)"},
        {"min_clearance", ExpectKind::min_clearance, 2, 2, Dim::length, false, true,
         "outline clearance", "not measured",
         "smallest outline clearance: the distance between the two footprints in any direction "
         "(0 when they touch), whatever their lanes"},
        {"min_gap", ExpectKind::min_gap, 2, 2, Dim::length, false, true, "same-lane bumper gap",
         "never in the same lane",
         "smallest bumper gap along the lane (rear bumper of the one ahead minus front bumper of "
         "the one behind), measured only while both centres are in the same lane (or the one "
         "ahead in the lane that directly follows); none when never in the same lane"},
        {"min_lateral", ExpectKind::min_lateral, 2, 2, Dim::length, false, true,
         "lateral clearance", "never side by side",
         "smallest lateral clearance: the distance between the footprints across the heading of "
         "either vehicle, while they overlap along it (side by side); none when never side by "
         "side"},
        {"min_ttc", ExpectKind::min_ttc, 2, 2, Dim::time, false, true,
         "same-lane time to collision", "never closing",
         "smallest time to collision: same-lane bumper gap over the closing speed along the lane, "
         "while the one behind is faster by more than 0.1 m/s; none when never closing"},
        {"min_headway", ExpectKind::min_headway, 2, 2, Dim::time, false, true,
         "same-lane time headway", "never following",
         "smallest time headway: same-lane bumper gap over the speed along the lane of the one "
         "behind, while it drives forward; none when never following"},
        {"max_jerk", ExpectKind::max_jerk, 1, 1, Dim::jerk, false, true, "largest |jerk|",
         "not measured",
         "largest absolute jerk: the rate of change of the longitudinal acceleration"},
        {"min_acc", ExpectKind::min_acc, 1, 1, Dim::accel, false, true,
         "smallest longitudinal acceleration", "not measured",
         "smallest signed longitudinal acceleration: the hardest braking is the most negative "
         "value (`min_acc(v) < -3 m/s²` requires braking harder than 3 m/s²)"},
        {"max_acc", ExpectKind::max_acc, 1, 1, Dim::accel, false, true,
         "largest longitudinal acceleration", "not measured",
         "largest signed longitudinal acceleration: speeding up is positive, braking never "
         "counts"},
        {"min_speed", ExpectKind::min_speed, 1, 1, Dim::speed, false, true,
         "smallest signed speed", "not measured",
         "smallest signed speed along the vehicle's heading (negative when reversing)"},
        {"max_speed", ExpectKind::max_speed, 1, 1, Dim::speed, false, true,
         "largest signed speed", "not measured",
         "largest signed speed along the vehicle's heading (reversing is negative)"},
        {"fallback_used", ExpectKind::fallback_used, 1, 1, Dim::none, true, false, "fallback",
         "",
         "some planning cycle of the vehicle found no feasible candidate (whole run)"},
        {"fallback_share", ExpectKind::fallback_share, 1, 1, Dim::ratio, false, false,
         "share of fallback plans", "",
         "share of the vehicle's planning cycles that found no feasible candidate (fallback "
         "plans / plans; 0 without plans; whole run)"},
        {"timeout", ExpectKind::timeout, 0, 0, Dim::none, true, false, "timeout", "",
         "the run ended at its timeout (whole run)"},
    };
}

template <typename T>
const T* find_by_name(std::span<const T> items, std::string_view name) {
    for (const T& t : items) {
        if (t.name == name) return &t;
    }
    return nullptr;
}

}  // namespace

std::string ParamDef::allowed(const std::function<std::string(double)>& write) const {
    if (std::isinf(min)) return std::isinf(max) ? "any finite number" : "at most " + write(max);
    const std::string from =
        (min_exclusive ? "more than " : std::isinf(max) ? "at least " : "") + write(min);
    return std::isinf(max) ? from : from + " to " + write(max);
}

std::string format_number(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

std::string_view to_string(Agent agent) {
    switch (agent) {
        case Agent::vehicle: return "vehicle";
        case Agent::pedestrian: return "pedestrian";
        case Agent::any: return "any";
    }
    return "?";
}

std::string_view to_string(ParamType type) {
    switch (type) {
        case ParamType::quantity: return "quantity";
        case ParamType::integer: return "integer";
        case ParamType::boolean: return "bool";
        case ParamType::choice: return "choice";
        case ParamType::vehicle: return "vehicle";
    }
    return "?";
}

const ParamDef* ManeuverDef::find_param(std::string_view n) const {
    return find_by_name<ParamDef>(params, n);
}
const ParamDef* ConditionDef::find_param(std::string_view n) const {
    return find_by_name<ParamDef>(params, n);
}

std::span<const ManeuverDef> maneuvers() {
    static const std::vector<ManeuverDef> kManeuvers = build_maneuvers();
    return kManeuvers;
}
std::span<const ConditionDef> conditions() {
    static const std::vector<ConditionDef> kConditions = build_conditions();
    return kConditions;
}
std::span<const ExpectDef> expectations() {
    static const std::vector<ExpectDef> kExpectations = build_expectations();
    return kExpectations;
}

const ManeuverDef* find_maneuver(std::string_view name) { return find_by_name(maneuvers(), name); }

bool ManeuverDef::never_fails() const {
    return kind == ManeuverKind::keep_velocity || kind == ManeuverKind::stop || kind == ManeuverKind::reverse;
}
const ConditionDef* find_condition(std::string_view name) {
    return find_by_name(conditions(), name);
}
const ExpectDef* find_expectation(std::string_view name) {
    return find_by_name(expectations(), name);
}
const ManeuverDef& maneuver(ManeuverKind kind) { return maneuvers()[static_cast<size_t>(kind)]; }
const ConditionDef& condition(ConditionKind kind) {
    return conditions()[static_cast<size_t>(kind)];
}

std::span<const std::string> vehicle_zones() {
    static const std::vector<std::string> kZones = {
        "self",  "ego",       "front", "front_left", "left",       "back_left",
        "back",  "back_right", "right", "front_right"};
    return kZones;
}

std::string format_default(const ParamDef& p) {
    if (!p.def) return p.optional ? "(optional)" : "(required)";
    const DefaultValue& d = *p.def;
    switch (p.type) {
        case ParamType::boolean: return d.value != 0 ? "true" : "false";
        case ParamType::integer: return format_number(d.value);
        case ParamType::choice: return p.choices.at(static_cast<size_t>(d.value));
        case ParamType::vehicle: return "";
        case ParamType::quantity: break;
    }
    std::string s = format_number(d.value);
    if (auto u = si_unit(p.dim); !u.empty()) s += " " + std::string(u);
    if (d.spread_pct > 0) s += " ±" + format_number(d.spread_pct) + "%";
    if (d.samples > 1) s += " samples " + std::to_string(d.samples);
    return s;
}

namespace {

std::string type_label(const ParamDef& p) {
    switch (p.type) {
        case ParamType::quantity:
            return p.dim == Dim::none ? "number" : std::string(to_string(p.dim));
        case ParamType::choice: {
            std::string s;
            for (size_t i = 0; i < p.choices.size(); ++i) s += (i ? "|" : "") + p.choices[i];
            return s;
        }
        default: return std::string(to_string(p.type));
    }
}

std::string range_label(const ParamDef& p) {
    if (p.type != ParamType::quantity && p.type != ParamType::integer) return "";
    if (std::isinf(p.min) && std::isinf(p.max)) return "";
    std::string unit(si_unit(p.dim));
    std::string s = (p.min_exclusive ? "(" : "[") + format_number(p.min) + ", " +
                    format_number(p.max) + "]";
    if (!unit.empty()) s += " " + unit;
    return s;
}

nlohmann::ordered_json param_json(const ParamDef& p) {
    nlohmann::ordered_json j;
    j["name"] = p.name;
    j["type"] = to_string(p.type);
    if (p.type == ParamType::quantity) {
        j["dimension"] = to_string(p.dim);
        j["unit"] = si_unit(p.dim);
    }
    if (!p.choices.empty()) j["choices"] = p.choices;
    j["required"] = p.required();
    if (p.def) {
        if (p.type == ParamType::choice) {
            j["default"] = p.choices.at(static_cast<size_t>(p.def->value));
        } else if (p.type == ParamType::boolean) {
            j["default"] = p.def->value != 0;
        } else {
            j["default"] = p.def->value;
            if (p.def->spread_pct > 0) j["spread_pct"] = p.def->spread_pct;
            if (p.def->samples > 1) j["samples"] = p.def->samples;
        }
    }
    if (!std::isinf(p.min)) j["min"] = p.min;
    if (!std::isinf(p.max)) j["max"] = p.max;
    if (p.min_exclusive) j["min_exclusive"] = true;
    j["sampleable"] = p.sampleable;
    if (!p.group.empty()) j["group"] = p.group;
    j["doc"] = p.doc;
    return j;
}

}  // namespace

nlohmann::ordered_json to_json() {
    nlohmann::ordered_json j;
    j["maneuvers"] = nlohmann::ordered_json::array();
    for (const auto& m : maneuvers()) {
        nlohmann::ordered_json mj;
        mj["name"] = m.name;
        mj["for"] = to_string(m.agent);
        mj["doc"] = m.doc;
        mj["returns"] = m.status;
        mj["default_candidates"] = m.default_candidates;
        mj["params"] = nlohmann::ordered_json::array();
        for (const auto& p : m.params) mj["params"].push_back(param_json(p));
        j["maneuvers"].push_back(mj);
    }
    j["conditions"] = nlohmann::ordered_json::array();
    for (const auto& c : conditions()) {
        nlohmann::ordered_json cj;
        cj["name"] = c.name;
        cj["for"] = to_string(c.agent);
        cj["doc"] = c.doc;
        cj["params"] = nlohmann::ordered_json::array();
        for (const auto& p : c.params) cj["params"].push_back(param_json(p));
        if (!c.at_least_one_of.empty()) cj["at_least_one_of"] = c.at_least_one_of;
        if (!c.exclusive.empty()) cj["exclusive"] = c.exclusive;
        j["conditions"].push_back(cj);
    }
    j["expectations"] = nlohmann::ordered_json::array();
    for (const auto& e : expectations()) {
        nlohmann::ordered_json ej;
        ej["name"] = e.name;
        ej["vehicles"] = {e.min_vehicles, e.max_vehicles};
        ej["result"] = e.boolean ? "bool" : std::string(to_string(e.result));
        ej["windowed"] = e.windowed;
        ej["label"] = e.label;
        ej["doc"] = e.doc;
        j["expectations"].push_back(ej);
    }
    j["units"] = nlohmann::ordered_json::array();
    for (const auto& u : all_units()) {
        j["units"].push_back({{"unit", u.spelling}, {"dimension", to_string(u.dim)},
                              {"to_si", u.to_si}});
    }
    j["agent_sizes"] = nlohmann::ordered_json::array();
    for (const auto& [agent, size] : kAgentSizes) {
        j["agent_sizes"].push_back({{"agent", agent}, {"max_length_m", size.length}, {"max_width_m", size.width}});
    }
    return j;
}

std::string render_text() {
    std::ostringstream out;
    auto params = [&](const std::vector<ParamDef>& ps, bool skip_common) {
        for (const auto& p : ps) {
            if (skip_common && !p.group.empty()) continue;
            out << "    " << p.name << ": " << type_label(p) << " = " << format_default(p);
            if (auto r = range_label(p); !r.empty()) out << "  in " << r;
            out << "\n        " << p.doc << "\n";
        }
    };
    out << "MANEUVERS (vehicles)\n";
    for (const auto& m : maneuvers()) {
        if (m.agent != Agent::vehicle) continue;
        out << "\n  " << m.name << "  (" << m.default_candidates << " candidates by default)\n"
            << "    " << m.doc << "\n    returns " << m.status << "\n";
        params(m.params, true);
    }
    out << "\n  common to every vehicle maneuver:\n";
    params(maneuvers()[0].params, false);
    out << "\nPEDESTRIAN MANEUVERS\n";
    for (const auto& m : maneuvers()) {
        if (m.agent != Agent::pedestrian) continue;
        out << "\n  " << m.name << "\n    " << m.doc << "\n    returns " << m.status << "\n";
        params(m.params, false);
    }
    out << "\nCONDITIONS\n";
    for (const auto& c : conditions()) {
        out << "\n  " << c.name << "  (for " << (c.agent == Agent::any ? "any agent" : c.agent == Agent::vehicle ? "vehicles" : "pedestrians")
            << ")\n    " << c.doc << "\n";
        params(c.params, false);
        if (!c.at_least_one_of.empty()) {
            out << "    (at least one of:";
            for (const auto& n : c.at_least_one_of) out << " " << n;
            out << ")\n";
        }
    }
    out << "\nEXPECTATIONS\n";
    for (const auto& e : expectations()) {
        out << "  " << e.name << " -> " << (e.boolean ? "bool" : to_string(e.result))
            << (e.windowed ? "" : "  (whole run)") << "\n    " << e.doc << "\n";
    }
    return out.str();
}

std::string render_markdown() {
    std::ostringstream out;
    out << "# Catalog\n\n"
        << "Generated by `sdv catalog --format markdown`; do not edit by hand.\n"
        << "Every maneuver and condition the language knows, with parameters, units, defaults "
           "and allowed ranges (inclusive; `(` marks an exclusive bound).\n\n";
    auto table = [&](const std::vector<ParamDef>& ps, bool skip_common) {
        out << "| parameter | type | default | allowed | meaning |\n|---|---|---|---|---|\n";
        for (const auto& p : ps) {
            if (skip_common && !p.group.empty()) continue;
            out << "| `" << p.name << "` | " << type_label(p) << " | " << format_default(p)
                << " | " << range_label(p) << " | " << p.doc << " |\n";
        }
        out << "\n";
    };
    out << "## Maneuvers\n\n";
    for (const auto& m : maneuvers()) {
        if (m.agent != Agent::vehicle) continue;
        out << "### `" << m.name << "`\n\n" << m.doc << ". Returns " << m.status << ". "
            << m.default_candidates << " candidate trajectories with the defaults.\n\n";
        table(m.params, true);
    }
    out << "### Common maneuver parameters\n\n"
        << "Every vehicle maneuver also takes these (`stop` has `max_long_acc` 30 m/s²; `reverse` has "
           "`direction` false).\n\n";
    table(maneuvers()[0].params, false);
    out << "## Pedestrian maneuvers\n\n"
        << "The leaves of a pedestrian's (`sdp`) tree: each sets where and how fast the pedestrian "
           "walks; the social force model moves it (docs/pedestrians.md).\n\n";
    for (const auto& m : maneuvers()) {
        if (m.agent != Agent::pedestrian) continue;
        out << "### `" << m.name << "`\n\n" << m.doc << ". Returns " << m.status << ".\n\n";
        if (!m.params.empty()) table(m.params, false);
    }
    out << "## Conditions\n\n"
        << "*For*: whose trees may use the condition: vehicles (`sdv`), pedestrians (`sdp`) or any.\n\n";
    for (const auto& c : conditions()) {
        out << "### `" << c.name << "`\n\n*For " << (c.agent == Agent::any ? "any agent" : c.agent == Agent::vehicle ? "vehicles" : "pedestrians")
            << ".* " << c.doc << ".";
        if (!c.at_least_one_of.empty()) {
            out << " At least one of";
            for (const auto& n : c.at_least_one_of) out << " `" << n << "`";
            out << " is required.";
        }
        if (!c.exclusive.empty()) {
            out << " Exclusive:";
            for (const auto& n : c.exclusive) out << " `" << n << "`";
            out << ".";
        }
        out << "\n\n";
        if (!c.params.empty()) table(c.params, false);
    }
    out << "## Expectations\n\n"
        << "Functions of `expect` statements (docs/language.md, Expectations). A minimum that was "
           "never measured is none: it compares as +infinity (`< X` fails, `> X` holds) and is "
           "`null` in summary.json. *window*: whether the function can be restricted to a time "
           "window (`after`, `before`, `during`).\n\n"
        << "| function | vehicles | result | window | meaning |\n|---|---|---|---|---|\n";
    for (const auto& e : expectations()) {
        out << "| `" << e.name << "` | " << e.min_vehicles << "–" << e.max_vehicles << " | "
            << (e.boolean ? "bool" : to_string(e.result)) << " | " << (e.windowed ? "yes" : "no")
            << " | " << e.doc << " |\n";
    }
    out << "\n## Units\n\n| unit | dimension | factor to SI |\n|---|---|---|\n";
    for (const auto& u : all_units()) {
        out << "| `" << u.spelling << "` | " << to_string(u.dim) << " | " << format_number(u.to_si)
            << " |\n";
    }
    out << "\nASCII spellings: `m/s^2`, `m/s2` and `m/s²` are the same unit; `+-` is `±`.\n";
    out << "\n## Agent sizes\n\n"
        << "The `length` and `width` an agent may have (above 0, at most these); the readers of recorded "
           "traffic (CommonRoad, INTERACTION) refuse an agent beyond them, so that every recording "
           "they read replays as a scenario.\n\n"
        << "| agent | length | width |\n|---|---|---|\n";
    for (const auto& [agent, size] : kAgentSizes) {
        out << "| " << agent << " | " << format_number(size.length) << " m | " << format_number(size.width) << " m |\n";
    }
    return out.str();
}

}  // namespace sdv::catalog
