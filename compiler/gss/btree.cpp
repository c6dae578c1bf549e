// The .btree parser: ANTLR lexer → Denter (indentation into INDENT/DEDENT) → ANTLR parser →
// owned AST. Positions are mapped from ANTLR's code points to byte offsets.
#include "compiler/gss/btree.h"

#include "compiler/diag/suggest.h"
#include "compiler/syntax/parser.h"
#include "compiler/syntax/utf8.h"

#include <BtreeLexer.h>
#include <BtreeParser.h>
#include <antlr4-runtime.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <deque>

namespace sdv::compiler::gss {
namespace {

using antlr4::Token;
using sdv_btree_antlr::BtreeLexer;
using sdv_btree_antlr::BtreeParser;

struct CancelParse : std::exception {};

// Code point → byte offset mapping of one file.
struct Positions {
    diag::FileId file = 0;
    std::vector<uint32_t> offs;

    diag::SourceLocation loc(size_t cp) const { return {file, offs[std::min(cp, offs.size() - 1)]}; }
    diag::SourceRange range(size_t start_cp, size_t stop_cp) const { return {loc(start_cp), loc(stop_cp)}; }
    diag::SourceRange range(const Token* t) const {
        if (t->getType() == Token::EOF) return range(t->getStartIndex(), t->getStartIndex());
        return range(t->getStartIndex(), t->getStopIndex() + 1);
    }
};

// Sits between the lexer and the parser. A NL token carries the next line's indentation: blank
// lines are dropped, a deeper indentation opens a block (INDENT), a shallower one closes blocks
// (DEDENT) down to a level seen before. End of file closes every open block.
class Denter : public antlr4::TokenSource {
public:
    Denter(BtreeLexer& lexer, const Positions& pos, diag::DiagnosticEngine& diags)
        : lexer_(lexer), pos_(pos), diags_(diags) {}

    std::unique_ptr<Token> nextToken() override {
        if (pending_.empty()) fill();
        auto t = std::move(pending_.front());
        pending_.pop_front();
        return t;
    }
    size_t getLine() const override { return lexer_.getLine(); }
    size_t getCharPositionInLine() override { return lexer_.getCharPositionInLine(); }
    antlr4::CharStream* getInputStream() override { return lexer_.getInputStream(); }
    std::string getSourceName() override { return lexer_.getSourceName(); }
    antlr4::TokenFactory<antlr4::CommonToken>* getTokenFactory() override {
        return lexer_.getTokenFactory();
    }

private:
    static constexpr int kTab = 4;  // a tab advances the indentation to the next multiple of 4

    std::unique_ptr<Token> synth(size_t type, const std::string& text, const Token& at) {
        // With a source, like the lexer's tokens: ANTLR's error recovery builds "missing"
        // tokens from the current one's source.
        auto t = std::make_unique<antlr4::CommonToken>(std::pair<antlr4::TokenSource*, antlr4::CharStream*>{this, lexer_.getInputStream()},
                                                       type, Token::DEFAULT_CHANNEL, at.getStartIndex(), at.getStartIndex());
        t->setText(text);
        t->setLine(at.getLine());
        t->setCharPositionInLine(at.getCharPositionInLine());
        t->setStartIndex(at.getStartIndex());
        t->setStopIndex(at.getStartIndex() == 0 ? 0 : at.getStartIndex() - 1);
        return t;
    }

    static int width(const std::string& nl_text) {
        int w = 0;
        for (char c : nl_text) {
            if (c == ' ') ++w;
            else if (c == '\t') w = (w / kTab + 1) * kTab;
        }
        return w;
    }

    // Brackets nest values (tuples, calls) that the builder walks recursively: refuse input that
    // nests deeper than the .sdv parser allows before it reaches the builder. A '(' right after a
    // name opens a call (CALL_OPEN, see grammar/Btree.g4), so the parser never has to look ahead
    // to tell a call from a name followed by a tuple.
    void track(Token& t) {
        const std::string text = t.getText();
        const bool opens_call = text == "(" && after_name_;
        after_name_ = t.getType() == BtreeParser::NAME;
        if (opens_call) {
            if (auto* w = dynamic_cast<antlr4::WritableToken*>(&t)) w->setType(BtreeParser::CALL_OPEN);
        }
        if (text == "(" || text == "[") {
            if (++brackets_ > syntax::kMaxNesting) {
                diags_.error("E0004", pos_.range(t.getStartIndex(), t.getStartIndex() + 1),
                             "nesting too deep: more than " + std::to_string(syntax::kMaxNesting) +
                                 " levels of brackets")
                    .notes.push_back({{}, "a value nests tuples and calls; flatten it"});
                throw CancelParse{};
            }
        } else if ((text == ")" || text == "]") && brackets_ > 0) {
            --brackets_;
        }
    }

