// Campaigns: a scenario's `vary` block checked and lowered to ir::Vary. Each varied path names
// a value of the scenario (seed, timeout, rates), of a vehicle (speed, length, width, start,
// goal) or an argument of a vehicle's tree call; its domain is a set, a range with an optional
// count, or a distribution. How a value reaches the IR is found by compiling the scenario with
// the parameter set to the ends (and the middle) of its domain: every IR number that changes
// becomes a binding `scale * value + offset`, proved linear on those probes. The probes are
// full checks, so a value of the domain the scenario cannot take (out of a catalog range, off
// the road) is reported at the vary block, with the check's own code.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>

#include "runtime/ir/bindings.h"
#include "compiler/sema/checker_internal.h"

namespace sdv::compiler::sema {
namespace {

constexpr int64_t kMaxGridVariants = 1'000'000;
constexpr int64_t kMaxSampledVariants = 10'000'000;
constexpr int64_t kMaxLevels = 100'000;
constexpr size_t kMaxSetProbes = 8;

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

// The scenario without its vary block, to be changed and checked as a probe.
ast::ScenarioDecl probe_copy(const ast::ScenarioDecl& s) {
    ast::ScenarioDecl c;
    c.name = s.name;
    c.settings = s.settings;
    c.vehicles = s.vehicles;
    c.lights = s.lights;
    for (const auto& e : s.expects) c.expects.push_back(clone(*e));
    c.range = s.range;
    return c;
}

// A number in SI as a written primary, located at `where` (so that what a check finds wrong
// with it points into the vary block).
ast::Primary si_primary(double v, TypeInfo t, SourceRange where) {
    ast::Primary p;
    p.kind = ast::Primary::Kind::quantity;
    p.range = where;
    p.quantity.unit_range = where;
    if (t.type == ParamType::integer) {
        p.quantity.value = std::round(v);
        p.quantity.is_integer = true;
        p.quantity.text = std::to_string(std::llround(v));
        return p;
    }
    p.quantity.value = v;
    switch (t.dim) {
        case Dim::none: break;
        case Dim::ratio: p.quantity.value = v * 100; p.quantity.unit = "%"; break;
        case Dim::accel: p.quantity.unit = "m/s^2"; break;
        case Dim::jerk: p.quantity.unit = "m/s^3"; break;
        default: p.quantity.unit = std::string(catalog::si_unit(t.dim)); break;
    }
    p.quantity.text = fmt(p.quantity.value);
    return p;
}

std::string ir_unit(TypeInfo t) {
    if (t.type != ParamType::quantity) return "";
    if (t.dim == Dim::accel) return "m/s^2";
    if (t.dim == Dim::jerk) return "m/s^3";
    return std::string(catalog::si_unit(t.dim));
}

// The catalog parameters of a leaf node; null for composites and unknown leaves (reported
// where the tree is checked).
const std::vector<ParamDef>* catalog_params(const ast::Node& n) {
    if (n.kind == ast::NodeKind::maneuver) {
        const auto* m = catalog::find_maneuver(n.callee.str());
        return m != nullptr ? &m->params : nullptr;
    }
    if (n.kind == ast::NodeKind::condition) {
        const auto* c = catalog::find_condition(n.callee.str());
        return c != nullptr ? &c->params : nullptr;
    }
    return nullptr;
}

bool inside(SourceRange inner, SourceRange outer) {
    return inner.begin.file == outer.begin.file && inner.begin.offset >= outer.begin.offset &&
           inner.end.offset <= outer.end.offset;
}

}  // namespace

// Where a varied path lands in the scenario's AST.
struct Checker::VaryTarget {
    enum class Kind { seed, setting, vehicle_setting, start, goal, tree_arg } kind = Kind::setting;
    std::string key;  // setting key, position field (s, offset, x, y, heading) or argument name
    size_t vehicle = 0;
    TypeInfo type{ParamType::quantity, Dim::none};
};

std::vector<std::string> Checker::vary_paths(const ast::ScenarioDecl& s) {
    std::vector<std::string> out = {"seed", "timeout", "rate.traffic", "rate.planning", "rate.latency",
                                    "rate.sensor_range"};
    for (const auto& v : s.vehicles) {
        const std::string n = v.name.text;
        for (const char* k : {".speed", ".length", ".width", ".start", ".start.offset", ".goal", ".goal.offset"}) {
            out.push_back(n + k);
        }
        if (v.trees.empty()) continue;
        TreeSym* t = nullptr;
        if (auto it = tree_index_.find(v.trees[0].name.str()); it != tree_index_.end()) t = &trees_[it->second];
        if (t == nullptr || t->decl == nullptr) continue;
        for (const auto& p : t->decl->params) out.push_back(n + ".tree." + p.name.text);
        for (const auto& [label, node] : t->labels) {
            if (const auto* ps = catalog_params(*node)) {
                for (const auto& p : *ps) out.push_back(n + ".tree." + label + "." + p.name);
            }
        }
    }
    return out;
}

std::optional<Checker::VaryTarget> Checker::vary_target(const ast::VaryParam& vp, const ast::ScenarioDecl& s) {
    const auto& parts = vp.path.parts;
    const std::string path = vp.path.str();
    auto unknown = [&](const std::string& why) -> std::optional<VaryTarget> {
        const auto candidates = vary_paths(s);  // before error(): it may report, which moves diagnostics
        auto* d = error("E0601", vp.path.range, "cannot vary '" + path + "': " + why);
        add_suggestion(*d, path, candidates);
        d->notes.push_back({{}, "a campaign varies the seed, timeout, rate.*, a vehicle's speed, length, width, "
                                "start, start.offset, goal, or an argument of its tree: VEHICLE.tree.PARAM or "
                                "VEHICLE.tree.LABEL.PARAM (docs/campaigns.md)"});
        return std::nullopt;
    };
    VaryTarget t;
    if (parts.size() == 1 && parts[0].text == "seed") {
        t.kind = VaryTarget::Kind::seed;
        t.type = {ParamType::integer, Dim::none};
        return t;
    }
    if (parts.size() == 1 && parts[0].text == "timeout") {
        t.key = "timeout";
        t.type = {ParamType::quantity, Dim::time};
        return t;
    }
    if (parts.size() == 2 && parts[0].text == "rate") {
        const std::string& r = parts[1].text;
        const Dim dim = r == "latency" ? Dim::time : r == "sensor_range" ? Dim::length : Dim::frequency;
        if (r != "traffic" && r != "planning" && r != "latency" && r != "sensor_range") {
            return unknown("there is no rate '" + r + "'");
        }
        t.key = "rate " + r;
        t.type = {ParamType::quantity, dim};
        return t;
    }
    size_t vi = s.vehicles.size();
    for (size_t i = 0; i < s.vehicles.size(); ++i) {
        if (s.vehicles[i].name.text == parts[0].text) vi = i;
    }
    if (vi == s.vehicles.size()) {
        return unknown("'" + parts[0].text + "' is not a vehicle of scenario '" + s.name.text + "' nor a scenario setting");
    }
    const ast::VehicleDecl& v = s.vehicles[vi];
    t.vehicle = vi;
    if (parts.size() < 2) return unknown("name what of vehicle '" + v.name.text + "' to vary");
    const std::string& what = parts[1].text;
    if (parts.size() == 2 && (what == "speed" || what == "length" || what == "width")) {
        t.kind = VaryTarget::Kind::vehicle_setting;
        t.key = what;
        t.type = {ParamType::quantity, what == "speed" ? Dim::speed : Dim::length};
        return t;
    }
    if ((what == "start" || what == "goal") && parts.size() <= 3) {
        const auto& positions = what == "start" ? v.starts : v.goals;
        if (positions.empty()) return unknown("vehicle '" + v.name.text + "' has no " + what);
        const bool xy = positions[0].xy;
        const std::string field = parts.size() == 3 ? parts[2].text : xy ? "" : "s";
        const bool ok = xy ? (field == "x" || field == "y" || field == "heading")
                           : (field == "s" || field == "offset");
        if (!ok) {
            return unknown(xy ? "the " + what + " of '" + v.name.text + "' is a point: vary ." + what + ".x, ." + what +
                                    ".y or ." + what + ".heading"
                              : "a lane position has 's' (the default) and 'offset'");
        }
        t.kind = what == "start" ? VaryTarget::Kind::start : VaryTarget::Kind::goal;
        t.key = field;
        t.type = {ParamType::quantity, field == "heading" ? Dim::angle : Dim::length};
        return t;
    }
    if (what == "tree" && (parts.size() == 3 || parts.size() == 4)) {
        if (v.trees.empty()) return unknown("vehicle '" + v.name.text + "' has no tree");
        auto it = tree_index_.find(v.trees[0].name.str());
        if (it == tree_index_.end()) return std::nullopt;  // reported at the vehicle
        TreeSym& tree = trees_[it->second];
        t.kind = VaryTarget::Kind::tree_arg;
        if (parts.size() == 3) {
            auto p = tree.params.find(parts[2].text);
            if (p == tree.params.end()) {
                return unknown("tree '" + tree.qname + "' has no parameter '" + parts[2].text + "'");
            }
            auto type = find_type_quiet(p->second->type.text);
            if (!type) return std::nullopt;  // reported at the tree
            t.key = parts[2].text;
            t.type = *type;
        } else {
            auto l = tree.labels.find(parts[2].text);
            if (l == tree.labels.end()) {
                return unknown("tree '" + tree.qname + "' has no node labelled '" + parts[2].text + "'");
            }
            const auto* params = catalog_params(*l->second);
            const ParamDef* def = nullptr;
            if (params != nullptr) {
                for (const auto& p : *params) {
                    if (p.name == parts[3].text) def = &p;
                }
            }
            if (def == nullptr) {
                return unknown("node '" + parts[2].text + "' of tree '" + tree.qname + "' has no parameter '" +
                               parts[3].text + "'");
            }
            t.key = parts[2].text + "." + parts[3].text;
            t.type = type_of(*def);
        }
        if (t.type.type != ParamType::quantity && t.type.type != ParamType::integer) {
            return unknown("it is " + type_phrase(t.type) + "; only numbers can be varied");
        }
        return t;
    }
    return unknown("vehicle '" + v.name.text + "' has no '" + vp.path.str().substr(parts[0].text.size() + 1) + "'");
}

// The value the target names in a probe copy of the scenario, created when it is not written.
ast::Value* Checker::vary_slot(const VaryTarget& t, ast::ScenarioDecl& s, SourceRange where) {
    auto setting = [&](std::vector<ast::Setting>& settings, const std::string& key) -> ast::Value* {
        for (auto& st : settings) {
            if (st.key.text == key && !st.values.empty()) return &st.values[0];
        }
        ast::Setting st;
        st.key = {key, where};
        st.values.emplace_back();
        st.values[0].range = where;
        st.range = where;
        settings.push_back(std::move(st));
        return &settings.back().values[0];
    };
    auto position = [&](ast::Position& p) -> ast::Value* {
        std::optional<ast::Value>* field = t.key == "s"        ? &p.s
                                           : t.key == "offset" ? &p.offset
                                           : t.key == "x"      ? &p.x
                                           : t.key == "y"      ? &p.y
                                                               : &p.heading;
        if (!*field) {
            *field = ast::Value{};
            (*field)->range = where;
        }
        return &**field;
    };
    switch (t.kind) {
        case VaryTarget::Kind::seed: return nullptr;
        case VaryTarget::Kind::setting: return setting(s.settings, t.key);
        case VaryTarget::Kind::vehicle_setting: return setting(s.vehicles[t.vehicle].settings, t.key);
        case VaryTarget::Kind::start: return position(s.vehicles[t.vehicle].starts[0]);
        case VaryTarget::Kind::goal: return position(s.vehicles[t.vehicle].goals[0]);
        case VaryTarget::Kind::tree_arg: {
            auto& args = s.vehicles[t.vehicle].trees[0].args;
            for (auto& a : args) {
                if (a.name.str() == t.key) return &a.value;
            }
            ast::Arg a;
            size_t from = 0;
            while (from <= t.key.size()) {
                const size_t dot = t.key.find('.', from);
                const size_t end = dot == std::string::npos ? t.key.size() : dot;
                a.name.parts.push_back({t.key.substr(from, end - from), where});
                from = end + 1;
            }
            a.name.range = where;
            a.value.range = where;
            a.range = where;
            args.push_back(std::move(a));
            return &args.back().value;
        }
    }
    return nullptr;
}

void Checker::check_vary(const ast::ScenarioDecl& s, ir::Program& program, size_t index,
                         size_t instances_before) {
    const ast::VaryDecl& va = s.varies[0];
    for (size_t i = 1; i < s.varies.size(); ++i) {
        auto* d = error("E0604", s.varies[i].keyword_range,
                        "scenario '" + s.name.text + "' has more than one vary block");
        d->notes.push_back({va.keyword_range, "the first is here; put every varied parameter in it"});
    }
    ir::Vary out;
    out.loc = loc(va.keyword_range);
    out.seed = program.scenarios[index].seed;
    const size_t errors_before = diags_->error_count();
    // ---- settings: sample METHOD [N], seed N
    const ast::Setting* sample = nullptr;
    const ast::Setting* seed = nullptr;
    for (const auto& st : va.settings) {
        const ast::Setting*& slot = st.key.text == "sample" ? sample : seed;
        if (slot != nullptr) {
            auto* d = error("E0504", st.key.range, "duplicate '" + st.key.text + "' in the vary block");
            d->notes.push_back({slot->range, "first given here"});
            continue;
        }
        slot = &st;
    }
    if (sample != nullptr) {
        const ast::Value& m = sample->values[0];
        const std::string method = m.lo.name.str();
        const bool has_n = sample->values.size() > 1;
        if (method == "grid") {
            out.sample = ir::Vary::Sample::grid;
            if (has_n) {
                error("E0603", sample->values[1].range, "a grid takes no count: it runs every combination of the levels")
                    ->notes.push_back({{}, "for a fixed number of variants write 'sample random N' or 'sample latin N'"});
            }
        } else if (method == "random" || method == "latin") {
            out.sample = method == "random" ? ir::Vary::Sample::random : ir::Vary::Sample::latin;
            if (!has_n) {
                error("E0603", sample->range, "'sample " + method + "' needs the number of variants, e.g. 'sample " +
                                                  method + " 100'");
            } else {
                const auto& q = sample->values[1].lo.quantity;
                errno = 0;
                const long long n = std::strtoll(q.text.c_str(), nullptr, 10);
                if (errno == ERANGE || n < 1 || n > kMaxSampledVariants) {
                    error("E0602", sample->values[1].range,
                          "sample count " + q.text + " is out of range: use 1 to " + std::to_string(kMaxSampledVariants));
                } else {
                    out.count = n;
                }
            }
        } else {
            auto* d = error("E0206", m.range, "unknown sampling '" + method + "'");
            add_suggestion(*d, method, {"grid", "random", "latin"});
            d->notes.push_back({{}, "expected grid, random N or latin N"});
        }
    }
    if (seed != nullptr) {
        const std::string& text = seed->values[0].lo.quantity.text;
        errno = 0;
        out.seed = std::strtoull(text.c_str(), nullptr, 10);
        if (errno == ERANGE) {
            error("E0301", seed->values[0].range, "seed " + text + " is out of range")
                ->notes.push_back({{}, "allowed: 0 to 18446744073709551615"});
        }
    }
    if (va.params.empty()) {
        error("E0602", va.keyword_range, "the vary block of scenario '" + s.name.text + "' varies nothing")
            ->notes.push_back({{}, "name a parameter and its values, e.g. 'v2.speed in 10 m/s .. 20 m/s count 5'"});
    }
    // ---- parameters
    ir::Program probe_base = program;
    probe_base.scenarios.erase(probe_base.scenarios.begin() + static_cast<std::ptrdiff_t>(index));
    probe_base.instances.resize(instances_before);
    const std::vector<double> base = ir::scenario_number_values(program, static_cast<int>(index));
    std::map<std::string, SourceRange> seen;
    int64_t grid = 1;
    for (const auto& vp : va.params) {
        const std::string path = vp.path.str();
        if (auto it = seen.find(path); it != seen.end()) {
            auto* d = error("E0604", vp.path.range, "'" + path + "' is varied twice");
            d->notes.push_back({it->second, "first varied here"});
            continue;
        }
        seen.emplace(path, vp.path.range);
        auto target = vary_target(vp, s);
        if (!target) continue;
        ir::VaryParam p;
        p.name = path;
        p.loc = loc(vp.path.range);
        p.unit = ir_unit(target->type);
        p.seed = target->kind == VaryTarget::Kind::seed;
        p.integer = target->type.type == ParamType::integer;
        {
            const auto text = sm_.contents(vp.domain_range.begin.file);
            const auto b = vp.domain_range.begin.offset, e = vp.domain_range.end.offset;
            p.domain = b <= e && e <= text.size() ? std::string(text.substr(b, e - b)) : "";
        }
        const std::string what = "'" + path + "'";
        // Values in SI; every one located for the probes.
        auto value_of = [&](const ast::Primary& x) -> std::optional<double> {
            if (p.integer) {
                if (x.kind != ast::Primary::Kind::quantity || !x.quantity.is_integer || !x.quantity.unit.empty()) {
                    error("E0204", x.range, what + " takes whole numbers without unit");
                    return std::nullopt;
                }
                if (p.seed && x.quantity.value < 0) {
                    error("E0301", x.range, "a seed must not be negative");
                    return std::nullopt;
                }
                return x.quantity.value;
            }
            return to_si(x, target->type.dim, what);
        };
        std::vector<std::pair<double, SourceRange>> probes;  // value, where it is written
        bool ok = true;
        std::vector<double> xs;
        for (const auto& x : vp.values) {
            auto v = value_of(x);
            if (!v) ok = false;
            xs.push_back(v.value_or(0.0));
        }
        if (!ok) continue;
        int64_t levels = 0;  // grid levels; 0: continuous
        switch (vp.kind) {
            case ast::VaryParam::Kind::set: {
                p.kind = ir::VaryParam::Kind::set;
                p.values = xs;
                levels = static_cast<int64_t>(xs.size());
                std::vector<size_t> order(xs.size());
                for (size_t i = 0; i < order.size(); ++i) order[i] = i;
                std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return xs[a] < xs[b]; });
                if (order.size() <= kMaxSetProbes) {
                    for (size_t i : order) probes.push_back({xs[i], vp.values[i].range});
                } else {
                    for (size_t i : {order.front(), order[order.size() / 2], order.back()}) {
                        probes.push_back({xs[i], vp.values[i].range});
                    }
                }
                break;
            }
            case ast::VaryParam::Kind::range: {
                p.kind = ir::VaryParam::Kind::range;
                p.lo = xs[0];
                p.hi = xs[1];
                if (!(p.lo <= p.hi)) {
                    error("E0602", vp.domain_range, "empty range: the lower end " + with_unit(p.lo, target->type.dim) +
                                                        " is above the upper end " + with_unit(p.hi, target->type.dim));
                    continue;
                }
                if (vp.count) {
                    const int64_t n = *vp.count;
                    if (n < 1 || n > kMaxLevels || (n == 1 && p.lo != p.hi)) {
                        auto* d = error("E0602", vp.count_range,
                                        "count " + (n < 0 ? std::string("(too large)") : std::to_string(n)) +
                                            " is out of range: use 2 to " + std::to_string(kMaxLevels));
                        if (n == 1) d->notes.push_back({{}, "a single value is a set: write '[" + fmt(p.lo) + "]'"});
                        continue;
                    }
                    p.count = static_cast<int32_t>(n);
                    levels = n;
                    if (p.integer && n > 1) {
                        const double step = (p.hi - p.lo) / static_cast<double>(n - 1);
                        if (std::fabs(step - std::round(step)) > 1e-9) {
                            error("E0602", vp.count_range, "the " + std::to_string(n) + " levels from " + fmt(p.lo) +
                                                               " to " + fmt(p.hi) + " are not whole numbers");
                            continue;
                        }
                    }
                }
                probes.push_back({p.lo, vp.values[0].range});
                if (p.hi != p.lo) {
                    probes.push_back({p.hi, vp.values[1].range});
                    const double mid = p.integer ? std::floor(0.5 * (p.lo + p.hi)) : 0.5 * (p.lo + p.hi);
                    if (mid != p.lo && mid != p.hi) probes.push_back({mid, vp.domain_range});
                }
                break;
            }
            case ast::VaryParam::Kind::distribution: {
                const std::string& dist = vp.distribution.text;
                if (dist != "normal" && dist != "uniform") {
                    auto* d = error("E0206", vp.distribution.range, "unknown distribution '" + dist + "'");
                    add_suggestion(*d, dist, {"normal", "uniform"});
                    d->notes.push_back({{}, "expected normal(MEAN, SD) or uniform(LO, HI)"});
                    continue;
                }
                if (p.integer && dist == "normal") {
                    error("E0204", vp.distribution.range, what + " takes whole numbers: use a set or a range");
                    continue;
                }
                if (dist == "normal") {
                    p.kind = ir::VaryParam::Kind::normal;
                    p.mean = xs[0];
                    p.sd = xs[1];
                    if (!(p.sd > 0)) {
                        error("E0602", vp.values[1].range, "the standard deviation must be > 0");
                        continue;
                    }
                    p.lo = p.mean - 3 * p.sd;
                    p.hi = p.mean + 3 * p.sd;
                    probes = {{p.lo, vp.domain_range}, {p.hi, vp.domain_range}, {p.mean, vp.values[0].range}};
                } else {
                    p.kind = ir::VaryParam::Kind::uniform;
                    p.lo = xs[0];
                    p.hi = xs[1];
                    if (!(p.lo <= p.hi)) {
                        error("E0602", vp.domain_range, "empty range: the lower end " + with_unit(p.lo, target->type.dim) +
                                                            " is above the upper end " + with_unit(p.hi, target->type.dim));
                        continue;
                    }
                    probes = {{p.lo, vp.values[0].range}, {p.hi, vp.values[1].range}};
                    if (p.lo != p.hi) probes.push_back({0.5 * (p.lo + p.hi), vp.domain_range});
                }
                break;
            }
        }
        if (out.sample == ir::Vary::Sample::grid) {
            if (levels == 0) {
                auto* d = error("E0603", vp.domain_range, "a grid needs the levels of '" + path + "'");
                d->notes.push_back({{}, vp.kind == ast::VaryParam::Kind::range
                                            ? "write 'LO .. HI count N', or sample it with 'sample random N'"
                                            : "a distribution is sampled: write 'sample random N' or 'sample latin N'"});
                continue;
            }
            grid = grid > kMaxGridVariants ? grid : grid * levels;
        }
        if (!p.seed && !probe_bindings(s, vp, *target, probes, probe_base, index, base, p)) continue;
        out.params.push_back(std::move(p));
    }
    if (out.sample == ir::Vary::Sample::grid && grid > kMaxGridVariants) {
        auto* d = error("E0603", va.keyword_range, "the grid has " + std::string(grid > kMaxGridVariants * 1000 ? "more than " : "") +
                                                       std::to_string(grid) + " variants, more than " +
                                                       std::to_string(kMaxGridVariants));
        d->notes.push_back({{}, "use fewer levels, or 'sample latin N' to cover the space with N variants"});
    }
    if (diags_->error_count() != errors_before) return;
    program.scenarios[index].vary = std::move(out);
}

