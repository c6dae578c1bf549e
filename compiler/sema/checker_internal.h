// Private to compiler/sema: the checker's shared state and the helpers its passes share. The
// Checker class is declared here once; its member functions are defined by pass, one file each:
//   checker.cpp    the driver (the order of the passes), diagnostics, source locations, and the
//                  public entry points of compile.h;
//   names.cpp      loading files and imports, symbols (trees, roads), name look-ups;
//   values.cpp     units and values: evaluation against an expected type, samples, ranges;
//   trees.cpp      tree declarations and bodies, subtree references, cycles, unused warnings;
//   roads.cpp      settings, built-in roads, junctions and maps;
//   scenarios.cpp  scenarios: settings, vehicles, positions and lanes, lights, expectations;
//   expand.cpp     a vehicle's tree expanded with its arguments into a flat IR instance;
//   repeat.cpp     arithmetic on quantities, and agent templates (`vehicle v[1..50]`) expanded
//                  into agents, their errors reported once with the instances they failed for.
// Nothing outside compiler/sema includes this header.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "compiler/sema/compile.h"
#include "runtime/catalog/catalog.h"

namespace sdv::compiler::sema {

namespace fs = std::filesystem;
using catalog::Dim;
using catalog::ParamDef;
using catalog::ParamType;
using diag::SourceRange;

using catalog::kMaxSamples;
inline constexpr int kMaxCandidates = 20000;
inline constexpr int kMaxExpansionDepth = 64;
inline constexpr int64_t kMaxRepeat = 10000;         // agents of one template
// The agents of one scenario: CompileOptions::max_scenario_agents (E0511).
// The nodes of one agent's tree with its subtrees inlined (E0306; those of all the agents' trees
// of a scenario: CompileOptions::max_scenario_tree_nodes). A subtree referenced twice is inlined
// twice, so a chain of trees each referencing the next twice doubles its size at every level.
inline constexpr size_t kMaxTreeNodes = 10000;

// ------------------------------------------------------------------ small helpers

// A tree parameter's declared type.
struct TypeInfo {
    ParamType type = ParamType::quantity;
    Dim dim = Dim::none;
};

// Numbers and units in messages (values.cpp).
constexpr auto fmt = catalog::format_number;
std::string with_unit(double si, Dim dim);
std::string dim_phrase(Dim dim);
std::string example_unit(Dim dim);
// The parameter type names a tree may declare, and how messages name a type (values.cpp).
const std::vector<std::pair<std::string, TypeInfo>>& param_types();
std::string type_phrase(TypeInfo t);

// Names and "did you mean" notes (names.cpp).
std::vector<std::string> names_of(const std::vector<ParamDef>& ps);
void add_suggestion(diag::Diagnostic& d, std::string_view word,
                    const std::vector<std::string>& candidates);

// ------------------------------------------------------------------ the checker's symbols

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
    // label → overriding args (evaluated in `env`). An arg's name is a path
    // `a.b...label.field`; `depth` is the index of this tree's label in it (the labels before
    // it are subtree references of the trees above).
    struct Override {
        const ast::Arg* arg = nullptr;
        const Env* env = nullptr;
        size_t depth = 0;
    };
    std::map<std::string, std::vector<Override>> overrides;
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

// ------------------------------------------------------------------ the checker

class Checker {
public:
    Checker(diag::SourceManager& sm, diag::DiagnosticEngine& diags, const CompileOptions& options)
        : sm_(sm), diags_(&diags), options_(options) {}

    Compilation run(const std::string& display, std::string text);

private:
    // ---------------------------------------------------------------- diagnostics (checker.cpp)
    diag::Diagnostic* error(const std::string& code, SourceRange r, const std::string& msg);
    ir::SourceLoc loc(SourceRange r) const;

    // ---------------------------------------------------------------- loading (names.cpp)
    void load(const std::string& display, std::string text, fs::path dir, std::string qualifier,
              bool is_main, bool is_stdlib);
    void import_file(const ast::ImportDecl& imp, const fs::path& base, bool from_stdlib);

    // ---------------------------------------------------------------- symbols (names.cpp)
    static void qualify_local_references(Unit& u);
    void collect_symbols();
    std::vector<std::string> tree_names() const;
    TreeSym* find_tree(const ast::QualName& name);
    std::optional<TypeInfo> find_type(const ast::Ident& name);
    std::optional<TypeInfo> find_type_quiet(const std::string& name) const;

