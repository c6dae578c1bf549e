// The formatter walks the token stream of a file that parsed, with two facts taken from the
// parse tree: which tokens start a statement (they begin a new line) and which tokens belong to
// top-level declarations (blank lines between them). Hidden-channel comments are re-attached
// to the token they precede or follow.
#include "compiler/syntax/format.h"

#include <SdvLexer.h>
#include <SdvParser.h>
#include <antlr4-runtime.h>

#include <vector>

#include "compiler/syntax/parser.h"
#include "compiler/syntax/utf8.h"

namespace sdv::compiler::syntax {
namespace {

using antlr4::Token;
using sdv_antlr::SdvLexer;
using sdv_antlr::SdvParser;

// Tells a parse tree's rule contexts from its terminals by ANTLR's double dispatch (accept)
// instead of dynamic_cast: under libFuzzer every dynamic_cast into these hierarchies compares
// type names with an intercepted strcmp, and marking was a sixth of the fuzz target's time.
class NodeKind final : public antlr4::tree::AbstractParseTreeVisitor {
public:
    // A node as one of the two: a rule context, or a terminal (a token or an error node).
    struct Node {
        antlr4::ParserRuleContext* rule = nullptr;
        antlr4::tree::TerminalNode* leaf = nullptr;
    };
    Node of(antlr4::tree::ParseTree* t) {
        node_ = {};
        t->accept(this);
        return node_;
    }

    antlrcpp::Any visitChildren(antlr4::tree::ParseTree* node) override {
        // Only RuleContext::accept comes here, and every rule context of a parser's tree is a
        // ParserRuleContext.
        node_.rule = static_cast<antlr4::ParserRuleContext*>(node);
        return {};
    }
    antlrcpp::Any visitTerminal(antlr4::tree::TerminalNode* node) override {
        node_.leaf = node;
        return {};
    }
    antlrcpp::Any visitErrorNode(antlr4::tree::ErrorNode* node) override {
        node_.leaf = node;
        return {};
    }

private:
    Node node_;
};

// What the parse tree says about each token, by token index: whether it starts a statement (it
// begins a new line) or a top-level item (blank lines between items), and the tokens spaced by
// the tree rather than by their text: arithmetic operators (`20 - 5`, `100 / 4`: never a sign or
// a unit's slash), signs of names and groups (`-(2 * i) m`), and the brackets of a repeated agent
// (`v[1..50]`).
struct Marks {
    explicit Marks(size_t tokens)
        : start(tokens), item(tokens), binary(tokens), glue_right(tokens), glue_left(tokens), group_open(tokens) {}
    std::vector<char> start, item, binary, glue_right, glue_left, group_open;

