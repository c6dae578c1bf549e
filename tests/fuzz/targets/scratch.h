// What the fuzz targets share: a private scratch directory for the readers that take a path
// rather than bytes, and the one way to report a broken property.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "compiler/diag/diagnostic_engine.h"
#include "compiler/sema/compile.h"

namespace sdv::fuzz {

// An empty directory of this process for one target's files: <scratch>/<name>, emptied on
// every call. The scratch directory is /dev/shm/sdv-fuzz-<pid>-XXXXXX (or under $TMPDIR
// when /dev/shm is missing), created on first use and removed at exit; ones left behind by
// processes that died (a crash) are removed the next time a process creates its own.
std::string fresh_dir(const std::string& name);

// Writes `bytes` to `path`; aborts when it cannot (a broken environment, not a finding).
void write_file(const std::string& path, std::string_view bytes);

// The directories of the GeoScenario reference's .btree library (../shared/data), those that
// exist: subtrees named by the inputs resolve there, as with `--btree-path`.
const std::vector<std::string>& btree_library();

// How the targets compile a scenario: the checker's limits on what one scenario expands to
// lowered (2,000 agents, 3,000 tree nodes with 300,000 characters of node paths, instead of
// 100,000, 1,000,000 and 100,000,000), so that the work
// of an input stays within the fuzzer's second however many agents its templates declare. The
// work is linear in those (the IR holds each agent and its tree: about 8 KB and, in the fuzz
// build, 2 ms for a std.drive vehicle); at the documented limits 100 bytes can declare 10,000
// of them. The same code path refuses them (E0511, E0306), at a lower count; the largest
// scenario of examples/ expands to 21 agents and 562 nodes.
compiler::CompileOptions compile_options();

// A broken property of `target`: prints what and aborts, which libFuzzer reports as a crash
// (and the replay test as a failure).
[[noreturn]] void fail(const char* target, const std::string& what);

// The GeoScenario front ends' property: a file the converter accepts compiles, so `diags` has no
// error located in the converted text (`display`, the file name it was compiled under), which
// the user does not have: the converter reports a value the checker refuses at its tag. The
// checker's limits on what a scenario expands to (E0306, E0511; lowered by compile_options())
// are no broken property: they are reported at the agent or tree that passes them.
void require_converted_text_compiles(const char* target, const std::string& display, const diag::SourceManager& sm,
                                     const diag::DiagnosticEngine& diags);

// What every diagnostic a user sees has (docs/diagnostics.md): a code (E or W and four digits), a
// message, and a place in a file of `sm` (a range within its text) unless it is one of the
// notes about the limits (E0007, W0001), which belong to no place; notes with a place have one
// within their file too.
void require_located_diagnostics(const char* target, const diag::SourceManager& sm, const diag::DiagnosticEngine& diags);

}  // namespace sdv::fuzz