// Compiles the scenario at each probe value of one parameter and fits its bindings.
bool Checker::probe_bindings(const ast::ScenarioDecl& s, const ast::VaryParam& vp, const VaryTarget& target,
                             const std::vector<std::pair<double, SourceRange>>& probes,
                             const ir::Program& probe_base, size_t index, const std::vector<double>& base,
                             ir::VaryParam& out) {
    const std::string path = vp.path.str();
    std::vector<std::vector<double>> ys;
    for (const auto& [x, where] : probes) {
        ast::ScenarioDecl copy = probe_copy(s);
        ast::Value* slot = vary_slot(target, copy, vp.path.range);
        if (slot == nullptr) return false;
        if (slot->kind != ast::Value::Kind::single) {
            auto* d = error("E0605", vp.path.range, "cannot vary '" + path + "': it is written as " +
                                                        (slot->kind == ast::Value::Kind::list ? "a list" : "a range"));
            d->notes.push_back({slot->range, "written here; a varied value must be a single value (a spread is kept)"});
            return false;
        }
        slot->lo = si_primary(x, target.type, where);
        if (!slot->spread && !slot->samples) slot->range = where;
        ir::Program probe = probe_base;
        diag::DiagnosticEngine quiet;
        diag::DiagnosticEngine* saved = diags_;
        auto saved_reported = std::move(reported_);
        auto saved_instance_errors = std::move(instance_errors_);
        auto saved_instance_index = std::move(instance_error_index_);
        reported_.clear();
        instance_errors_.clear();
        instance_error_index_.clear();
        diags_ = &quiet;
        check_scenario(copy, probe);
        attach_instance_notes();
        diags_ = saved;
        reported_ = std::move(saved_reported);
        instance_errors_ = std::move(saved_instance_errors);
        instance_error_index_ = std::move(saved_instance_index);
        if (quiet.has_errors()) {
            for (auto d : quiet.sorted()) {
                if (d.severity != diag::Severity::error) continue;
                const std::string value = with_unit(x, target.type.dim);
                if (!inside(d.range, vp.range)) {
                    d.notes.insert(d.notes.begin(), {vp.range, "with '" + path + "' = " + value + " from this vary block"});
                } else {
                    d.notes.push_back({{}, "'" + path + "' = " + value + " is one of the values the vary block gives it"});
                }
                auto key = std::make_tuple(d.code, d.range.begin.file, d.range.begin.offset, std::string());
                if (reported_.insert(key).second) diags_->report(std::move(d));
            }
            return false;
        }
        (void)index;  // the probe's scenario is the last, as the checked one is
        ys.push_back(ir::scenario_number_values(probe, static_cast<int>(probe.scenarios.size() - 1)));
        if (ys.back().size() != base.size()) {
            error("E0605", vp.path.range, "cannot vary '" + path + "': its values change the shape of the scenario, "
                                          "not only its numbers");
            return false;
        }
    }
    // Fit number = scale * value + offset through the outermost probes; the others must agree.
    size_t lo = 0, hi = 0;
    for (size_t i = 0; i < probes.size(); ++i) {
        if (probes[i].first < probes[lo].first) lo = i;
        if (probes[i].first > probes[hi].first) hi = i;
    }
    bool changes = false;
    for (size_t j = 0; j < base.size(); ++j) {
        bool differs = false;
        for (const auto& y : ys) differs = differs || y[j] != base[j];
        if (!differs) continue;
        changes = true;
        ir::VaryBinding b;
        b.number = static_cast<int32_t>(j);
        const double x0 = probes[lo].first, x1 = probes[hi].first;
        if (x1 == x0) {
            b.scale = 0;
            b.offset = ys[lo][j];
        } else {
            b.scale = (ys[hi][j] - ys[lo][j]) / (x1 - x0);
            b.offset = ys[lo][j] - b.scale * x0;
        }
        for (size_t i = 0; i < probes.size(); ++i) {
            const double want = b.scale * probes[i].first + b.offset;
            if (std::fabs(want - ys[i][j]) > 1e-9 * std::max({1.0, std::fabs(want), std::fabs(ys[i][j])})) {
                auto* d = error("E0605", vp.path.range, "cannot vary '" + path + "': a value depends on it non-linearly "
                                                        "over its domain");
                d->notes.push_back({{}, "e.g. a spread in % around a value that changes sign, or a range clipped at 0; "
                                        "narrow the domain or vary the value it is derived from"});
                return false;
            }
        }
        out.bindings.push_back(b);
    }
    if (!changes && probes.size() > 1) {
        auto* d = error("E0605", vp.path.range, "varying '" + path + "' changes nothing in scenario '" + s.name.text + "'");
        d->notes.push_back({{}, "is the parameter used by the tree? (a tree parameter that no node reads has no effect)"});
        return false;
    }
    return true;
}

}  // namespace sdv::compiler::sema
