// Lowering of .btree trees to .sdv text: the mapping of the reference's conditions, MConfig
// classes and value forms onto the catalog (docs/geoscenario.md documents the same table).
#include "compiler/gss/lower.h"

#include "compiler/diag/suggest.h"
#include "runtime/catalog/catalog.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

namespace sdv::compiler::gss {
namespace fs = std::filesystem;
namespace {

std::string num_text(double v) {
    if (v == 0) return "0";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

std::string upper(std::string s) {
    for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

// The unit the catalog gives a parameter, as written in .sdv ("m/s"; "" for plain numbers).
std::string unit_of(const catalog::ParamDef& p) {
    if (p.type != catalog::ParamType::quantity) return "";
    return std::string(catalog::si_unit(p.dim));
}

std::string with_unit(double v, const std::string& unit) { return unit.empty() ? num_text(v) : num_text(v) + " " + unit; }

// One lowered argument: `name = text`.
struct Arg {
    std::string name;
    std::string text;
};

// The reading of one call's arguments: lookups by name (with the reference's aliases), each
// marking the item used; what is left is reported by finish().
class Args {
public:
    Args(const BtValue& call, diag::DiagnosticEngine& diags, std::string what)
        : call_(call), diags_(diags), what_(std::move(what)), used_(call.items.size(), false) {}

    const BtItem* take(std::initializer_list<const char*> names) {
        for (size_t i = 0; i < call_.items.size(); ++i) {
            const auto& it = call_.items[i];
            if (!it.key) continue;
            for (const char* n : names) {
                if (*it.key == n) {
                    used_[i] = true;
                    return &it;
                }
            }
        }
        return nullptr;
    }

    // Leftover named items: an error when `strict` (MConfig classes reject unknown fields),
    // otherwise a warning (the reference's conditions ignore what they do not read).
    // Positional items are always errors.
    void finish(bool strict, const std::vector<std::string>& known) {
        for (size_t i = 0; i < call_.items.size(); ++i) {
            if (used_[i]) continue;
            const auto& it = call_.items[i];
            if (!it.key) {
                diags_.error("E0906", it.range, "unexpected positional value in " + what_)
                    .notes.push_back({{}, "arguments of " + what_ + " are written name=value"});
                continue;
            }
            if (strict) {
                auto& d = diags_.error("E0903", it.key_range, "unknown parameter '" + *it.key + "' of " + what_);
                if (auto m = diag::closest_match(*it.key, known)) d.notes.push_back({{}, "did you mean '" + *m + "'?"});
                d.notes.push_back({{}, "known parameters: " + join(known)});
            } else {
                auto& d = diags_.warning("W0901", "gss-ignored-parameter", it.key_range,
                                         "parameter '" + *it.key + "' of " + what_ + " is ignored");
                if (auto m = diag::closest_match(*it.key, known)) d.notes.push_back({{}, "did you mean '" + *m + "'?"});
                d.notes.push_back({{}, "the reference ignores it as well; sdv reads: " + join(known)});
            }
        }
    }

    // A parameter the reference reads but sdv has no equivalent for: taken, with warning W0901
    // saying what differs.
    void ignore(std::initializer_list<const char*> names, const std::string& note) {
        for (const char* n : names) {
            if (const BtItem* it = take({n})) {
                diags_.warning("W0901", "gss-ignored-parameter", it->key_range,
                               "parameter '" + *it->key + "' of " + what_ + " is ignored")
                    .notes.push_back({{}, note});
            }
        }
    }

    const std::string& what() const { return what_; }

private:
    static std::string join(const std::vector<std::string>& v) {
        std::string s;
        for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
        return s.empty() ? "(none)" : s;
    }

    const BtValue& call_;
    diag::DiagnosticEngine& diags_;
    std::string what_;
    std::vector<bool> used_;
};

// Value conversions. Each reports E0906 at the value and returns nullopt when the shape is wrong.
class Values {
public:
    explicit Values(diag::DiagnosticEngine& diags) : diags_(diags) {}

    std::optional<double> number(const BtItem& it) {
        const BtValue& v = it.value;
        if (v.kind == BtValue::Kind::number) return v.number;
        if (v.kind == BtValue::Kind::call && v.text == "MP" && v.items.size() == 1 &&
            v.items[0].value.kind == BtValue::Kind::number) {
            return v.items[0].value.number;
        }
        if (v.kind == BtValue::Kind::name && (v.text == "True" || v.text == "False")) return v.text == "True" ? 1 : 0;
        bad(it, "a number");
        return std::nullopt;
    }

    // `p`: the catalog parameter the value sets, whose range it must be in.
    std::optional<std::string> quantity(const BtItem& it, const std::string& unit, const catalog::ParamDef* p) {
        auto n = number(it);
        if (!n || !in_range(it, p, *n, 0, 0, unit)) return std::nullopt;
        return with_unit(*n, unit);
    }

    std::optional<std::string> integer(const BtItem& it, const catalog::ParamDef* p) {
        auto n = number(it);
        if (!n || !in_range(it, p, std::round(*n), 0, 0, "")) return std::nullopt;
        return num_text(std::round(*n));
    }

    std::optional<std::string> boolean(const BtItem& it) {
        const BtValue& v = it.value;
        if (v.kind == BtValue::Kind::name && (v.text == "True" || v.text == "False" || v.text == "true" || v.text == "false")) {
            return v.text == "True" || v.text == "true" ? "true" : "false";
        }
        if (v.kind == BtValue::Kind::number && (v.number == 0 || v.number == 1)) return v.number == 1 ? "true" : "false";
        bad(it, "True, False, 1 or 0");
        return std::nullopt;
    }

    // MP(value, bound %, samples[, method[, sigma]]) or a plain number. Every number the text
    // writes is one the checker takes: the value and both ends of its spread in `p`'s range, the
    // count 1 to kMaxSamples, a normal method's σ above 0.
    std::optional<std::string> sampled(const BtItem& it, const std::string& unit, const catalog::ParamDef* p) {
        const BtValue& v = it.value;
        if (v.kind == BtValue::Kind::number) {
            if (!in_range(it, p, v.number, 0, 0, unit)) return std::nullopt;
            return with_unit(v.number, unit);
        }
        if (v.kind != BtValue::Kind::call || v.text != "MP" || v.items.empty() || v.items.size() > 5) {
            bad(it, "a number or MP(value, bound%, samples[, method, sigma])");
            return std::nullopt;
        }
        double a[5] = {0, 0, 1, 1, 1};
        if (!numbers(v, a)) return std::nullopt;
        std::string s = with_unit(a[0], unit);
        auto n = sample_count(it, 2, a[2]);
        if (!n) return std::nullopt;
        const bool spread = a[1] > 0 && *n > 1;
        if (!in_range(it, p, a[0], spread ? a[1] : 0, 0, unit)) return std::nullopt;
        if (!spread) return s;
        auto m = method(it, 3, a[3], 4, a[4], unit);
        if (!m) return std::nullopt;
        return s + " ±" + num_text(a[1]) + "% samples " + std::to_string(*n) + *m;
    }

    // LT(target, samples, method, sigma, limit_lane_width, limit_vehicle_size) or a number: the
    // lateral target as an offset from the lane centre. The reference spreads several samples
    // over the lane width less the vehicle's radius; sdv spreads them ±0.75 m about the target
    // (that width on a 3.5 m lane), or ±1.75 m when the vehicle's size is not subtracted. The
    // offset and both ends of the spread are in `p`'s range, as in sampled().
    std::optional<std::string> lateral(const BtItem& it, const catalog::ParamDef* p) {
        const BtValue& v = it.value;
        if (v.kind == BtValue::Kind::number) {
            if (!in_range(it, p, v.number, 0, 0, "m")) return std::nullopt;
            return with_unit(v.number, "m");
        }
        if (v.kind != BtValue::Kind::call || v.text != "LT" || v.items.empty() || v.items.size() > 6) {
            bad(it, "a number or LT(target, samples, method, sigma, limit_lane, limit_size)");
            return std::nullopt;
        }
        double a[6] = {0, 1, 3, 1, 1, 1};
        if (!numbers(v, a)) return std::nullopt;
        std::string s = with_unit(a[0], "m");
        auto n = sample_count(it, 1, a[1]);
        if (!n) return std::nullopt;
        // Without limit_vehicle_size the samples may reach the lane's edges: ±1.75 m.
        const double half_width = a[5] != 0 ? 0.75 : 1.75;
        if (!in_range(it, p, a[0], 0, *n > 1 ? half_width : 0, "m")) return std::nullopt;
        if (*n <= 1) return s;
        // The reference's default sampling for LT is NORMAL.
        auto m = method(it, 2, a[2], 3, a[3], "m");
        if (!m) return std::nullopt;
        return s + " ±" + num_text(half_width) + " m samples " + std::to_string(*n) + *m;
    }

    // LEFT / RIGHT / 1 / -1 → left / right.
    std::optional<std::string> side(const BtItem& it) {
        const BtValue& v = it.value;
        if (v.kind == BtValue::Kind::name) {
            const std::string u = upper(v.text);
            if (u == "LEFT") return "left";
            if (u == "RIGHT") return "right";
        }
        if (v.kind == BtValue::Kind::number && (v.number == 1 || v.number == -1)) return v.number > 0 ? "left" : "right";
        bad(it, "LEFT, RIGHT, 1 or -1");
        return std::nullopt;
    }

    // A vehicle id → the name the scenario converter gives it (`v<vid>`): a whole number from 0
    // to 1,000,000, as the scenario reader takes a vehicle's `vid`.
    std::optional<std::string> vehicle_id(const BtItem& it) {
        const BtValue& v = it.value;
        if (v.kind != BtValue::Kind::number || v.number != std::floor(v.number) || v.number < 0 || v.number > 1e6) {
            bad(it, "a vehicle id (a whole number from 0 to 1000000)");
            return std::nullopt;
        }
        return "v" + std::to_string(static_cast<int>(v.number));
    }

    // An occupancy zone → the catalog's zone word.
    std::optional<std::string> zone(const BtItem& it) {
        static const std::map<std::string, std::string> kZones = {
            {"FRONT", "front"}, {"BACK", "back"}, {"LEFT", "left"}, {"RIGHT", "right"},
            {"LEFT_FRONT", "front_left"}, {"FRONT_LEFT", "front_left"}, {"RIGHT_FRONT", "front_right"},
            {"FRONT_RIGHT", "front_right"}, {"LEFT_BACK", "back_left"}, {"BACK_LEFT", "back_left"},
            {"RIGHT_BACK", "back_right"}, {"BACK_RIGHT", "back_right"}};
        if (it.value.kind == BtValue::Kind::name) {
            if (auto f = kZones.find(upper(it.value.text)); f != kZones.end()) return f->second;
        }
        bad(it, "a zone (FRONT, BACK, LEFT, RIGHT, LEFT_FRONT, RIGHT_FRONT, LEFT_BACK, RIGHT_BACK)");
        return std::nullopt;
    }

    // A named constant among `choices` (case-insensitive), or its number.
    std::optional<std::string> constant(const BtItem& it, const std::vector<std::pair<std::string, std::string>>& choices,
                                        const std::map<int, std::string>& numbers = {}) {
        if (it.value.kind == BtValue::Kind::name) {
            for (const auto& [k, v] : choices) {
                if (upper(it.value.text) == k) return v;
            }
        }
        if (it.value.kind == BtValue::Kind::number) {
            if (auto f = numbers.find(static_cast<int>(std::lround(it.value.number))); f != numbers.end()) return f->second;
        }
        std::string list;
        for (const auto& [k, v] : choices) list += (list.empty() ? "" : ", ") + k;
        bad(it, "one of " + list);
        return std::nullopt;
    }

    // Whether the checker will take `value` (±pct %, ±abs) for `p` as the converted text writes
    // them (num_text), both ends of the spread in the range too (a magnitude's lower end clipped
    // at 0, SPEC §3.6); else E0906 at the value.
    bool in_range(const BtItem& it, const catalog::ParamDef* p, double value, double pct, double abs,
                  const std::string& unit) {
        if (p == nullptr) return true;
        const auto written = [](double x) { return std::strtod(num_text(x).c_str(), nullptr); };
        const double v = written(value), delta = std::fabs(v) * written(pct) / 100 + abs;
        double lo = v - delta;
        if (p->min >= 0 && lo < 0 && v >= 0) lo = 0;
        for (const double x : {v, lo, v + delta}) {
            if (p->accepts(x)) continue;
            const std::string u = unit.empty() ? "" : " " + unit;
            const std::string spread =
                abs > 0 ? catalog::format_number(abs) + u : catalog::format_number(written(pct)) + "%";
            const std::string what = x == v ? "value " + catalog::format_number(x) + u + " is"
                                            : "value " + catalog::format_number(v) + u + " ±" + spread + " reaches " +
                                                  catalog::format_number(x) + u + ", which is";
            diags_.error("E0906", it.value.range, what + " out of range" + of(it) +
                                                      " (sdv's " + p->name + ")")
                .notes.push_back(
                    {{}, "allowed: " + p->allowed([&](double b) { return catalog::format_number(b) + u; })});
            return false;
        }
        return true;
    }

    void bad(const BtItem& it, const std::string& expected) {
        diags_.error("E0906", it.value.range, "invalid value" + of(it))
            .notes.push_back({{}, "expected " + expected});
    }

private:
    // The numbers of a call's positional items into `a` (as many as it has); E0906 at the first
    // that is named or not a number.
    bool numbers(const BtValue& call, double* a) {
        for (size_t i = 0; i < call.items.size(); ++i) {
            if (call.items[i].key || call.items[i].value.kind != BtValue::Kind::number) {
                bad(call.items[i], "a number");
                return false;
            }
            a[i] = call.items[i].value.number;
        }
        return true;
    }

    // " for 'vel'": the field a value is written for, in a message.
    static std::string of(const BtItem& it) { return it.key ? " for '" + *it.key + "'" : std::string(); }

    // Where item `i` of `call` is written; the call when it has no such item (its default).
    static const diag::SourceRange& at(const BtValue& call, size_t i) {
        return i < call.items.size() ? call.items[i].value.range : call.range;
    }

    // The sample count written at item `i` of the sampler `it` (`x`, the default when it has no
    // such item), rounded as the reference's int(): at most kMaxSamples, else E0906 at it. A count
    // below 2 is one value, as in the reference.
    std::optional<int> sample_count(const BtItem& it, size_t i, double x) {
        if (x < catalog::kMaxSamples + 0.5) return x < 1.5 ? 1 : static_cast<int>(std::lround(x));
        diags_.error("E0906", at(it.value, i),
                     "sample count " + catalog::format_number(x) + " is out of range" + of(it))
            .notes.push_back({{}, "sdv samples a value at 1 to " + std::to_string(catalog::kMaxSamples) + " points"});
        return std::nullopt;
    }

    // The reference's SamplingMethod at item `mi` of the sampler `it` (`m`; 1 linear, 2 uniform,
    // 3 normal), its σ at item `si` (`sigma`, in the value's unit, above 0 as written): the words
    // after the count, else E0906 at the item.
    std::optional<std::string> method(const BtItem& it, size_t mi, double m, size_t si, double sigma,
                                      const std::string& unit) {
        const BtValue& call = it.value;
        const double r = std::round(m);
        if (r == 1) return "";
        if (r == 2) return " uniform";
        if (r != 3) {
            bad(call.items[mi], "a sampling method: 1 (linear), 2 (uniform) or 3 (normal)");
            return std::nullopt;
        }
        if (!(std::strtod(num_text(sigma).c_str(), nullptr) > 0)) {
            diags_.error("E0906", at(call, si),
                         "the standard deviation " + catalog::format_number(sigma) + (unit.empty() ? "" : " " + unit) +
                             " of normal sampling" + of(it) + " must be above 0");
            return std::nullopt;
        }
        return " normal(" + with_unit(sigma, unit) + ")";
    }

    diag::DiagnosticEngine& diags_;
};

// ------------------------------------------------------------------ MConfig classes

// ignore: W0901 (FieldMap::note says why); accept: read and not needed (the maneuver does what
// the reference does whatever it says); unsupported: E0913 (FieldMap::note says what sdv lacks).
enum class Conv {
    sampled, quantity, integer, boolean, side, vehicle, stop_target, lateral, delta_s, ignore_if_zero, ignore, accept,
    vehicle_or_none,  // a vehicle id, -1 meaning none
};

struct FieldMap {
    const char* ref;
    const char* ours;  // catalog parameter ("" for ignored fields)
    Conv conv;
    // ignore: why (default: sdv's planner has no equivalent setting); unsupported: what sdv
    // lacks (the field is an error unless it is -1, the reference's "not set").
    const char* note = nullptr;
};

struct ClassMap {
    const char* mconfig;
    const char* maneuver;
    std::vector<FieldMap> fields;
    std::vector<Arg> fixed = {};       // parameters every node of the class gets
    const char* comment = nullptr;     // kept above each node: what differs from the reference
    bool pedestrian = false;           // a class of the reference's pedestrians (sp/ManeuverConfig.py)
    // A node that follows the maneuver in a sequence: what the reference's maneuver also does
    // and the catalog's does not.
    const char* then = nullptr;
};

// Fields every MConfig has.
const std::vector<FieldMap>& common_fields() {
    static const std::vector<FieldMap> k = {
        {"max_long_jerk", "max_long_jerk", Conv::quantity},
        {"max_lat_jerk", "max_lat_jerk", Conv::quantity},
        {"max_long_acc", "max_long_acc", Conv::quantity},
        {"max_lat_acc", "max_lat_acc", Conv::quantity},
        {"lat_target", "lat_offset", Conv::lateral},
        {"cost_precision", "eval_points", Conv::integer},
        {"fc_collision", "collision", Conv::boolean},
        {"fc_off_lane", "off_lane", Conv::boolean},
        {"lane_offset_cost", "w_lane_offset", Conv::quantity},
        {"expected_offset_per_sec", "expected_offset", Conv::quantity},
        {"expected_long_acc_per_sec", "expected_acc", Conv::quantity},
        {"expected_long_jerk_per_sec", "expected_jerk", Conv::quantity},
        {"expected_lat_acc_per_sec", "", Conv::ignore},
        {"expected_lat_jerk_per_sec", "", Conv::ignore},
        {"use_low_level_planner", "", Conv::ignore},
    };
    return k;
}

const std::vector<ClassMap>& classes() {
    static const std::vector<ClassMap> k = {
        {"MVelKeepConfig", "keep_velocity",
         {{"vel", "speed", Conv::sampled}, {"time", "duration", Conv::sampled},
          {"max_diff", "max_speed_change", Conv::quantity}, {"time_lowvel", "", Conv::ignore},
          {"vel_threshold", "", Conv::ignore}}},
        {"MFollowConfig", "follow",
         {{"target_vid", "", Conv::ignore,
           "the reference follows the vehicle ahead in the lane whatever target_vid says (its follow "
           "maneuver sets target_vid to that vehicle on every tick, and fails without one), as sdv's "
           "follow without a leader does"},
          {"time", "duration", Conv::sampled},
          {"time_gap", "time_gap", Conv::quantity}, {"stop_distance", "stop_distance", Conv::quantity},
          {"decel", "", Conv::ignore}}},
        {"MLaneSwerveConfig", "lane_change", {{"target_lid", "lane", Conv::side}, {"time", "duration", Conv::sampled}}},
        {"MCutInConfig", "cut_in",
         {{"target_vid", "target", Conv::vehicle}, {"target_lid", "lane", Conv::side},
          {"time", "duration", Conv::sampled}, {"delta_s", "delta_s", Conv::delta_s},
          {"delta_d", "", Conv::ignore_if_zero}}},
        {"MStopConfig", "stop",
         {{"target", "at", Conv::stop_target}, {"distance", "distance", Conv::quantity},
          {"pos", "position", Conv::quantity}, {"max_deceleration", "", Conv::ignore},
          {"decel", "", Conv::ignore}, {"time", "", Conv::ignore}}},
        {"MReverseConfig", "reverse", {{"vel", "speed", Conv::sampled}, {"time", "duration", Conv::sampled}}},
    };
    return k;
}

// The reference's pedestrians (sp/Pedestrian.py) walk at their default desired speed, 2 m/s
// (SP.default_desired_speed): every pedestrian maneuver plans with it (sp/ManeuverModels.py),
// whatever the MConfig says; the return to the entrance and the increase of the walking speed
// use 1.5 times it.
constexpr const char* kPedestrianSpeed = "2 m/s";
constexpr const char* kPedestrianFastSpeed = "3 m/s";
constexpr const char* kWalkOn = "maneuver walk(speed = 2 m/s)";  // on to the next waypoint
constexpr const char* kPedestrianIgnores =
    "the reference's pedestrians do not read it either: they walk by the social force model at their desired "
    "speed (2 m/s)";

// Fields every MConfig of the reference's pedestrians has (sp/ManeuverConfig.py): the vehicle
// planner's settings, which no pedestrian maneuver reads.
const std::vector<FieldMap>& pedestrian_common_fields() {
    static const std::vector<FieldMap> k = {
        {"max_long_jerk", "", Conv::ignore, kPedestrianIgnores},
        {"max_lat_jerk", "", Conv::ignore, kPedestrianIgnores},
        {"max_long_acc", "", Conv::ignore, kPedestrianIgnores},
        {"max_lat_acc", "", Conv::ignore, kPedestrianIgnores},
        {"expected_offset_per_sec", "", Conv::ignore, kPedestrianIgnores},
        {"expected_long_acc_per_sec", "", Conv::ignore, kPedestrianIgnores},
        {"expected_lat_acc_per_sec", "", Conv::ignore, kPedestrianIgnores},
        {"expected_long_jerk_per_sec", "", Conv::ignore, kPedestrianIgnores},
        {"expected_lat_jerk_per_sec", "", Conv::ignore, kPedestrianIgnores},
        {"feasibility_constraints", "", Conv::ignore, kPedestrianIgnores},
        {"cost_weight", "", Conv::ignore, kPedestrianIgnores},
        {"aggressiveness_level", "", Conv::ignore,
         "only the reference's crosswalk selection reads it (MSelectCrosswalkByLightConfig)"},
    };
    return k;
}

const std::vector<ClassMap>& pedestrian_classes() {
    static const std::vector<ClassMap> k = {
        {"MKeepInLaneConfig", "walk",
         {{"vel", "", Conv::ignore,
           "the reference's pedestrian walks at its desired speed, 2 m/s (sp/Pedestrian.py), and does not read vel; "
           "so does sdv's"},
          {"time", "", Conv::ignore, kPedestrianIgnores},
          {"max_diff", "", Conv::ignore, kPedestrianIgnores},
          {"collision_vehicle_vid", "meet", Conv::vehicle_or_none}},
         {{"speed", kPedestrianSpeed}},
         "MKeepInLaneConfig: on to its next waypoint (the target crosswalk's entrance or far end, else the goal) at "
         "the reference's desired speed",
         true},
        // The reference's pedestrian stops where it is, whatever the type (plan_stop).
        {"MStopConfig", "stand",
         {{"type", "", Conv::accept}, {"pos", "", Conv::accept}, {"distance", "", Conv::accept}},
         {},
         nullptr,
         true},
        {"MEnterCrosswalkConfig", "enter_crosswalk", {}, {{"speed", kPedestrianSpeed}}, nullptr, true},
        {"MExitCrosswalkConfig", "exit_crosswalk", {}, {{"speed", kPedestrianSpeed}}, nullptr, true},
        {"MWaitAtCrosswalkConfig", "wait_at_crosswalk", {}, {{"speed", kPedestrianSpeed}}, nullptr, true},
        {"MReturnToEntranceConfig", "turn_back", {}, {{"speed", kPedestrianFastSpeed}},
         "MReturnToEntranceConfig: back to the entrance at 1.5 times the desired speed; the reference's turns "
         "back from anywhere, sdv's only on the crosswalk (FAILURE elsewhere)",
         true},
        {"MIncreaseWalkingSpeedConfig", "speed_up", {}, {{"factor", "1.5"}, {"max_speed", kPedestrianFastSpeed}},
         nullptr, true},
        {"MSelectCrosswalkByLightConfig", "select_crosswalk",
         {{"aggressiveness_level", "", Conv::ignore,
           "sdv's select_crosswalk(by = light) takes the nearest crosswalk on the way whose signal is green, else the "
           "nearest; the reference weighs yellow and red signals by aggressiveness (1: waits on yellow, 3: crosses "
           "on red)"}},
         {{"by", "light"}},
         "MSelectCrosswalkByLightConfig: choose the crosswalk by its pedestrian signal and walk on to its entrance",
         true,
         kWalkOn},
    };
    return k;
}

const ClassMap* find_class(const std::string& name, BtAgent agent) {
    for (const auto& c : agent == BtAgent::pedestrian ? pedestrian_classes() : classes()) {
        if (name == c.mconfig) return &c;
    }
    return nullptr;
}

std::vector<std::string> class_names(BtAgent agent) {
    std::vector<std::string> v;
    for (const auto& c : agent == BtAgent::pedestrian ? pedestrian_classes() : classes()) v.emplace_back(c.mconfig);
    return v;
}

// The catalog parameters a configuration call sets, as `name = text`; nullopt after errors.
std::optional<std::vector<Arg>> lower_config(const BtValue& call, const ClassMap& cm, diag::DiagnosticEngine& diags) {
    const size_t before = diags.error_count();
    const catalog::ManeuverDef* m = catalog::find_maneuver(cm.maneuver);
    Args args(call, diags, cm.mconfig);
    Values val(diags);
    std::vector<Arg> out;
    std::vector<std::string> known;
    std::vector<FieldMap> fields = cm.fields;
    std::map<std::string, std::pair<const char*, diag::SourceRange>> written;  // ours -> its field
    // Warning W0901: a parameter of the call that the conversion leaves out.
    const auto ignored = [&](diag::SourceRange at, const char* ref, std::string why) {
        diags.warning("W0901", "gss-ignored-parameter", at,
                      "parameter '" + std::string(ref) + "' of " + cm.mconfig + " is ignored")
            .notes.push_back({{}, std::move(why)});
    };
    for (const FieldMap& f : cm.pedestrian ? pedestrian_common_fields() : common_fields()) {
        // A class may read a common field its own way (MSelectCrosswalkByLightConfig).
        const bool own = std::any_of(cm.fields.begin(), cm.fields.end(), [&](const FieldMap& g) { return std::string(g.ref) == f.ref; });
        if (!own) fields.push_back(f);
    }
    for (const FieldMap& f : fields) {
        known.emplace_back(f.ref);
        const BtItem* it = args.take({f.ref});
        if (it == nullptr) continue;
        const catalog::ParamDef* p = *f.ours ? m->find_param(f.ours) : nullptr;
        if (*f.ours && p == nullptr) {  // the mapping table names a parameter the catalog lacks
            diags.error("E0903", it->key_range, std::string("'") + f.ref + "' maps to '" + f.ours + "', which maneuver " +
                                                    cm.maneuver + " does not have (an sdv bug: please report it)");
            continue;
        }
        std::optional<std::string> text;
        switch (f.conv) {
            case Conv::sampled: text = val.sampled(*it, unit_of(*p), p); break;
            case Conv::quantity: text = val.quantity(*it, unit_of(*p), p); break;
            case Conv::integer: text = val.integer(*it, p); break;
            case Conv::boolean: text = val.boolean(*it); break;
            case Conv::side: text = val.side(*it); break;
            case Conv::vehicle: text = val.vehicle_id(*it); break;
            case Conv::lateral: text = val.lateral(*it, p); break;
            case Conv::stop_target:
                text = val.constant(*it, {{"GOAL_POINT", "goal"}, {"GOAL", "goal"}, {"STOP_LINE", "stop_line"},
                                          {"NOW", "now"}, {"S_POS", "position"}, {"POS", "position"}},
                                    {{0, "now"}, {1, "position"}, {2, "goal"}, {3, "stop_line"}});
                break;
            case Conv::delta_s: {
                // (s, v, a) of the final state relative to the target.
                const BtValue& v = it->value;
                if (v.kind != BtValue::Kind::tuple || v.items.empty() || v.items.size() > 3) {
                    val.bad(*it, "a tuple (s, v, a)");
                    break;
                }
                static const char* kNames[] = {"delta_s", "delta_v", "delta_a"};
                for (size_t i = 0; i < v.items.size(); ++i) {
                    const catalog::ParamDef* d = m->find_param(kNames[i]);
                    auto q = val.quantity(v.items[i], unit_of(*d), d);
                    if (q) out.push_back({kNames[i], *q});
                }
                continue;
            }
            case Conv::ignore_if_zero: {
                bool zero = it->value.kind == BtValue::Kind::tuple;
                for (const auto& e : it->value.items) zero = zero && e.value.kind == BtValue::Kind::number && e.value.number == 0;
                if (!zero) ignored(it->key_range, f.ref, "sdv plans lateral motion to the target lane's centre plus lat_offset");
                continue;
            }
            case Conv::ignore:
                ignored(it->key_range, f.ref, f.note != nullptr ? f.note : "sdv's planner has no equivalent setting");
                continue;
            case Conv::accept: continue;
            case Conv::vehicle_or_none:
                if (auto n = val.number(*it); n && *n == -1) continue;
                text = val.vehicle_id(*it);
                break;
        }
        if (text) {
            out.push_back({f.ours, *text});
            written[f.ours] = {f.ref, it->key_range};
        }
    }
    args.finish(true, known);
    if (diags.error_count() > before) return std::nullopt;
    for (const Arg& a : cm.fixed) out.push_back(a);
    // A cut-in needs a target vehicle; the reference also accepts only a target lane, where the
    // vehicle cut in front of is the one beside in that lane.
    // The reference's efficiency cost (CostFunctions.effic_cost), for its configurations with a
    // velocity: rewards a higher mean speed.
    if (std::string(cm.maneuver) == "keep_velocity" || std::string(cm.maneuver) == "reverse") {
        out.push_back({"efficiency", "reference"});
    }
    if (std::string(cm.maneuver) == "cut_in") {
        // The reference's delta_s counts beyond two own lengths ahead of the target's centre.
        out.push_back({"gap_from", "reference"});
        bool has_target = false, has_lane = false;
        std::string lane;
        for (const auto& a : out) {
            has_target = has_target || a.name == "target";
            if (a.name == "lane") {
                has_lane = true;
                lane = a.text;
            }
        }
        if (!has_target) {
            if (!has_lane) {
                diags.error("E0906", call.range, "MCutInConfig needs target_vid or target_lid");
                return std::nullopt;
            }
            out.insert(out.begin(), {"target", lane});
        }
    }
    // Where the reference's default differs from the catalog's, the reference's, unless the call
    // sets the parameter: MStopConfig.target is StopTarget.GOAL (sdv's stop: now); a
    // MLaneSwerveConfig without target_lid takes its planner's lane_swerve_target, the lane the
    // route needs (sdv's lane_change: left; with `route` it succeeds in place where the route
    // needs no change).
    static const std::map<std::string, Arg> kReferenceDefaults = {{"stop", {"at", "goal"}},
                                                                  {"lane_change", {"lane", "route"}}};
    if (auto d = kReferenceDefaults.find(cm.maneuver); d != kReferenceDefaults.end() &&
        std::none_of(out.begin(), out.end(), [&](const Arg& a) { return a.name == d->second.name; })) {
        out.insert(out.begin(), d->second);
    }
    // MStopConfig reads pos only with target=POS (otherwise it stops at its target, the goal by
    // default); sdv's stop, likewise, reads position only with at = position.
    const auto at = std::find_if(out.begin(), out.end(), [](const Arg& a) { return a.name == "at"; });
    const auto pos = std::find_if(out.begin(), out.end(), [](const Arg& a) { return a.name == "position"; });
    if (std::string(cm.maneuver) == "stop" && pos != out.end() && at != out.end() && at->text != "position") {
        const auto w = written.find("position");
        ignored(w != written.end() ? w->second.second : call.range, w != written.end() ? w->second.first : "pos",
                "the reference reads it only with target=POS; this stop is " +
                    std::string(at->text == "goal"        ? "at the goal"
                                : at->text == "stop_line" ? "at the next stop line"
                                                          : "now"));
        out.erase(pos);
    }
    return out;
}

// ------------------------------------------------------------------ conditions

struct CondOut {
    std::string name;
    std::vector<Arg> args;
    bool negate = false;
    bool once = false;
    bool drop = false;     // an action the .sdv model does implicitly (set_target_lane)
    std::string comment;   // kept above the node in the output
    // Instead of one condition: a fallback of these nodes (`condition ...`, `maneuver ...`),
    // labelled as the node was.
    std::vector<std::string> any_of;
    std::string unsupported;  // what sdv lacks: the condition is an error (E0913)
};

using CondLower = std::function<void(Args&, Values&, CondOut&)>;

struct CondMap {
    const char* ref;
    std::vector<std::string> reads;  // parameters sdv reads (for messages)
    CondLower lower;
};

// The parameter `arg` of the catalog's condition `cond`, whose range bounds the value written for
// it; nullptr (no bound) when the catalog has no such pair, which the converted text's compilation
// would then report.
const catalog::ParamDef* cond_param(const char* cond, const char* arg) {
    const catalog::ConditionDef* c = catalog::find_condition(cond);
    return c != nullptr ? c->find_param(arg) : nullptr;
}

// What keeps a lowered condition from compiling as sdv's condition `o.name` (a parameter it
// requires, one of a group it needs, two that exclude each other, one given twice), in words;
// empty when nothing does. The reference's arguments may leave out what sdv's condition needs
// (traffic_light_state without a colour): the converter says so (E0913) instead of writing text
// that does not compile.
std::string unmet_needs(const CondOut& o) {
    const catalog::ConditionDef* c = catalog::find_condition(o.name);
    if (c == nullptr) return "";  // a lowering's bug: the compilation of the converted text reports it
    std::set<std::string> given;
    for (const Arg& a : o.args) {
        if (!given.insert(a.name).second) return "sdv's condition '" + o.name + "' would get '" + a.name + "' twice";
    }
    for (const auto& p : c->params) {
        if (p.required() && !given.count(p.name)) {
            return "sdv's condition '" + o.name + "' needs its '" + p.name + "', which none of the arguments given sets";
        }
    }
    if (!c->at_least_one_of.empty() &&
        std::none_of(c->at_least_one_of.begin(), c->at_least_one_of.end(), [&](const auto& g) { return given.count(g) > 0; })) {
        std::string list;
        for (const auto& g : c->at_least_one_of) list += (list.empty() ? "" : ", ") + g;
        return "sdv's condition '" + o.name + "' needs one of " + list + ", which none of the arguments given sets";
    }
    if (std::count_if(c->exclusive.begin(), c->exclusive.end(), [&](const auto& g) { return given.count(g) > 0; }) > 1) {
        return "the arguments given set parameters of sdv's condition '" + o.name + "' that exclude each other";
    }
    return "";
}

// Whether a leaf written as .sdv text ("maneuver stop()", "condition ...") never fails.
bool leaf_never_fails(std::string_view leaf) {
    constexpr std::string_view kManeuver = "maneuver ";
    if (leaf.substr(0, kManeuver.size()) != kManeuver) return false;
    leaf.remove_prefix(kManeuver.size());
    const catalog::ManeuverDef* m = catalog::find_maneuver(leaf.substr(0, leaf.find('(')));
    return m != nullptr && m->never_fails();
}

void opt(std::vector<Arg>& out, const char* name, const std::optional<std::string>& text) {
    if (text) out.push_back({name, *text});
}

// The vehicle a condition observes: vid=N, or zid=ZONE.
bool vehicle_arg(Args& a, Values& v, CondOut& o, const char* name = "vehicle") {
    if (const auto* it = a.take({"vid"})) {
        opt(o.args, name, v.vehicle_id(*it));
        return true;
    }
    if (const auto* it = a.take({"zid"})) {
        opt(o.args, name, v.zone(*it));
        return true;
    }
    return false;
}

bool repeat_false(Args& a, Values& v) {
    if (const auto* it = a.take({"repeat"})) {
        auto b = v.boolean(*it);
        return b && *b == "false";
    }
    return false;
}

const std::vector<CondMap>& condition_map() {
    static const std::vector<CondMap> k = {
        {"sim_time", {"t", "tmin", "tmax", "repeat"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "sim_time";
             if (const auto* t = a.take({"t"})) {
                 // An exact time, accepted up to one planning cycle late (the reference's 5 Hz, at
                 // which converted scenarios run).
                 const catalog::ParamDef* before = cond_param("sim_time", "before");
                 if (auto after = v.quantity(*t, "s", cond_param("sim_time", "after"))) {
                     o.args.push_back({"after", *after});
                     const double late = *v.number(*t) + 0.2;
                     o.args.push_back({"before", with_unit(before != nullptr ? std::min(late, before->max) : late, "s")});
                 }
                 // The reference's sim_time looks at 't' alone when it is given.
                 a.ignore({"tmin", "tmax"}, "the reference compares the time with 't' when it is given");
             } else {
                 if (const auto* lo = a.take({"tmin"})) opt(o.args, "after", v.quantity(*lo, "s", cond_param("sim_time", "after")));
                 if (const auto* hi = a.take({"tmax"})) opt(o.args, "before", v.quantity(*hi, "s", cond_param("sim_time", "before")));
             }
             if (o.args.empty()) o.args.push_back({"after", "0 s"});
             o.once = repeat_false(a, v);
         }},
        {"reached_goal", {"distance"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "reached_goal";
             const auto* d = a.take({"distance"});
             o.args.push_back({"distance", d ? v.quantity(*d, "m", cond_param("reached_goal", "distance")).value_or("40 m") : "40 m"});
         }},
        {"at_lane_change_segment", {}, [](Args&, Values&, CondOut& o) { o.name = "at_lane_change_segment"; }},
        {"target_lane", {"lid"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "at_lane_change_segment";
             if (const auto* it = a.take({"lid", "target_lid", "target_lane_id", "target_lane"})) opt(o.args, "lane", v.side(*it));
         }},
        {"out_of_route", {}, [](Args&, Values&, CondOut& o) { o.name = "out_of_route"; }},
        {"reroute", {},
         [](Args&, Values&, CondOut& o) {
             o.name = "out_of_route";
             o.comment = "reroute(): sdv re-plans routes by itself; the node succeeds when off the route";
         }},
        {"set_target_lane", {"lid"},
         [](Args& a, Values& v, CondOut& o) {
             if (const auto* it = a.take({"lid", "target_lid", "target_lane_id", "target_lane"})) v.side(*it);
             o.drop = true;
         }},
        {"can_lane_change", {"lid", "gap"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "can_lane_change";
             if (const auto* it = a.take({"lid", "target_lid", "target_lane_id", "target_lane"})) opt(o.args, "lane", v.side(*it));
             const auto* g = a.take({"gap", "distance_gap"});
             o.args.push_back({"gap", g ? v.quantity(*g, "m", cond_param("can_lane_change", "gap")).value_or("20 m") : "20 m"});
         }},
        {"lane_occupied", {"zid", "lid", "distance"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "lane_occupied";
             if (const auto* it = a.take({"zid"})) {
                 if (auto z = v.zone(*it)) {
                     const bool left = z->find("left") != std::string::npos, right = z->find("right") != std::string::npos;
                     o.args.push_back({"lane", left ? "left" : right ? "right" : "current"});
                 }
             } else if (const auto* l = a.take({"lid"})) {
                 opt(o.args, "lane", v.side(*l));
             }
             if (const auto* d = a.take({"distance"})) opt(o.args, "distance", v.quantity(*d, "m", cond_param("lane_occupied", "distance")));
             // The reference's lane occupancy holds vehicles only: static objects are avoided
             // by the planner's collision check, not followed.
             o.args.push_back({"objects", "false"});
         }},
        {"vehicle_moving", {"vid", "zid", "vel"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "vehicle_moving";
             vehicle_arg(a, v, o);
             const auto* s = a.take({"vel"});
             o.args.push_back({"min_speed", s ? v.quantity(*s, "m/s", cond_param("vehicle_moving", "min_speed")).value_or("0.05 m/s") : "0.05 m/s"});
         }},
        {"vehicle_stopped", {"vid", "zid", "vel"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "vehicle_stopped";
             vehicle_arg(a, v, o);
             const auto* s = a.take({"vel"});
             o.args.push_back({"max_speed", s ? v.quantity(*s, "m/s", cond_param("vehicle_stopped", "max_speed")).value_or("0.05 m/s") : "0.05 m/s"});
         }},
        {"vehicle_parked", {"vid", "zid"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "vehicle_parked";
             vehicle_arg(a, v, o);
         }},
        {"lv_stopped", {}, [](Args&, Values&, CondOut& o) {
             o.name = "vehicle_stopped";
             o.args = {{"vehicle", "front"}, {"max_speed", "0.05 m/s"}};
         }},
        {"lv_moving", {}, [](Args&, Values&, CondOut& o) {
             o.name = "vehicle_moving";
             o.args = {{"vehicle", "front"}, {"min_speed", "0.05 m/s"}};
         }},
        {"approaching_intersection", {"distance"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "approaching_stop";
             const auto* d = a.take({"distance"});
             o.args.push_back({"distance", d ? v.quantity(*d, "m", cond_param("approaching_stop", "distance")).value_or("30 m") : "30 m"});
             // The reference looks for the stop position of a regulated intersection (right of
             // way, all-way stop, traffic light): a stop line or a junction entry.
             o.args.push_back({"kind", "any"});
         }},
        {"approaching_stop_sign", {"threshold"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "approaching_stop";
             const auto* d = a.take({"threshold"});
             o.args.push_back({"distance", d ? v.quantity(*d, "m", cond_param("approaching_stop", "distance")).value_or("30 m") : "30 m"});
             o.args.push_back({"kind", "stop_line"});
         }},
        {"intersection_type", {"type"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "intersection_type";
             if (const auto* t = a.take({"type"})) {
                 opt(o.args, "type", v.constant(*t, {{"RIGHT_OF_WAY", "yield"}, {"ALL_WAY_STOP", "all_way_stop"},
                                                      {"TRAFFIC_LIGHT", "traffic_light"},
                                                      {"PEDESTRIAN_CROSS", "pedestrian_crossing"}}));
             }
         }},
        {"yield_role", {}, [](Args&, Values&, CondOut& o) {
             o.name = "yield_role";
             o.args = {{"role", "yield"}};
         }},
        {"intersection_occupied", {"distance"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "intersection_occupied";
             if (const auto* d = a.take({"distance"})) opt(o.args, "distance", v.quantity(*d, "m", cond_param("intersection_occupied", "distance")));
         }},
        {"aws_yielding", {}, [](Args&, Values&, CondOut& o) {
             // The reference's driver, after 5 s at the line, goes out of turn with probability
             // 0.05 per planning cycle (BTreeConditions.aws_yielding).
             o.name = "all_way_stop_turn";
             o.args = {{"impatient_after", "5 s"}, {"impatient_chance", "0.05"}};
             o.negate = true;
         }},
        {"traffic_light_state", {"color", "threshold"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "traffic_light";
             if (const auto* c = a.take({"color"})) {
                 opt(o.args, "state", v.constant(*c, {{"RED", "red"}, {"YELLOW", "yellow"}, {"GREEN", "green"}}));
             }
             if (const auto* d = a.take({"threshold"})) opt(o.args, "distance", v.quantity(*d, "m", cond_param("traffic_light", "distance")));
         }},
        {"wait", {"time"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "wait";
             if (const auto* t = a.take({"time"})) opt(o.args, "time", v.quantity(*t, "s", cond_param("wait", "time")));
         }},
        {"gap", {"vid", "zid", "lid", "distance", "time"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "gap";
             if (!vehicle_arg(a, v, o)) {
                 if (const auto* l = a.take({"lid"})) opt(o.args, "lane", v.side(*l));
             }
             const auto* d = a.take({"distance"});
             const auto* t = a.take({"time"});
             if (d) opt(o.args, "min", v.quantity(*d, "m", cond_param("gap", "min")));
             if (t) opt(o.args, "time_max", v.quantity(*t, "s", cond_param("gap", "time_max")));
             if (!d && !t) o.unsupported = "sdv's gap condition compares the gap with a distance or a time: give 'distance' or 'time'";
         }},
        {"reached_gap", {"vid", "zid", "distance", "repeat"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "gap";
             vehicle_arg(a, v, o);
             const auto* d = a.take({"distance"});
             if (d) opt(o.args, "max", v.quantity(*d, "m", cond_param("gap", "max")));
             if (!d) o.unsupported = "sdv's gap condition compares the gap with a distance: give 'distance'";
             o.once = repeat_false(a, v);
         }},
    };
    return k;
}

// A distance condition of the reference's pedestrians: `threshold` (default `def`) in metres,
// the `distance` of sdv's condition `cond`.
std::string threshold(Args& a, Values& v, const char* cond, const char* def) {
    const auto* t = a.take({"threshold"});
    return t ? v.quantity(*t, "m", cond_param(cond, "distance")).value_or(def) : std::string(def);
}

// The conditions of the reference's pedestrians (sp/btree/BehaviorModels.py test_condition) on
// the catalog's pedestrian conditions. Their "target crosswalk" is planned by the reference's
// SPPlanner when the pedestrian starts and after each crossing; sdv's pedestrian chooses it with
// select_crosswalk, which the lowering of has_target_crosswalk() does.
const std::vector<CondMap>& pedestrian_condition_map() {
    static const std::vector<CondMap> k = {
        {"reached_goal", {"threshold"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "reached_goal";
             o.args.push_back({"distance", threshold(a, v, "reached_goal", "1 m")});
         }},
        {"has_target_crosswalk", {},
         [](Args&, Values&, CondOut& o) {
             o.comment = "has_target_crosswalk(): the reference plans a target crosswalk on the way to the goal when the "
                         "pedestrian starts and after each crossing; sdv's chooses the nearest here";
             o.any_of = {"condition has_target_crosswalk()", "maneuver select_crosswalk(by = nearest)"};
         }},
        {"approaching_crosswalk", {"threshold"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "approaching_crosswalk";
             o.args.push_back({"distance", threshold(a, v, "approaching_crosswalk", "3 m")});
         }},
        {"reached_crosswalk_entrance", {"threshold"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "at_crosswalk_entrance";
             o.args.push_back({"distance", threshold(a, v, "at_crosswalk_entrance", "1.5 m")});
         }},
        {"waiting_at_crosswalk_entrance", {},
         [](Args&, Values&, CondOut& o) {
             o.name = "at_crosswalk_entrance";
             o.comment = "waiting_at_crosswalk_entrance(): the reference's holds while its last maneuver was "
                         "MWaitAtCrosswalkConfig; sdv's pedestrian waits at the entrance, within this distance";
             o.args.push_back({"distance", "1.5 m"});
         }},
        {"reached_crosswalk_exit", {"threshold"},
         [](Args& a, Values& v, CondOut& o) {
             o.name = "crosswalk_exit_reached";
             o.args.push_back({"distance", threshold(a, v, "crosswalk_exit_reached", "1.5 m")});
         }},
        {"reached_curr_waypoint", {"threshold"},
         [](Args& a, Values& v, CondOut& o) {
             const std::string d = threshold(a, v, "crosswalk_exit_reached", "1 m");
             o.comment = "reached_curr_waypoint(): its waypoint is the target crosswalk's entrance, its far end, or the goal";
             o.any_of = {"condition at_crosswalk_entrance(distance = " + d + ")",
                         "condition crosswalk_exit_reached(distance = " + d + ")", "condition reached_goal(distance = " + d + ")"};
         }},
        {"crosswalk_has_light", {}, [](Args&, Values&, CondOut& o) { o.name = "crosswalk_has_light"; }},
        {"pedestrian_light_green", {}, [](Args&, Values&, CondOut& o) {
             o.name = "pedestrian_light";
             o.args = {{"state", "green"}};
         }},
        {"pedestrian_light_yellow", {}, [](Args&, Values&, CondOut& o) {
             o.name = "pedestrian_light";
             o.args = {{"state", "yellow"}};
         }},
        {"pedestrian_light_red", {}, [](Args&, Values&, CondOut& o) {
             o.name = "pedestrian_light";
             o.args = {{"state", "red"}};
         }},
        {"can_cross_before_red", {},
         [](Args& a, Values&, CondOut& o) {
             o.name = "can_cross_before_red";
             o.comment = "can_cross_before_red(): the reference also accepts crossing at up to 1.75 times the desired "
                         "speed, or to 3 m short of the far end, and then walks faster; sdv's holds at the desired speed";
             a.ignore({"speed_increase_pct", "dist_from_xwalk_exit"},
                      "sdv's can_cross_before_red compares the time to walk the rest of the crosswalk at the desired "
                      "speed with the time until red");
         }},
        {"in_crosswalk_area", {}, [](Args&, Values&, CondOut& o) {
             o.name = "on_crosswalk";
             o.comment = "in_crosswalk_area(): the reference's holds on any crosswalk, sdv's on the target crosswalk";
         }},
        {"vehicle_approaching_crosswalk", {}, [](Args&, Values&, CondOut& o) {
             // sim_time(after = 0 s) always holds: negated, never.
             o.name = "sim_time";
             o.args = {{"after", "0 s"}};
             o.negate = true;
             o.comment = "vehicle_approaching_crosswalk(): never true, as the reference's (a stub in BehaviorModels.py)";
         }},
        {"at_desired_speed", {}, [](Args&, Values&, CondOut& o) {
             o.unsupported = "sdv's pedestrians have no speed of their own besides the desired one to compare with";
         }},
        {"past_crosswalk_halfway", {}, [](Args&, Values&, CondOut& o) {
             o.unsupported = "no condition of sdv's catalog tells how far along its crosswalk the pedestrian is";
         }},
    };
    return k;
}

// The condition mapping of a tree: a pedestrian's reads the pedestrian conditions, then the
// ones any agent shares (sim_time, wait).
const CondMap* find_condition(const std::string& name, BtAgent agent) {
    if (agent == BtAgent::pedestrian) {
        for (const auto& c : pedestrian_condition_map()) {
            if (name == c.ref) return &c;
        }
        if (name != "sim_time" && name != "wait") return nullptr;
    }
    for (const auto& c : condition_map()) {
        if (name == c.ref) return &c;
    }
    return nullptr;
}

std::vector<std::string> condition_names(BtAgent agent) {
    std::vector<std::string> names;
    if (agent == BtAgent::pedestrian) {
        for (const auto& c : pedestrian_condition_map()) names.emplace_back(c.ref);
        names.emplace_back("sim_time");
        names.emplace_back("wait");
    } else {
        for (const auto& c : condition_map()) names.emplace_back(c.ref);
    }
    return names;
}

// Whose tree a .btree tree is by its own leaves: the MConfig classes and conditions only one of
// the reference's agents has. unknown when it names none (only MStopConfig, reached_goal, ...).
BtAgent agent_of(const BtNode& root) {
    int ped = 0, veh = 0;
    std::function<void(const BtNode&)> visit = [&](const BtNode& n) {
        if (n.kind == BtNode::Kind::maneuver) {
            if (n.call.text != "MStopConfig") {
                ped += find_class(n.call.text, BtAgent::pedestrian) != nullptr;
                veh += find_class(n.call.text, BtAgent::vehicle) != nullptr;
            }
        } else if (n.kind == BtNode::Kind::condition) {
            const std::string& c = n.call.text;
            if (c != "reached_goal" && c != "sim_time" && c != "wait") {
                ped += find_condition(c, BtAgent::pedestrian) != nullptr;
                veh += find_condition(c, BtAgent::vehicle) != nullptr;
            }
        }
        for (const BtNode& ch : n.children) visit(ch);
    };
    visit(root);
    if (ped == veh) return BtAgent::unknown;
    return ped > veh ? BtAgent::pedestrian : BtAgent::vehicle;
}

}  // namespace

// ------------------------------------------------------------------ the library

struct BtreeLibrary::TreeState {
    std::string path;
    Lowered lowered;
    std::set<std::string> labels;  // .sdv labels used in this tree
};

BtreeLibrary::BtreeLibrary(std::vector<std::string> search_path, diag::SourceManager& sm, diag::DiagnosticEngine& diags)
    : search_path_(std::move(search_path)), sm_(sm), diags_(diags) {}

std::string BtreeLibrary::tree_name(const std::string& stem) {
    std::string s;
    for (char c : stem) s += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) s = "t_" + s;
    return s;
}

std::vector<ReferenceCondition> reference_conditions(BtAgent agent) {
    std::vector<ReferenceCondition> out;
    for (const std::string& name : condition_names(agent)) out.push_back({name, find_condition(name, agent)->reads});
    return out;
}

std::vector<ReferenceManeuver> reference_maneuvers(BtAgent agent) {
    std::vector<ReferenceManeuver> out;
    for (const ClassMap& c : agent == BtAgent::pedestrian ? pedestrian_classes() : classes()) {
        ReferenceManeuver m{c.mconfig, {}};
        for (const FieldMap& f : c.fields) m.fields.emplace_back(f.ref);
        for (const FieldMap& f : c.pedestrian ? pedestrian_common_fields() : common_fields()) {
            if (std::find(m.fields.begin(), m.fields.end(), f.ref) == m.fields.end()) m.fields.emplace_back(f.ref);
        }
        out.push_back(std::move(m));
    }
    return out;
}

BtAgent BtreeLibrary::agent(const std::string& name) const {
    for (const auto& [path, l] : done_) {
        if (l.name == name) return l.agent;
    }
    return BtAgent::unknown;
}

std::optional<std::string> BtreeLibrary::find(const std::string& name, BtAgent agent) const {
    std::string file = name;
    if (fs::path(file).extension() != ".btree") file += ".btree";
    std::vector<fs::path> under = {fs::path()};
    if (agent != BtAgent::pedestrian) under.emplace_back("sdv");
    if (agent != BtAgent::vehicle) under.emplace_back("sp");
    for (const auto& dir : search_path_) {
        for (const auto& sub : under) {
            std::error_code ec;
            fs::path p = fs::path(dir) / sub / file;
            if (fs::is_regular_file(p, ec)) return p.lexically_normal().string();
        }
    }
    return std::nullopt;
}

std::optional<std::string> BtreeLibrary::call_with_config(const std::string& name, const std::string& config,
                                                          const std::string& who, diag::SourceRange where, BtAgent agent) {
    auto tree = add_named(name, where, agent);
    if (!tree) return std::nullopt;
    // The reference splits btconfig at ';' into ID=config items (BTreeInterpreter
    // .reconfigure_nodes): `NODE=MConfigClass(...)` for a maneuver, `NODE=condition,args=(k=v,...)`
    // for a condition. The maneuvers' are read as the overrides of a subtree reference, the
    // conditions' as condition nodes.
    // One line of the synthetic .btree text below: a tag value's line breaks (&#10;) are spaces.
    std::string flat = config;
    std::replace_if(flat.begin(), flat.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
    std::string maneuvers, conditions;
    size_t begin = 0;
    while (begin <= flat.size()) {
        size_t end = flat.find(';', begin);
        if (end == std::string::npos) end = flat.size();
        std::string item = flat.substr(begin, end - begin);
        begin = end + 1;
        item.erase(0, std::min(item.find_first_not_of(" \t"), item.size()));
        while (!item.empty() && (item.back() == ' ' || item.back() == '\t')) item.pop_back();
        if (item.empty()) continue;
        const size_t eq = item.find('='), args = item.find(",args=(");
        if (eq != std::string::npos && args != std::string::npos && eq < args && item.back() == ')') {
            conditions += "            condition " + item.substr(0, eq) + "(" + item.substr(eq + 1, args - eq - 1) + "(" +
                          item.substr(args + 7, item.size() - args - 8) + "))\n";
        } else {
            maneuvers += (maneuvers.empty() ? "" : ", ") + item;
        }
    }
    const std::string stem = fs::path(name).extension() == ".btree" ? fs::path(name).stem().string() : name;
    const diag::FileId f = sm_.add_file(who, "behaviortree btconfig:\n    ->\n        subtree " + stem + "(" + maneuvers + ")\n" +
                                                 (conditions.empty() ? "" : "        ->\n" + conditions));
    const size_t before = diags_.error_count();
    auto parsed = parse_btree(f, sm_, diags_);
    if (!parsed || parsed->trees.empty() || parsed->trees[0].root.children.empty()) return std::nullopt;
    const BtNode& root = parsed->trees[0].root;
    std::string call = lower_subtree(root.children[0], agent, nullptr, true);
    if (diags_.error_count() > before || call.rfind("subtree ", 0) != 0) return std::nullopt;
    call = call.substr(8);
    while (!call.empty() && call.back() == '\n') call.pop_back();
    if (root.children.size() > 1) {
        const Lowered* l = nullptr;
        for (const auto& [path, lowered] : done_) {
            if (lowered.name == *tree) l = &lowered;
        }
        // The entries of each condition node, in the order the nodes first appear: the reference
        // reconfigures a node once per entry, and a condition's arguments accumulate.
        std::vector<std::vector<const BtNode*>> entries;
        std::map<std::string, size_t> entries_of;
        for (const BtNode& c : root.children[1].children) {
            const auto [slot, fresh] = entries_of.try_emplace(c.label, entries.size());
            if (fresh) {
                entries.emplace_back();
            } else {
                auto& d = diags_.warning("W0905", "gss-reconfigured-twice", c.label_range,
                                         "condition node '" + c.label + "' of '" + stem +
                                             "' is reconfigured again; its arguments replace the earlier ones of the same name");
                d.notes.push_back({entries[slot->second].front()->label_range, "first reconfigured here"});
                d.notes.push_back({{}, "the reference merges each entry's arguments into the node's (BCondition.reconfigure)"});
            }
            entries[slot->second].push_back(&c);
        }
        std::vector<std::string> extra;
        for (const auto& node_entries : entries) {
            if (l != nullptr) condition_overrides(node_entries, *l, extra);
        }
        if (diags_.error_count() > before) return std::nullopt;
        call.pop_back();  // ')'
        for (const std::string& e : extra) call += (call.back() == '(' ? "" : ", ") + e;
        call += ")";
    }
    return call;
}

void BtreeLibrary::condition_overrides(const std::vector<const BtNode*>& entries, const Lowered& root,
                                       std::vector<std::string>& out) {
    const BtNode& leaf = *entries.front();
    const auto found = find_node(root, leaf.label, true);
    if (!found || !found->info->mconfig.empty()) {
        auto& d = diags_.error("E0908", leaf.label_range, "the tree '" + root.name + "' has no condition node '" + leaf.label + "'");
        if (found) {
            d.notes.push_back({{}, "its first node named '" + leaf.label + "' is a maneuver: write " + leaf.label +
                                       "=MConfigClass(...)"});
        }
        return;
    }
    const NodeInfo& info = *found->info;
    if (!info.condition) {
        diags_.error("E0913", leaf.label_range, "the condition node '" + leaf.label + "' cannot be reconfigured by sdv")
            .notes.push_back({{}, "it is lowered to several sdv conditions (docs/geoscenario.md)"});
        return;
    }
    // BCondition.reconfigure, once per entry: the arguments given replace the node's of the same
    // name; the others keep theirs.
    BtValue merged = *info.condition;
    for (const BtNode* entry : entries) {
        if (entry->call.text != info.condition->text) {
            diags_.error("E0909", entry->call.name_range,
                         "the reconfiguration of '" + leaf.label + "' changes its condition from " + info.condition->text + " to " +
                             entry->call.text)
                .notes.push_back({{}, "sdv overrides change a node's parameters, not its condition"});
            return;
        }
        for (const BtItem& it : entry->call.items) {
            if (!it.key) {
                diags_.error("E0906", it.range, "unexpected positional value in a condition's reconfiguration")
                    .notes.push_back({{}, "write ID=condition,args=(name=value, ...)"});
                return;
            }
            auto same = std::find_if(merged.items.begin(), merged.items.end(), [&](const BtItem& m) { return m.key == it.key; });
            if (same != merged.items.end()) {
                *same = it;
            } else {
                merged.items.push_back(it);
            }
        }
    }
    const CondMap* cmap = find_condition(merged.text, root.agent);
    if (cmap == nullptr) return;  // the node itself lowered: cannot happen
    Args args(merged, diags_, "condition " + merged.text);
    Values val(diags_);
    CondOut lowered;
    cmap->lower(args, val, lowered);
    args.finish(false, cmap->reads);
    // The node as the tree has it (its diagnostics were reported when the tree was lowered).
    diag::DiagnosticEngine quiet;
    Args original_args(*info.condition, quiet, "condition " + merged.text);
    Values original_val(quiet);
    CondOut original;
    cmap->lower(original_args, original_val, original);
    if (!lowered.unsupported.empty() || !lowered.any_of.empty() || lowered.drop || lowered.name != original.name ||
        lowered.once != original.once || lowered.negate != original.negate) {
        diags_.error("E0913", leaf.label_range, "the condition node '" + leaf.label + "' cannot be reconfigured so by sdv")
            .notes.push_back({{}, lowered.unsupported.empty() ? "its arguments lower it to another shape of sdv nodes"
                                                               : lowered.unsupported});
        return;
    }
    for (const Arg& a : lowered.args) out.push_back(found->path + info.sdv_label + "." + a.name + " = " + a.text);
}

std::optional<std::string> BtreeLibrary::add_file(const std::string& path, diag::SourceRange where, BtAgent agent) {
    const Lowered* l = lower_file(path, where, agent);
    if (l == nullptr) return std::nullopt;
    return l->name;
}

std::optional<std::string> BtreeLibrary::add_named(const std::string& name, diag::SourceRange where, BtAgent agent) {
    auto path = find(name, agent);
    if (!path) {
        std::string dirs;
        for (const auto& d : search_path_) dirs += (dirs.empty() ? "" : ", ") + d;
        const std::string subs = agent == BtAgent::vehicle      ? "sdv/"
                                 : agent == BtAgent::pedestrian ? "sp/"
                                                                : "sdv/ and sp/";
        auto& d = diags_.error("E0905", where, "no behavior tree '" + name + "' on the search path");
        d.notes.push_back({{}, "looked for " + (fs::path(name).extension() == ".btree" ? name : name + ".btree") +
                                   " in each directory and its " + subs + ": " + (dirs.empty() ? "(no directory)" : dirs)});
        d.notes.push_back({{}, "add directories with --btree-path DIR"});
        return std::nullopt;
    }
    return add_file(*path, where, agent);
}

const BtreeLibrary::Lowered* BtreeLibrary::lower_file(const std::string& path, diag::SourceRange where, BtAgent agent) {
    std::error_code ec;
    const std::string key = fs::weakly_canonical(path, ec).string();
    if (auto f = done_.find(key); f != done_.end()) return &f->second;
    if (in_progress_.count(key)) {
        diags_.error("E0907", where, "the behavior tree '" + fs::path(path).stem().string() + "' uses itself")
            .notes.push_back({{}, "subtree references must not form a cycle"});
        return nullptr;
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        diags_.error("E0006", where, "cannot read file '" + path + "'");
        return nullptr;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    const diag::FileId file = sm_.add_file(path, ss.str());
    files_.push_back(path);
    auto parsed = parse_btree(file, sm_, diags_);
    if (!parsed) return nullptr;
    if (parsed->trees.empty()) return nullptr;
    for (size_t i = 1; i < parsed->trees.size(); ++i) {
        diags_.warning("W0902", "gss-extra-tree", parsed->trees[i].name_range,
                       "only the first tree of a .btree file is used; '" + parsed->trees[i].name + "' is ignored")
            .notes.push_back({{}, "the reference reads one tree per file, named by the file"});
    }
    in_progress_.insert(key);
    TreeState t;
    t.path = path;
    std::string name = tree_name(fs::path(path).stem().string());
    while (names_.count(name)) name += "_";
    names_.insert(name);
    t.lowered.name = name;
    const BtTree& tree = parsed->trees.front();
    // Its own leaves say whose tree it is; else who uses it; else a vehicle's.
    const BtAgent own = agent_of(tree.root);
    t.lowered.agent = own != BtAgent::unknown ? own : agent != BtAgent::unknown ? agent : BtAgent::vehicle;
    const size_t before = diags_.error_count();
    const NodeText root = lower_node(tree.root, 1, t);
    const std::string& body = root.text;
    t.lowered.never_fails = root.never_fails;
    in_progress_.erase(key);
    if (diags_.error_count() > before) return nullptr;
    if (!t.lowered.selects) {
        // The .sdv checker's E0404: a tree (each subtree too) selects a maneuver on some path.
        diags_.error("E0913", tree.name_range, "the behavior tree '" + tree.name + "' never selects a maneuver, which sdv's trees must")
            .notes.push_back({{}, "give it a maneuver node, or a subtree that has one"});
        return nullptr;
    }
    text_ += "# " + fs::path(path).filename().string() + ": GeoScenario behavior tree '" + tree.name + "'\n";
    text_ += "tree " + name + "() {\n" + body + "}\n\n";
    return &(done_[key] = std::move(t.lowered));
}

BtreeLibrary::NodeText BtreeLibrary::lower_node(const BtNode& n, int depth, TreeState& t) {
    const std::string ind(static_cast<size_t>(depth) * 4, ' ');
    NodeText out;
    if (n.kind == BtNode::Kind::subtree) {
        out.text = lower_subtree(n, t.lowered.agent, &t, false, &out.never_fails);
        if (!out.text.empty()) out.text = ind + out.text;
        out.nodes = out.text.empty() ? 0 : 1;
        return out;
    }
    if (n.kind == BtNode::Kind::condition || n.kind == BtNode::Kind::maneuver) {
        out.text = lower_leaf(n, ind, t, out.never_fails);
        // Its comment lines aside, a leaf is one .sdv node (a sequence or fallback of a few).
        std::istringstream lines(out.text);
        for (std::string line; std::getline(lines, line);) {
            if (line.find_first_not_of(' ') != std::string::npos && line[line.find_first_not_of(' ')] != '#') out.nodes = 1;
        }
        return out;
    }
    const bool fallback = n.kind == BtNode::Kind::fallback;
    out.text = ind + (fallback ? "fallback" : n.kind == BtNode::Kind::sequence ? "sequence" : "parallel(policy = all)") + " {\n";
    out.nodes = 1;
    int children = 0;
    bool all_never_fail = true;
    for (size_t i = 0; i < n.children.size(); ++i) {
        const NodeText c = lower_node(n.children[i], depth + 1, t);
        out.text += c.text;
        if (c.nodes == 0) continue;
        ++children;
        all_never_fail = all_never_fail && c.never_fails;
        if (fallback && c.never_fails) {
            out.never_fails = true;
            // The reference's fallback never ticks what follows either: dead, left out (the
            // checker refuses unreachable children, E0403).
            if (i + 1 < n.children.size()) {
                auto& d = diags_.warning("W0906", "gss-unreachable", n.children[i + 1].range,
                                         "the fallback never gets past the child before this one: it is left out");
                d.notes.push_back({n.children[i].range, "this child never fails"});
                d.notes.push_back({{}, "a keep-velocity, stop or reverse maneuver never fails (it runs, then succeeds), in the "
                                       "reference too, which never ticks the children after it"});
            }
            break;
        }
    }
    if (children == 0) {
        // Only conditions that the maneuver after them implies, which always hold: so does this.
        out.text += ind + "    condition sim_time(after = 0 s)  # always holds, as its conditions did\n";
    }
    if (n.kind == BtNode::Kind::sequence) out.never_fails = children > 0 && all_never_fail;
    out.text += ind + "}\n";
    return out;
}

std::string BtreeLibrary::lower_leaf(const BtNode& n, const std::string& ind, TreeState& t, bool& never_fails) {
    // A unique label per tree; repeated names get a suffix (an override reaches the first, as
    // the reference's reconfigure_nodes does).
    std::string label = tree_name(n.label);
    for (int k = 2; t.labels.count(label); ++k) label = tree_name(n.label) + "_" + std::to_string(k);
    const BtValue& call = n.call;
    const BtAgent agent = t.lowered.agent;
    const std::string whose = agent == BtAgent::pedestrian ? "a pedestrian's tree" : "a vehicle's tree";
    const std::string others = agent == BtAgent::pedestrian ? "vehicles" : "pedestrians";
    if (n.kind == BtNode::Kind::maneuver) {
        const ClassMap* cm = find_class(call.text, agent);
        if (cm == nullptr) {
            const bool other =
            find_class(call.text, agent == BtAgent::pedestrian ? BtAgent::vehicle : BtAgent::pedestrian) != nullptr;
            auto& d = diags_.error("E0902", call.name_range,
                                   other ? "maneuver configuration class '" + call.text + "' is for " + others + ", and this is " + whose
                                         : "unknown maneuver configuration class '" + call.text + "'");
            if (auto m = diag::closest_match(call.text, class_names(agent))) d.notes.push_back({{}, "did you mean '" + *m + "'?"});
            std::string all;
            for (const auto& c : class_names(agent)) all += (all.empty() ? "" : ", ") + c;
            d.notes.push_back({{}, "known classes: " + all});
            return "";
        }
        auto args = lower_config(call, *cm, diags_);
        if (!args) return "";
        t.labels.insert(label);
        NodeInfo info{label, cm->mconfig, {}, std::nullopt};
        std::string s = cm->comment != nullptr ? ind + "# " + cm->comment + "\n" : "";
        const std::string inner = cm->then != nullptr ? ind + "    " : ind;
        if (cm->then != nullptr) s += ind + "sequence {\n";
        s += inner + label + ": maneuver " + cm->maneuver + "(";
        for (size_t i = 0; i < args->size(); ++i) {
            s += (i ? ", " : "") + (*args)[i].name + " = " + (*args)[i].text;
            info.fields.insert((*args)[i].name);
        }
        t.lowered.nodes[n.label].push_back(std::move(info));
        t.lowered.order.push_back({n.label, t.lowered.nodes[n.label].size() - 1, "", nullptr, {}});
        t.lowered.selects = true;
        s += ")\n";
        if (cm->then != nullptr) s += inner + cm->then + "\n" + ind + "}\n";
        never_fails = leaf_never_fails(std::string("maneuver ") + cm->maneuver + "()") &&
                      (cm->then == nullptr || leaf_never_fails(cm->then));
        return s;
    }
    const CondMap* cmap = find_condition(call.text, agent);
    if (cmap == nullptr) {
        const bool other =
            find_condition(call.text, agent == BtAgent::pedestrian ? BtAgent::vehicle : BtAgent::pedestrian) != nullptr;
        auto& d = diags_.error("E0904", call.name_range,
                               other ? "condition '" + call.text + "' is for " + others + ", and this is " + whose
                                     : "unknown condition '" + call.text + "'");
        if (auto m = diag::closest_match(call.text, condition_names(agent))) d.notes.push_back({{}, "did you mean '" + *m + "'?"});
        d.notes.push_back({{}, "`sdv catalog` lists sdv's conditions; docs/geoscenario.md maps the reference's onto them"});
        return "";
    }
    Args args(call, diags_, "condition " + call.text);
    Values val(diags_);
    CondOut out;
    const size_t errors = diags_.error_count();
    cmap->lower(args, val, out);
    args.finish(false, cmap->reads);
    // A value refused above (E0906) leaves its parameter out: that error says enough.
    if (out.unsupported.empty() && out.any_of.empty() && !out.drop && diags_.error_count() == errors) {
        if (std::string unmet = unmet_needs(out); !unmet.empty()) {
            diags_.error("E0913", call.name_range, "condition '" + call.text + "' with these arguments is not supported by sdv")
                .notes.push_back({{}, unmet});
            return "";
        }
    }
    if (!out.unsupported.empty()) {
        diags_.error("E0913", call.name_range, "condition '" + call.text + "' is not supported by sdv")
            .notes.push_back({{}, out.unsupported});
        return "";
    }
    if (out.drop) return ind + "# " + n.label + ": " + call.text + "(...) is implied by the maneuver that follows\n";
    t.labels.insert(label);
    t.lowered.nodes[n.label].push_back({label, "", {}, std::nullopt});
    if (out.any_of.empty()) t.lowered.nodes[n.label].back().condition = call;
    t.lowered.order.push_back({n.label, t.lowered.nodes[n.label].size() - 1, "", nullptr, {}});
    std::string s;
    if (!out.comment.empty()) s += ind + "# " + out.comment + "\n";
    if (!out.any_of.empty()) {
        s += ind + label + ": fallback {\n";
        for (const auto& alt : out.any_of) {
            s += ind + "    " + alt + "\n";
            if (alt.rfind("maneuver ", 0) == 0) t.lowered.selects = true;
            never_fails = never_fails || leaf_never_fails(alt);
        }
        return s + ind + "}\n";
    }
    s += ind + (out.once ? "once " : "") + (out.negate ? "not " : "") + label + ": condition " + out.name + "(";
    for (size_t i = 0; i < out.args.size(); ++i) s += (i ? ", " : "") + out.args[i].name + " = " + out.args[i].text;
    return s + ")\n";
}

std::optional<BtreeLibrary::Found> BtreeLibrary::find_node(const Lowered& l, const std::string& name, bool deep) {
    for (const Item& item : l.order) {
        if (item.sub == nullptr) {
            if (item.name == name) return Found{"", &l.nodes.at(name)[item.info], {}};
            continue;
        }
        if (!deep) continue;
        auto f = find_node(*item.sub, name, deep);
        if (!f) continue;
        // Found in the referenced tree itself: the fields this reference overrides are reset too.
        if (f->path.empty()) {
            if (auto it = item.sub_fields.find(f->info->sdv_label); it != item.sub_fields.end()) {
                f->fields.insert(it->second.begin(), it->second.end());
            }
        }
        f->path = item.sub_label + "." + f->path;
        return f;
    }
    return std::nullopt;
}

void BtreeLibrary::node_names(const Lowered& l, bool deep, std::vector<std::string>& out) {
    for (const Item& item : l.order) {
        if (item.sub == nullptr) {
            if (!l.nodes.at(item.name)[item.info].mconfig.empty()) out.push_back(item.name);
        } else if (deep) {
            node_names(*item.sub, deep, out);
        }
    }
}

std::string BtreeLibrary::lower_subtree(const BtNode& n, BtAgent agent, TreeState* t, bool deep, bool* never_fails) {
    const Lowered* sub = nullptr;
    if (auto path = find(n.label, agent)) {
        sub = lower_file(*path, n.label_range, agent);
    } else {
        add_named(n.label, n.label_range, agent);  // reports E0905
    }
    if (sub == nullptr) return "";
    if (t != nullptr && sub->selects) t->lowered.selects = true;
    if (never_fails != nullptr) *never_fails = sub->never_fails;
    // Overrides: NODE=MConfigClass(...) replaces the configuration of the first node of that
    // name (BTreeInterpreter.reconfigure_nodes): fields the trees set and the override leaves
    // out fall back to the catalog defaults. A subtree reference in a .btree reaches the
    // tree's own nodes (the reference reconfigures a subtree before linking its subtrees in);
    // a vehicle's btconfig (`deep`) reaches the nodes of the whole tree.
    // The arguments of each node reconfigured, in the order the nodes first appear; a node
    // reconfigured again takes the later configuration whole, as the reference's reconfigure
    // replaces a node's MConfig each time.
    std::vector<std::vector<Arg>> node_args;
    // `path.label.` → its entry in node_args, and where it was first reconfigured.
    std::map<std::string, std::pair<size_t, diag::SourceRange>> node_index;
    std::map<std::string, std::set<std::string>> fields_of;  // label in `sub` → fields overridden
    for (const BtItem& it : n.call.items) {
        if (!it.key) {
            diags_.error("E0906", it.range, "unexpected positional value in a subtree reference")
                .notes.push_back({{}, "overrides are written NODE=MConfigClass(field=value, ...)"});
            continue;
        }
        const auto found = find_node(*sub, *it.key, deep);
        if (!found || found->info->mconfig.empty()) {
            std::vector<std::string> names;
            node_names(*sub, deep, names);
            auto& d = diags_.error("E0908", it.key_range, "the tree '" + n.label + "' has no maneuver node '" + *it.key + "'");
            if (auto m = diag::closest_match(*it.key, names)) d.notes.push_back({{}, "did you mean '" + *m + "'?"});
            if (found) d.notes.push_back({{}, "its first node named '" + *it.key + "' is a condition"});
            continue;
        }
        const NodeInfo& info = *found->info;
        if (it.value.kind != BtValue::Kind::call) {
            diags_.error("E0906", it.value.range, "invalid value for '" + *it.key + "'")
                .notes.push_back({{}, "expected a configuration, e.g. MVelKeepConfig(vel=MP(12,10,6))"});
            continue;
        }
        const ClassMap* cm = find_class(it.value.text, sub->agent);
        if (cm == nullptr) {
            auto& d = diags_.error("E0902", it.value.name_range, "unknown maneuver configuration class '" + it.value.text + "'");
            if (auto m = diag::closest_match(it.value.text, class_names(sub->agent))) d.notes.push_back({{}, "did you mean '" + *m + "'?"});
            continue;
        }
        if (cm->mconfig != info.mconfig) {
            diags_.error("E0909", it.value.name_range,
                         "the override of '" + *it.key + "' changes its class from " + info.mconfig + " to " + cm->mconfig)
                .notes.push_back({{}, "sdv overrides change a node's parameters, not its maneuver"});
            continue;
        }
        auto args = lower_config(it.value, *cm, diags_);
        if (!args) continue;
        const catalog::ManeuverDef* m = catalog::find_maneuver(cm->maneuver);
        const std::string path = found->path + info.sdv_label + ".";
        const auto [slot, fresh] = node_index.try_emplace(path, node_args.size(), it.key_range);
        if (fresh) {
            node_args.emplace_back();
        } else {
            auto& d = diags_.warning("W0905", "gss-reconfigured-twice", it.key_range,
                                     "node '" + *it.key + "' of '" + n.label + "' is reconfigured again; this configuration replaces the earlier one");
            d.notes.push_back({slot->second.second, "first reconfigured here"});
            d.notes.push_back({{}, "the reference reconfigures the node once per entry, so the last one wins"});
        }
        std::vector<Arg>& out = node_args[slot->second.first];
        out.clear();
        std::set<std::string> given;
        for (const Arg& a : *args) {
            out.push_back({path + a.name, a.text});
            given.insert(a.name);
        }
        std::set<std::string> reset = info.fields;
        reset.insert(found->fields.begin(), found->fields.end());
        for (const std::string& f : reset) {
            if (given.count(f)) continue;
            const catalog::ParamDef* p = m->find_param(f);
            if (p != nullptr && p->def) out.push_back({path + f, catalog::format_default(*p)});
        }
        if (found->path.empty()) {
            for (const Arg& a : *args) fields_of[info.sdv_label].insert(a.name);
            fields_of[info.sdv_label].insert(reset.begin(), reset.end());
        }
    }
    std::string label;
    if (t != nullptr) {
        // A label, so that a vehicle's btconfig can reach the nodes inside (`label.node.field`).
        label = sub->name;
        for (int k = 2; t->labels.count(label); ++k) label = sub->name + "_" + std::to_string(k);
        t->labels.insert(label);
        t->lowered.order.push_back({"", 0, label, sub, std::move(fields_of)});
    }
    std::string s = (label.empty() ? "" : label + ": ") + "subtree " + sub->name + "(";
    bool comma = false;
    for (const auto& args : node_args) {
        for (const Arg& a : args) {
            s += (comma ? ", " : "") + a.name + " = " + a.text;
            comma = true;
        }
    }
    return s + ")\n";
}

}  // namespace sdv::compiler::gss
