// The GeoScenario `.btree` front end, part 1: the owned AST of a .btree file and its parser
// (grammar/Btree.g4, with the indentation turned into INDENT/DEDENT tokens here). Every node
// keeps its source range so that the lowering (gss/lower.h) can point back into the file.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/source_manager.h"
#include "compiler/syntax/parser.h"

namespace sdv::compiler::gss {

using diag::SourceRange;

struct BtItem;

// A value: a number, a constant name (LEFT, GOAL_POINT, True), a call (MP(14,10,6),
// MVelKeepConfig(vel=...)) or a tuple ((5, -3, 0)).
struct BtValue {
    enum class Kind { number, name, call, tuple } kind = Kind::number;
    double number = 0.0;
    std::string text;          // the number or name as written; the callee of a call
    std::vector<BtItem> items;  // call arguments (named or positional); tuple elements
    SourceRange range;
    SourceRange name_range;    // the callee of a call
};

struct BtItem {
    std::optional<std::string> key;  // `vel=` in `vel=MP(...)`; empty for positional values
    SourceRange key_range;
    BtValue value;
    SourceRange range;
};

struct BtNode {
    enum class Kind { fallback, sequence, parallel, condition, maneuver, subtree } kind = Kind::sequence;
    std::string label;      // the leaf's name (`c_goal`, `m_follow_lead`); the subtree's name
    SourceRange label_range;
    BtValue call;           // condition / maneuver: the call; subtree: its overrides as items
    std::vector<BtNode> children;
    SourceRange range;      // the whole line of a leaf; the operator of a composite
};

struct BtTree {
    std::string name;
    SourceRange name_range;
    BtNode root;
    SourceRange range;
};

struct BtFile {
    diag::FileId file = 0;
    std::vector<BtTree> trees;
};

// What the parser's adaptive prediction did on one file: for tests that pin the grammar's cost
// to the input's size (fuzz finding 34: calls nested a hundred deep took ANTLR seconds).
using BtreeParseStats = syntax::ParseStats;

// Parses one .btree file. Returns nullopt when it has lexical, indentation or syntax errors
// (reported in `diags` with E0001, E0003 or E0901). Never throws. With `stats`, the parser is
// profiled (slower) and its prediction counts are added there.
std::optional<BtFile> parse_btree(diag::FileId file, const diag::SourceManager& sm, diag::DiagnosticEngine& diags,
                                  BtreeParseStats* stats = nullptr);

}  // namespace sdv::compiler::gss