    void close_all(const Token& at) {
        if (!last_was_nl_) pending_.push_back(synth(BtreeParser::NL, "\n", at));
        while (stack_.size() > 1) {
            stack_.pop_back();
            pending_.push_back(synth(BtreeParser::DEDENT, "<dedent>", at));
        }
    }

    void fill() {
        auto t = lexer_.nextToken();
        if (t->getType() == Token::EOF) {
            close_all(*t);
            pending_.push_back(std::move(t));
            return;
        }
        if (t->getType() != BtreeParser::NL) {
            if (first_) {
                first_ = false;
                // Indentation before the very first line opens no block.
                stack_.back() = static_cast<int>(t->getCharPositionInLine());
            }
            last_was_nl_ = false;
            track(*t);
            pending_.push_back(std::move(t));
            return;
        }
        // Collapse blank lines: only the last NL before real text counts.
        after_name_ = false;  // a '(' on the next line opens no call
        auto next = lexer_.nextToken();
        while (next->getType() == BtreeParser::NL) {
            t = std::move(next);
            next = lexer_.nextToken();
        }
        if (first_) {  // blank lines before the first declaration
            track(*next);
            pending_.push_back(std::move(next));
            if (pending_.back()->getType() != Token::EOF) {
                first_ = false;
                stack_.back() = static_cast<int>(pending_.back()->getCharPositionInLine());
            } else {
                pending_.pop_back();
                pending_.push_back(synth(Token::EOF, "<EOF>", *t));
            }
            return;
        }
        if (next->getType() == Token::EOF) {
            pending_.push_back(std::move(t));
            last_was_nl_ = true;
            close_all(*next);
            pending_.push_back(std::move(next));
            return;
        }
        const int w = width(t->getText());
        const Token& at = *next;
        pending_.push_back(std::move(t));
        last_was_nl_ = true;
        if (w > stack_.back()) {
            if (static_cast<int>(stack_.size()) > syntax::kMaxNesting) {
                diags_.error("E0004", pos_.range(at.getStartIndex(), at.getStartIndex() + 1),
                             "nesting too deep: more than " + std::to_string(syntax::kMaxNesting) + " levels of indentation")
                    .notes.push_back({{}, "split the tree into subtrees"});
                throw CancelParse{};
            }
            stack_.push_back(w);
            pending_.push_back(synth(BtreeParser::INDENT, "<indent>", at));
        } else {
            // The first level (the first line's indentation) is never closed: a line indented
            // less than the first one matches no block.
            while (stack_.size() > 1 && w < stack_.back()) {
                stack_.pop_back();
                pending_.push_back(synth(BtreeParser::DEDENT, "<dedent>", at));
            }
            if (w != stack_.back()) {
                // The columns beyond the enclosing block (all of them under the first level).
                const size_t start = at.getStartIndex();
                const auto extra = static_cast<size_t>(w > stack_.back() ? w - stack_.back() : w);
                diags_.error("E0901", pos_.range(start - std::min(start, extra), start),
                             "inconsistent indentation: this line is indented by " + std::to_string(w) +
                                 " columns, which matches no enclosing block")
                    .notes.push_back({{}, "a line closing a block must line up with a line above it"});
                stack_.push_back(w);  // recover: treat it as a new level
            }
        }
        track(*next);
        pending_.push_back(std::move(next));
    }

    BtreeLexer& lexer_;
    const Positions& pos_;
    diag::DiagnosticEngine& diags_;
    std::deque<std::unique_ptr<Token>> pending_;
    std::vector<int> stack_{0};
    bool first_ = true;
    bool last_was_nl_ = true;
    int brackets_ = 0;
    bool after_name_ = false;  // the last token passed on was a NAME
};

class ErrorListener : public antlr4::BaseErrorListener {
public:
    ErrorListener(const Positions& pos, diag::DiagnosticEngine& diags) : pos_(pos), diags_(diags) {}

    void syntaxError(antlr4::Recognizer* recognizer, Token* offending, size_t, size_t, const std::string& msg,
                     std::exception_ptr) override {
        if (offending != nullptr && last_ >= 0 && static_cast<long>(offending->getTokenIndex()) < last_ + 4) return;
        if (offending != nullptr) last_ = static_cast<long>(offending->getTokenIndex());
        ++count_;
        // Without an offending token (none is known), the error is at the end of the text.
        const size_t end = pos_.offs.empty() ? 0 : pos_.offs.size() - 1;
        diag::SourceRange range = pos_.offs.empty() ? diag::SourceRange{{pos_.file, 0}, {pos_.file, 0}} : pos_.range(end, end);
        std::string found = "end of file";
        if (offending != nullptr) {
            range = pos_.range(offending);
            switch (offending->getType()) {
                case Token::EOF: break;
                case BtreeParser::NL: found = "end of line"; break;
                case BtreeParser::INDENT: found = "a deeper indentation"; break;
                case BtreeParser::DEDENT: found = "the end of the block"; break;
                default: found = "'" + offending->getText() + "'";
            }
        }
        auto& d = diags_.error("E0003", range, "syntax error: unexpected " + found);
        if (auto* parser = dynamic_cast<antlr4::Parser*>(recognizer)) {
            if (auto e = expected(*parser); !e.empty()) d.notes.push_back({{}, "expected " + e});
        } else if (!msg.empty()) {
            d.notes.push_back({{}, msg});
        }
        if (count_ >= syntax::kMaxSyntaxErrors) throw CancelParse{};
    }

