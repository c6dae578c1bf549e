// Scenarios written in the tests as text, compiled as `sdv run` would (diagnostics shown as
// doctest messages when the text does not compile).
#pragma once

#include <doctest/doctest.h>

#include <optional>
#include <string>

#include "compiler/sema/compile.h"

namespace sdv::test {

inline std::optional<ir::Program> compile_text(const std::string& text) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    auto c = compiler::compile_source("test.sdv", text, sm, diags);
    if (!c.program) {
        for (const auto& d : diags.sorted()) MESSAGE(d.message);
    }
    return std::move(c.program);
}

}  // namespace sdv::test
