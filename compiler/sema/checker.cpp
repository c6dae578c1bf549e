// The semantic checker and lowering to IR. In order:
//   1. load: the main file and its imports (stdlib embedded, user files relative), parsed;
//   2. symbols: trees (qualified names), roads / junctions / maps, duplicates reported;
//   3. trees: every declaration checked once on its own (names, parameters, units, types,
//      literal ranges, structure: one root, no empty composites, unreachable children, a
//      maneuver somewhere), subtree cycles;
//   4. scenarios: settings, road, vehicles, lights, expectations; each vehicle's tree is
//      expanded with its arguments and overrides, every resolved value range-checked, and
//      written as a flat IR instance;
//   5. warnings: unused trees and parameters.
// Diagnostics from expanding the same tree twice are reported once.
#include "compiler/sema/compile.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "compiler/diag/suggest.h"
#include "compiler/syntax/parser.h"
#include "runtime/catalog/catalog.h"
#include "stdlib-trees/stdlib.h"

namespace sdv::compiler {
namespace {

namespace fs = std::filesystem;
using catalog::Dim;
using catalog::ParamDef;
using catalog::ParamType;
using diag::SourceRange;

constexpr int kMaxSamples = 100;
constexpr int kMaxCandidates = 20000;
constexpr int kMaxExpansionDepth = 64;

// ------------------------------------------------------------------ small helpers

std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

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

// A tree parameter's declared type.
struct TypeInfo {
    ParamType type = ParamType::quantity;
    Dim dim = Dim::none;
};

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

std::vector<std::string> names_of(const std::vector<ParamDef>& ps) {
    std::vector<std::string> out;
    for (const auto& p : ps) out.push_back(p.name);
    return out;
}

void add_suggestion(diag::Diagnostic& d, std::string_view word,
                    const std::vector<std::string>& candidates) {
    if (auto m = diag::closest_match(word, candidates)) {
        d.notes.push_back({{}, "did you mean '" + *m + "'?"});
    }
}

// ------------------------------------------------------------------ the checker

struct Unit {
    ast::File* file = nullptr;
    diag::FileId id = 0;
    std::string display;  // as shown in IR files[] and traces
    std::string qualifier;
    fs::path dir;  // for relative imports; empty for stdlib files
    bool is_main = false;
    bool is_stdlib = false;
    uint32_t ir_file = 0;
};

struct TreeSym {
    const ast::TreeDecl* decl = nullptr;
    std::string qname;
    Unit* unit = nullptr;
    int32_t ir_index = -1;
    bool used = false;
    bool ok = true;  // passed the declaration checks
    std::map<std::string, const ast::Param*> params;
    std::map<std::string, const ast::Node*> labels;
    std::set<std::string> used_params;
};

struct RoadSym {
    std::string name;
    ir::Road road;
    Unit* unit = nullptr;
    SourceRange range;
    bool ok = true;
    int32_t ir_index = -1;
    double length = 0.0;  // built-in road: centre length
};

// What a parameter name stands for while checking or expanding a tree.
struct Env;
struct Binding {
    const ast::Value* value = nullptr;  // null: declared without a bound value (generic check)
    const Env* env = nullptr;           // where `value` is evaluated
    TypeInfo type;
    bool untyped = false;  // its declared type is unknown (reported): accept any use
};
struct Env {
    const TreeSym* tree = nullptr;
    std::map<std::string, Binding> params;
    // label → overriding args (evaluated in `env`)
    std::map<std::string, std::vector<std::pair<const ast::Arg*, const Env*>>> overrides;
    std::vector<std::string> stack;  // tree names, for cycle detection while expanding
};

// A value after evaluation: a number (SI, possibly sampled), a word, or a string.
struct Eval {
    enum class Kind { number, word, string, invalid } kind = Kind::invalid;
    ir::Sampled num;
    bool known = true;  // false: a parameter whose value is not known (generic check)
    bool ranged = false;
    std::string word;
    SourceRange range;  // where the value was written (for range errors)
    TypeInfo type;      // for unknown values: their declared type
};

class Checker {
public:
    Checker(diag::SourceManager& sm, diag::DiagnosticEngine& diags, const CompileOptions& options)
        : sm_(sm), diags_(diags), options_(options) {}

    Compilation run(const std::string& display, std::string text) {
        Compilation out;
        load(display, std::move(text), fs::path(display).parent_path(), "", true, false);
        for (auto& u : units_) {
            out.files.push_back(std::move(owned_[u.id]));
            out.file_ids.push_back(u.id);
        }
        // The files vector now owns the ASTs; units_ keep raw pointers into them.
        if (units_.empty() || units_[0].file == nullptr) return out;
        collect_symbols();
        check_trees();
        ir::Program program;
        program.compiler_version = kCompilerVersion;
        for (auto& u : units_) {
            u.ir_file = static_cast<uint32_t>(program.files.size());
            program.files.push_back(u.display);
        }
        for (auto& t : trees_) {
            t.ir_index = static_cast<int32_t>(program.trees.size());
            ir::TreeDecl d;
            d.name = t.qname;
            for (const auto& p : t.decl->params) d.params.push_back(p.name.text);
            d.node_count = count_nodes(t.decl->body);
            d.loc = loc(t.decl->name.range);
            program.trees.push_back(std::move(d));
        }
        check_roads();
        for (auto& u : units_) {
            if (!u.is_main || u.file == nullptr) continue;
            for (const auto& s : u.file->scenarios) check_scenario(s, program);
        }
        warn_unused();
        if (diags_.has_errors()) return out;
        out.program = std::move(program);
        return out;
    }

private:
    // ---------------------------------------------------------------- diagnostics
    diag::Diagnostic* error(const std::string& code, SourceRange r, const std::string& msg) {
        // One error per code and place: expanding a tree re-checks values already checked at
        // the subtree reference, with other words for the same mistake.
        auto key = std::make_tuple(code, r.begin.file, r.begin.offset, std::string());
        (void)msg;
        if (!reported_.insert(key).second) return &scratch_;
        return &diags_.error(code, r, msg);
    }

    ir::SourceLoc loc(SourceRange r) const {
        ir::SourceLoc l;
        for (const auto& u : units_) {
            if (u.id == r.begin.file) l.file = u.ir_file;
        }
        if (r.begin.file != 0) {
            auto lc = sm_.line_col(r.begin);
            l.line = lc.line;
            l.col = lc.col;
        }
        return l;
    }

    // ---------------------------------------------------------------- loading
    void load(const std::string& display, std::string text, fs::path dir, std::string qualifier,
              bool is_main, bool is_stdlib) {
        const diag::FileId id = sm_.add_file(display, std::move(text));
        Unit u;
        u.id = id;
        u.display = display;
        u.qualifier = std::move(qualifier);
        u.dir = std::move(dir);
        u.is_main = is_main;
        u.is_stdlib = is_stdlib;
        auto parsed = syntax::parse(id, sm_, diags_);
        u.file = parsed.get();
        owned_[id] = std::move(parsed);
        units_.push_back(u);
        loaded_.insert(display);
        if (u.file == nullptr) return;
        // Copy: units_ may reallocate while imports load.
        const std::vector<ast::ImportDecl> imports = u.file->imports;
        const fs::path base = u.dir;
        const bool from_stdlib = is_stdlib;
        for (const auto& imp : imports) import_file(imp, base, from_stdlib);
    }

    void import_file(const ast::ImportDecl& imp, const fs::path& base, bool from_stdlib) {
        if (imp.path.rfind("std/", 0) == 0) {
            const stdlib::File* f = stdlib::find(imp.path);
            if (f == nullptr) {
                std::vector<std::string> names;
                for (const auto& sf : stdlib::files()) names.emplace_back(sf.path);
                auto* d = error("E0107", imp.path_range,
                                "unknown standard library file '" + imp.path + "'");
                add_suggestion(*d, imp.path, names);
                std::string list;
                for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
                d->notes.push_back({{}, "the standard library has: " + list});
                return;
            }
            if (loaded_.count(imp.path)) return;
            load(imp.path, std::string(f->contents), {}, imp.alias ? imp.alias->text : "std",
                 false, true);
            return;
        }
        if (from_stdlib) {
            error("E0107", imp.path_range, "the standard library can only import std/ files");
            return;
        }
        std::vector<fs::path> candidates = {base / imp.path};
        for (const auto& d : options_.import_dirs) candidates.push_back(fs::path(d) / imp.path);
        for (const auto& c : candidates) {
            std::error_code ec;
            if (!fs::is_regular_file(c, ec)) continue;
            const std::string display = c.lexically_normal().string();
            if (loaded_.count(display)) return;
            std::ifstream in(c, std::ios::binary);
            std::stringstream ss;
            ss << in.rdbuf();
            if (!in.good() && !in.eof()) break;
            load(display, ss.str(), c.parent_path(), imp.alias ? imp.alias->text : "", false, false);
            return;
        }
        auto* d = error("E0107", imp.path_range, "cannot find imported file '" + imp.path + "'");
        d->notes.push_back({{}, "looked in " + (base.empty() ? std::string(".") : base.string()) +
                                    (options_.import_dirs.empty() ? "" : " and the -I directories")});
    }

    // ---------------------------------------------------------------- symbols
    // In an imported file, a subtree reference to a tree of the same file is written without
    // the file's qualifier (`subtree give_way()` inside std/junction.sdv): qualify it, so that
    // it names the same tree however the file is imported.
    static void qualify_local_references(Unit& u) {
        if (u.qualifier.empty()) return;
        std::set<std::string> local;
        for (const auto& t : u.file->trees) local.insert(t.name.text);
        std::vector<ast::Ident> prefix;
        std::stringstream q(u.qualifier);
        for (std::string part; std::getline(q, part, '.');) prefix.push_back({part, {}});
        std::function<void(ast::Node&)> walk = [&](ast::Node& n) {
            if (n.kind == ast::NodeKind::subtree && n.callee.parts.size() == 1 && local.count(n.callee.parts[0].text)) {
                for (auto& p : prefix) p.range = n.callee.range;
                n.callee.parts.insert(n.callee.parts.begin(), prefix.begin(), prefix.end());
            }
            for (auto& c : n.children) walk(*c);
        };
        for (auto& t : u.file->trees) {
            for (auto& n : t.body) walk(*n);
        }
    }

