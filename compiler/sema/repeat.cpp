// Arithmetic on quantities and agent templates.
//
// Arithmetic (`20 m + 25 m * i`, `(20 + 25*i) m`) is folded to one SI number with its
// dimension: sums need one dimension, products and quotients combine them (length / time is a
// speed), a unit after a parenthesis applies to the plain number inside. The number is then
// checked like a written one, so `speed (10 + i) km/h` and `speed 13 km/h` lower alike.
//
// A template (`vehicle v[1..50]: sdv { ... }`) is expanded, before anything else of the
// scenario is checked, into the agents v1 .. v50: copies of the template with the index
// variable (`i`, or the name written `v[k = 1..50]`) replaced by each index. The agents keep the
// template's source ranges, so an error in the body is reported once, at the template, with a
// note naming the instances it failed for.
#include <algorithm>
#include <cmath>

#include "compiler/diag/suggest.h"
#include "compiler/sema/checker_internal.h"

namespace sdv::compiler::sema {
namespace {

// The dimension of a product or quotient, or nullopt when it has none of the catalog's.
std::optional<Dim> multiply(Dim a, Dim b) {
    if (a == Dim::none) return b;
    if (b == Dim::none) return a;
    auto is = [&](Dim x, Dim y) { return (a == x && b == y) || (a == y && b == x); };
    if (is(Dim::speed, Dim::time)) return Dim::length;
    if (is(Dim::accel, Dim::time)) return Dim::speed;
    if (is(Dim::jerk, Dim::time)) return Dim::accel;
    if (is(Dim::frequency, Dim::time)) return Dim::none;
    if (is(Dim::length, Dim::frequency)) return Dim::speed;
    return std::nullopt;
}

std::optional<Dim> divide(Dim a, Dim b) {
    if (b == Dim::none) return a;
    if (a == b) return Dim::none;
    auto is = [&](Dim x, Dim y) { return a == x && b == y; };
    if (is(Dim::length, Dim::time)) return Dim::speed;
    if (is(Dim::speed, Dim::time)) return Dim::accel;
    if (is(Dim::accel, Dim::time)) return Dim::jerk;
    if (is(Dim::length, Dim::speed)) return Dim::time;
    if (is(Dim::speed, Dim::accel)) return Dim::time;
    if (is(Dim::accel, Dim::jerk)) return Dim::time;
    if (is(Dim::none, Dim::time)) return Dim::frequency;
    if (is(Dim::none, Dim::frequency)) return Dim::time;
    return std::nullopt;
}

ast::Quantity index_quantity(int64_t k, SourceRange where) {
    ast::Quantity q;
    q.value = static_cast<double>(k);
    q.text = std::to_string(k);
    q.is_integer = true;
    q.unit_range = where;
    return q;
}

// The index variable replaced by `k` in a value of an expanded agent.
struct Substitute {
    const std::string& var;
    int64_t k;
    mutable bool replaced = false;  // whether it replaced the index anywhere