    static bool has(const std::vector<char>& set, size_t idx) { return idx < set.size() && set[idx] != 0; }
    static void add(std::vector<char>& set, size_t idx) {
        if (idx < set.size()) set[idx] = 1;
    }
};

void mark(antlr4::ParserRuleContext* ctx, Marks& marks, NodeKind& kind) {
    const size_t rule = ctx->getRuleIndex();
    bool statement = false;
    switch (rule) {
        case SdvParser::RuleItem:
        case SdvParser::RuleRoadStmt:
        case SdvParser::RuleJunctionStmt:
        case SdvParser::RuleMapStmt:
        case SdvParser::RuleScenarioStmt:
        case SdvParser::RuleVehicleStmt:
        case SdvParser::RuleLightStmt:
        case SdvParser::RuleVaryStmt:
        case SdvParser::RuleWaypoint:
        case SdvParser::RulePathPoint: statement = true; break;
        case SdvParser::RuleNode: {
            // Not the node a decorator applies to (`not maneuver ...` stays on one line): the
            // decorator alternative of nodeBody is the one that starts with a decorator.
            auto* parent = ctx->parent != nullptr ? kind.of(ctx->parent).rule : nullptr;
            auto* first = parent != nullptr && parent->getRuleIndex() == SdvParser::RuleNodeBody && !parent->children.empty()
                              ? kind.of(parent->children[0]).rule
                              : nullptr;
            statement = first == nullptr || first->getRuleIndex() != SdvParser::RuleDecorator;
            break;
        }
        default: break;
    }
    if (ctx->getStart() != nullptr) {
        const size_t first = ctx->getStart()->getTokenIndex();
        if (statement) Marks::add(marks.start, first);
        if (rule == SdvParser::RuleItem) Marks::add(marks.item, first);
    }
    // A waypoint's time and a phase's duration: a primary whose first factor is its own.
    const bool arith = rule == SdvParser::RulePrimary || rule == SdvParser::RuleLeadPrimary;
    const bool repeat = rule == SdvParser::RuleRepeat;
    const bool group = rule == SdvParser::RuleGroup || rule == SdvParser::RuleLeadFactor;
    for (auto* child : ctx->children) {
        const NodeKind::Node node = kind.of(child);
        if (node.rule != nullptr) {
            mark(node.rule, marks, kind);
            continue;
        }
        auto* leaf = node.leaf;
        if (leaf == nullptr) continue;
        const Token* token = leaf->getSymbol();
        const size_t idx = token->getTokenIndex();
        const size_t type = token->getType();
        if (arith && type != SdvLexer::STRING) Marks::add(marks.binary, idx);
        if (repeat || group) {
            const std::string text = leaf->getText();  // '[' and '(' have no token name
            if (repeat && (text == "[" || type == SdvLexer::DOTDOT)) {
                Marks::add(marks.glue_left, idx);
                Marks::add(marks.glue_right, idx);
            }
            if (group && text == "(") Marks::add(marks.group_open, idx);
        }
    }
    if (rule == SdvParser::RuleFactor) {
        // `-x`: the sign of a name factor (a quantity's sign is spaced as a unary sign below).
        if (ctx->children.size() == 2) {
            if (auto* sign = kind.of(ctx->children[0]).leaf) Marks::add(marks.glue_right, sign->getSymbol()->getTokenIndex());
        }
    } else if (rule == SdvParser::RuleGroup) {
        auto* g = static_cast<SdvParser::GroupContext*>(ctx);
        if (g->sign != nullptr) Marks::add(marks.glue_right, g->sign->getTokenIndex());
    }
}

constexpr size_t kLineWidth = 100;

bool binds_left(const std::string& t) { return t == "," || t == ")" || t == "]" || t == "." || t == ":" || t == "/" || t == "^" ||
                                               t == "²" || t == "³" || t == "%"; }
bool binds_right(const std::string& t) { return t == "(" || t == "[" || t == "." || t == "/" || t == "^" || t == "±" || t == "+-"; }

}  // namespace

std::optional<std::string> format(diag::FileId file, const diag::SourceManager& sm, diag::DiagnosticEngine& diags) {
    // One parse of the whole token stream, comments included, after the checks that bound the
    // parser's stack: SLL prediction, then full LL, each stopping at the first syntax error
    // (ANTLR's two stages). A file that does not parse goes through parse() for its diagnostics.
    // The file is lexed once, for the checks and the parse.
    if (!check_encoding(file, sm, diags)) return std::nullopt;  // reports why
    const std::string_view text = sm.contents(file);
    antlr4::ANTLRInputStream input(text.data(), text.size());
    SdvLexer lexer(&input);
    lexer.removeErrorListeners();
    antlr4::CommonTokenStream stream(&lexer);
    try {
        stream.fill();
    } catch (const std::exception& e) {
        diags.error("E0003", {{file, 0}, {file, 0}},
                    std::string("the parser failed on this file: ") + e.what());
        return std::nullopt;
    }
    if (!precheck(file, sm, stream.getTokens(), diags)) return std::nullopt;  // reports why
    SdvParser parser(&stream);
    parser.removeErrorListeners();
    parser.setErrorHandler(std::make_shared<antlr4::BailErrorStrategy>());
    auto* interpreter = parser.getInterpreter<antlr4::atn::ParserATNSimulator>();
    SdvParser::FileContext* tree = nullptr;
    for (const auto mode : {antlr4::atn::PredictionMode::SLL, antlr4::atn::PredictionMode::LL}) {
        interpreter->setPredictionMode(mode);
        try {
            tree = parser.file();
            break;
        } catch (const antlr4::ParseCancellationException&) {
            parser.reset();  // back to the first token
        }
    }
    if (tree == nullptr) {
        if (parse(file, sm, diags) != nullptr) {
            // Not expected: parse() accepts what full LL rejects. Say so rather than format.
            diags.error("E0003", {{file, 0}, {file, 0}}, "the formatter could not parse this file");
        }
        return std::nullopt;
    }
    Marks marks(stream.getTokens().size());
    NodeKind kind;
    mark(tree, marks, kind);
    size_t prev_idx = SIZE_MAX;

    std::string out;
    int depth = 0;
    bool line_empty = true;
    std::string prev;      // previous default-channel token text
    size_t prev_type = 0;
    bool first_item = true;
    bool prev_item_import = false;
    bool last_comment = false;  // the last line written is an own-line comment
    std::vector<size_t> paren_cols;  // columns just after each open '(' on the current line
    auto newline = [&] {
        while (!out.empty() && out.back() == ' ') out.pop_back();
        out += "\n";
        line_empty = true;
    };
    auto indent = [&] {
        if (line_empty) {
            out += std::string(static_cast<size_t>(std::max(depth, 0)) * 4, ' ');
            line_empty = false;
        }
    };
    const auto& all = stream.getTokens();
    for (size_t i = 0; i < all.size(); ++i) {
        Token* t = all[i];
        if (t->getType() == Token::EOF) break;
        if (t->getChannel() != Token::DEFAULT_CHANNEL) {
            if (t->getType() != SdvLexer::COMMENT) continue;
            // Own-line comment when a line break (or the file start) separates it from the
            // previous token; otherwise it trails that token.
            bool own_line = true;
            if (i > 0) {
                const Token* p = all[i - 1];
                own_line = p->getType() == SdvLexer::WS && p->getText().find('\n') != std::string::npos;
            }
            if (own_line) {
                if (!line_empty) newline();
                // A comment block documenting the next declaration takes the blank line before it.
                size_t next = i + 1;
                while (next < all.size() && all[next]->getChannel() != Token::DEFAULT_CHANNEL) ++next;
                if (!last_comment && next < all.size() && Marks::has(marks.item, all[next]->getTokenIndex()) && !first_item &&
                    !(all[next]->getType() == SdvLexer::IMPORT && prev_item_import) && out.size() >= 2 &&
                    out.substr(out.size() - 2) != "\n\n") {
                    out += "\n";
                }
                // Keep one blank line before a comment block if the source had one.
                if (i > 0 && all[i - 1]->getType() == SdvLexer::WS) {
                    const std::string ws = all[i - 1]->getText();
                    if (std::count(ws.begin(), ws.end(), '\n') >= 2 && !out.empty() && out != "\n" &&
                        out.size() >= 2 && out.substr(out.size() - 2) != "\n\n") {
                        out += "\n";
                    }
                }
                indent();
                out += t->getText();
                newline();
                last_comment = true;
            } else {
                // Trailing: back onto the line of the token it follows (a '{' already broke it).
                if (line_empty && !out.empty() && out.back() == '\n') out.pop_back();
                out += "  " + t->getText();
                newline();
            }
            continue;
        }
        const std::string tx = t->getType() == SdvLexer::PLUSMINUS ? "±" : t->getText();
        const size_t idx = t->getTokenIndex();
        if (tx == "}") {
            --depth;
            if (!line_empty) newline();
        } else if (Marks::has(marks.start, idx)) {
            if (!line_empty) newline();
            if (Marks::has(marks.item, idx)) {
                // A blank line between declarations; consecutive imports stay together.
                const bool import = t->getType() == SdvLexer::IMPORT;
                if (!first_item && !last_comment && !(import && prev_item_import) && out.size() >= 2 &&
                    out.substr(out.size() - 2) != "\n\n") {
                    out += "\n";
                }
                first_item = false;
                prev_item_import = import;
            } else if (i > 0 && all[i - 1]->getType() == SdvLexer::WS) {
                const std::string ws = all[i - 1]->getText();
                if (std::count(ws.begin(), ws.end(), '\n') >= 2 && out.size() >= 2 && out.substr(out.size() - 2) != "\n\n" &&
                    prev != "{") {
                    out += "\n";
                }
            }
        }
        // Long lists wrap after a comma, aligned with the open parenthesis.
        if (!line_empty && prev == "," && !paren_cols.empty()) {
            size_t width = 0, level = 0;
            for (size_t k = i; k < all.size(); ++k) {
                if (all[k]->getChannel() != Token::DEFAULT_CHANNEL) continue;
                const std::string w = all[k]->getText();
                if (level == 0 && (w == "," || w == ")")) break;
                if (w == "(" || w == "[") ++level;
                if (w == ")" || w == "]") --level;
                width += w.size() + 1;
            }
            const size_t col = out.size() - (out.rfind('\n') == std::string::npos ? 0 : out.rfind('\n') + 1);
            if (col + 1 + width > kLineWidth) {
                newline();
                out += std::string(paren_cols.back(), ' ');
                line_empty = false;
                out += tx;
                prev = tx;
                prev_type = t->getType();
                prev_idx = idx;
                last_comment = false;
                continue;
            }
        }
        if (line_empty) {
            indent();
        } else {
            const bool call = tx == "(" && !Marks::has(marks.group_open, idx) && (prev_type == SdvLexer::ID || (!prev.empty() && std::isalpha(static_cast<unsigned char>(prev[0])) &&
                                                                          prev_type != SdvLexer::AT && prev_type != SdvLexer::ORIGIN));
            const bool sign = (prev == "-" || prev == "+") && (prev_type != SdvLexer::PLUSMINUS);
            const bool unary = sign && !Marks::has(marks.binary, prev_idx) &&
                               (t->getType() == SdvLexer::INT || t->getType() == SdvLexer::FLOAT);
            if (Marks::has(marks.binary, idx) || Marks::has(marks.binary, prev_idx)) {
                out += " ";
            } else if (!(binds_left(tx) || binds_right(prev) || call || unary || Marks::has(marks.glue_left, idx) ||
                         Marks::has(marks.glue_right, prev_idx))) {
                out += " ";
            }
        }
        out += tx;
        last_comment = false;
        if (tx == "(") paren_cols.push_back(out.size() - (out.rfind('\n') == std::string::npos ? 0 : out.rfind('\n') + 1));
        if (tx == ")" && !paren_cols.empty()) paren_cols.pop_back();
        if (tx == "{") {
            ++depth;
            // Empty braces stay together.
            size_t k = i + 1;
            while (k < all.size() && all[k]->getChannel() != Token::DEFAULT_CHANNEL) ++k;
            if (k < all.size() && all[k]->getText() == "}") {
                out += "}";
                --depth;
                i = k;
                prev = "}";
                prev_type = all[k]->getType();
                prev_idx = all[k]->getTokenIndex();
                continue;
            }
            newline();
        } else if (tx == "}") {
            newline();
        }
        prev = tx;
        prev_type = t->getType();
        prev_idx = idx;
    }
    if (!line_empty) newline();
    while (out.size() >= 2 && out.substr(out.size() - 2) == "\n\n") out.pop_back();
    return out;
}

std::string string_literal(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

bool fits_string_literal(const std::string& s) {
    return s.find_first_of("\r\n") == std::string::npos && find_invalid_utf8(s) == std::string::npos;
}

std::string comment_text(const std::string& raw) {
    std::string out;
    for (size_t i = 0; i < raw.size();) {
        const auto c = static_cast<unsigned char>(raw[i]);
        const size_t n = utf8_sequence_length(raw, i);
        if (n == 0) {
            out += '?';
            ++i;
        } else if (n == 1 && (c < 0x20 || c == 0x7f)) {
            out += ' ';
            ++i;
        } else {
            out.append(raw, i, n);
            i += n;
        }
    }
    return out;
}

}  // namespace sdv::compiler::syntax
