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
//
// This file holds the driver (the passes in that order), diagnostics and source locations, and
// the public entry points; the passes live in names.cpp, values.cpp, trees.cpp, roads.cpp,
// scenarios.cpp and expand.cpp, sharing the Checker declared in checker_internal.h.
#include "compiler/sema/compile.h"

#include <fstream>
#include <sstream>
#include <tuple>

#include "compiler/sema/checker_internal.h"

namespace sdv::compiler {
namespace sema {

Compilation Checker::run(const std::string& display, std::string text) {
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
    attach_instance_notes();
    if (diags_->has_errors()) return out;
    out.program = std::move(program);
    return out;
}

// ------------------------------------------------------------------ diagnostics
diag::Diagnostic* Checker::error(const std::string& code, SourceRange r, const std::string& msg) {
    // One error per code and place: expanding a tree re-checks values already checked at
    // the subtree reference, with other words for the same mistake.
    auto key = std::make_tuple(code, r.begin.file, r.begin.offset, std::string());
    if (error_log_ != nullptr) error_log_->emplace_back(code, r);
    const bool first = reported_.insert(key).second;
    // An agent expanded from a template: the error is reported once, at the template, with a
    // note naming every instance it failed for (attach_instance_notes, repeat.cpp).
    if (instance_ != nullptr) {
        auto it = instance_error_index_.find(key);
        if (first) {
            instance_error_index_[key] = instance_errors_.size();
            instance_errors_.push_back({code, r, instance_->of, {instance_->label}, {instance_->label}});
        } else if (it != instance_error_index_.end()) {
            auto& e = instance_errors_[it->second];
            if (e.seen.insert(instance_->label).second) e.labels.push_back(instance_->label);
        }
    }
    if (!first) return &scratch_;
    return &diags_->error(code, r, msg);
}

ir::SourceLoc Checker::loc(SourceRange r) const {
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

}  // namespace sema

Compilation compile_source(const std::string& display_path, std::string text, diag::SourceManager& sm,
                           diag::DiagnosticEngine& diags, const CompileOptions& options) {
    sema::Checker checker(sm, diags, options);
    return checker.run(display_path, std::move(text));
}

Compilation compile_file(const std::string& path, diag::SourceManager& sm, diag::DiagnosticEngine& diags,
                         const CompileOptions& options) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        diags.error("E0006", {}, "'" + path + "' is a directory, not a file")
            .notes.push_back({{}, "give the .sdv file (or .sdvir, .btree, .gs.osm) to read"});
        return {};
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        diags.error("E0006", {}, "cannot read '" + path + "'" + (std::filesystem::exists(path, ec) ? "" : ": no such file"));
        return {};
    }
    std::stringstream ss;
    ss << in.rdbuf();
    return compile_source(path, ss.str(), sm, diags, options);
}

}  // namespace sdv::compiler