    // ---------------------------------------------------------------- repeat.cpp
    // Arithmetic folded to SI: the value, its dimension, and whether it is a whole number
    // written without unit. nullopt when reported.
    struct Folded {
        double si = 0.0;
        Dim dim = Dim::none;
        bool integer = true;
    };
    std::optional<Folded> fold(const ast::Arith& a, const std::string& what);
    // The scenario with its agent templates expanded (`s` itself when it has none).
    const ast::ScenarioDecl& expand_templates(const ast::ScenarioDecl& s);
    std::optional<int64_t> repeat_bound(const ast::Primary& p);
    // While checking an expanded agent, errors are noted as failing for it (see error()).
    void set_instance(const ast::VehicleDecl* v) {
        instance_ = v != nullptr ? v->instance.get() : nullptr;
    }
    void attach_instance_notes();

    // ---------------------------------------------------------------- values (values.cpp)
    std::optional<double> to_si(const ast::Primary& p, Dim expected, const std::string& what);
    Eval eval(const ast::Value& v, const Env* env, TypeInfo expect, const std::string& what,
              const ParamDef* def, int depth = 0);
    static bool compatible(TypeInfo have, TypeInfo want);
    void apply_spread_and_samples(const ast::Value& v, Eval& e, TypeInfo expect,
                                  const std::string& what, const ParamDef* def);
    void apply_samples(const ast::Value& v, Eval& e, TypeInfo expect, const std::string& what,
                       const ParamDef* def);
    bool check_range(const Eval& e, const ParamDef& def, const std::string& what);

    // ---------------------------------------------------------------- trees (trees.cpp)
    static int32_t count_nodes(const std::vector<std::unique_ptr<ast::Node>>& nodes);
    void collect_labels(const ast::Node& n, TreeSym& t);
    void check_trees();
    void declare_tree(TreeSym& t, Env& env);
    void check_tree_body(TreeSym& t, const Env& env);
    bool can_select(const ast::Node& n, int depth);
    bool always_succeeds(const ast::Node& n, int depth);
    void check_node(const ast::Node& n, const Env& env);
    int32_t parallel_threshold(const ast::Node& n, const Env* env);
    const std::vector<ParamDef>* leaf_params(const ast::Node& n, std::string& kind_word);
    static TypeInfo type_of(const ParamDef& p) { return {p.type, p.dim}; }
    void check_leaf(const ast::Node& n, const Env& env);
    Eval check_arg(const ast::Value& v, const Env& env, const ParamDef& def,
                   const std::string& what);
    TreeSym* check_subtree_ref(const ast::QualName& name, const std::vector<ast::Arg>& args,
                               const Env& env, SourceRange);
    void check_cycles();
    void warn_unused();

    // ---------------------------------------------------------------- roads (roads.cpp)
    struct RoadDeclRef {
        Unit* unit;
        const ast::RoadDecl* road;
        const ast::JunctionDecl* junction;
        const ast::MapDecl* map;
    };

    std::optional<double> setting_number(const ast::Setting& s, size_t i, Dim dim, double lo,
                                         double hi, bool lo_exclusive);
    bool read_setting(std::map<std::string, const ast::Setting*>& set, const char* key, Dim dim,
                      double lo, double hi, bool lo_exclusive, double& out);
    std::map<std::string, const ast::Setting*> settings_map(const std::vector<ast::Setting>& ss,
                                                           const std::vector<std::string>& known,
                                                           const std::string& where);
    void check_roads();
    void check_builtin_road(const ast::RoadDecl& r, RoadSym& sym);
    void check_junction(const ast::JunctionDecl& j, RoadSym& sym);
    void check_map(const ast::MapDecl& m, RoadSym& sym);

    // ---------------------------------------------------------------- scenarios (scenarios.cpp)
    // A tree expanded for the first instance of a template (Instance::tree_of), for the
    // others: the IR instance (-1 if it failed) and the errors it reported, reported again for
    // each of them so that the template's errors name every instance they fail for.
    struct ExpandedTree {
        int32_t instance = -1;
        std::vector<std::pair<std::string, SourceRange>> errors;
    };
    struct ScenarioCtx {
        ir::Scenario* ir = nullptr;
        const RoadSym* road = nullptr;
        std::map<std::string, int32_t> vehicle_index;
        std::vector<std::string> vehicle_names;
        int32_t ego = -1;
        std::string name;
        std::map<const ast::VehicleDecl*, ExpandedTree> expanded_trees;
        size_t tree_nodes = 0;       // of the agents' trees expanded so far (max_scenario_tree_nodes)
        size_t tree_path_chars = 0;  // and of their nodes' paths (max_scenario_tree_path_chars)
    };

