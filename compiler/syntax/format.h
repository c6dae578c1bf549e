// `sdv fmt`: the canonical layout of a .sdv file. One statement per line, four-space
// indentation per brace level, single spaces between tokens except where punctuation binds
// (calls, units, labels), a blank line between top-level declarations, at most one blank line
// kept between statements, comments kept where they were (own line or end of line). Formatting
// is idempotent and never changes the meaning: the output parses to the same AST.
#pragma once

#include <optional>
#include <string>

#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/source_manager.h"

namespace sdv::compiler::syntax {

// The formatted text, or nullopt when the file does not parse (diagnostics in `diags`).
std::optional<std::string> format(diag::FileId file, const diag::SourceManager& sm, diag::DiagnosticEngine& diags);

// `s` as a .sdv string literal: in double quotes, with '"' and '\\' escaped (what the front ends
// that write .sdv text, GeoScenario and recorded traffic, put around names and paths).
std::string string_literal(const std::string& s);
// Whether string_literal(s) reads back as `s`: valid UTF-8 without line breaks (a .sdv string
// holds nothing else, escaped or not).
bool fits_string_literal(const std::string& s);

// Text from an input file put into a `#` comment of generated .sdv text: one line of valid UTF-8,
// whatever the file holds. Control characters (line breaks included) become spaces and bytes
// that are not UTF-8 '?', so the text can neither end the comment and add statements nor make
// the generated file unreadable.
std::string comment_text(const std::string& raw);

}  // namespace sdv::compiler::syntax
