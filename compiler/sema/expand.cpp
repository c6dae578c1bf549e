// Tree expansion: a vehicle's tree instantiated with its arguments and node overrides into a
// flat IR instance (subtrees inlined), every resolved leaf value range-checked, vehicle words
// resolved against the scenario, and the number of candidate trajectories per maneuver capped.
#include <algorithm>
#include <cmath>

#include "compiler/sema/checker_internal.h"

namespace sdv::compiler::sema {

// The instances of a template whose tree reference does not use the index share one expansion
// (a template of 10,000 agents expands its tree once, not 10,000 times): each gets a copy of the
// first one's IR instance, and its errors again.
int32_t Checker::expand_vehicle_tree(const ast::VehicleDecl& v, ScenarioCtx& ctx, ir::Program& program) {
    const ast::VehicleDecl* same = v.instance != nullptr ? v.instance->tree_of : nullptr;
    if (same == nullptr) return expand_tree_ref(v.trees[0], ctx, program);
    if (auto it = ctx.expanded_trees.find(same); it != ctx.expanded_trees.end()) {
        // Each was reported already: error() counts this instance in the template's error.
        for (const auto& [code, range] : it->second.errors) (void)error(code, range, std::string());
        if (it->second.instance < 0 || !within_tree_budget(program.instances[static_cast<size_t>(it->second.instance)], v.trees[0], ctx)) {
            return -1;
        }
        ir::TreeInstance copy = program.instances[static_cast<size_t>(it->second.instance)];
        program.instances.push_back(std::move(copy));
        return static_cast<int32_t>(program.instances.size() - 1);
    }
    ExpandedTree first;
    auto* outer = error_log_;
    error_log_ = &first.errors;
    first.instance = expand_tree_ref(v.trees[0], ctx, program);
    error_log_ = outer;
    if (outer != nullptr) outer->insert(outer->end(), first.errors.begin(), first.errors.end());
    if (!first.errors.empty()) first.instance = -1;
    const int32_t index = first.instance;
    ctx.expanded_trees.emplace(same, std::move(first));
    return index;
}

int32_t Checker::expand_tree_ref(const ast::TreeRef& ref, ScenarioCtx& ctx, ir::Program& program) {
    Env caller;  // scenario level: no parameters
    TreeSym* t = check_subtree_ref(ref.name, ref.args, caller, ref.range);
    if (t == nullptr || !t->ok || cyclic_.count(tree_index_[t->qname])) return -1;
    ir::TreeInstance inst;
    const size_t errors_before = diags_->error_count();
    Env env = bind(*t, ref.args, &caller, caller);
    expansion_path_chars_ = 0;
    if (t->decl->body.size() == 1) expand_node(*t->decl->body[0], env, ctx, inst, t->qname);
    if (inst.nodes.size() > kMaxTreeNodes) {
        auto* d = error("E0306", ref.range, "tree '" + t->qname + "' expands to more than " + std::to_string(kMaxTreeNodes) +
                                                " nodes with its subtrees inlined");
        d->notes.push_back({{}, "each reference to a subtree inlines it again: a tree referencing another twice, which "
                                "references a third twice, doubles at every level"});
        return -1;
    }
    if (diags_->error_count() != errors_before || inst.nodes.empty()) return -1;
    if (!within_tree_budget(inst, ref, ctx)) return -1;
    check_candidate_counts(inst, ref);
    program.instances.push_back(std::move(inst));
    return static_cast<int32_t>(program.instances.size() - 1);
}

// The environment of a tree instance: its parameters bound to the caller's arguments or
// to their defaults, and the caller's node overrides.
Env Checker::bind(const TreeSym& t, const std::vector<ast::Arg>& args, const Env* caller_env,
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
        } else {
            env.overrides[a.name.parts[0].text].push_back({&a, caller_env, 0});
        }
    }
    return env;
}

