// Fuzz target of the IR reader: the input as a .sdvir file through what `sdv check-ir` and
// `sdv run x.sdvir` do with it (ir::read_ir, the program hash, the size of each scenario's
// variant space). Properties: a program that reads is written back canonically (write_ir), that
// text reads again to the same program hash, and writing it again gives the same bytes.
#include <string>
#include <string_view>

#include "runtime/campaign/variants.h"
#include "runtime/ir/ir_io.h"
#include "tests/fuzz/targets/scratch.h"
#include "tests/fuzz/targets/targets.h"

using namespace sdv;

namespace {
constexpr const char* kTarget = "ir_reader";
}  // namespace

int sdv_fuzz_ir_reader(const uint8_t* data, size_t size) {
    auto r = ir::read_ir(std::string_view(reinterpret_cast<const char*>(data), size));
    if (!r.program) {
        if (r.error.empty()) fuzz::fail(kTarget, "rejected without an error message");
        return 0;
    }
    const std::string hash = ir::program_hash(*r.program);
    for (const auto& s : r.program->scenarios) (void)campaign::VariantSpace(s.vary).size();
    const std::string text = ir::write_ir(*r.program);
    auto back = ir::read_ir(text);
    if (!back.program) fuzz::fail(kTarget, "the canonical text of a valid program does not read back: " + back.error);
    if (ir::program_hash(*back.program) != hash) fuzz::fail(kTarget, "the program read back has another hash");
    if (ir::write_ir(*back.program) != text) fuzz::fail(kTarget, "writing the program read back gives other bytes");
    return 0;
}