    void check_scenario(const ast::ScenarioDecl& s, ir::Program& program);
    ir::Position check_position(const ast::Position& p, const ScenarioCtx& ctx,
                                const std::string& what);
    std::string resolve_lane(const ast::LaneRef& l, const ScenarioCtx& ctx,
                             const std::string& what);
    ir::Vehicle check_vehicle(const ast::VehicleDecl& v, ScenarioCtx& ctx, ir::Program& program);
    void check_overlaps(const ast::ScenarioDecl& s, const ir::Scenario& sc);
    void check_light(const ast::LightDecl& l, ScenarioCtx& ctx);
    int32_t check_expr(const ast::Expr& e, ScenarioCtx& ctx);
    // The window of an `expect` statement (its root expression `e`, lowered at `root`).
    void check_window(const ast::Expr& e, int32_t root, ScenarioCtx& ctx);

    // ---------------------------------------------------------------- campaigns (vary.cpp)
    struct VaryTarget;
    void check_vary(const ast::ScenarioDecl& s, ir::Program& program, size_t index, size_t instances_before);
    std::vector<std::string> vary_paths(const ast::ScenarioDecl& s);
    std::optional<VaryTarget> vary_target(const ast::VaryParam& vp, const ast::ScenarioDecl& s);
    ast::Value* vary_slot(const VaryTarget& t, ast::ScenarioDecl& s, SourceRange where);
    bool probe_bindings(const ast::ScenarioDecl& s, const ast::VaryParam& vp, const VaryTarget& target,
                        const std::vector<std::pair<double, SourceRange>>& probes, const ir::Program& probe_base,
                        size_t index, const std::vector<double>& base, ir::VaryParam& out);

    // ---------------------------------------------------------------- expansion (expand.cpp)
    int32_t expand_vehicle_tree(const ast::VehicleDecl& v, ScenarioCtx& ctx, ir::Program& program);
    int32_t expand_tree_ref(const ast::TreeRef& ref, ScenarioCtx& ctx, ir::Program& program);
    bool within_tree_budget(const ir::TreeInstance& inst, const ast::TreeRef& ref, ScenarioCtx& ctx);
    void check_crosswalks(const std::vector<ast::CrosswalkDecl>& xs, RoadSym& sym, bool junction);
    void check_tree_agent(const ast::TreeRef& ref, const ir::Vehicle& v, const ir::Program& program);
    std::optional<double> check_speed(const ast::Value& v, const std::string& what);
    void check_path(const ast::VehicleDecl& v, ir::Vehicle& out, ScenarioCtx& ctx, const std::string& what);
    Env bind(const TreeSym& t, const std::vector<ast::Arg>& args, const Env* caller_env,
             const Env& caller);
    int32_t expand_node(const ast::Node& n, const Env& env, ScenarioCtx& ctx,
                        ir::TreeInstance& inst, const std::string& path);
    void resolve_leaf(const ast::Node& n, const Env& env, ScenarioCtx& ctx, ir::Node& out,
                      const std::string& label);
    ir::VehicleRef resolve_vehicle(const Eval& e, const ScenarioCtx& ctx, const std::string& what);
    void check_candidate_counts(const ir::TreeInstance& inst, const ast::TreeRef& ref);

    diag::SourceManager& sm_;
    diag::DiagnosticEngine* diags_;  // swapped while probing a campaign (vary.cpp)
    const CompileOptions& options_;
    std::vector<Unit> units_;
    std::map<diag::FileId, std::unique_ptr<ast::File>> owned_;
    std::set<std::string> loaded_;
    std::vector<TreeSym> trees_;
    std::map<std::string, size_t> tree_index_;
    std::vector<RoadDeclRef> road_decls_;
    std::vector<RoadSym> roads_;
    std::set<size_t> cyclic_;
    // can_select and always_succeeds of a tree's body at a depth (trees.cpp).
    std::map<std::pair<size_t, int>, bool> can_select_memo_, succeeds_memo_;
    std::set<std::tuple<std::string, uint32_t, uint32_t, std::string>> reported_;
    // Where error() also notes each error's code and place, when set (expand_vehicle_tree).
    std::vector<std::pair<std::string, SourceRange>>* error_log_ = nullptr;
    // The characters of the node paths of the tree being expanded (expand_tree_ref).
    size_t expansion_path_chars_ = 0;
    diag::Diagnostic scratch_;
    // Agent templates: the expanded scenarios (owned here, the AST keeps what was written),
    // the instance being checked, and per error first reported for an instance the instances
    // it failed for (in order of first report).
    std::vector<std::unique_ptr<ast::ScenarioDecl>> expanded_;
    const ast::VehicleDecl::Instance* instance_ = nullptr;
    struct InstanceErrors {
        std::string code;
        SourceRange range;
        std::string of;
        std::vector<std::string> labels;
        std::set<std::string> seen;
    };
    std::vector<InstanceErrors> instance_errors_;
    std::map<std::tuple<std::string, uint32_t, uint32_t, std::string>, size_t> instance_error_index_;
};

}  // namespace sdv::compiler::sema
