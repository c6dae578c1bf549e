// Units and values: a written value evaluated against the type a parameter or setting expects
// (units converted to SI, parameter references resolved through their environment, intervals,
// spreads and samples), and a resolved number checked against its catalog range. Also how
// messages print numbers, units and types.
#include <algorithm>
#include <cmath>

#include "compiler/diag/suggest.h"
#include "compiler/sema/checker_internal.h"

namespace sdv::compiler::sema {

std::string with_unit(double si, Dim dim) {
    std::string u(catalog::si_unit(dim));
    if (dim == Dim::angle) return fmt(si * 180.0 / M_PI) + " deg";
    return u.empty() ? fmt(si) : fmt(si) + " " + u;
}

std::string dim_phrase(Dim dim) {
    switch (dim) {
        case Dim::none: return "a plain number";
        case Dim::length: return "a length (m)";
        case Dim::time: return "a time (s)";
        case Dim::speed: return "a speed (m/s)";
        case Dim::accel: return "an acceleration (m/s²)";
        case Dim::jerk: return "a jerk (m/s³)";
        case Dim::angle: return "an angle (deg or rad)";
        case Dim::ratio: return "a ratio (%)";
        case Dim::frequency: return "a frequency (Hz)";
    }
    return "a value";
}

std::string example_unit(Dim dim) {
    switch (dim) {
        case Dim::length: return "e.g. '5 m'";
        case Dim::time: return "e.g. '3 s'";
        case Dim::speed: return "e.g. '14 m/s' or '50 km/h'";
        case Dim::accel: return "e.g. '2 m/s^2'";
        case Dim::jerk: return "e.g. '10 m/s^3'";
        case Dim::angle: return "e.g. '90 deg'";
        case Dim::ratio: return "e.g. '10%'";
        case Dim::frequency: return "e.g. '30 Hz'";
        case Dim::none: return "";
    }
    return "";
}

const std::vector<std::pair<std::string, TypeInfo>>& param_types() {
    static const std::vector<std::pair<std::string, TypeInfo>> kTypes = {
        {"length", {ParamType::quantity, Dim::length}},
        {"time", {ParamType::quantity, Dim::time}},
        {"duration", {ParamType::quantity, Dim::time}},
        {"speed", {ParamType::quantity, Dim::speed}},
        {"accel", {ParamType::quantity, Dim::accel}},
        {"acceleration", {ParamType::quantity, Dim::accel}},
        {"jerk", {ParamType::quantity, Dim::jerk}},
        {"angle", {ParamType::quantity, Dim::angle}},
        {"number", {ParamType::quantity, Dim::none}},
        {"int", {ParamType::integer, Dim::none}},
        {"bool", {ParamType::boolean, Dim::none}},
        {"vehicle", {ParamType::vehicle, Dim::none}},
        {"choice", {ParamType::choice, Dim::none}},
        {"lane", {ParamType::choice, Dim::none}},
    };
    return kTypes;
}

std::string type_phrase(TypeInfo t) {
    switch (t.type) {
        case ParamType::quantity: return dim_phrase(t.dim);
        case ParamType::integer: return "a whole number";
        case ParamType::boolean: return "true or false";
        case ParamType::choice: return "a word";
        case ParamType::vehicle: return "a vehicle";
    }
    return "a value";
}

// ------------------------------------------------------------------ values

// Converts a written number to SI for the expected dimension, or reports why it cannot.
std::optional<double> Checker::to_si(const ast::Primary& p, Dim expected, const std::string& what) {
    if (p.kind == ast::Primary::Kind::expr && p.expr) {
        auto f = fold(*p.expr, what);
        if (!f) return std::nullopt;
        if (f->dim == expected) return f->si;
        if (f->dim == Dim::none) {
            if (f->si == 0.0 && expected != Dim::ratio) return 0.0;  // 0 needs no unit
            auto* d = error("E0202", p.range,
                            "missing unit: " + what + " is " + dim_phrase(expected) +
                                ", but the arithmetic gives a plain number");
            d->notes.push_back({{}, "write the unit, " + example_unit(expected) +
                                        ", on each term or after the parenthesis: '(20 + 25 * i) m'"});
            return std::nullopt;
        }
        auto* d = error("E0201", p.range,
                        "wrong unit: " + what + " is " + dim_phrase(expected) +
                            ", but the arithmetic gives " + dim_phrase(f->dim));
        if (expected != Dim::none) d->notes.push_back({{}, "write " + example_unit(expected)});
        return std::nullopt;
    }
    if (p.kind != ast::Primary::Kind::quantity) {
        error("E0204", p.range, "expected " + dim_phrase(expected) + " for " + what +
                                    ", found " +
                                    (p.kind == ast::Primary::Kind::string
                                         ? "a string"
                                         : "the name '" + p.name.str() + "'"));
        return std::nullopt;
    }
    const ast::Quantity& q = p.quantity;
    if (q.unit.empty()) {
        if (expected == Dim::none) return q.value;
        if (q.value == 0.0 && expected != Dim::ratio) return 0.0;  // 0 needs no unit
        auto* d = error("E0202", p.range,
                        "missing unit: " + what + " is " + dim_phrase(expected));
        d->notes.push_back({{}, "write the unit, " + example_unit(expected)});
        return std::nullopt;
    }
    auto unit = catalog::find_unit(q.unit);
    if (!unit) {
        auto* d = error("E0203", q.unit_range, "unknown unit '" + q.unit + "'");
        std::vector<std::string> spellings;
        for (const auto& u : catalog::all_units()) spellings.emplace_back(u.spelling);
        add_suggestion(*d, q.unit, spellings);
        return std::nullopt;
    }
    if (unit->dim != expected) {
        auto* d = error("E0201", p.range,
                        "wrong unit: " + what + " is " + dim_phrase(expected) + ", but '" +
                            q.unit + "' is " + dim_phrase(unit->dim));
        if (expected != Dim::none) d->notes.push_back({{}, "write " + example_unit(expected)});
        return std::nullopt;
    }
    return q.value * unit->to_si;
}

// Evaluates a value against an expected type. `what` names it in messages.
Eval Checker::eval(const ast::Value& v, const Env* env, TypeInfo expect, const std::string& what,
                   const ParamDef* def, int depth) {
    Eval out;
    out.range = v.range;
    if (depth > kMaxExpansionDepth) return out;
    if (v.kind == ast::Value::Kind::list) {
        error("E0204", v.range, "a list is not allowed for " + what);
        return out;
    }
    // A parameter reference?
    if (v.lo.kind == ast::Primary::Kind::name && env != nullptr && v.lo.name.parts.size() == 1) {
        auto it = env->params.find(v.lo.name.parts[0].text);
        if (it != env->params.end()) {
            const Binding& b = it->second;
            if (env->tree != nullptr) {
                const_cast<TreeSym*>(env->tree)->used_params.insert(it->first);
            }
            if (b.untyped) return Eval{};
            if (!compatible(b.type, expect)) {
                error("E0201", v.lo.range,
                      "parameter '" + it->first + "' is " + type_phrase(b.type) + ", but " +
                          what + " is " + type_phrase(expect));
                return out;
            }
            if (b.value == nullptr) {  // generic check: type only
                out.kind = expect.type == ParamType::choice || expect.type == ParamType::vehicle
                               ? Eval::Kind::word
                               : Eval::Kind::number;
                out.known = false;
                out.type = b.type;
                return out;
            }
            Eval inner = eval(*b.value, b.env, expect, what, def, depth + 1);
            if (inner.kind != Eval::Kind::number || (!v.spread && !v.samples) ||
                v.kind != ast::Value::Kind::single) {
                if (v.spread || v.samples) {
                    if (inner.kind == Eval::Kind::number) {
                        apply_spread_and_samples(v, inner, expect, what, def);
                    }
                }
                return inner;
            }
            apply_spread_and_samples(v, inner, expect, what, def);
            return inner;
        }
    }
    switch (expect.type) {
        case ParamType::quantity:
        case ParamType::integer: {
            if (v.lo.kind != ast::Primary::Kind::quantity && v.lo.kind != ast::Primary::Kind::expr) {
                if (v.lo.kind == ast::Primary::Kind::name && v.lo.name.parts.size() == 1 &&
                    env != nullptr && env->tree != nullptr) {
                    auto* d = error("E0104", v.lo.range,
                                    "unknown parameter '" + v.lo.name.str() + "' in tree '" +
                                        env->tree->qname + "'");
                    std::vector<std::string> names;
                    for (const auto& [n, b] : env->params) names.push_back(n);
                    add_suggestion(*d, v.lo.name.str(), names);
                    if (names.empty() || !diag::closest_match(v.lo.name.str(), names)) {
                        d->notes.push_back({{}, what + " expects " + type_phrase(expect)});
                    }
                    return out;
                }
                to_si(v.lo, expect.dim, what);
                return out;
            }
            if (expect.type == ParamType::integer && v.lo.kind == ast::Primary::Kind::expr) {
                auto f = fold(*v.lo.expr, what);
                if (!f) return out;
                if (f->dim != Dim::none || !f->integer) {
                    error("E0204", v.lo.range, what + " must be a whole number without unit");
                    return out;
                }
            } else if (expect.type == ParamType::integer &&
                (!v.lo.quantity.is_integer || !v.lo.quantity.unit.empty())) {
                error("E0204", v.lo.range, what + " must be a whole number without unit");
                return out;
            }
            auto base = to_si(v.lo, expect.dim, what);
            if (!base) return out;
            out.kind = Eval::Kind::number;
            out.num.value = out.num.lo = out.num.hi = *base;
            if (v.kind == ast::Value::Kind::interval) {
                auto hi = to_si(*v.hi, expect.dim, what);
                if (!hi) return Eval{};
                if (*hi < *base) {
                    error("E0304", v.range, "empty interval: the lower bound " +
                                                with_unit(*base, expect.dim) +
                                                " is above the upper bound " +
                                                with_unit(*hi, expect.dim));
                    return Eval{};
                }
                out.num.hi = *hi;
                out.num.value = 0.5 * (*base + *hi);
                out.ranged = true;
                apply_samples(v, out, expect, what, def);
                return out;
            }
            apply_spread_and_samples(v, out, expect, what, def);
            return out;
        }
        case ParamType::boolean: {
            if (v.lo.kind == ast::Primary::Kind::name &&
                (v.lo.name.str() == "true" || v.lo.name.str() == "false") && !v.spread &&
                !v.samples) {
                out.kind = Eval::Kind::number;
                const double b = v.lo.name.str() == "true" ? 1.0 : 0.0;
                out.num.value = out.num.lo = out.num.hi = b;
                return out;
            }
            error("E0204", v.range, what + " must be true or false");
            return out;
        }
        case ParamType::choice:
        case ParamType::vehicle: {
            if (v.lo.kind != ast::Primary::Kind::name || v.lo.name.parts.size() != 1 ||
                v.kind != ast::Value::Kind::single || v.spread || v.samples) {
                error("E0204", v.range,
                      what + " must be " +
                          (expect.type == ParamType::vehicle ? std::string("a vehicle name or zone")
                                                             : "one of its words"));
                return out;
            }
            out.kind = Eval::Kind::word;
            out.word = v.lo.name.str();
            if (def != nullptr && def->type == ParamType::choice) {
                if (std::find(def->choices.begin(), def->choices.end(), out.word) ==
                    def->choices.end()) {
                    std::string list;
                    for (const auto& c : def->choices) list += (list.empty() ? "" : ", ") + c;
                    auto* d = error("E0206", v.range,
                                    "'" + out.word + "' is not a valid value of " + what);
                    add_suggestion(*d, out.word, def->choices);
                    d->notes.push_back({{}, "expected one of: " + list});
                    return Eval{};
                }
            }
            return out;
        }
    }
    return out;
}

bool Checker::compatible(TypeInfo have, TypeInfo want) {
    if (have.type == ParamType::integer && want.type == ParamType::quantity &&
        want.dim == Dim::none) {
        return true;
    }
    if (have.type != want.type) return false;
    return have.type != ParamType::quantity || have.dim == want.dim;
}

void Checker::apply_spread_and_samples(const ast::Value& v, Eval& e, TypeInfo expect,
                                       const std::string& what, const ParamDef* def) {
    if (v.spread) {
        const ast::Primary& sp = *v.spread;
        double delta = 0.0;
        if (sp.kind == ast::Primary::Kind::quantity && sp.quantity.unit == "%") {
            delta = std::fabs(e.num.value) * sp.quantity.value / 100.0;
        } else {
            auto d = to_si(sp, expect.dim, "the spread of " + what);
            if (!d) {
                e.kind = Eval::Kind::invalid;
                return;
            }
            delta = *d;
        }
        if (delta < 0 || (sp.kind == ast::Primary::Kind::quantity && sp.quantity.value < 0)) {
            error("E0304", sp.range, "a spread must not be negative");
            e.kind = Eval::Kind::invalid;
            return;
        }
        e.num.lo = e.num.value - delta;
        e.num.hi = e.num.value + delta;
        e.ranged = true;
    }
    apply_samples(v, e, expect, what, def);
}

void Checker::apply_samples(const ast::Value& v, Eval& e, TypeInfo expect, const std::string& what,
                            const ParamDef* def) {
    if (v.samples) {
        const ast::Samples& s = *v.samples;
        if (s.count < 1 || s.count > kMaxSamples) {
            error("E0302", s.count_range,
                  "sample count " + (s.count < 0 ? std::string("(too large)") : std::to_string(s.count)) +
                      " is out of range: use 1 to " + std::to_string(kMaxSamples));
            e.kind = Eval::Kind::invalid;
            return;
        }
        e.num.samples = static_cast<int>(s.count);
        if (s.method) {
            const std::string m = s.method->text;
            if (m == "linear") {
                e.num.method = ir::SampleMethod::linear;
            } else if (m == "uniform") {
                e.num.method = ir::SampleMethod::uniform;
            } else if (m == "normal") {
                e.num.method = ir::SampleMethod::normal;
                if (!s.method_arg) {
                    error("E0401", s.method->range,
                          "normal sampling needs its standard deviation, e.g. normal(1 m/s)");
                    e.kind = Eval::Kind::invalid;
                    return;
                }
                auto sigma = to_si(*s.method_arg, expect.dim, "the standard deviation");
                if (!sigma) {
                    e.kind = Eval::Kind::invalid;
                    return;
                }
                if (*sigma <= 0) {
                    error("E0301", s.method_arg->range, "the standard deviation must be > 0");
                    e.kind = Eval::Kind::invalid;
                    return;
                }
                e.num.sigma = *sigma;
            } else {
                auto* d = error("E0206", s.method->range,
                                "unknown sampling method '" + m + "'");
                add_suggestion(*d, m, {"linear", "uniform", "normal"});
                d->notes.push_back({{}, "expected linear, uniform or normal(σ)"});
                e.kind = Eval::Kind::invalid;
                return;
            }
            if (m != "normal" && s.method_arg) {
                error("E0204", s.method_arg->range, "only normal sampling takes a parameter");
            }
        }
        if (e.num.samples > 1 && !e.ranged) {
            error("E0304", s.range, "samples need a range: write 'value ±p%' or 'lo..hi'");
            e.kind = Eval::Kind::invalid;
            return;
        }
    } else if (e.ranged) {
        // A range without a count: the catalog's default count, at least 3.
        int n = 3;
        if (def != nullptr && def->def && def->def->samples > 1) n = def->def->samples;
        e.num.samples = n;
    }
    (void)what;
}

// Checks a resolved number against the catalog parameter's allowed range (E0301).
bool Checker::check_range(const Eval& e, const ParamDef& def, const std::string& what) {
    if (e.kind != Eval::Kind::number || !e.known) return true;
    // Magnitudes: the lower bound of a sampled range is clipped at 0 (SPEC §3.6).
    ir::Sampled s = e.num;
    if (def.min >= 0 && s.lo < 0 && s.value >= 0) s.lo = 0;
    for (double x : {s.value, s.lo, s.hi}) {
        if (!def.accepts(x)) {
            auto* d = error("E0301", e.range,
                            "value " + with_unit(x, def.dim) + " is out of range for " + what);
            const auto write = [&](double v) { return with_unit(v, def.dim); };
            d->notes.push_back({{}, "allowed: " + def.allowed(write)});
            return false;
        }
    }
    return true;
}

}  // namespace sdv::compiler::sema
