// Fuzz target of the GeoScenario .btree front end: the input as a .btree file through what
// `sdv lint x.btree` does with it (compiler/gss/scenario.h convert_btrees: parse, lower to .sdv
// text; then compile that text), the diagnostics rendered as text and as JSON; and the
// converted text formatted as `sdv convert` does. Subtrees resolve in the reference's library
// (../shared/data) when it is there, as with --btree-path.
//
// Property: trees the converter accepts compile (no error located in the converted text).
#include <string>

#include "compiler/diag/render.h"
#include "compiler/gss/scenario.h"
#include "compiler/sema/compile.h"
#include "compiler/syntax/format.h"
#include "tests/fuzz/targets/scratch.h"
#include "tests/fuzz/targets/targets.h"

using namespace sdv;

int sdv_fuzz_btree(const uint8_t* data, size_t size) {
    const std::string path = fuzz::fresh_dir("btree") + "/input.btree";
    fuzz::write_file(path, std::string_view(reinterpret_cast<const char*>(data), size));
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    const compiler::gss::ConvertOptions options{fuzz::btree_library(), {}, ""};
    auto converted = compiler::gss::convert_btrees({path}, options, sm, diags);
    if (converted && !diags.has_errors()) {
        const std::string display = path + ".sdv";
        (void)compiler::compile_source(display, converted->text, sm, diags, fuzz::compile_options());
        fuzz::require_converted_text_compiles("btree", display, sm, diags);
        (void)compiler::syntax::format(sm.add_file(display, converted->text), sm, diags);
    }
    fuzz::require_located_diagnostics("btree", sm, diags);
    (void)diag::render_all_text(diags, sm);
    (void)diag::render_all_json(diags, sm);
    return 0;
}
