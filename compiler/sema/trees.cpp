// Tree checks: every tree declaration checked once on its own (parameters and their types,
// node names, one root, no empty composites, unreachable fallback children, a maneuver on some
// path, leaf and subtree arguments), subtree cycles, and the closing warnings (unused trees,
// parameters and imports; scenarios without expectations).
#include <algorithm>
#include <functional>

#include "compiler/sema/checker_internal.h"

namespace sdv::compiler::sema {

int32_t Checker::count_nodes(const std::vector<std::unique_ptr<ast::Node>>& nodes) {
    int32_t n = 0;
    for (const auto& c : nodes) n += 1 + count_nodes(c->children);
    return n;
}

void Checker::collect_labels(const ast::Node& n, TreeSym& t) {
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

void Checker::check_trees() {
    // First every tree's parameters and labels, so that subtree references in any tree can
    // be checked against them; then the bodies.
    std::vector<Env> envs(trees_.size());
    for (size_t i = 0; i < trees_.size(); ++i) declare_tree(trees_[i], envs[i]);
    check_cycles();
    for (size_t i = 0; i < trees_.size(); ++i) check_tree_body(trees_[i], envs[i]);
}

void Checker::declare_tree(TreeSym& t, Env& env) {
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

void Checker::check_tree_body(TreeSym& t, const Env& env) {
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

// Whether a node can select a maneuver on some path.
bool Checker::can_select(const ast::Node& n, int depth) {
    if (depth > kMaxExpansionDepth) return true;
    switch (n.kind) {
        case ast::NodeKind::maneuver: return true;
        case ast::NodeKind::condition: return false;
        case ast::NodeKind::subtree: {
            auto it = tree_index_.find(n.callee.str());
            if (it == tree_index_.end() || cyclic_.count(it->second)) return true;  // reported
            // Memoised by tree and depth: a tree referencing another twice, which references a
            // third twice, ... would otherwise be walked once per path (2^64 at the depth limit).
            const auto key = std::make_pair(it->second, depth + 1);
            if (auto m = can_select_memo_.find(key); m != can_select_memo_.end()) return m->second;
            const auto& body = trees_[it->second].decl->body;
            const bool result = body.empty() ? false : can_select(*body[0], depth + 1);
            can_select_memo_.emplace(key, result);
            return result;
        }
        default:
            for (const auto& c : n.children) {
                if (can_select(*c, depth)) return true;
            }
            return false;
    }
}

// Whether a node always returns SUCCESS when ticked (for unreachable-child detection).
bool Checker::always_succeeds(const ast::Node& n, int depth) {
    if (depth > kMaxExpansionDepth) return false;
    switch (n.kind) {
        case ast::NodeKind::maneuver: {
            const auto* m = catalog::find_maneuver(n.callee.str());
            return m != nullptr && m->never_fails();
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
            const auto key = std::make_pair(it->second, depth + 1);  // memoised as can_select
            if (auto m = succeeds_memo_.find(key); m != succeeds_memo_.end()) return m->second;
            const auto& body = trees_[it->second].decl->body;
            const bool result = body.size() == 1 && always_succeeds(*body[0], depth + 1);
            succeeds_memo_.emplace(key, result);
            return result;
        }
        default: return false;
    }
}

void Checker::check_node(const ast::Node& n, const Env& env) {
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
        case ast::NodeKind::latch:
            for (const auto& c : n.children) check_node(*c, env);
            break;
    }
}

// parallel(policy = all | one) or parallel(success = N); returns the success threshold.
int32_t Checker::parallel_threshold(const ast::Node& n, const Env* env) {
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
const std::vector<ParamDef>* Checker::leaf_params(const ast::Node& n, std::string& kind_word) {
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

// Checks a leaf's arguments: names, duplicates, values, required and grouped parameters.
void Checker::check_leaf(const ast::Node& n, const Env& env) {
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

Eval Checker::check_arg(const ast::Value& v, const Env& env, const ParamDef& def,
                        const std::string& what) {
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
TreeSym* Checker::check_subtree_ref(const ast::QualName& name, const std::vector<ast::Arg>& args,
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
                } else {
                    // Its parameters as declared: name, type and default, in order.
                    std::string list;
                    for (const auto& p : target->decl->params) {
                        list += (list.empty() ? "" : ", ") + p.name.text + ": " + p.type.text;
                        if (p.def && p.def->range.valid()) {
                            const auto text = sm_.contents(p.def->range.begin.file);
                            const uint32_t b = p.def->range.begin.offset, e = p.def->range.end.offset;
                            if (b <= e && e <= text.size()) list += " = " + std::string(text.substr(b, e - b));
                        }
                    }
                    d->notes.push_back({{}, "tree '" + target->qname + "' takes " + list + " (sdv catalog --trees lists the standard trees)"});
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
        // label.field override; labels of subtree references lead into their trees
        // (sub.label.field), as deep as the path goes.
        const TreeSym* in = target;
        const ast::Node* found = nullptr;
        size_t depth = 0;
        for (;; ++depth) {
            const std::string& label = a.name.parts[depth].text;
            auto lit = in->labels.find(label);
            if (lit == in->labels.end()) {
                std::vector<std::string> labels;
                for (const auto& [l, n] : in->labels) labels.push_back(l);
                auto* d = error("E0110", a.name.parts[depth].range,
                                "tree '" + in->qname + "' has no node named '" + label + "'");
                add_suggestion(*d, label, labels);
                if (labels.empty()) {
                    d->notes.push_back({{}, "name a node in the tree to override it: "
                                            "'keep: maneuver keep_velocity(...)'"});
                }
                break;
            }
            const ast::Node& node = *lit->second;
            if (node.kind == ast::NodeKind::subtree && depth + 2 < a.name.parts.size()) {
                auto sub = tree_index_.find(node.callee.str());
                if (sub == tree_index_.end()) break;  // the unknown tree is reported at the reference
                in = &trees_[sub->second];
                continue;
            }
            if (depth + 2 != a.name.parts.size() ||
                (node.kind != ast::NodeKind::maneuver && node.kind != ast::NodeKind::condition)) {
                auto* d = error("E0110", a.name.range, "only a field of a maneuver or condition node can be "
                                                       "overridden ('" + label + ".field = value')");
                if (node.kind == ast::NodeKind::subtree) {
                    d->notes.push_back({{}, "'" + label + "' is a subtree reference: name a node inside it, '" + label +
                                                ".NODE.field = value'"});
                }
                break;
            }
            found = &node;
            break;
        }
        if (found == nullptr) continue;
        const ast::Node& node = *found;
        const std::string field = a.name.parts[depth + 1].text;
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
            auto* d = error("E0104", a.name.parts[depth + 1].range,
                            "unknown parameter '" + field + "' of " + kind_word + " '" +
                                node.callee.str() + "'");
            if (const auto* m = catalog::find_maneuver(node.callee.str())) {
                add_suggestion(*d, field, names_of(m->params));
            } else if (const auto* c = catalog::find_condition(node.callee.str())) {
                add_suggestion(*d, field, names_of(c->params));
            }
            continue;
        }
        check_arg(a.value, env, *def, "'" + field + "' of node '" + a.name.parts[depth].text + "'");
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

void Checker::check_cycles() {
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

// ------------------------------------------------------------------ warnings

void Checker::warn_unused() {
    const ast::File* main = units_[0].file;
    if (main == nullptr) return;
    for (auto& t : trees_) {
        if (!t.unit->is_main) continue;
        if (!t.used && !main->scenarios.empty()) {
            diags_->warning("W0101", "unused-tree", t.decl->name.range,
                           "tree '" + t.qname + "' is never used");
        }
        for (const auto& p : t.decl->params) {
            if (!t.used_params.count(p.name.text)) {
                diags_->warning("W0102", "unused-parameter", p.name.range,
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
            // An import that failed (E0107) is reported once, as the error.
            const bool failed = reported_.count(std::make_tuple(std::string("E0107"), imp.path_range.begin.file,
                                                                imp.path_range.begin.offset, std::string())) > 0;
            if (!used && !failed && !main->scenarios.empty()) {
                diags_->warning("W0103", "unused-import", imp.path_range,
                               "nothing from '" + imp.path + "' is used");
            }
        }
    }
    for (const auto& s : main->scenarios) {
        if (s.expects.empty()) {
            diags_->warning("W0104", "no-expectations", s.name.range,
                           "scenario '" + s.name.text + "' has no expect statements; its run always passes");
        }
    }
}

}  // namespace sdv::compiler::sema
