// Fuzz target of the .sdv front end: the input as a .sdv file through what `sdv lint`,
// `sdv compile` (IR, --emit ast, --emit tokens) and `sdv fmt` do with it: parse, check and
// lower (compiler::compile_source), the diagnostics rendered as text and as JSON, and the
// canonical layout. Properties besides not crashing: the IR exists only without errors, reads
// back (runtime/ir/ir_io.h) and is written again byte for byte; formatting is idempotent and its
// output parses (compiler/syntax/format.h promises both). It compiles with the lowered limits
// of fuzz::compile_options() (scratch.h): the IR's round trip costs about 2 ms per std.drive
// vehicle in the fuzz build, and a template of 100 bytes may declare 10,000 of them.
#include <string>

#include "compiler/ast/ast.h"
#include "compiler/diag/render.h"
#include "compiler/sema/compile.h"
#include "compiler/syntax/format.h"
#include "compiler/syntax/parser.h"
#include "runtime/ir/ir_io.h"
#include "tests/fuzz/targets/scratch.h"
#include "tests/fuzz/targets/targets.h"

using namespace sdv;

namespace {

constexpr const char* kTarget = "sdv_frontend";
// Relative imports resolve against a directory that does not exist: the input alone is read
// (the embedded std/ library still resolves).
constexpr const char* kPath = "/nonexistent/sdv-fuzz/input.sdv";

void render(const diag::DiagnosticEngine& diags, const diag::SourceManager& sm) {
    fuzz::require_located_diagnostics(kTarget, sm, diags);
    (void)diag::render_all_text(diags, sm);
    (void)diag::render_all_json(diags, sm);
}

// sdv lint / sdv compile.
void compile(const std::string& text) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    auto result = compiler::compile_source(kPath, text, sm, diags, fuzz::compile_options());
    render(diags, sm);
    if (!result.files.empty() && result.files[0]) (void)compiler::ast::dump(*result.files[0], sm);
    if (!result.program) return;
    if (diags.has_errors()) fuzz::fail(kTarget, "the IR exists although there were errors");
    const std::string ir = ir::write_ir(*result.program);
    auto back = ir::read_ir(ir);
    if (!back.program) fuzz::fail(kTarget, "the IR the compiler wrote does not read back: " + back.error);
    // Written again, the program read back is the same text: a stronger property than an equal
    // program hash, at two thirds of its cost (the IR's JSON is most of an execution's time).
    if (ir::write_ir(*back.program) != ir) fuzz::fail(kTarget, "the IR read back writes other text");
}

// sdv fmt (and sdv compile --emit tokens).
void format(const std::string& text) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    const auto id = sm.add_file(kPath, text);
    (void)compiler::syntax::dump_tokens(id, sm);
    auto formatted = compiler::syntax::format(id, sm, diags);
    render(diags, sm);
    if (!formatted) return;
    if (*formatted == text) return;  // formatting it again would repeat this very call
    diag::SourceManager sm2;
    diag::DiagnosticEngine diags2;
    auto again = compiler::syntax::format(sm2.add_file(kPath, *formatted), sm2, diags2);
    if (!again) fuzz::fail(kTarget, "the formatted text does not parse");
    if (*again != *formatted) fuzz::fail(kTarget, "formatting is not idempotent");
}

}  // namespace

int sdv_fuzz_sdv_frontend(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    compile(text);
    format(text);
    return 0;
}