    void collect_symbols() {
        std::map<std::string, SourceRange> road_names;
        for (auto& u : units_) {
            if (u.file == nullptr) continue;
            qualify_local_references(u);
            for (const auto& t : u.file->trees) {
                TreeSym sym;
                sym.decl = &t;
                sym.unit = &u;
                sym.qname = u.qualifier.empty() ? t.name.text : u.qualifier + "." + t.name.text;
                if (auto it = tree_index_.find(sym.qname); it != tree_index_.end()) {
                    auto* d = error("E0108", t.name.range, "duplicate tree '" + sym.qname + "'");
                    d->notes.push_back({trees_[it->second].decl->name.range,
                                        "first declared here"});
                    continue;
                }
                tree_index_[sym.qname] = trees_.size();
                trees_.push_back(std::move(sym));
            }
            auto add_road = [&](const ast::Ident& name, SourceRange range) -> bool {
                if (auto it = road_names.find(name.text); it != road_names.end()) {
                    auto* d = error("E0108", name.range, "duplicate road '" + name.text + "'");
                    d->notes.push_back({it->second, "first declared here"});
                    return false;
                }
                road_names[name.text] = name.range;
                (void)range;
                return true;
            };
            for (const auto& r : u.file->roads) {
                if (add_road(r.name, r.range)) road_decls_.push_back({&u, &r, nullptr, nullptr});
            }
            for (const auto& j : u.file->junctions) {
                if (add_road(j.name, j.range)) road_decls_.push_back({&u, nullptr, &j, nullptr});
            }
            for (const auto& m : u.file->maps) {
                if (add_road(m.name, m.range)) road_decls_.push_back({&u, nullptr, nullptr, &m});
            }
        }
    }

    std::vector<std::string> tree_names() const {
        std::vector<std::string> out;
        for (const auto& t : trees_) out.push_back(t.qname);
        return out;
    }

    TreeSym* find_tree(const ast::QualName& name) {
        auto it = tree_index_.find(name.str());
        if (it == tree_index_.end()) {
            auto* d = error("E0101", name.range, "unknown tree '" + name.str() + "'");
            add_suggestion(*d, name.str(), tree_names());
            if (name.parts.size() == 2 && name.parts[0].text == "std") {
                d->notes.push_back({{}, "standard trees need an import, e.g. import \"std/" +
                                            name.parts[1].text + ".sdv\""});
            }
            return nullptr;
        }
        return &trees_[it->second];
    }

