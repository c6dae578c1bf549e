// What the subcommands of `sdv` share: exit codes, warning flags, the common options, and
// loading a scenario from any input (.sdv, .sdvir, GeoScenario) with its diagnostics printed.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/source_manager.h"
#include "compiler/sema/compile.h"
#include "runtime/ir/ir.h"

namespace sdv::cli {

constexpr int kOk = 0;
constexpr int kFailure = 1;
constexpr int kUsage = 2;
constexpr int kInternal = 3;

// Warning flags in the compiler style (-Werror, -Werror=NAME, -Wno-NAME, -w) are taken out of
// argv before CLI11 sees them.
struct WarningFlags {
    diag::DiagnosticEngine::WarningPolicy policy;
    std::vector<std::string> unknown;
};

extern const std::vector<std::string> kWarningNames;

WarningFlags extract_warning_flags(std::vector<std::string>& args);

struct Common {
    std::string format = "text";
    std::vector<std::string> import_dirs;
    std::vector<std::string> btree_path;  // GeoScenario inputs: where .btree files are
    std::vector<std::string> map_dirs;    // and where maps are
    bool color = false;
};

// Writes `text` to `path`; on failure says so on stderr and returns false.
bool write_file(const std::string& path, std::string_view text);

// `sdv view` / `sdv plot`: a report built from a run directory (or the error building it), to
// `out` ('-': stdout); `announce` prints where it went.
int emit_report(const std::string& text, const std::string& error, const std::string& out, bool announce);

// GeoScenario inputs (.btree, .gs.osm) converted to .sdv text; nullopt after errors.
std::optional<std::string> convert_input(const std::string& file, const Common& c, const std::string& out_dir,
                                         diag::SourceManager& sm, diag::DiagnosticEngine& diags);

// Compiles any input: a .sdv file, or a GeoScenario scenario or .btree file through its
// conversion (so both give the same IR as the converted .sdv).
compiler::Compilation compile_input(const std::string& file, const Common& c, diag::SourceManager& sm,
                                    diag::DiagnosticEngine& diags);

// Prints diagnostics (text to stderr, JSON to stdout) and returns whether there were errors.
bool report(diag::DiagnosticEngine& diags, const diag::SourceManager& sm, const Common& c);

// A scenario to run, from .sdv (compiled), .sdvir (read and validated) or a GeoScenario input.
struct Loaded {
    ir::Program program;
    int index = 0;     // the scenario (-1: all of them, when asked for with `all_if_several`)
    std::string text;  // the file's bytes
};

// Loads `file` and picks `scenario` (empty: the only one; with several, an error, or index -1
// with `all_if_several`). Returns an exit code (kOk: `out` holds it); what went wrong is printed.
int load_scenario(const std::string& file, const std::string& scenario, const Common& c, const WarningFlags& w,
                  Loaded& out, bool all_if_several = false);

}  // namespace sdv::cli