    int count() const { return count_; }

private:
    static std::string expected(antlr4::Parser& parser) {
        antlr4::misc::IntervalSet set;
        try {
            set = parser.getExpectedTokens();
        } catch (...) {
            return "";
        }
        std::vector<std::string> names;
        const auto& vocab = parser.getVocabulary();
        for (ssize_t t : set.toList()) {
            if (t < 0) names.emplace_back("end of file");
            else if (t == BtreeParser::NAME) names.emplace_back("a name");
            else if (t == BtreeParser::NUMBER) names.emplace_back("a number");
            else if (t == BtreeParser::NL) names.emplace_back("end of line");
            else if (t == BtreeParser::INDENT) names.emplace_back("an indented block");
            else if (t == BtreeParser::DEDENT) names.emplace_back("the end of the block");
            else if (t == BtreeParser::CALL_OPEN) names.emplace_back("'('");
            else if (auto lit = vocab.getLiteralName(static_cast<size_t>(t)); !lit.empty()) names.push_back(lit);
        }
        // CALL_OPEN and a tuple's '(' read the same: name each once, in the order found.
        std::vector<std::string> unique;
        for (auto& n : names) {
            if (std::find(unique.begin(), unique.end(), n) == unique.end()) unique.push_back(std::move(n));
        }
        return diag::alternatives(unique);
    }

    const Positions& pos_;
    diag::DiagnosticEngine& diags_;
    int count_ = 0;
    long last_ = -1;
};

class Builder {
public:
    Builder(const Positions& pos, diag::DiagnosticEngine& diags) : pos_(pos), diags_(diags) {}

    BtFile build(BtreeParser::BtreeFileContext* ctx) {
        BtFile f;
        f.file = pos_.file;
        for (auto* t : ctx->treeDecl()) {
            BtTree tree;
            tree.name = t->NAME()->getText();
            tree.name_range = pos_.range(t->NAME()->getSymbol());
            tree.range = range(t);
            tree.root = node(t->node());
            f.trees.push_back(std::move(tree));
        }
        return f;
    }

private:
    diag::SourceRange range(antlr4::ParserRuleContext* c) const {
        const Token* stop = c->getStop();
        if (stop == nullptr || stop->getType() == Token::EOF || stop->getStopIndex() + 1 < c->getStart()->getStartIndex()) {
            return pos_.range(c->getStart()->getStartIndex(), c->getStart()->getStartIndex());
        }
        return pos_.range(c->getStart()->getStartIndex(), stop->getStopIndex() + 1);
    }

    BtNode node(BtreeParser::NodeContext* c) {
        BtNode n;
        if (auto* comp = c->composite()) {
            const std::string op = comp->op->getText();
            n.kind = op == "?" ? BtNode::Kind::fallback : op == "->" ? BtNode::Kind::sequence : BtNode::Kind::parallel;
            n.range = pos_.range(comp->op);
            for (auto* child : comp->node()) n.children.push_back(node(child));
            return n;
        }
        auto* leaf = c->leaf();
        if (auto* cond = leaf->condition()) {
            n.kind = BtNode::Kind::condition;
            n.label = cond->NAME()->getText();
            n.label_range = pos_.range(cond->NAME()->getSymbol());
            n.call = call(cond->call());
            n.range = range(cond);
        } else if (auto* man = leaf->maneuver()) {
            n.kind = BtNode::Kind::maneuver;
            n.label = man->NAME()->getText();
            n.label_range = pos_.range(man->NAME()->getSymbol());
            n.call = call(man->call());
            n.range = range(man);
        } else {
            auto* sub = leaf->subtree();
            n.kind = BtNode::Kind::subtree;
            n.label = sub->NAME()->getText();
            n.label_range = pos_.range(sub->NAME()->getSymbol());
            n.call.kind = BtValue::Kind::call;
            n.call.text = n.label;
            n.call.name_range = n.label_range;
            n.call.range = range(sub);
            for (auto* it : sub->item()) n.call.items.push_back(item(it));
            n.range = range(sub);
        }
        return n;
    }

