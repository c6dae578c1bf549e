// The compiler's public entry point: a .sdv file (and everything it imports) in, the checked
// IR plus diagnostics out. The IR exists only when there were no errors.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "compiler/ast/ast.h"
#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/source_manager.h"
#include "runtime/ir/ir.h"

namespace sdv::compiler {

inline constexpr const char* kCompilerVersion = "sdv 0.1.0";

struct CompileOptions {
    // Extra directories searched for relative imports after the importing file's directory.
    std::vector<std::string> import_dirs;
    // Limits of what one scenario may expand to, docs/language.md's: its agents, templates
    // expanded (E0511), and the nodes of all its agents' trees, subtrees inlined, and the
    // characters of those nodes' paths, which name the trees above each node (E0306). A caller
    // may lower them: tests, to reach them with small scenarios; the fuzz targets, so that an
    // input of a few bytes cannot make work in proportion to 100,000 agents.
    int64_t max_scenario_agents = 100000;
    size_t max_scenario_tree_nodes = 1000000;
    size_t max_scenario_tree_path_chars = 100000000;
};

struct Compilation {
    // Parsed files, the main file first; an entry is null when that file failed to parse.
    std::vector<std::unique_ptr<ast::File>> files;
    std::vector<diag::FileId> file_ids;
    std::optional<ir::Program> program;
};

// Reads, parses and checks `path` and its imports. Never throws.
Compilation compile_file(const std::string& path, diag::SourceManager& sm,
                         diag::DiagnosticEngine& diags, const CompileOptions& options = {});

// The same for text already in memory (`display_path` names it in messages; relative imports
// resolve against its directory).
Compilation compile_source(const std::string& display_path, std::string text,
                           diag::SourceManager& sm, diag::DiagnosticEngine& diags,
                           const CompileOptions& options = {});

// The source `text` of `display` with scenario `scenario`'s vary block replaced by fixed
// values: each (path, value with unit) written where the scenario states that value, or added
// where it would be written; `comment` (one line) takes the vary block's place. nullopt with
// `error` when the text does not parse or a path has no place. (sdv search writes its worst
// case with this.)
std::optional<std::string> concretize(const std::string& display, const std::string& text, const std::string& scenario,
                                      const std::vector<std::pair<std::string, std::string>>& values,
                                      const std::string& comment, std::string& error);

}  // namespace sdv::compiler
