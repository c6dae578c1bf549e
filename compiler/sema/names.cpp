// The checker's names: loading the main file and its imports (the standard library embedded,
// user files relative to the importing file or an -I directory), collecting the symbols of all
// loaded files (trees under their qualified names, roads / junctions / maps, duplicates
// reported), and looking names up with "did you mean" notes.
#include <fstream>
#include <functional>
#include <sstream>

#include "compiler/diag/suggest.h"
#include "compiler/sema/checker_internal.h"
#include "compiler/syntax/parser.h"
#include "stdlib-trees/stdlib.h"

namespace sdv::compiler::sema {

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

// ------------------------------------------------------------------ loading

void Checker::load(const std::string& display, std::string text, fs::path dir,
                   std::string qualifier, bool is_main, bool is_stdlib) {
    const diag::FileId id = sm_.add_file(display, std::move(text));
    Unit u;
    u.id = id;
    u.display = display;
    u.qualifier = std::move(qualifier);
    u.dir = std::move(dir);
    u.is_main = is_main;
    u.is_stdlib = is_stdlib;
    auto parsed = syntax::parse(id, sm_, *diags_);
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

void Checker::import_file(const ast::ImportDecl& imp, const fs::path& base, bool from_stdlib) {
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

// ------------------------------------------------------------------ symbols

// In an imported file, a subtree reference to a tree of the same file is written without
// the file's qualifier (`subtree give_way()` inside std/junction.sdv): qualify it, so that
// it names the same tree however the file is imported.
void Checker::qualify_local_references(Unit& u) {
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

void Checker::collect_symbols() {
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

std::vector<std::string> Checker::tree_names() const {
    std::vector<std::string> out;
    for (const auto& t : trees_) out.push_back(t.qname);
    return out;
}

TreeSym* Checker::find_tree(const ast::QualName& name) {
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

std::optional<TypeInfo> Checker::find_type(const ast::Ident& name) {
    for (const auto& [n, t] : param_types()) {
        if (n == name.text) return t;
    }
    std::vector<std::string> names;
    for (const auto& [n, t] : param_types()) names.push_back(n);
    auto* d = error("E0112", name.range, "unknown parameter type '" + name.text + "'");
    add_suggestion(*d, name.text, names);
    return std::nullopt;
}

std::optional<TypeInfo> Checker::find_type_quiet(const std::string& name) const {
    for (const auto& [n, t] : param_types()) {
        if (n == name) return t;
    }
    return std::nullopt;
}

}  // namespace sdv::compiler::sema