    BtValue call(BtreeParser::CallContext* c) {
        BtValue v;
        v.kind = BtValue::Kind::call;
        v.text = c->NAME()->getText();
        v.name_range = pos_.range(c->NAME()->getSymbol());
        v.range = range(c);
        for (auto* it : c->item()) v.items.push_back(item(it));
        return v;
    }

    BtItem item(BtreeParser::ItemContext* c) {
        BtItem it;
        if (c->NAME()) {
            it.key = c->NAME()->getText();
            it.key_range = pos_.range(c->NAME()->getSymbol());
        }
        it.value = value(c->value());
        it.range = range(c);
        return it;
    }

    BtValue value(BtreeParser::ValueContext* c) {
        if (auto* n = dynamic_cast<BtreeParser::NumberValueContext*>(c)) {
            BtValue v;
            v.kind = BtValue::Kind::number;
            v.text = n->NUMBER()->getText();
            v.range = range(n);
            errno = 0;
            v.number = std::strtod(v.text.c_str(), nullptr);
            if (errno == ERANGE || !std::isfinite(v.number)) {
                diags_.error("E0005", v.range, "number '" + v.text + "' is out of range");
                v.number = 0.0;
            }
            return v;
        }
        if (auto* n = dynamic_cast<BtreeParser::NameValueContext*>(c)) {
            BtValue v;
            v.kind = BtValue::Kind::name;
            v.text = n->NAME()->getText();
            v.range = range(n);
            return v;
        }
        if (auto* n = dynamic_cast<BtreeParser::CallValueContext*>(c)) return call(n->call());
        auto* t = dynamic_cast<BtreeParser::TupleValueContext*>(c);
        BtValue v;
        v.kind = BtValue::Kind::tuple;
        v.range = range(t);
        for (auto* e : t->value()) {
            BtItem it;
            it.value = value(e);
            it.range = it.value.range;
            v.items.push_back(std::move(it));
        }
        return v;
    }

    const Positions& pos_;
    diag::DiagnosticEngine& diags_;
};

}  // namespace

std::optional<BtFile> parse_btree(diag::FileId file, const diag::SourceManager& sm, diag::DiagnosticEngine& diags,
                                  BtreeParseStats* stats) {
    const std::string_view text = sm.contents(file);
    if (size_t bad = syntax::find_invalid_utf8(text); bad != std::string_view::npos) {
        const auto at = static_cast<uint32_t>(bad);
        diags.error("E0001", {{file, at}, {file, at + 1}}, "invalid UTF-8 in the file");
        return std::nullopt;
    }
    Positions pos{file, syntax::code_point_offsets(text)};
    // Stray characters first: the lexer's ANY token would only derail the parser.
    const size_t errors_before = diags.error_count();
    antlr4::ANTLRInputStream input{std::string(text)};
    {
        BtreeLexer probe(&input);
        probe.removeErrorListeners();
        for (auto t = probe.nextToken(); t->getType() != Token::EOF; t = probe.nextToken()) {
            if (t->getType() == BtreeLexer::ANY) {
                diags.error("E0001", pos.range(t.get()), "unexpected character '" + t->getText() + "'");
                if (diags.error_count() - errors_before >= static_cast<size_t>(syntax::kMaxSyntaxErrors)) break;
            }
        }
        input.reset();
    }
    if (diags.error_count() > errors_before) return std::nullopt;
    try {
        BtreeLexer lexer(&input);
        lexer.removeErrorListeners();
        Denter denter(lexer, pos, diags);
        antlr4::CommonTokenStream tokens(&denter);
        BtreeParser parser(&tokens);
        parser.removeErrorListeners();
        ErrorListener listener(pos, diags);
        parser.addErrorListener(&listener);
        if (stats != nullptr) parser.setProfile(true);
        // Counted however the parse ends (a syntax error cancels it by throwing).
        struct Count {
            BtreeParser& parser;
            BtreeParseStats* stats;
            ~Count() {
                try {
                    if (stats != nullptr) syntax::add_parse_stats(parser.getParseInfo(), *stats);
                } catch (...) {  // a count lost, never a second exception while unwinding
                }
            }
        } count{parser, stats};
        auto* tree = parser.btreeFile();
        if (listener.count() > 0 || diags.error_count() > errors_before) return std::nullopt;
        Builder builder(pos, diags);
        BtFile f = builder.build(tree);
        if (diags.error_count() > errors_before) return std::nullopt;
        return f;
    } catch (const CancelParse&) {
        return std::nullopt;
    } catch (const std::exception& e) {
        diags.error("E0003", {{file, 0}, {file, 0}}, std::string("the .btree parser failed: ") + e.what());
        return std::nullopt;
    }
}

}  // namespace sdv::compiler::gss