// A labelled subtree reference's environment also takes the overrides that reach through it
// (`label.node.field` above it); they come after the reference's own, so they win.
static void pass_through(const Env& outer, const std::string& label, Env& sub) {
    auto it = outer.overrides.find(label);
    if (it == outer.overrides.end()) return;
    for (const Env::Override& o : it->second) {
        if (o.depth + 2 < o.arg->name.parts.size()) {
            sub.overrides[o.arg->name.parts[o.depth + 1].text].push_back({o.arg, o.env, o.depth + 1});
        }
    }
}

// Whether a scenario's agents' trees, with this one, stay within max_scenario_tree_nodes and
// max_scenario_tree_path_chars; if not, an error (once per scenario).
bool Checker::within_tree_budget(const ir::TreeInstance& inst, const ast::TreeRef& ref, ScenarioCtx& ctx) {
    const size_t node_limit = options_.max_scenario_tree_nodes, path_limit = options_.max_scenario_tree_path_chars;
    const bool over = ctx.tree_nodes > node_limit || ctx.tree_path_chars > path_limit;
    size_t chars = 0;
    for (const auto& n : inst.nodes) chars += n.path.size();
    ctx.tree_nodes += inst.nodes.size();
    ctx.tree_path_chars += chars;
    if (ctx.tree_nodes <= node_limit && ctx.tree_path_chars <= path_limit) return true;
    if (over) return false;
    if (ctx.tree_nodes > node_limit) {
        auto* d = error("E0306", ref.range, "the agents' trees of scenario '" + ctx.name + "' expand to more than " +
                                                std::to_string(node_limit) + " nodes");
        d->notes.push_back({{}, "this agent's tree has " + std::to_string(inst.nodes.size()) +
                                " nodes with its subtrees inlined; the agents before it have " +
                                std::to_string(ctx.tree_nodes - inst.nodes.size())});
    } else {
        auto* d = error("E0306", ref.range, "the agents' trees of scenario '" + ctx.name + "' name their nodes with more than " +
                                                std::to_string(path_limit) + " characters of paths");
        d->notes.push_back({{}, "a node's path names the trees above it (t/sub/keep_velocity): references to long-named "
                                "trees nested deep make every node below them long"});
    }
    return false;
}

int32_t Checker::expand_node(const ast::Node& n, const Env& env, ScenarioCtx& ctx,
                             ir::TreeInstance& inst, const std::string& path) {
    if (env.stack.size() > kMaxExpansionDepth) return -1;
    // Past a limit the expansion stops (E0306, expand_tree_ref): its work is bounded by the limits.
    if (inst.nodes.size() > kMaxTreeNodes || expansion_path_chars_ > options_.max_scenario_tree_path_chars) return -1;
    if (n.kind == ast::NodeKind::subtree) {
        TreeSym* t = nullptr;
        auto it = tree_index_.find(n.callee.str());
        if (it == tree_index_.end() || cyclic_.count(it->second)) return -1;
        t = &trees_[it->second];
        if (!t->ok || t->decl->body.size() != 1) return -1;
        Env sub = bind(*t, n.args, &env, env);
        if (n.label) pass_through(env, n.label->text, sub);
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
        case ast::NodeKind::latch: out.kind = ir::NodeKind::latch; break;
        case ast::NodeKind::subtree: break;
    }
    out.name = !label.empty() ? label : n.callee.parts.empty() ? ast::to_string(n.kind) : n.callee.str();
    out.path = path + "/" + out.name;
    expansion_path_chars_ += out.path.size();
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

void Checker::resolve_leaf(const ast::Node& n, const Env& env, ScenarioCtx& ctx, ir::Node& out,
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
            for (const Env::Override& o : it->second) {
                if (o.depth + 2 == o.arg->name.parts.size()) given[o.arg->name.parts[o.depth + 1].text] = {&o.arg->value, o.env};
            }
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

ir::VehicleRef Checker::resolve_vehicle(const Eval& e, const ScenarioCtx& ctx,
                                        const std::string& what) {
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

void Checker::check_candidate_counts(const ir::TreeInstance& inst, const ast::TreeRef& ref) {
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

}  // namespace sdv::compiler::sema
