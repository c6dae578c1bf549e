// The front door of the compiler: text in, AST plus diagnostics out. This is the only part of
// the project that touches ANTLR (parser.cpp); everything after it works on the owned AST.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "compiler/ast/ast.h"
#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/source_manager.h"

namespace antlr4 {
class Token;
namespace atn {
class ParseInfo;
}
}

namespace sdv::compiler::syntax {

// Deepest nesting of braces, brackets, parentheses and decorators the parser accepts. Deeper
// input is rejected with E0004 before parsing, so pathological files cannot exhaust the stack.
inline constexpr int kMaxNesting = 128;
// Most `and` / `or` in one expectation: each one nests the expression one level deeper.
inline constexpr int kMaxOperators = 256;
// Syntax errors reported per file before the parser gives up on it.
inline constexpr int kMaxSyntaxErrors = 20;

// What ANTLR's adaptive prediction did in one parse, counted by its profiler: for tests that pin
// a grammar's cost to the input's size (fuzz findings 34 and 37).
struct ParseStats {
    long long decisions = 0;      // predictions made
    long long lookahead = 0;      // tokens they examined, summed
    long long max_lookahead = 0;  // most tokens one prediction examined
    long long full_context = 0;   // predictions that fell back to full-context (LL) prediction
};

// Parses one file. Returns the AST, or nullptr when the file has lexical or syntax errors
// (they are in `diags`). Never throws. With `stats`, the parser is profiled (slower) and its
// predictions are counted into it, however the parse ends.
std::unique_ptr<ast::File> parse(diag::FileId file, const diag::SourceManager& sm,
                                 diag::DiagnosticEngine& diags, ParseStats* stats = nullptr);
// Adds the predictions of a profiled ANTLR parser to `stats` (the .sdv and .btree parsers).
void add_parse_stats(antlr4::atn::ParseInfo info, ParseStats& stats);

// The encoding check parse() makes first: E0001 at the first byte that is not UTF-8. True when
// the text is valid UTF-8, which the lexer needs.
bool check_encoding(diag::FileId file, const diag::SourceManager& sm, diag::DiagnosticEngine& diags);

// The checks parse() makes after lexing and before it parses (stray characters, unterminated
// strings, nesting depth, expression length, a file declaring nothing), reported as parse()
// reports them; false when one fails. `tokens` are the file's tokens on every channel, as a
// CommonTokenStream over its text (valid UTF-8) holds them. A file that passes them cannot
// exhaust a parser's stack: for the formatter, which lexes and parses the whole stream itself.
bool precheck(diag::FileId file, const diag::SourceManager& sm,
              const std::vector<antlr4::Token*>& tokens, diag::DiagnosticEngine& diags);

// One line per token, `line:col KIND 'text'`, for `sdv compile --emit tokens`.
std::string dump_tokens(diag::FileId file, const diag::SourceManager& sm);

}  // namespace sdv::compiler::syntax