    void arith(ast::Arith& a) const {
        if (a.kind == ast::Arith::Kind::name && a.name.parts.size() == 1 && a.name.parts[0].text == var) {
            replaced = true;
            a.kind = ast::Arith::Kind::quantity;
            a.quantity = index_quantity(a.negate ? -k : k, a.range);
            if (a.negate) a.quantity.text = "-" + std::to_string(k);
            a.negate = false;
            a.name = {};
            return;
        }
        for (auto& o : a.operands) arith(o);
    }
    void primary(ast::Primary& p) const {
        if (p.kind == ast::Primary::Kind::name && p.name.parts.size() == 1 && p.name.parts[0].text == var) {
            replaced = true;
            p.kind = ast::Primary::Kind::quantity;
            p.quantity = index_quantity(k, p.range);
            p.name = {};
        } else if (p.kind == ast::Primary::Kind::expr && p.expr) {
            ast::Arith copy = *p.expr;
            arith(copy);
            p.expr = std::make_shared<const ast::Arith>(std::move(copy));
        }
    }
    void value(ast::Value& v) const {
        primary(v.lo);
        if (v.spread) primary(*v.spread);
        if (v.hi) primary(*v.hi);
        if (v.samples && v.samples->method_arg) primary(*v.samples->method_arg);
        for (auto& item : v.items) value(item);
    }
    void value(std::optional<ast::Value>& v) const {
        if (v) value(*v);
    }
    void position(ast::Position& p) const {
        value(p.s);
        value(p.offset);
        value(p.x);
        value(p.y);
        value(p.heading);
    }
    void agent(ast::VehicleDecl& v) const {
        for (auto& p : v.starts) position(p);
        for (auto& p : v.goals) position(p);
        for (auto& s : v.settings) {
            for (auto& x : s.values) value(x);
        }
        for (auto& t : v.trees) {
            for (auto& a : t.args) value(a.value);
        }
        for (auto& traj : v.trajectories) {
            for (auto& w : traj) {
                value(w.time);
                position(w.position);
                value(w.speed);
            }
        }
        for (auto& path : v.paths) {
            for (auto& pt : path) {
                position(pt.position);
                value(pt.speed);
            }
        }
    }
};

std::unique_ptr<ast::Expr> clone(const ast::Expr& e) {
    auto c = std::make_unique<ast::Expr>();
    c->kind = e.kind;
    if (e.lhs) c->lhs = clone(*e.lhs);
    if (e.rhs) c->rhs = clone(*e.rhs);
    c->function = e.function;
    c->args = e.args;
    c->cmp = e.cmp;
    c->bound = e.bound;
    c->range = e.range;
    c->window = e.window;
    return c;
}

std::string primary_text(const ast::Primary& p) {
    switch (p.kind) {
        case ast::Primary::Kind::quantity: return p.quantity.text + (p.quantity.unit.empty() ? "" : " " + p.quantity.unit);
        case ast::Primary::Kind::name: return p.name.str();
        default: return "...";
    }
}

}  // namespace

std::optional<Checker::Folded> Checker::fold(const ast::Arith& a, const std::string& what) {
    switch (a.kind) {
        case ast::Arith::Kind::quantity: {
            const ast::Quantity& q = a.quantity;
            if (q.unit.empty()) return Folded{q.value, Dim::none, q.is_integer};
            auto unit = catalog::find_unit(q.unit);
            if (!unit) {
                auto* d = error("E0203", q.unit_range, "unknown unit '" + q.unit + "'");
                std::vector<std::string> spellings;
                for (const auto& u : catalog::all_units()) spellings.emplace_back(u.spelling);
                add_suggestion(*d, q.unit, spellings);
                return std::nullopt;
            }
            return Folded{q.value * unit->to_si, unit->dim, false};
        }
        case ast::Arith::Kind::name: {
            auto* d = error("E0207", a.range, "'" + a.name.str() + "' is not a number in the arithmetic of " + what);
            d->notes.push_back({{}, "arithmetic takes quantities and the index of a repeated agent "
                                    "(`vehicle v[1..50]`: `i`)"});
            return std::nullopt;
        }
        case ast::Arith::Kind::sum: {
            auto acc = fold(a.operands[0], what);
            if (!acc) return std::nullopt;
            for (size_t k = 1; k < a.operands.size(); ++k) {
                auto x = fold(a.operands[k], what);
                if (!x) return std::nullopt;
                if (x->dim != acc->dim) {
                    const bool add = a.ops[k - 1] == '+';
                    auto* d = error("E0207", a.range,
                                    std::string("cannot ") + (add ? "add " : "subtract ") + dim_phrase(x->dim) +
                                        (add ? " to " : " from ") + dim_phrase(acc->dim) + " in " + what);
                    if (acc->dim == Dim::none || x->dim == Dim::none) {
                        d->notes.push_back({{}, "give every term its unit, e.g. '20 m + 25 m * i', or write the "
                                                "unit after the parenthesis: '(20 + 25 * i) m'"});
                    }
                    return std::nullopt;
                }
                acc->si = a.ops[k - 1] == '+' ? acc->si + x->si : acc->si - x->si;
                acc->integer = acc->integer && x->integer;
            }
            return acc;
        }
        case ast::Arith::Kind::product: {
            auto acc = fold(a.operands[0], what);
            if (!acc) return std::nullopt;
            for (size_t k = 1; k < a.operands.size(); ++k) {
                auto x = fold(a.operands[k], what);
                if (!x) return std::nullopt;
                const bool mul = a.ops[k - 1] == '*';
                auto dim = mul ? multiply(acc->dim, x->dim) : divide(acc->dim, x->dim);
                if (!dim) {
                    error("E0207", a.range,
                          std::string("cannot ") + (mul ? "multiply " : "divide ") + dim_phrase(acc->dim) +
                              (mul ? " by " : " by ") + dim_phrase(x->dim) + " in " + what +
                              ": the result has no unit of the language");
                    return std::nullopt;
                }
                if (!mul && x->si == 0.0) {
                    error("E0207", a.operands[k].range, "division by zero in " + what);
                    return std::nullopt;
                }
                acc->si = mul ? acc->si * x->si : acc->si / x->si;
                acc->integer = acc->integer && x->integer && acc->si == std::round(acc->si);
                acc->dim = *dim;
            }
            return acc;
        }
        case ast::Arith::Kind::group: {
            auto x = fold(a.operands[0], what);
            if (!x) return std::nullopt;
            if (a.negate) x->si = -x->si;
            if (a.unit.empty()) return x;
            auto unit = catalog::find_unit(a.unit);
            if (!unit) {
                auto* d = error("E0203", a.unit_range, "unknown unit '" + a.unit + "'");
                std::vector<std::string> spellings;
                for (const auto& u : catalog::all_units()) spellings.emplace_back(u.spelling);
                add_suggestion(*d, a.unit, spellings);
                return std::nullopt;
            }
            if (x->dim != Dim::none) {
                auto* d = error("E0207", a.unit_range,
                                "the unit '" + a.unit + "' applies to a plain number, but the parenthesis holds " +
                                    dim_phrase(x->dim));
                d->notes.push_back({{}, "write the unit either after the parenthesis or on its terms, not both"});
                return std::nullopt;
            }
            return Folded{x->si * unit->to_si, unit->dim, false};
        }
    }
    return std::nullopt;
}

// A bound of `v[LO..HI]`: a whole number, without unit, not negative.
std::optional<int64_t> Checker::repeat_bound(const ast::Primary& p) {
    if (p.kind != ast::Primary::Kind::quantity || !p.quantity.is_integer || !p.quantity.unit.empty()) {
        auto* d = error("E0511", p.range, "the bounds of a repeated agent must be whole numbers without unit, found '" +
                                              primary_text(p) + "'");
        d->notes.push_back({{}, "write e.g. 'vehicle v[1..50]: sdv { ... }'"});
        return std::nullopt;
    }
    if (p.quantity.value < 0 || p.quantity.value > 1e15) {
        error("E0511", p.range, "the bound " + p.quantity.text + " of a repeated agent is out of range")
            ->notes.push_back({{}, "allowed: 0 to 1e15, with at most " + std::to_string(kMaxRepeat) +
                                   " agents per declaration"});
        return std::nullopt;
    }
    return static_cast<int64_t>(p.quantity.value);
}

const ast::ScenarioDecl& Checker::expand_templates(const ast::ScenarioDecl& s) {
    if (std::none_of(s.vehicles.begin(), s.vehicles.end(), [](const ast::VehicleDecl& v) { return v.repeat.has_value(); })) {
        return s;
    }
    auto c = std::make_unique<ast::ScenarioDecl>();
    c->name = s.name;
    c->settings = s.settings;
    c->lights = s.lights;
    for (const auto& e : s.expects) c->expects.push_back(clone(*e));
    c->varies = s.varies;
    c->range = s.range;
    int64_t total = 0;
    bool over = false;
    for (const auto& v : s.vehicles) {
        if (!v.repeat) {
            c->vehicles.push_back(v);
            ++total;
            continue;
        }
        const ast::VehicleDecl::Repeat& r = *v.repeat;
        if (v.is_ego) {
            auto* d = error("E0512", r.range, "the ego cannot be repeated: a scenario has one ego");
            d->notes.push_back({{}, "declare the others as 'vehicle " + v.name.text + "[...]: KIND { ... }'"});
            // Checked as its first instance would be, so that its body is not a second error.
            ast::VehicleDecl one = v;
            one.repeat.reset();
            if (r.lo.kind == ast::Primary::Kind::quantity && r.lo.quantity.is_integer) {
                Substitute{r.var ? r.var->text : "i", static_cast<int64_t>(r.lo.quantity.value)}.agent(one);
            }
            c->vehicles.push_back(std::move(one));
            continue;
        }
        auto lo = repeat_bound(r.lo);
        auto hi = repeat_bound(r.hi);
        if (!lo || !hi) continue;
        const std::string var = r.var ? r.var->text : "i";
        // Whether its tree reference uses the index: if not, its instances' trees expand alike.
        ast::VehicleDecl trees_only;
        trees_only.trees = v.trees;
        const Substitute probe{var, *lo};
        probe.agent(trees_only);
        const ast::VehicleDecl* tree_of = probe.replaced ? nullptr : &v;
        const std::string of = v.name.text + "[" + (r.var ? var + " = " : "") + std::to_string(*lo) + ".." +
                               std::to_string(*hi) + "]";
        if (*hi < *lo) {
            auto* d = error("E0511", r.range, "'" + of + "' declares no agent: its range is empty");
            d->notes.push_back({{}, "write the lower bound first: '" + v.name.text + "[" + std::to_string(*hi) + ".." +
                                    std::to_string(*lo) + "]'"});
            continue;
        }
        const int64_t count = *hi - *lo + 1;
        if (count > kMaxRepeat) {
            auto* d = error("E0511", r.range, "'" + of + "' declares " + std::to_string(count) + " agents");
            d->notes.push_back({{}, "allowed: at most " + std::to_string(kMaxRepeat) + " agents per declaration"});
            continue;
        }
        total += count;
        if (total > options_.max_scenario_agents) {
            if (!over) {
                auto* d = error("E0511", r.range, "scenario '" + s.name.text + "' declares more than " +
                                                      std::to_string(options_.max_scenario_agents) + " agents");
                d->notes.push_back({{}, "allowed: at most " + std::to_string(options_.max_scenario_agents) + " agents per scenario"});
            }
            over = true;
            continue;
        }
        // A name ending in a digit gets a separator: `lane2car[1..12]` gives lane2car_1, not lane2car1.
        const bool digit = std::isdigit(static_cast<unsigned char>(v.name.text.back())) != 0;
        const std::string prefix = v.name.text + (digit ? "_" : "");
        for (int64_t k = *lo; k <= *hi; ++k) {
            ast::VehicleDecl one = v;
            one.repeat.reset();
            one.name.text = prefix + std::to_string(k);
            one.name.range = r.range;
            auto inst = std::make_shared<ast::VehicleDecl::Instance>();
            inst->label = one.name.text + " (" + var + " = " + std::to_string(k) + ")";
            inst->of = of;
            inst->tree_of = tree_of;
            one.instance = std::move(inst);
            Substitute{var, k}.agent(one);
            c->vehicles.push_back(std::move(one));
        }
    }
    expanded_.push_back(std::move(c));
    return *expanded_.back();
}

void Checker::attach_instance_notes() {
    constexpr size_t kShown = 3;
    for (const auto& e : instance_errors_) {
        diag::Diagnostic* d = diags_->find(e.code, e.range);
        if (d == nullptr) continue;
        std::string list;
        const size_t shown = e.labels.size() <= kShown + 1 ? e.labels.size() : kShown;
        for (size_t k = 0; k < shown; ++k) {
            if (k > 0) list += (k + 1 == e.labels.size() ? " and " : ", ");
            list += e.labels[k];
        }
        if (shown < e.labels.size()) list += " and " + std::to_string(e.labels.size() - shown) + " more";
        d->notes.push_back({{}, "for " + list + " of '" + e.of + "'"});
    }
    instance_errors_.clear();
    instance_error_index_.clear();
}

}  // namespace sdv::compiler::sema