    // ---------------------------------------------------------------- values
    // Converts a written number to SI for the expected dimension, or reports why it cannot.
    std::optional<double> to_si(const ast::Primary& p, Dim expected, const std::string& what) {
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
    Eval eval(const ast::Value& v, const Env* env, TypeInfo expect, const std::string& what,
              const ParamDef* def, int depth = 0) {
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
                if (v.lo.kind != ast::Primary::Kind::quantity) {
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
                if (expect.type == ParamType::integer &&
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

    static bool compatible(TypeInfo have, TypeInfo want) {
        if (have.type == ParamType::integer && want.type == ParamType::quantity &&
            want.dim == Dim::none) {
            return true;
        }
        if (have.type != want.type) return false;
        return have.type != ParamType::quantity || have.dim == want.dim;
    }

    void apply_spread_and_samples(const ast::Value& v, Eval& e, TypeInfo expect,
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

    void apply_samples(const ast::Value& v, Eval& e, TypeInfo expect, const std::string& what,
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
    bool check_range(const Eval& e, const ParamDef& def, const std::string& what) {
        if (e.kind != Eval::Kind::number || !e.known) return true;
        // Magnitudes: the lower bound of a sampled range is clipped at 0 (SPEC §3.6).
        ir::Sampled s = e.num;
        if (def.min >= 0 && s.lo < 0 && s.value >= 0) s.lo = 0;
        for (double x : {s.value, s.lo, s.hi}) {
            const bool below = def.min_exclusive ? !(x > def.min) : !(x >= def.min);
            if (!std::isfinite(x) || below || !(x <= def.max)) {
                std::string allowed = (def.min_exclusive ? "more than " : "") +
                                      with_unit(def.min, def.dim) + " to " +
                                      with_unit(def.max, def.dim);
                if (std::isinf(def.min)) allowed = "at most " + with_unit(def.max, def.dim);
                if (std::isinf(def.max)) {
                    allowed = (def.min_exclusive ? "more than " : "at least ") +
                              with_unit(def.min, def.dim);
                }
                auto* d = error("E0301", e.range,
                                "value " + with_unit(x, def.dim) + " is out of range for " + what);
                d->notes.push_back({{}, "allowed: " + allowed});
                return false;
            }
        }
        return true;
    }

    // ---------------------------------------------------------------- trees
    static int32_t count_nodes(const std::vector<std::unique_ptr<ast::Node>>& nodes) {
        int32_t n = 0;
        for (const auto& c : nodes) n += 1 + count_nodes(c->children);
        return n;
    }

    void collect_labels(const ast::Node& n, TreeSym& t) {
        if (n.label) {
            if (auto it = t.labels.find(n.label->text); it != t.labels.end()) {
                auto* d = error("E0108", n.label->range, "duplicate node name '" + n.label->text +
                                                             "' in tree '" + t.qname + "'");
                d->notes.push_back({it->second->label->range, "first used here"});
            } else {
                t.labels[n.label->text] = &n;
            }
        }
        for (const auto& c : n.children) collect_labels(*c, t);
    }

    void check_trees() {
        // First every tree's parameters and labels, so that subtree references in any tree can
        // be checked against them; then the bodies.
        std::vector<Env> envs(trees_.size());
        for (size_t i = 0; i < trees_.size(); ++i) declare_tree(trees_[i], envs[i]);
        check_cycles();
        for (size_t i = 0; i < trees_.size(); ++i) check_tree_body(trees_[i], envs[i]);
    }

    void declare_tree(TreeSym& t, Env& env) {
        {
            env.tree = &t;
            for (const auto& p : t.decl->params) {
                if (t.params.count(p.name.text)) {
                    auto* d = error("E0108", p.name.range, "duplicate parameter '" + p.name.text +
                                                               "' of tree '" + t.qname + "'");
                    d->notes.push_back({t.params[p.name.text]->name.range, "first declared here"});
                    continue;
                }
                t.params[p.name.text] = &p;
                auto type = find_type(p.type);
                if (!type) {
                    t.ok = false;
                    env.params[p.name.text] = Binding{nullptr, nullptr, {}, true};
                    t.used_params.insert(p.name.text);  // no follow-on warning
                    continue;
                }
                env.params[p.name.text] = Binding{nullptr, nullptr, *type};
                if (p.def) {
                    Eval e = eval(*p.def, nullptr, *type,
                                  "the default of parameter '" + p.name.text + "'", nullptr);
                    if (e.kind == Eval::Kind::invalid) t.ok = false;
                }
            }
            for (const auto& n : t.decl->body) collect_labels(*n, t);
        }
    }

    void check_tree_body(TreeSym& t, const Env& env) {
        {
            if (t.decl->body.size() != 1) {
                auto* d = error("E0405",
                                t.decl->body.empty() ? t.decl->name.range : t.decl->body[1]->range,
                                t.decl->body.empty()
                                    ? "tree '" + t.qname + "' is empty"
                                    : "tree '" + t.qname + "' has more than one root node");
                d->notes.push_back({{}, "a tree has exactly one root; wrap the nodes in a "
                                        "sequence or fallback"});
                t.ok = false;
            }
            for (const auto& n : t.decl->body) check_node(*n, env);
            if (t.decl->body.size() == 1 && !can_select(*t.decl->body[0], 0)) {
                auto* d = error("E0404", t.decl->name.range,
                                "tree '" + t.qname + "' never selects a maneuver");
                d->notes.push_back({{}, "every tree needs a maneuver leaf on some path"});
            }
        }
    }

    std::optional<TypeInfo> find_type(const ast::Ident& name) {
        for (const auto& [n, t] : param_types()) {
            if (n == name.text) return t;
        }
        std::vector<std::string> names;
        for (const auto& [n, t] : param_types()) names.push_back(n);
        auto* d = error("E0112", name.range, "unknown parameter type '" + name.text + "'");
        add_suggestion(*d, name.text, names);
        return std::nullopt;
    }

    // Whether a node can select a maneuver on some path.
    bool can_select(const ast::Node& n, int depth) {
        if (depth > kMaxExpansionDepth) return true;
        switch (n.kind) {
            case ast::NodeKind::maneuver: return true;
            case ast::NodeKind::condition: return false;
            case ast::NodeKind::subtree: {
                auto it = tree_index_.find(n.callee.str());
                if (it == tree_index_.end() || cyclic_.count(it->second)) return true;  // reported
                const auto& body = trees_[it->second].decl->body;
                return body.empty() ? false : can_select(*body[0], depth + 1);
            }
            default:
                for (const auto& c : n.children) {
                    if (can_select(*c, depth)) return true;
                }
                return false;
        }
    }

    // Whether a node always returns SUCCESS when ticked (for unreachable-child detection).
    bool always_succeeds(const ast::Node& n, int depth) {
        if (depth > kMaxExpansionDepth) return false;
        switch (n.kind) {
            case ast::NodeKind::maneuver: {
                const auto* m = catalog::find_maneuver(n.callee.str());
                return m != nullptr && (m->kind == catalog::ManeuverKind::keep_velocity ||
                                        m->kind == catalog::ManeuverKind::stop ||
                                        m->kind == catalog::ManeuverKind::reverse);
            }
            case ast::NodeKind::sequence:
            case ast::NodeKind::reactive_sequence:
                for (const auto& c : n.children) {
                    if (!always_succeeds(*c, depth)) return false;
                }
                return !n.children.empty();
            case ast::NodeKind::fallback:
                for (const auto& c : n.children) {
                    if (always_succeeds(*c, depth)) return true;
                }
                return false;
            case ast::NodeKind::subtree: {
                auto it = tree_index_.find(n.callee.str());
                if (it == tree_index_.end() || cyclic_.count(it->second)) return false;
                const auto& body = trees_[it->second].decl->body;
                return body.size() == 1 && always_succeeds(*body[0], depth + 1);
            }
            default: return false;
        }
    }

    void check_node(const ast::Node& n, const Env& env) {
        switch (n.kind) {
            case ast::NodeKind::condition:
            case ast::NodeKind::maneuver: check_leaf(n, env); break;
            case ast::NodeKind::subtree: check_subtree_ref(n.callee, n.args, env, n.range); break;
            case ast::NodeKind::parallel:
            case ast::NodeKind::fallback:
            case ast::NodeKind::sequence:
            case ast::NodeKind::reactive_sequence: {
                if (n.kind == ast::NodeKind::parallel) {
                    parallel_threshold(n, &env);
                } else {
                    for (const auto& a : n.args) {
                        error("E0104", a.name.range, std::string("'") + ast::to_string(n.kind) +
                                                         "' takes no parameters");
                    }
                }
                if (n.children.empty()) {
                    error("E0410", n.keyword_range,
                          std::string("empty ") + ast::to_string(n.kind) + ": it needs at least one child");
                }
                if (n.kind == ast::NodeKind::fallback) {
                    for (size_t i = 0; i + 1 < n.children.size(); ++i) {
                        if (always_succeeds(*n.children[i], 0)) {
                            auto* d = error("E0403", n.children[i + 1]->range,
                                            "unreachable: the fallback never gets past the "
                                            "child before this one");
                            d->notes.push_back({n.children[i]->range,
                                                "this child always succeeds"});
                            break;
                        }
                    }
                }
                for (const auto& c : n.children) check_node(*c, env);
                break;
            }
            case ast::NodeKind::not_:
            case ast::NodeKind::once:
                for (const auto& c : n.children) check_node(*c, env);
                break;
        }
    }

    // parallel(policy = all | one) or parallel(success = N); returns the success threshold.
    int32_t parallel_threshold(const ast::Node& n, const Env* env) {
        const auto count = static_cast<int32_t>(n.children.size());
        int32_t threshold = count;
        for (const auto& a : n.args) {
            const std::string key = a.name.str();
            if (key == "policy") {
                ParamDef def;
                def.type = ParamType::choice;
                def.choices = {"all", "one"};
                Eval e = eval(a.value, env, {ParamType::choice, Dim::none}, "'policy'", &def);
                if (e.kind == Eval::Kind::word && e.known) threshold = e.word == "one" ? 1 : count;
            } else if (key == "success") {
                Eval e = eval(a.value, env, {ParamType::integer, Dim::none}, "'success'", nullptr);
                if (e.kind == Eval::Kind::number && e.known) {
                    if (e.num.value < 1 || e.num.value > count) {
                        error("E0301", a.value.range,
                              "'success' must be between 1 and the number of children (" +
                                  std::to_string(count) + ")");
                    } else {
                        threshold = static_cast<int32_t>(e.num.value);
                    }
                }
            } else {
                auto* d = error("E0104", a.name.range, "unknown parameter '" + key + "' of parallel");
                add_suggestion(*d, key, {"policy", "success"});
            }
        }
        return threshold;
    }

    // The catalog parameters of a leaf, or null (reported) when the name is unknown.
    const std::vector<ParamDef>* leaf_params(const ast::Node& n, std::string& kind_word) {
        const std::string name = n.callee.str();
        if (n.kind == ast::NodeKind::maneuver) {
            kind_word = "maneuver";
            if (const auto* m = catalog::find_maneuver(name)) return &m->params;
            std::vector<std::string> names;
            for (const auto& m : catalog::maneuvers()) names.push_back(m.name);
            auto* d = error("E0102", n.callee.range, "unknown maneuver '" + name + "'");
            add_suggestion(*d, name, names);
            return nullptr;
        }
        kind_word = "condition";
        if (const auto* c = catalog::find_condition(name)) return &c->params;
        std::vector<std::string> names;
        for (const auto& c : catalog::conditions()) names.push_back(c.name);
        auto* d = error("E0103", n.callee.range, "unknown condition '" + name + "'");
        add_suggestion(*d, name, names);
        return nullptr;
    }

    static TypeInfo type_of(const ParamDef& p) { return {p.type, p.dim}; }

    // Checks a leaf's arguments: names, duplicates, values, required and grouped parameters.
    void check_leaf(const ast::Node& n, const Env& env) {
        std::string kind_word;
        const auto* params = leaf_params(n, kind_word);
        if (params == nullptr) return;
        const std::string leaf = n.callee.str();
        std::map<std::string, const ast::Arg*> given;
        for (const auto& a : n.args) {
            const std::string key = a.name.str();
            const ParamDef* def = nullptr;
            for (const auto& p : *params) {
                if (p.name == key) def = &p;
            }
            if (def == nullptr) {
                auto* d = error("E0104", a.name.range, "unknown parameter '" + key + "' of " +
                                                           kind_word + " '" + leaf + "'");
                add_suggestion(*d, key, names_of(*params));
                continue;
            }
            if (auto it = given.find(key); it != given.end()) {
                auto* d = error("E0408", a.name.range, "parameter '" + key + "' given twice");
                d->notes.push_back({it->second->name.range, "first given here"});
                continue;
            }
            given[key] = &a;
            check_arg(a.value, env, *def, "'" + key + "' of " + kind_word + " '" + leaf + "'");
        }
        for (const auto& p : *params) {
            if (p.required() && !given.count(p.name)) {
                auto* d = error("E0401", n.callee.range, "missing required parameter '" + p.name +
                                                             "' of " + kind_word + " '" + leaf + "'");
                d->notes.push_back({{}, p.name + ": " + p.doc});
            }
        }
        if (n.kind == ast::NodeKind::condition) {
            const auto* c = catalog::find_condition(leaf);
            if (!c->at_least_one_of.empty()) {
                bool any = false;
                for (const auto& g : c->at_least_one_of) any = any || given.count(g);
                if (!any) {
                    std::string list;
                    for (const auto& g : c->at_least_one_of) list += (list.empty() ? "" : ", ") + g;
                    error("E0407", n.callee.range,
                          "condition '" + leaf + "' needs at least one of: " + list);
                }
            }
            if (!c->exclusive.empty()) {
                std::vector<const ast::Arg*> both;
                for (const auto& g : c->exclusive) {
                    if (given.count(g)) both.push_back(given[g]);
                }
                if (both.size() > 1) {
                    auto* d = error("E0406", both[1]->name.range,
                                    "'" + both[0]->name.str() + "' and '" + both[1]->name.str() +
                                        "' exclude each other in condition '" + leaf + "'");
                    d->notes.push_back({both[0]->name.range, "given here"});
                }
            }
        }
    }

    Eval check_arg(const ast::Value& v, const Env& env, const ParamDef& def, const std::string& what) {
        Eval e = eval(v, &env, type_of(def), what, &def);
        if (e.kind == Eval::Kind::number && e.ranged && !def.sampleable &&
            def.type != ParamType::quantity) {
            error("E0205", v.range, what + " cannot be a range");
        } else if (e.kind == Eval::Kind::number && e.ranged && !def.sampleable &&
                   e.num.samples > 1 && v.samples) {
            auto* d = error("E0205", v.samples->range, what + " cannot be sampled");
            d->notes.push_back({{}, "only parameters marked sampleable in `sdv catalog` take "
                                    "'samples'; a range on a condition threshold is drawn once "
                                    "per run"});
        }
        check_range(e, def, what);
        return e;
    }

    // Checks a subtree reference's arguments against the target tree: parameters by name,
    // `label.field` node overrides.
    TreeSym* check_subtree_ref(const ast::QualName& name, const std::vector<ast::Arg>& args,
                               const Env& env, SourceRange) {
        TreeSym* target = find_tree(name);
        if (target == nullptr) return nullptr;
        target->used = true;
        std::set<std::string> seen;
        for (const auto& a : args) {
            const std::string key = a.name.str();
            if (!seen.insert(key).second) {
                error("E0408", a.name.range, "argument '" + key + "' given twice");
                continue;
            }
            if (a.name.parts.size() == 1) {
                auto it = target->params.find(key);
                if (it == target->params.end()) {
                    auto* d = error("E0104", a.name.range, "tree '" + target->qname +
                                                               "' has no parameter '" + key + "'");
                    std::vector<std::string> names;
                    for (const auto& [n, p] : target->params) names.push_back(n);
                    add_suggestion(*d, key, names);
                    if (target->params.empty()) {
                        d->notes.push_back({{}, "it takes no parameters; to change a node, "
                                                "write node.field = value"});
                    }
                    continue;
                }
                auto type = find_type_quiet(it->second->type.text);
                if (!type) continue;
                ParamDef def;  // no catalog def: only type-check here
                def.type = type->type;
                def.dim = type->dim;
                def.sampleable = true;
                eval(a.value, &env, *type, "argument '" + key + "' of tree '" + target->qname + "'",
                     nullptr);
                continue;
            }
            // label.field override
            const std::string label = a.name.parts[0].text;
            auto lit = target->labels.find(label);
            if (lit == target->labels.end()) {
                std::vector<std::string> labels;
                for (const auto& [l, n] : target->labels) labels.push_back(l);
                auto* d = error("E0110", a.name.parts[0].range,
                                "tree '" + target->qname + "' has no node named '" + label + "'");
                add_suggestion(*d, label, labels);
                if (labels.empty()) {
                    d->notes.push_back({{}, "name a node in the tree to override it: "
                                            "'keep: maneuver keep_velocity(...)'"});
                }
                continue;
            }
            const ast::Node& node = *lit->second;
            if (a.name.parts.size() != 2 ||
                (node.kind != ast::NodeKind::maneuver && node.kind != ast::NodeKind::condition)) {
                error("E0110", a.name.range, "only a field of a maneuver or condition node can be "
                                             "overridden ('" + label + ".field = value')");
                continue;
            }
            const std::string field = a.name.parts[1].text;
            std::string kind_word;
            const ParamDef* def = nullptr;
            if (node.kind == ast::NodeKind::maneuver) {
                if (const auto* m = catalog::find_maneuver(node.callee.str())) def = m->find_param(field);
                kind_word = "maneuver";
            } else {
                if (const auto* c = catalog::find_condition(node.callee.str())) def = c->find_param(field);
                kind_word = "condition";
            }
            if (def == nullptr) {
                auto* d = error("E0104", a.name.parts[1].range,
                                "unknown parameter '" + field + "' of " + kind_word + " '" +
                                    node.callee.str() + "'");
                if (const auto* m = catalog::find_maneuver(node.callee.str())) {
                    add_suggestion(*d, field, names_of(m->params));
                } else if (const auto* c = catalog::find_condition(node.callee.str())) {
                    add_suggestion(*d, field, names_of(c->params));
                }
                continue;
            }
            check_arg(a.value, env, *def, "'" + field + "' of node '" + label + "'");
        }
        for (const auto& [pname, p] : target->params) {
            if (!p->def && !seen.count(pname)) {
                auto* d = error("E0401", name.range, "missing argument '" + pname + "' of tree '" +
                                                         target->qname + "'");
                d->notes.push_back({p->range, "declared here without a default"});
            }
        }
        return target;
    }

    std::optional<TypeInfo> find_type_quiet(const std::string& name) const {
        for (const auto& [n, t] : param_types()) {
            if (n == name) return t;
        }
        return std::nullopt;
    }

    void check_cycles() {
        // Colour DFS over tree → subtree edges.
        std::vector<int> colour(trees_.size(), 0);
        std::vector<size_t> stack;
        std::function<void(size_t)> visit = [&](size_t i) {
            colour[i] = 1;
            stack.push_back(i);
            std::function<void(const ast::Node&)> walk = [&](const ast::Node& n) {
                if (n.kind == ast::NodeKind::subtree) {
                    auto it = tree_index_.find(n.callee.str());
                    if (it != tree_index_.end()) {
                        if (colour[it->second] == 1) {
                            std::string chain;
                            auto from = std::find(stack.begin(), stack.end(), it->second);
                            for (auto s = from; s != stack.end(); ++s) chain += trees_[*s].qname + " → ";
                            chain += trees_[it->second].qname;
                            auto* d = error("E0402", n.callee.range,
                                            "subtree cycle: " + chain);
                            d->notes.push_back({{}, "a tree cannot contain itself"});
                            cyclic_.insert(it->second);
                            cyclic_.insert(i);
                        } else if (colour[it->second] == 0) {
                            visit(it->second);
                        }
                    }
                }
                for (const auto& c : n.children) walk(*c);
            };
            for (const auto& n : trees_[i].decl->body) walk(*n);
            stack.pop_back();
            colour[i] = 2;
        };
        for (size_t i = 0; i < trees_.size(); ++i) {
            if (colour[i] == 0) visit(i);
        }
    }

    // ---------------------------------------------------------------- roads
    struct RoadDeclRef {
        Unit* unit;
        const ast::RoadDecl* road;
        const ast::JunctionDecl* junction;
        const ast::MapDecl* map;
    };

    std::optional<double> setting_number(const ast::Setting& s, size_t i, Dim dim,
                                         double lo, double hi, bool lo_exclusive) {
        if (i >= s.values.size()) return std::nullopt;
        ParamDef def;
        def.dim = dim;
        def.min = lo;
        def.max = hi;
        def.min_exclusive = lo_exclusive;
        Eval e = eval(s.values[i], nullptr, {ParamType::quantity, dim}, "'" + s.key.text + "'", &def);
        if (e.kind != Eval::Kind::number) return std::nullopt;
        if (e.ranged) {
            error("E0205", s.values[i].range, "'" + s.key.text + "' cannot be a range");
            return std::nullopt;
        }
        if (!check_range(e, def, "'" + s.key.text + "'")) return std::nullopt;
        return e.num.value;
    }

    // Reads an optional numeric setting into `out`; false when it is present but invalid.
    bool read_setting(std::map<std::string, const ast::Setting*>& set, const char* key, Dim dim, double lo,
                      double hi, bool lo_exclusive, double& out) {
        const ast::Setting* s = set[key];
        if (s == nullptr) return true;
        if (auto v = setting_number(*s, 0, dim, lo, hi, lo_exclusive)) {
            out = *v;
            return true;
        }
        return false;
    }

    // Reports duplicate settings and returns the first occurrence of each key.
    std::map<std::string, const ast::Setting*> settings_map(const std::vector<ast::Setting>& ss,
                                                           const std::vector<std::string>& known,
                                                           const std::string& where) {
        std::map<std::string, const ast::Setting*> out;
        for (const auto& s : ss) {
            if (!known.empty() && std::find(known.begin(), known.end(), s.key.text) == known.end()) {
                auto* d = error("E0113", s.key.range, "unknown setting '" + s.key.text + "' in " + where);
                add_suggestion(*d, s.key.text, known);
                continue;
            }
            if (auto it = out.find(s.key.text); it != out.end()) {
                auto* d = error("E0504", s.key.range, "duplicate '" + s.key.text + "' in " + where);
                d->notes.push_back({it->second->range, "first given here"});
                continue;
            }
            out[s.key.text] = &s;
        }
        return out;
    }

    void check_roads() {
        for (const auto& r : road_decls_) {
            RoadSym sym;
            sym.unit = r.unit;
            if (r.road != nullptr) {
                sym.name = r.road->name.text;
                sym.range = r.road->name.range;
                check_builtin_road(*r.road, sym);
            } else if (r.junction != nullptr) {
                sym.name = r.junction->name.text;
                sym.range = r.junction->name.range;
                check_junction(*r.junction, sym);
            } else {
                sym.name = r.map->name.text;
                sym.range = r.map->name.range;
                check_map(*r.map, sym);
            }
            sym.road.name = sym.name;
            sym.road.loc = loc(sym.range);
            roads_.push_back(std::move(sym));
        }
    }

    void check_builtin_road(const ast::RoadDecl& r, RoadSym& sym) {
        ir::Road& road = sym.road;
        road.kind = ir::RoadKind::road;
        const std::string where = "road '" + r.name.text + "'";
        if (r.lanes.empty()) {
            auto* d = error("E0401", r.name.range, where + " does not say its lanes");
            d->notes.push_back({{}, "add e.g. 'lanes 2 forward, 1 backward'"});
            sym.ok = false;
        }
        road.lanes_forward = 0;
        road.lanes_backward = 0;
        std::set<std::string> dirs;
        for (const auto& l : r.lanes) {
            if (l.direction.text != "forward" && l.direction.text != "backward") {
                auto* d = error("E0206", l.direction.range,
                                "lane direction must be 'forward' or 'backward'");
                add_suggestion(*d, l.direction.text, {"forward", "backward"});
                sym.ok = false;
                continue;
            }
            if (!dirs.insert(l.direction.text).second) {
                error("E0504", l.direction.range, "'" + l.direction.text + "' lanes given twice");
                sym.ok = false;
                continue;
            }
            if (l.count < 0 || l.count > 8) {
                auto* d = error("E0301", l.count_range, "lane count " + std::to_string(l.count) +
                                                            " is out of range");
                d->notes.push_back({{}, "allowed: 0 to 8 lanes per direction"});
                sym.ok = false;
                continue;
            }
            (l.direction.text == "forward" ? road.lanes_forward : road.lanes_backward) =
                static_cast<int32_t>(l.count);
        }
        if (!r.lanes.empty() && road.lanes_forward + road.lanes_backward == 0 && sym.ok) {
            error("E0301", r.lanes_range, where + " has no lanes");
            sym.ok = false;
        }
        auto set = settings_map(r.settings, {"lane_width", "speed_limit", "origin", "heading"}, where);
        sym.ok = read_setting(set, "lane_width", Dim::length, 1.0, 10.0, false, road.lane_width) && sym.ok;
        sym.ok = read_setting(set, "speed_limit", Dim::speed, 0.0, 100.0, true, road.speed_limit) && sym.ok;
        if (auto* s = set["origin"]) {
            auto x = setting_number(*s, 0, Dim::length, -1e7, 1e7, false);
            auto y = setting_number(*s, 1, Dim::length, -1e7, 1e7, false);
            if (x && y) {
                road.origin_x = *x;
                road.origin_y = *y;
            } else {
                sym.ok = false;
            }
        }
        sym.ok = read_setting(set, "heading", Dim::angle, -10.0, 10.0, false, road.heading) && sym.ok;
        if (r.segments.empty()) {
            auto* d = error("E0401", r.name.range, where + " has no segments");
            d->notes.push_back({{}, "add e.g. 'straight 300 m'"});
            sym.ok = false;
        }
        // The reference line runs between the directions: a left arc has the backward lanes on
        // its inside, a right arc the forward lanes; the radius must exceed what lies inside.
        const double inside_left = road.lane_width * road.lanes_backward + 0.5;
        const double inside_right = road.lane_width * road.lanes_forward + 0.5;
        for (const auto& seg : r.segments) {
            ParamDef def;
            def.dim = Dim::length;
            def.min = 0;
            def.min_exclusive = true;
            def.max = 100000;
            Eval len = eval(seg.length, nullptr, {ParamType::quantity, Dim::length},
                            "the segment length", &def);
            if (len.kind != Eval::Kind::number || !check_range(len, def, "the segment length")) {
                sym.ok = false;
                continue;
            }
            ir::Segment out;
            out.arc = seg.arc;
            out.length = len.num.value;
            if (seg.arc) {
                ParamDef rdef = def;
                const bool right = seg.side && seg.side->text == "right";
                rdef.min = right ? inside_right : inside_left;
                rdef.min_exclusive = false;
                rdef.max = 1e6;
                Eval rad = eval(*seg.radius, nullptr, {ParamType::quantity, Dim::length},
                                "the arc radius", &rdef);
                if (rad.kind != Eval::Kind::number) {
                    sym.ok = false;
                    continue;
                }
                if (!check_range(rad, rdef, "the arc radius (it must exceed the width of the lanes on the inside of the turn)")) {
                    sym.ok = false;
                    continue;
                }
                out.radius = (seg.side && seg.side->text == "right") ? -rad.num.value : rad.num.value;
            }
            sym.length += out.length;
            road.segments.push_back(out);
        }
    }

    void check_junction(const ast::JunctionDecl& j, RoadSym& sym) {
        ir::Road& road = sym.road;
        road.kind = ir::RoadKind::junction;
        road.control = "stop_signs";
        const std::string where = "junction '" + j.name.text + "'";
        auto set = settings_map(j.settings, {"lanes", "lane_width", "speed_limit", "arm_length", "control"},
                                where);
        if (auto* s = set["lanes"]) {
            if (auto v = setting_number(*s, 0, Dim::none, 1, 4, false)) {
                road.lanes_forward = static_cast<int32_t>(*v);
            } else {
                sym.ok = false;
            }
        }
        sym.ok = read_setting(set, "lane_width", Dim::length, 1.0, 10.0, false, road.lane_width) && sym.ok;
        sym.ok = read_setting(set, "speed_limit", Dim::speed, 0.0, 100.0, true, road.speed_limit) && sym.ok;
        sym.ok = read_setting(set, "arm_length", Dim::length, 20.0, 10000.0, false, road.arm_length) && sym.ok;
        if (auto* s = set["control"]) {
            const std::string c = s->values[0].lo.name.str();
            const std::vector<std::string> choices = {"stop_signs", "two_way_stops", "traffic_lights", "none"};
            if (std::find(choices.begin(), choices.end(), c) == choices.end()) {
                auto* d = error("E0206", s->values[0].range, "unknown junction control '" + c + "'");
                add_suggestion(*d, c, choices);
                d->notes.push_back({{}, "expected stop_signs, two_way_stops, traffic_lights or none"});
                sym.ok = false;
            } else {
                road.control = c;
            }
        }
        sym.length = road.arm_length;
    }

    void check_map(const ast::MapDecl& m, RoadSym& sym) {
        ir::Road& road = sym.road;
        road.kind = ir::RoadKind::lanelet2;
        const std::string where = "map '" + m.name.text + "'";
        auto set = settings_map(m.settings, {"file", "origin"}, where);
        if (auto* s = set["file"]) {
            fs::path p = s->values[0].lo.string;
            if (p.is_relative() && !sym.unit->dir.empty()) p = sym.unit->dir / p;
            std::error_code ec;
            if (!fs::is_regular_file(p, ec)) {
                error("E0510", s->values[0].range, "map file '" + s->values[0].lo.string +
                                                       "' not found (looked at " + p.string() + ")");
                sym.ok = false;
            }
            road.map_file = p.lexically_normal().string();
        } else {
            error("E0401", m.name.range, where + " needs a 'file \"path.osm\"'");
            sym.ok = false;
        }
        if (auto* s = set["origin"]) {
            if (s->values.size() < 2) {
                error("E0401", s->range, "origin needs latitude and longitude");
                sym.ok = false;
            } else {
                auto lat = setting_number(*s, 0, Dim::none, -90, 90, false);
                auto lon = setting_number(*s, 1, Dim::none, -180, 180, false);
                auto alt = s->values.size() > 2 ? setting_number(*s, 2, Dim::length, -1000, 10000, false)
                                                : std::optional<double>(0.0);
                if (lat && lon && alt) {
                    road.origin_lat = *lat;
                    road.origin_lon = *lon;
                    road.origin_alt = *alt;
                    road.has_origin = true;
                } else {
                    sym.ok = false;
                }
            }
        }
    }

    // ---------------------------------------------------------------- scenarios
    struct ScenarioCtx {
        ir::Scenario* ir = nullptr;
        const RoadSym* road = nullptr;
        std::map<std::string, int32_t> vehicle_index;
        std::vector<std::string> vehicle_names;
        int32_t ego = -1;
        std::string name;
    };

    void check_scenario(const ast::ScenarioDecl& s, ir::Program& program) {
        ir::Scenario sc;
        sc.name = s.name.text;
        sc.loc = loc(s.name.range);
        ScenarioCtx ctx;
        ctx.name = s.name.text;
        const std::string where = "scenario '" + s.name.text + "'";
        for (const auto& other : program.scenarios) {
            if (other.name == sc.name) error("E0108", s.name.range, "duplicate scenario '" + sc.name + "'");
        }
        auto set = settings_map(s.settings,
                                {"road", "timeout", "seed", "rate traffic", "rate planning",
                                 "rate latency", "rate sensor_range"},
                                where);
        // `rate X` keys carry the word after `rate`; unknown ones are reported by settings_map
        // as "rate foo", so point at the word with a clearer message there.
        if (auto* r = set["road"]) {
            const std::string name = r->values[0].lo.name.str();
            const RoadSym* found = nullptr;
            for (const auto& rs : roads_) {
                if (rs.name == name) found = &rs;
            }
            if (found == nullptr) {
                std::vector<std::string> names;
                for (const auto& rs : roads_) names.push_back(rs.name);
                auto* d = error("E0109", r->values[0].range, "unknown road '" + name + "'");
                add_suggestion(*d, name, names);
            } else {
                ctx.road = found;
            }
        } else {
            auto* d = error("E0501", s.name.range, where + " has no road");
            d->notes.push_back({{}, "add 'road NAME' naming a road, junction or map"});
        }
        read_setting(set, "timeout", Dim::time, 0, 86400, true, sc.timeout);
        if (auto* t = set["seed"]) {
            // Parsed from the text: a double would round seeds above 2^53.
            const std::string& text = t->values[0].lo.quantity.text;
            errno = 0;
            sc.seed = std::strtoull(text.c_str(), nullptr, 10);
            if (errno == ERANGE) {
                error("E0301", t->values[0].range, "seed " + text + " is out of range")
                    ->notes.push_back({{}, "allowed: 0 to 18446744073709551615"});
            }
        }
        read_setting(set, "rate traffic", Dim::frequency, 1, 1000, false, sc.traffic_rate);
        read_setting(set, "rate planning", Dim::frequency, 0.1, 100, false, sc.planning_rate);
        read_setting(set, "rate latency", Dim::time, 0, 10, false, sc.planning_latency);
        read_setting(set, "rate sensor_range", Dim::length, 1, 10000, true, sc.sensor_range);
        if (ctx.road != nullptr && ctx.road->ok) {
            auto it = std::find_if(program.roads.begin(), program.roads.end(),
                                   [&](const ir::Road& r) { return r.name == ctx.road->name; });
            if (it == program.roads.end()) {
                sc.road = static_cast<int32_t>(program.roads.size());
                program.roads.push_back(ctx.road->road);
            } else {
                sc.road = static_cast<int32_t>(it - program.roads.begin());
            }
        }
        // Vehicle names first: trees and expectations refer to any of them.
        for (const auto& v : s.vehicles) {
            if (auto it = ctx.vehicle_index.find(v.name.text); it != ctx.vehicle_index.end()) {
                auto* d = error("E0108", v.name.range, "duplicate vehicle '" + v.name.text + "'");
                d->notes.push_back({s.vehicles[static_cast<size_t>(it->second)].name.range,
                                    "first declared here"});
            }
            ctx.vehicle_index.emplace(v.name.text, static_cast<int32_t>(ctx.vehicle_names.size()));
            ctx.vehicle_names.push_back(v.name.text);
            if (v.is_ego) {
                if (ctx.ego >= 0) {
                    auto* d = error("E0507", v.name.range, where + " has more than one ego");
                    d->notes.push_back({s.vehicles[static_cast<size_t>(ctx.ego)].name.range,
                                        "the ego is declared here"});
                } else {
                    ctx.ego = static_cast<int32_t>(ctx.vehicle_names.size() - 1);
                }
            }
        }
        ctx.ir = &sc;
        for (const auto& v : s.vehicles) sc.vehicles.push_back(check_vehicle(v, ctx, program));
        check_overlaps(s, sc);
        for (const auto& l : s.lights) check_light(l, ctx);
        for (const auto& e : s.expects) sc.expect_roots.push_back(check_expr(*e, ctx));
        program.scenarios.push_back(std::move(sc));
    }

    ir::Position check_position(const ast::Position& p, const ScenarioCtx& ctx, const std::string& what) {
        ir::Position out;
        out.loc = loc(p.range);
        auto num = [&](const ast::Value& v, Dim dim, const std::string& w, double lo, double hi) -> double {
            ParamDef def;
            def.dim = dim;
            def.min = lo;
            def.max = hi;
            Eval e = eval(v, nullptr, {ParamType::quantity, dim}, w, &def);
            if (e.kind == Eval::Kind::number) {
                if (e.ranged) error("E0205", v.range, w + " cannot be a range");
                check_range(e, def, w);
                return e.num.value;
            }
            return 0.0;
        };
        if (p.xy) {
            out.xy = true;
            out.x = num(*p.x, Dim::length, "x", -1e7, 1e7);
            out.y = num(*p.y, Dim::length, "y", -1e7, 1e7);
            if (p.heading) {
                out.heading = num(*p.heading, Dim::angle, "the heading", -10, 10);
                out.has_heading = true;
            }
            return out;
        }
        out.s = num(*p.s, Dim::length, "the position along the lane", -1e6, 1e6);
        if (p.offset) out.offset = num(*p.offset, Dim::length, "the lateral offset", -20, 20);
        out.lane = resolve_lane(p.lane, ctx, what);
        if (ctx.road != nullptr && ctx.road->ok && ctx.road->road.kind == ir::RoadKind::road &&
            !out.lane.empty()) {
            if (out.s < 0 || out.s > ctx.road->length) {
                auto* d = error("E0503", p.s->range,
                                what + " is off the road: s = " + fmt(out.s) + " m");
                d->notes.push_back({ctx.road->range, "road '" + ctx.road->name + "' is " +
                                                         fmt(ctx.road->length) + " m long"});
            }
            if (std::fabs(out.offset) > ctx.road->road.lane_width * 0.5 + 1e-9 && p.offset) {
                error("E0503", p.offset->range, what + " is outside its lane: the offset exceeds "
                                                       "half the lane width");
            }
        }
        return out;
    }

    // Lane references: built-in roads use indices (1.. forward, -1.. backward) and are named
    // "<road>.<index>"; junction and map lanes are named and checked when the road loads.
    std::string resolve_lane(const ast::LaneRef& l, const ScenarioCtx& ctx, const std::string& what) {
        if (ctx.road == nullptr) return "";
        const ir::Road& r = ctx.road->road;
        if (r.kind == ir::RoadKind::road) {
            if (l.kind != ast::LaneRef::Kind::index) {
                auto* d = error("E0106", l.range, "unknown lane '" + l.str() + "' for " + what);
                d->notes.push_back({{}, "lanes of a built-in road are numbered: 1 is the "
                                        "right-most forward lane, -1 the first backward lane"});
                return "";
            }
            const bool ok = (l.index >= 1 && l.index <= r.lanes_forward) ||
                            (l.index <= -1 && -l.index <= r.lanes_backward);
            if (!ok) {
                auto* d = error("E0303", l.range, "lane " + std::to_string(l.index) +
                                                      " does not exist on road '" + r.name + "'");
                std::string lanes = r.lanes_forward > 0 ? "1.." + std::to_string(r.lanes_forward) : "";
                if (r.lanes_backward > 0) {
                    lanes += (lanes.empty() ? "" : " and ") + std::string("-1..-") +
                             std::to_string(r.lanes_backward);
                }
                d->notes.push_back({ctx.road->range, "its lanes are " + lanes});
                return "";
            }
            return r.name + "." + std::to_string(l.index);
        }
        if (r.kind == ir::RoadKind::junction) {
            if (l.kind == ast::LaneRef::Kind::index) {
                auto* d = error("E0106", l.range, "junction lanes are named, not numbered");
                d->notes.push_back({{}, "e.g. 'lane south.in' or 'lane south_to_west'"});
                return "";
            }
            return r.name + "." + (l.kind == ast::LaneRef::Kind::name ? l.name.str() : l.string);
        }
        return l.kind == ast::LaneRef::Kind::string ? l.string
               : l.kind == ast::LaneRef::Kind::name ? l.name.str()
                                                    : std::to_string(l.index);
    }

    ir::Vehicle check_vehicle(const ast::VehicleDecl& v, ScenarioCtx& ctx, ir::Program& program) {
        ir::Vehicle out;
        out.name = v.name.text;
        out.is_ego = v.is_ego;
        out.loc = loc(v.name.range);
        const std::string what = "vehicle '" + v.name.text + "'";
        const std::vector<std::string> kinds =
            v.is_ego ? std::vector<std::string>{"sdv", "trajectory", "external"}
                     : std::vector<std::string>{"sdv", "trajectory", "static"};
        const std::string kind = v.kind.text;
        if (kind == "sdv") out.kind = ir::VehicleKind::sdv;
        else if (kind == "trajectory") out.kind = ir::VehicleKind::trajectory;
        else if (kind == "static") out.kind = ir::VehicleKind::static_object;
        else if (kind == "external") out.kind = ir::VehicleKind::external;
        if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end()) {
            auto* d = error("E0113", v.kind.range, "unknown vehicle kind '" + kind + "'");
            add_suggestion(*d, kind, kinds);
            std::string list;
            for (const auto& k : kinds) list += (list.empty() ? "" : ", ") + k;
            d->notes.push_back({{}, std::string(v.is_ego ? "the ego" : "a vehicle") + " is one of: " + list});
        }
        if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end()) return out;
        if (out.kind == ir::VehicleKind::external) {
            auto* d = error("E0113", v.kind.range, "external egos (co-simulation) are not supported yet");
            d->notes.push_back({{}, "use 'sdv' (a placeholder driven by a tree) or 'trajectory'"});
        }
        auto set = settings_map(v.settings, {"speed", "length", "width"}, what);
        ParamDef def;
        auto num = [&](const ast::Setting* s, Dim dim, double lo, double hi, bool excl, double fallback) {
            if (s == nullptr) return fallback;
            auto r = setting_number(*s, 0, dim, lo, hi, excl);
            return r.value_or(fallback);
        };
        out.speed = num(set["speed"], Dim::speed, 0, 100, false, 0.0);
        out.length = num(set["length"], Dim::length, 0, 30, true, 4.5);
        out.width = num(set["width"], Dim::length, 0, 5, true, 1.8);
        if (v.is_object) {
            out.length = num(set["length"], Dim::length, 0, 100, true, 4.5);
        }
        for (size_t i = 1; i < v.starts.size(); ++i) {
            error("E0504", v.starts[i].range, "duplicate 'start' of " + what);
        }
        for (size_t i = 1; i < v.goals.size(); ++i) {
            error("E0504", v.goals[i].range, "duplicate 'goal' of " + what);
        }
        for (size_t i = 1; i < v.routes.size(); ++i) {
            error("E0504", v.routes[i].front().range, "duplicate 'route' of " + what);
        }
        for (size_t i = 1; i < v.trees.size(); ++i) {
            error("E0504", v.trees[i].range, "duplicate 'tree' of " + what);
        }
        if (!v.starts.empty()) {
            out.start = check_position(v.starts[0], ctx, "the start of " + what);
        } else if (out.kind != ir::VehicleKind::trajectory) {
            auto* d = error("E0506", v.name.range, what + " has no start position");
            d->notes.push_back({{}, "add e.g. 'start lane 1 at 20 m'"});
        }
        if (!v.goals.empty()) out.goal = check_position(v.goals[0], ctx, "the goal of " + what);
        out.goal_ends_run = v.goal_ends_run && !v.goals.empty();
        if (!v.routes.empty()) {
            for (const auto& l : v.routes[0]) out.route.push_back(resolve_lane(l, ctx, "the route of " + what));
        }
        if (out.kind == ir::VehicleKind::sdv) {
            if (v.trees.empty()) {
                auto* d = error("E0505", v.name.range, what + " is an sdv but has no tree");
                d->notes.push_back({{}, "add e.g. 'tree std.drive()' (import \"std/drive.sdv\")"});
            } else {
                out.tree = expand_vehicle_tree(v.trees[0], ctx, program);
            }
        } else if (!v.trees.empty()) {
            error("E0113", v.trees[0].range, "only sdv vehicles have trees; " + what + " is " + kind);
        }
        if (out.kind == ir::VehicleKind::trajectory) {
            if (v.trajectories.empty() || v.trajectories[0].size() < 2) {
                auto* d = error("E0506", v.name.range, what + " needs a trajectory with at least two waypoints");
                d->notes.push_back({{}, "trajectory { 0 s: lane 1 at 10 m  5 s: lane 1 at 80 m }"});
            } else {
                double last = -1;
                for (const auto& w : v.trajectories[0]) {
                    ir::Waypoint wp;
                    ParamDef tdef;
                    tdef.dim = Dim::time;
                    tdef.min = 0;
                    tdef.max = 86400;
                    Eval t = eval(w.time, nullptr, {ParamType::quantity, Dim::time}, "the waypoint time", &tdef);
                    if (t.kind == Eval::Kind::number) {
                        check_range(t, tdef, "the waypoint time");
                        wp.time = t.num.value;
                        if (wp.time <= last) {
                            error("E0301", w.time.range, "waypoint times must increase");
                        }
                        last = wp.time;
                    }
                    wp.position = check_position(w.position, ctx, "a waypoint of " + what);
                    if (w.speed) {
                        ParamDef sdef;
                        sdef.dim = Dim::speed;
                        sdef.min = 0;
                        sdef.max = 100;
                        Eval sp = eval(*w.speed, nullptr, {ParamType::quantity, Dim::speed}, "the waypoint speed", &sdef);
                        if (sp.kind == Eval::Kind::number && check_range(sp, sdef, "the waypoint speed")) {
                            wp.speed = sp.num.value;
                        }
                    }
                    out.trajectory.push_back(wp);
                }
                if (v.starts.empty()) out.start = out.trajectory.front().position;
            }
        } else if (!v.trajectories.empty()) {
            error("E0113", v.name.range, "only trajectory vehicles have a trajectory");
        }
        return out;
    }

    void check_overlaps(const ast::ScenarioDecl& s, const ir::Scenario& sc) {
        for (size_t i = 0; i < sc.vehicles.size(); ++i) {
            for (size_t j = i + 1; j < sc.vehicles.size(); ++j) {
                const auto& a = sc.vehicles[i];
                const auto& b = sc.vehicles[j];
                if (a.start.xy || b.start.xy || a.start.lane.empty() || a.start.lane != b.start.lane) {
                    continue;
                }
                const double gap = std::fabs(a.start.s - b.start.s) - 0.5 * (a.length + b.length);
                const double lat = std::fabs(a.start.offset - b.start.offset) - 0.5 * (a.width + b.width);
                if (gap < 0 && lat < 0) {
                    auto* d = error("E0502", s.vehicles[j].starts.empty() ? s.vehicles[j].name.range
                                                                          : s.vehicles[j].starts[0].range,
                                    "vehicles '" + b.name + "' and '" + a.name + "' start overlapped");
                    d->notes.push_back({s.vehicles[i].starts.empty() ? s.vehicles[i].name.range
                                                                     : s.vehicles[i].starts[0].range,
                                        "'" + a.name + "' starts here"});
                }
            }
        }
    }

    void check_light(const ast::LightDecl& l, ScenarioCtx& ctx) {
        ir::LightProgram out;
        out.name = l.name.str();
        out.loc = loc(l.range);
        if (ctx.road != nullptr && ctx.road->road.kind == ir::RoadKind::road) {
            error("E0106", l.name.range, "road '" + ctx.road->name + "' has no traffic lights");
        } else if (ctx.road != nullptr && ctx.road->road.kind == ir::RoadKind::junction) {
            const std::vector<std::string> names = {ctx.road->name + ".ns", ctx.road->name + ".ew"};
            if (ctx.road->road.control != "traffic_lights") {
                error("E0106", l.name.range, "junction '" + ctx.road->name + "' has no traffic lights (control " +
                                                  ctx.road->road.control + ")");
            } else if (std::find(names.begin(), names.end(), out.name) == names.end()) {
                auto* d = error("E0106", l.name.range, "unknown traffic light '" + out.name + "'");
                add_suggestion(*d, out.name, names);
                d->notes.push_back({{}, "the junction's lights are " + names[0] + " and " + names[1]});
            }
        }
        for (const auto& ph : l.phases) {
            const std::string st = ph.key.text;
            if (st != "red" && st != "yellow" && st != "green") {
                auto* d = error("E0206", ph.key.range, "unknown light state '" + st + "'");
                add_suggestion(*d, st, {"red", "yellow", "green"});
                continue;
            }
            if (auto v = setting_number(ph, 0, Dim::time, 0, 86400, true)) out.phases.push_back({st, *v});
        }
        if (l.phases.empty()) error("E0401", l.name.range, "light program without phases");
        if (l.offset) {
            ParamDef def;
            def.dim = Dim::time;
            def.min = 0;
            def.max = 86400;
            Eval e = eval(*l.offset, nullptr, {ParamType::quantity, Dim::time}, "the offset", &def);
            if (e.kind == Eval::Kind::number && check_range(e, def, "the offset")) out.offset = e.num.value;
        }
        ctx.ir->lights.push_back(std::move(out));
    }

    int32_t check_expr(const ast::Expr& e, ScenarioCtx& ctx) {
        ir::Expect out;
        out.loc = loc(e.range);
        out.text = std::string(sm_.contents(e.range.begin.file)
                                   .substr(e.range.begin.offset, e.range.end.offset - e.range.begin.offset));
        switch (e.kind) {
            case ast::Expr::Kind::not_: out.kind = ir::Expect::Kind::not_; break;
            case ast::Expr::Kind::and_: out.kind = ir::Expect::Kind::and_; break;
            case ast::Expr::Kind::or_: out.kind = ir::Expect::Kind::or_; break;
            case ast::Expr::Kind::call: out.kind = ir::Expect::Kind::call; break;
        }
        if (e.lhs) out.lhs = check_expr(*e.lhs, ctx);
        if (e.rhs) out.rhs = check_expr(*e.rhs, ctx);
        if (e.kind == ast::Expr::Kind::call) {
            const auto* f = catalog::find_expectation(e.function.text);
            if (f == nullptr) {
                std::vector<std::string> names;
                for (const auto& x : catalog::expectations()) names.push_back(x.name);
                auto* d = error("E0111", e.function.range, "unknown expectation '" + e.function.text + "'");
                add_suggestion(*d, e.function.text, names);
            } else {
                out.function = static_cast<int32_t>(f->kind);
                const int n = static_cast<int>(e.args.size());
                if (n < f->min_vehicles || n > f->max_vehicles) {
                    error("E0508", e.function.range,
                          "'" + f->name + "' takes " +
                              (f->min_vehicles == f->max_vehicles
                                   ? std::to_string(f->min_vehicles)
                                   : std::to_string(f->min_vehicles) + " to " + std::to_string(f->max_vehicles)) +
                              " vehicle(s), found " + std::to_string(n));
                }
                for (const auto& a : e.args) {
                    auto it = ctx.vehicle_index.find(a.text);
                    if (it == ctx.vehicle_index.end()) {
                        auto* d = error("E0105", a.range, "unknown vehicle '" + a.text + "' in scenario '" +
                                                              ctx.name + "'");
                        add_suggestion(*d, a.text, ctx.vehicle_names);
                    } else {
                        out.vehicles.push_back(it->second);
                    }
                }
                if (f->boolean && !e.cmp.empty()) {
                    error("E0204", e.bound->range, "'" + f->name + "' is true or false; it takes no comparison");
                } else if (!f->boolean && e.cmp.empty()) {
                    auto* d = error("E0204", e.function.range,
                                    "'" + f->name + "' is " + dim_phrase(f->result) + "; compare it");
                    d->notes.push_back({{}, "e.g. " + f->name + "(...) < " +
                                            (f->result == Dim::time ? "2 s" : f->result == Dim::length ? "1 m" : "5")});
                } else if (!f->boolean) {
                    out.cmp = e.cmp;
                    Eval b = eval(*e.bound, nullptr, {ParamType::quantity, f->result}, "the bound of '" + f->name + "'", nullptr);
                    if (b.kind == Eval::Kind::number) {
                        if (b.ranged) error("E0205", e.bound->range, "the bound cannot be a range");
                        out.bound = b.num.value;
                    }
                }
            }
        }
        ctx.ir->expects.push_back(std::move(out));
        return static_cast<int32_t>(ctx.ir->expects.size() - 1);
    }

    // ---------------------------------------------------------------- expansion
    int32_t expand_vehicle_tree(const ast::TreeRef& ref, ScenarioCtx& ctx, ir::Program& program) {
        Env caller;  // scenario level: no parameters
        TreeSym* t = check_subtree_ref(ref.name, ref.args, caller, ref.range);
        if (t == nullptr || !t->ok || cyclic_.count(tree_index_[t->qname])) return -1;
        ir::TreeInstance inst;
        const size_t errors_before = diags_.error_count();
        Env env = bind(*t, ref.args, &caller, caller);
        if (t->decl->body.size() == 1) expand_node(*t->decl->body[0], env, ctx, inst, t->qname);
        if (diags_.error_count() != errors_before || inst.nodes.empty()) return -1;
        check_candidate_counts(inst, ref);
        program.instances.push_back(std::move(inst));
        return static_cast<int32_t>(program.instances.size() - 1);
    }

    // The environment of a tree instance: its parameters bound to the caller's arguments or
    // to their defaults, and the caller's node overrides.
    Env bind(const TreeSym& t, const std::vector<ast::Arg>& args, const Env* caller_env,
             const Env& caller) {
        Env env;
        env.tree = &t;
        env.stack = caller.stack;
        env.stack.push_back(t.qname);
        for (const auto& p : t.decl->params) {
            auto type = find_type_quiet(p.type.text);
            if (!type) continue;
            env.params[p.name.text] = Binding{p.def ? &*p.def : nullptr, nullptr, *type};
        }
        for (const auto& a : args) {
            if (a.name.parts.size() == 1) {
                auto it = env.params.find(a.name.str());
                if (it != env.params.end()) {
                    it->second.value = &a.value;
                    it->second.env = caller_env;
                }
            } else if (a.name.parts.size() == 2) {
                env.overrides[a.name.parts[0].text].push_back({&a, caller_env});
            }
        }
        return env;
    }

    int32_t expand_node(const ast::Node& n, const Env& env, ScenarioCtx& ctx, ir::TreeInstance& inst,
                        const std::string& path) {
        if (env.stack.size() > kMaxExpansionDepth) return -1;
        if (n.kind == ast::NodeKind::subtree) {
            TreeSym* t = nullptr;
            auto it = tree_index_.find(n.callee.str());
            if (it == tree_index_.end() || cyclic_.count(it->second)) return -1;
            t = &trees_[it->second];
            if (!t->ok || t->decl->body.size() != 1) return -1;
            Env sub = bind(*t, n.args, &env, env);
            return expand_node(*t->decl->body[0], sub, ctx, inst, path + "/" + t->qname);
        }
        const auto index = static_cast<int32_t>(inst.nodes.size());
        inst.nodes.emplace_back();
        ir::Node out;
        out.loc = loc(n.keyword_range);
        out.tree = env.tree != nullptr ? env.tree->ir_index : -1;
        const std::string label = n.label ? n.label->text : "";
        switch (n.kind) {
            case ast::NodeKind::fallback: out.kind = ir::NodeKind::fallback; break;
            case ast::NodeKind::sequence: out.kind = ir::NodeKind::sequence; break;
            case ast::NodeKind::reactive_sequence: out.kind = ir::NodeKind::reactive_sequence; break;
            case ast::NodeKind::parallel: out.kind = ir::NodeKind::parallel; break;
            case ast::NodeKind::condition: out.kind = ir::NodeKind::condition; break;
            case ast::NodeKind::maneuver: out.kind = ir::NodeKind::maneuver; break;
            case ast::NodeKind::not_: out.kind = ir::NodeKind::not_; break;
            case ast::NodeKind::once: out.kind = ir::NodeKind::once; break;
            case ast::NodeKind::subtree: break;
        }
        out.name = !label.empty() ? label : n.callee.parts.empty() ? ast::to_string(n.kind) : n.callee.str();
        out.path = path + "/" + out.name;
        if (n.kind == ast::NodeKind::parallel) out.success_threshold = parallel_threshold(n, &env);
        if (n.kind == ast::NodeKind::condition || n.kind == ast::NodeKind::maneuver) {
            resolve_leaf(n, env, ctx, out, label);
        }
        std::map<std::string, int> seen;
        for (const auto& c : n.children) {
            const std::string cname = c->label ? c->label->text : c->callee.parts.empty() ? ast::to_string(c->kind) : c->callee.str();
            const int k = seen[cname]++;
            const int32_t child = expand_node(*c, env, ctx, inst, out.path + (k ? "#" + std::to_string(k) : ""));
            if (child >= 0) out.children.push_back(child);
        }
        inst.nodes[static_cast<size_t>(index)] = std::move(out);
        return index;
    }

    void resolve_leaf(const ast::Node& n, const Env& env, ScenarioCtx& ctx, ir::Node& out,
                      const std::string& label) {
        const std::vector<ParamDef>* params = nullptr;
        std::string kind_word;
        if (n.kind == ast::NodeKind::maneuver) {
            const auto* m = catalog::find_maneuver(n.callee.str());
            if (m == nullptr) return;
            params = &m->params;
            out.leaf = static_cast<int32_t>(m->kind);
            kind_word = "maneuver";
        } else {
            const auto* c = catalog::find_condition(n.callee.str());
            if (c == nullptr) return;
            params = &c->params;
            out.leaf = static_cast<int32_t>(c->kind);
            kind_word = "condition";
        }
        // Overrides from the referencing subtree call win over the node's own arguments.
        std::map<std::string, std::pair<const ast::Value*, const Env*>> given;
        for (const auto& a : n.args) given[a.name.str()] = {&a.value, &env};
        if (!label.empty()) {
            if (auto it = env.overrides.find(label); it != env.overrides.end()) {
                for (const auto& [arg, aenv] : it->second) given[arg->name.parts[1].text] = {&arg->value, aenv};
            }
        }
        for (const auto& p : *params) {
            ir::ParamValue pv;
            auto it = given.find(p.name);
            const std::string what = "'" + p.name + "' of " + kind_word + " '" + n.callee.str() + "'";
            if (it == given.end()) {
                if (!p.def) {
                    pv.given = false;
                } else {
                    pv.number.value = pv.number.lo = pv.number.hi = p.def->value;
                    if (p.def->spread_pct > 0) {
                        const double d = std::fabs(p.def->value) * p.def->spread_pct / 100.0;
                        pv.number.lo = p.def->value - d;
                        pv.number.hi = p.def->value + d;
                        if (p.min >= 0) pv.number.lo = std::max(0.0, pv.number.lo);
                    }
                    pv.number.samples = p.def->samples;
                    if (p.type == ParamType::choice) pv.choice = static_cast<int32_t>(p.def->value);
                }
                out.params.push_back(pv);
                continue;
            }
            Eval e = eval(*it->second.first, it->second.second, type_of(p), what, &p);
            if (e.kind == Eval::Kind::number) {
                check_range(e, p, what);
                pv.number = e.num;
                if (p.min >= 0 && pv.number.lo < 0) pv.number.lo = 0;
                if (!p.sampleable && n.kind == ast::NodeKind::maneuver && e.num.samples > 1 &&
                    p.type == ParamType::quantity) {
                    auto* d = error("E0205", e.range, what + " cannot be sampled");
                    d->notes.push_back({{}, "see `sdv catalog` for the sampleable parameters"});
                }
            } else if (e.kind == Eval::Kind::word) {
                if (p.type == ParamType::choice) {
                    auto c = std::find(p.choices.begin(), p.choices.end(), e.word);
                    if (c == p.choices.end()) {
                        auto* d = error("E0206", e.range, "'" + e.word + "' is not a valid value of " + what);
                        add_suggestion(*d, e.word, p.choices);
                    } else {
                        pv.choice = static_cast<int32_t>(c - p.choices.begin());
                    }
                } else {
                    pv.vehicle = resolve_vehicle(e, ctx, what);
                }
            }
            out.params.push_back(pv);
        }
    }

    ir::VehicleRef resolve_vehicle(const Eval& e, const ScenarioCtx& ctx, const std::string& what) {
        ir::VehicleRef ref;
        const auto zones = catalog::vehicle_zones();
        if (e.word == "self") {
            ref.kind = ir::VehicleRef::Kind::self;
            return ref;
        }
        if (e.word == "ego") {
            if (ctx.ego < 0) {
                auto* d = error("E0105", e.range, what + " refers to the ego, but scenario '" + ctx.name +
                                                      "' has none");
                d->notes.push_back({{}, "declare it with 'ego NAME: sdv { ... }'"});
                return ref;
            }
            ref.kind = ir::VehicleRef::Kind::vehicle;
            ref.vehicle = ctx.ego;
            return ref;
        }
        for (size_t z = 0; z < zones.size(); ++z) {
            if (zones[z] == e.word) {
                ref.kind = ir::VehicleRef::Kind::zone;
                ref.zone = static_cast<int32_t>(z);
                return ref;
            }
        }
        auto it = ctx.vehicle_index.find(e.word);
        if (it == ctx.vehicle_index.end()) {
            std::vector<std::string> options = ctx.vehicle_names;
            for (const auto& z : zones) options.push_back(z);
            auto* d = error("E0105", e.range, "unknown vehicle '" + e.word + "' in scenario '" + ctx.name + "'");
            add_suggestion(*d, e.word, options);
            d->notes.push_back({{}, "a vehicle is named by its declaration, 'ego', 'self' or a zone "
                                    "(front, front_left, left, back_left, back, back_right, right, front_right)"});
            return ref;
        }
        ref.kind = ir::VehicleRef::Kind::vehicle;
        ref.vehicle = it->second;
        return ref;
    }

    void check_candidate_counts(const ir::TreeInstance& inst, const ast::TreeRef& ref) {
        for (const auto& n : inst.nodes) {
            if (n.kind != ir::NodeKind::maneuver) continue;
            long long product = 1;
            for (const auto& p : n.params) product *= std::max(1, p.number.samples);
            if (product > kMaxCandidates) {
                auto* d = error("E0305", ref.range,
                                "maneuver '" + n.name + "' would plan " + std::to_string(product) +
                                    " candidate trajectories per cycle");
                d->notes.push_back({{}, "at most " + std::to_string(kMaxCandidates) +
                                        "; reduce the sample counts (node " + n.path + ")"});
            }
        }
    }

    // ---------------------------------------------------------------- warnings
    void warn_unused() {
        const ast::File* main = units_[0].file;
        if (main == nullptr) return;
        for (auto& t : trees_) {
            if (!t.unit->is_main) continue;
            if (!t.used && !main->scenarios.empty()) {
                diags_.warning("W0101", "unused-tree", t.decl->name.range,
                               "tree '" + t.qname + "' is never used");
            }
            for (const auto& p : t.decl->params) {
                if (!t.used_params.count(p.name.text)) {
                    diags_.warning("W0102", "unused-parameter", p.name.range,
                                   "parameter '" + p.name.text + "' of tree '" + t.qname +
                                       "' is never used");
                }
            }
        }
        for (const auto& u : units_) {
            if (!u.is_main || u.file == nullptr) continue;
            for (const auto& imp : u.file->imports) {
                bool used = false;
                for (const auto& t : trees_) {
                    if (t.unit->display == imp.path || (!t.unit->is_main && t.used &&
                                                        (t.unit->display.size() >= imp.path.size() &&
                                                         t.unit->display.compare(t.unit->display.size() - imp.path.size(),
                                                                                 imp.path.size(), imp.path) == 0))) {
                        used = used || t.used;
                    }
                }
                if (!used && !main->scenarios.empty()) {
                    diags_.warning("W0103", "unused-import", imp.path_range,
                                   "nothing from '" + imp.path + "' is used");
                }
            }
        }
        for (const auto& s : main->scenarios) {
            if (s.expects.empty()) {
                diags_.warning("W0104", "no-expectations", s.name.range,
                               "scenario '" + s.name.text + "' has no expect statements; its run always passes");
            }
        }
    }

    diag::SourceManager& sm_;
    diag::DiagnosticEngine& diags_;
    const CompileOptions& options_;
    std::vector<Unit> units_;
    std::map<diag::FileId, std::unique_ptr<ast::File>> owned_;
    std::set<std::string> loaded_;
    std::vector<TreeSym> trees_;
    std::map<std::string, size_t> tree_index_;
    std::vector<RoadDeclRef> road_decls_;
    std::vector<RoadSym> roads_;
    std::set<size_t> cyclic_;
    std::set<std::tuple<std::string, uint32_t, uint32_t, std::string>> reported_;
    diag::Diagnostic scratch_;
};

}  // namespace

Compilation compile_source(const std::string& display_path, std::string text, diag::SourceManager& sm,
                           diag::DiagnosticEngine& diags, const CompileOptions& options) {
    Checker checker(sm, diags, options);
    return checker.run(display_path, std::move(text));
}

Compilation compile_file(const std::string& path, diag::SourceManager& sm, diag::DiagnosticEngine& diags,
                         const CompileOptions& options) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        diags.error("E0006", {}, "cannot read '" + path + "'");
        return {};
    }
    std::stringstream ss;
    ss << in.rdbuf();
    return compile_source(path, ss.str(), sm, diags, options);
}

}  // namespace sdv::compiler
