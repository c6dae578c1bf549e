// The ANTLR adapter: lexing, the pre-parse checks (encoding, stray characters, unterminated
// strings, nesting depth), the parse with capped error recovery, and the parse-tree → AST
// builder. ANTLR counts positions in code points; the builder maps them to byte offsets.
// A file is parsed and built a chunk of top-level items at a time, from compact tokens, so that
// a 10 MB file never holds all its ANTLR tokens or its whole parse tree at once.
#include "compiler/syntax/parser.h"

#include "compiler/diag/suggest.h"
#include "compiler/syntax/utf8.h"
#include "runtime/catalog/units.h"

#include <SdvLexer.h>
#include <SdvParser.h>
#include <antlr4-runtime.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace sdv::compiler::syntax {
namespace {

using antlr4::Token;
using sdv_antlr::SdvLexer;
using sdv_antlr::SdvParser;

struct CancelParse : std::exception {};

// The byte offset of every code point, plus one for the end of the text: ANTLR counts code
// points, diagnostics count bytes. An ASCII text, the usual case, needs no table (40 MB for a
// 10 MB file): there, code points are bytes.
class CodePoints {
public:
    explicit CodePoints(std::string_view text) : size_(text.size() + 1) {
        const bool ascii = std::all_of(text.begin(), text.end(), [](char c) {
            return static_cast<unsigned char>(c) < 0x80;
        });
        if (!ascii) {
            offs_ = code_point_offsets(text);
            size_ = offs_.size();
        }
    }

    size_t size() const { return size_; }
    uint32_t operator[](size_t cp) const {
        return offs_.empty() ? static_cast<uint32_t>(cp) : offs_[cp];
    }

private:
    size_t size_;
    std::vector<uint32_t> offs_;
};

// The source as ANTLR's lexer reads it, code point by code point, decoded from the UTF-8 text
// in place: ANTLRInputStream would first convert a 10 MB file into a 200 MB UTF-32 string.
// Same contract as ANTLRInputStream; the text is valid UTF-8 (checked before).
class Utf8Stream : public antlr4::CharStream {
public:
    Utf8Stream(std::string_view text, const CodePoints& cps) : text_(text), cps_(cps) {}

    void consume() override {
        if (p_ + 1 >= cps_.size()) throw antlr4::IllegalStateException("cannot consume EOF");
        ++p_;
    }
    size_t LA(ssize_t i) override {
        if (i == 0) return 0;  // undefined
        const ssize_t at = static_cast<ssize_t>(p_) + (i < 0 ? i : i - 1);
        if (at < 0 || static_cast<size_t>(at) + 1 >= cps_.size()) return EOF;
        return decode(cps_[static_cast<size_t>(at)]);
    }
    ssize_t mark() override { return -1; }
    void release(ssize_t) override {}
    size_t index() override { return p_; }
    void seek(size_t index) override { p_ = std::min(index, cps_.size() - 1); }
    size_t size() override { return cps_.size() - 1; }
    std::string getSourceName() const override { return UNKNOWN_SOURCE_NAME; }
    std::string getText(const antlr4::misc::Interval& interval) override {
        const size_t n = cps_.size() - 1;
        const auto start = static_cast<size_t>(interval.a);
        if (start >= n) return "";
        const size_t stop = std::min(static_cast<size_t>(interval.b), n - 1);
        if (stop < start) return "";
        return std::string(text_.substr(cps_[start], cps_[stop + 1] - cps_[start]));
    }
    std::string toString() const override { return std::string(text_); }

private:
    size_t decode(size_t byte) const {
        const auto c = static_cast<unsigned char>(text_[byte]);
        if (c < 0x80) return c;
        const size_t n = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : 1;
        size_t cp = c & (0x3Fu >> n);
        for (size_t k = 1; k <= n; ++k) {
            cp = (cp << 6) | (static_cast<unsigned char>(text_[byte + k]) & 0x3Fu);
        }
        return cp;
    }

    std::string_view text_;
    const CodePoints& cps_;
    size_t p_ = 0;
};

// Reports syntax errors as diagnostics and stops the parse after kMaxSyntaxErrors.
class ErrorListener : public antlr4::BaseErrorListener {
public:
    ErrorListener(diag::FileId file, const CodePoints& offs, diag::DiagnosticEngine& diags)
        : file_(file), offs_(offs), diags_(diags) {}

    void syntaxError(antlr4::Recognizer* recognizer, Token* offending, size_t, size_t,
                     const std::string& msg, std::exception_ptr) override {
        // One mistake often derails the next few tokens: report an error only when the parser
        // got at least a few tokens past the previous one.
        if (offending != nullptr && last_ >= 0 &&
            static_cast<long>(offending->getTokenIndex()) < last_ + 4) {
            return;
        }
        if (offending != nullptr) last_ = static_cast<long>(offending->getTokenIndex());
        ++count_;
        // Without an offending token (none is known), the error is at the end of the text.
        const uint32_t end = offs_[offs_.size() - 1];
        diag::SourceRange range{{file_, end}, {file_, end}};
        std::string found = "end of file";
        if (offending != nullptr) {
            const size_t start = std::min(offending->getStartIndex(), offs_.size() - 1);
            size_t stop = offending->getStopIndex() + 1;
            if (offending->getType() == Token::EOF) stop = start;
            stop = std::min(std::max(stop, start), offs_.size() - 1);
            range = {{file_, offs_[start]}, {file_, offs_[stop]}};
            if (offending->getType() != Token::EOF) found = "'" + offending->getText() + "'";
        }
        // A word right after a number that is not a unit: say so rather than "syntax error".
        if (auto* parser = dynamic_cast<antlr4::Parser*>(recognizer);
            parser != nullptr && offending != nullptr && offending->getTokenIndex() > 0) {
            Token* prev = parser->getTokenStream()->get(offending->getTokenIndex() - 1);
            const auto type = offending->getType();
            if ((prev->getType() == SdvParser::INT || prev->getType() == SdvParser::FLOAT) &&
                type == SdvParser::ID) {
                std::vector<std::string> units;
                for (const auto& u : catalog::all_units()) units.emplace_back(u.spelling);
                last_range_ = range;
                auto& d = diags_.error("E0203", range, "unknown unit '" + offending->getText() + "'");
                if (auto m = diag::closest_match(offending->getText(), units)) {
                    d.notes.push_back({{}, "did you mean '" + *m + "'?"});
                }
                d.notes.push_back({{}, "units are listed in `sdv catalog` and docs/language.md"});
                if (count_ >= kMaxSyntaxErrors) throw CancelParse{};
                return;
            }
        }
        std::string expected;
        if (auto* parser = dynamic_cast<antlr4::Parser*>(recognizer)) {
            expected = describe_expected(*parser);
        }
        last_range_ = range;
        auto& d = diags_.error("E0003", range, "syntax error: unexpected " + found);
        if (!expected.empty()) {
            d.notes.push_back({{}, "expected " + expected});
        } else if (msg.rfind("no viable alternative", 0) != 0 && !msg.empty()) {
            d.notes.push_back({{}, msg});
        }
        if (count_ >= kMaxSyntaxErrors) throw CancelParse{};
    }

    int count() const { return count_; }
    // Where the last syntax error reported is: where the parse stops after too many.
    diag::SourceRange last_range() const { return last_range_; }

private:
    static std::string describe_expected(antlr4::Parser& parser) {
        antlr4::misc::IntervalSet set;
        try {
            set = parser.getExpectedTokens();
        } catch (...) {
            return "";
        }
        const auto& vocab = parser.getVocabulary();
        std::vector<std::string> names;
        bool name_like = false;
        for (ssize_t t : set.toList()) {
            if (t < 0) {  // end of file
                names.push_back("end of file");
                continue;
            }
            std::string lit = vocab.getLiteralName(static_cast<size_t>(t));
            if (t == SdvParser::ID || (!lit.empty() && std::isalpha(static_cast<unsigned char>(lit[1])))) {
                name_like = true;  // keywords double as names; list them as "a name"
                continue;
            }
            if (!lit.empty()) {
                names.push_back(lit);
            } else {
                std::string sym = vocab.getSymbolicName(static_cast<size_t>(t));
                if (sym == "INT" || sym == "FLOAT") sym = "a number";
                else if (sym == "STRING") sym = "a string";
                else if (sym == "PLUSMINUS") sym = "'±'";
                else continue;
                if (std::find(names.begin(), names.end(), sym) == names.end()) names.push_back(sym);  // INT, FLOAT
            }
        }
        if (name_like) names.insert(names.begin(), "a name");
        return diag::alternatives(names);
    }

    diag::FileId file_;
    const CodePoints& offs_;
    diag::DiagnosticEngine& diags_;
    int count_ = 0;
    long last_ = -1;
    diag::SourceRange last_range_{};
};

// Builds the owned AST from the parse trees of a file that had no syntax errors, one chunk of
// items at a time. Its own diagnostics wait in `pending` until the whole file has parsed: a file
// with a syntax error reports only that, as if it had been parsed in one piece.
class Builder {
public:
    Builder(diag::FileId file, const CodePoints& offs, std::vector<diag::Diagnostic>& pending)
        : file_(file), offs_(offs), pending_(pending) {}

    void add(SdvParser::FileContext* ctx, ast::File& f) {
        for (auto* item : ctx->item()) {
            if (auto* c = item->importDecl()) f.imports.push_back(import_decl(c));
            if (auto* c = item->roadDecl()) f.roads.push_back(road(c));
            if (auto* c = item->junctionDecl()) f.junctions.push_back(junction(c));
            if (auto* c = item->mapDecl()) f.maps.push_back(map(c));
            if (auto* c = item->treeDecl()) f.trees.push_back(tree(c));
            if (auto* c = item->scenarioDecl()) f.scenarios.push_back(scenario(c));
        }
    }

private:
    diag::Diagnostic& error(std::string code, diag::SourceRange range, std::string message) {
        diag::Diagnostic& d = pending_.emplace_back();
        d.code = std::move(code);
        d.range = range;
        d.message = std::move(message);
        return d;
    }

    // The text of a rule that spans one token (ident, number, unitAtom): the token's own,
    // without RuleContext::getText's string stream.
    static std::string spelling(antlr4::ParserRuleContext* c) { return c->getStart()->getText(); }

    diag::SourceLocation loc(size_t cp) const {
        return {file_, offs_[std::min(cp, offs_.size() - 1)]};
    }
    diag::SourceRange range(Token* t) const {
        return {loc(t->getStartIndex()), loc(t->getStopIndex() + 1)};
    }
    diag::SourceRange range(antlr4::tree::TerminalNode* n) const { return range(n->getSymbol()); }
    diag::SourceRange range(antlr4::ParserRuleContext* c) const {
        Token* stop = c->getStop();
        if (stop == nullptr || stop->getType() == Token::EOF ||
            stop->getStopIndex() + 1 < c->getStart()->getStartIndex()) {
            return {loc(c->getStart()->getStartIndex()), loc(c->getStart()->getStartIndex())};
        }
        return {loc(c->getStart()->getStartIndex()), loc(stop->getStopIndex() + 1)};
    }

    ast::Ident ident(SdvParser::IdentContext* c) { return {spelling(c), range(c)}; }

    ast::QualName qual(SdvParser::QualNameContext* c) {
        ast::QualName q;
        for (auto* i : c->ident()) q.parts.push_back(ident(i));
        q.range = range(c);
        return q;
    }

    static std::string unescape(const std::string& quoted) {
        std::string out;
        for (size_t i = 1; i + 1 < quoted.size(); ++i) {
            char ch = quoted[i];
            if (ch == '\\' && i + 2 < quoted.size()) {
                char e = quoted[++i];
                switch (e) {
                    case 'n': out += '\n'; break;
                    case 't': out += '\t'; break;
                    default: out += e;
                }
            } else {
                out += ch;
            }
        }
        return out;
    }

    ast::ImportDecl import_decl(SdvParser::ImportDeclContext* c) {
        ast::ImportDecl d;
        d.path = unescape(c->STRING()->getText());
        d.path_range = range(c->STRING());
        if (c->ident()) d.alias = ident(c->ident());
        d.range = range(c);
        return d;
    }

    // A number token, with overflow reported (E0005) instead of silently becoming inf.
    double number(SdvParser::NumberContext* c) {
        const std::string written = spelling(c);
        std::string digits;
        for (char ch : written) {
            if (ch != '_') digits += ch;
        }
        errno = 0;
        double v = std::strtod(digits.c_str(), nullptr);
        if (errno == ERANGE || !std::isfinite(v)) {
            if (std::isinf(v) || std::fabs(v) > 1.0) {
                error("E0005", range(c), "number '" + written + "' is out of range")
                    .notes.push_back({{}, "numbers must be finite double-precision values "
                                          "(magnitude below 1.8e308)"});
                v = 0.0;
            } else {
                v = 0.0;  // underflow to zero is harmless
            }
        }
        return v;
    }

    ast::Quantity quantity(SdvParser::QuantityContext* c) { return quantity(c->number(), c->sign, c->unit()); }

    // A number, its sign ('-', '+' or none) and its unit (or none).
    ast::Quantity quantity(SdvParser::NumberContext* n, Token* sign, SdvParser::UnitContext* u) {
        ast::Quantity q;
        q.value = number(n);
        q.text = spelling(n);
        q.is_integer = n->INT() != nullptr;
        if (sign != nullptr && sign->getText() == "-") {
            q.value = -q.value;
            q.text = "-" + q.text;
        }
        if (u != nullptr) {
            q.unit = canonical_unit(u);
            q.unit_range = range(u);
        }
        return q;
    }

    // "m/s²", "m/s2", "m/s^2" → "m/s^2".
    static std::string canonical_unit(SdvParser::UnitContext* u) {
        if (u->PERCENT()) return "%";
        std::string out;
        for (auto* child : u->children) {
            auto* rule = dynamic_cast<antlr4::ParserRuleContext*>(child);
            const std::string t = rule != nullptr ? spelling(rule) : child->getText();
            if (t == "²") out += "^2";
            else if (t == "³") out += "^3";
            else if (t == "s2") out += "s^2";
            else if (t == "s3") out += "s^3";
            else out += t;
        }
        return out;
    }

    ast::Primary primary(SdvParser::PrimaryContext* c) {
        ast::Primary p;
        p.range = range(c);
        if (c->STRING() != nullptr) {
            p.kind = ast::Primary::Kind::string;
            p.string = unescape(c->STRING()->getText());
            return p;
        }
        return of_arith(arith(c), std::move(p));
    }

    // A primary whose first factor is a number or a parenthesis (a waypoint's time, a phase's
    // duration; never a lone name).
    ast::Primary primary(SdvParser::LeadPrimaryContext* c) {
        ast::Primary p;
        p.range = range(c);
        return of_arith(arith(c), std::move(p));
    }

    // `p` with the arithmetic of its primary: a lone quantity or name as such, else the expression.
    static ast::Primary of_arith(ast::Arith e, ast::Primary p) {
        if (e.kind == ast::Arith::Kind::quantity) {
            p.kind = ast::Primary::Kind::quantity;
            p.quantity = std::move(e.quantity);
        } else if (e.kind == ast::Arith::Kind::name && !e.negate) {
            p.kind = ast::Primary::Kind::name;
            p.name = std::move(e.name);
        } else {
            p.kind = ast::Primary::Kind::expr;
            p.expr = std::make_shared<const ast::Arith>(std::move(e));
        }
        return p;
    }

    // A single value of one primary.
    static ast::Value single(ast::Primary p) {
        ast::Value v;
        v.kind = ast::Value::Kind::single;
        v.range = p.range;
        v.lo = std::move(p);
        return v;
    }

    // Factors and operators as written, precedence applied: a sum of products. A sum of one
    // term is the term, a product of one factor the factor (a lone number stays a quantity).
    // Recursion is bounded by the parentheses, which the nesting limit caps. `c` is a primary
    // or a lead primary (a waypoint's time, a phase's duration: the same factors and operators
    // after a first factor of its own).
    template <class Context>
    ast::Arith arith(Context* c) {
        // The operands in order: factors, and divisors after `/`.
        std::vector<antlr4::ParserRuleContext*> operands;
        for (auto* child : c->children) {
            if (auto* rule = dynamic_cast<antlr4::ParserRuleContext*>(child)) operands.push_back(rule);
        }
        if (operands.size() == 1) return operand(operands[0]);
        std::vector<ast::Arith> terms;
        std::vector<char> sum_ops;
        ast::Arith product;
        product.kind = ast::Arith::Kind::product;
        auto close = [&](antlr4::ParserRuleContext* last) {
            if (product.operands.size() == 1) {
                terms.push_back(std::move(product.operands[0]));
            } else {
                product.range.end = range(last).end;
                terms.push_back(std::move(product));
            }
            product = {};
            product.kind = ast::Arith::Kind::product;
        };
        for (size_t k = 0; k < operands.size(); ++k) {
            if (product.operands.empty()) product.range = range(operands[k]);
            product.operands.push_back(operand(operands[k]));
            if (k + 1 == operands.size()) {
                close(operands[k]);
                break;
            }
            const char op = c->op[k]->getText()[0];
            if (op == '*' || op == '/') {
                product.ops.push_back(op);
            } else {
                close(operands[k]);
                sum_ops.push_back(op);
            }
        }
        if (terms.size() == 1) return std::move(terms[0]);
        ast::Arith a;
        a.kind = ast::Arith::Kind::sum;
        a.range = range(c);
        a.operands = std::move(terms);
        a.ops = std::move(sum_ops);
        return a;
    }

    ast::Arith operand(antlr4::ParserRuleContext* c) {
        ast::Arith a;
        a.range = range(c);
        SdvParser::QuantityContext* q = nullptr;
        SdvParser::GroupContext* g = nullptr;
        if (auto* f = dynamic_cast<SdvParser::QuantityFactorContext*>(c)) {
            q = f->quantity();
        } else if (auto* n = dynamic_cast<SdvParser::NameFactorContext*>(c)) {
            a.kind = ast::Arith::Kind::name;
            a.name = qual(n->qualName());
            a.negate = n->sign != nullptr;
            return a;
        } else if (auto* gf = dynamic_cast<SdvParser::GroupFactorContext*>(c)) {
            g = gf->group();
        } else if (auto* d = dynamic_cast<SdvParser::DivisorContext*>(c)) {
            q = d->quantity();
            g = d->group();
        } else if (auto* lq = dynamic_cast<SdvParser::LeadQuantityContext*>(c)) {
            a.kind = ast::Arith::Kind::quantity;
            a.quantity = quantity(lq->number(), nullptr, lq->unit());
            return a;
        } else if (auto* lg = dynamic_cast<SdvParser::LeadGroupContext*>(c)) {
            return group(lg->primary(), nullptr, lg->unit(), a);
        }
        if (q != nullptr) {
            a.kind = ast::Arith::Kind::quantity;
            a.quantity = quantity(q);
        } else if (g != nullptr) {
            return group(g->primary(), g->sign, g->unit(), a);
        }
        return a;
    }

    // A parenthesis: its primary, its sign ('-' or none) and the unit after it, into `a`.
    ast::Arith group(SdvParser::PrimaryContext* inner, Token* sign, SdvParser::UnitContext* u, ast::Arith& a) {
        a.kind = ast::Arith::Kind::group;
        a.negate = sign != nullptr;
        if (inner->STRING() != nullptr) {
            error("E0003", range(inner), "syntax error: a string cannot be part of arithmetic");
            a.operands.push_back({});
        } else {
            a.operands.push_back(arith(inner));
        }
        if (u != nullptr) {
            a.unit = canonical_unit(u);
            a.unit_range = range(u);
        }
        return std::move(a);
    }

    ast::Samples samples(SdvParser::SamplesContext* c) {
        ast::Samples s;
        const std::string text = c->INT()->getText();
        errno = 0;
        long long n = std::strtoll(text.c_str(), nullptr, 10);
        s.count = (errno == ERANGE) ? -1 : n;  // the checker reports out-of-range counts
        s.count_range = range(c->INT());
        if (auto* m = c->method()) {
            s.method = ident(m->ident());
            if (auto* v = m->value()) {
                auto* sv = dynamic_cast<SdvParser::ScalarValueContext*>(v);
                if (sv != nullptr && !sv->spread() && sv->DOTDOT() == nullptr && !sv->samples()) {
                    s.method_arg = primary(sv->primary(0));
                } else {
                    error("E0003", range(v), "syntax error: expected a single quantity "
                                             "as the distribution's parameter");
                }
            }
        }
        s.range = range(c);
        return s;
    }

    ast::Value value(SdvParser::ValueContext* c) {
        ast::Value v;
        v.range = range(c);
        if (auto* s = dynamic_cast<SdvParser::ScalarValueContext*>(c)) {
            const bool interval = s->DOTDOT() != nullptr;
            v.kind = interval ? ast::Value::Kind::interval : ast::Value::Kind::single;
            v.lo = primary(s->primary(0));
            if (interval) v.hi = primary(s->primary(1));
            if (auto* sp = s->spread()) v.spread = primary(sp->primary());
            if (auto* sm = s->samples()) v.samples = samples(sm);
        } else if (auto* lv = dynamic_cast<SdvParser::ListValueContext*>(c)) {
            v.kind = ast::Value::Kind::list;
            for (auto* item : lv->value()) v.items.push_back(value(item));
        }
        return v;
    }

    std::vector<ast::Arg> args(SdvParser::ArgListContext* c) {
        std::vector<ast::Arg> out;
        if (c == nullptr) return out;
        const auto list = c->arg();
        out.reserve(list.size());  // an Arg is 1 kB: no spare capacity in a 10 MB file's AST
        for (auto* a : list) out.push_back({qual(a->qualName()), value(a->value()), range(a)});
        return out;
    }

    ast::Setting setting(antlr4::tree::TerminalNode* key, std::vector<SdvParser::ValueContext*> vs,
                         antlr4::ParserRuleContext* whole) {
        ast::Setting s;
        s.key = {key->getText(), range(key)};
        for (auto* v : vs) s.values.push_back(value(v));
        s.range = range(whole);
        return s;
    }

    ast::RoadDecl road(SdvParser::RoadDeclContext* c) {
        ast::RoadDecl r;
        r.name = ident(c->ident());
        r.range = range(c);
        for (auto* st : c->roadStmt()) {
            if (auto* s = dynamic_cast<SdvParser::RoadLanesContext*>(st)) {
                if (!r.lanes.empty()) {
                    error("E0504", range(s), "duplicate 'lanes' in road '" + r.name.text + "'");
                    continue;
                }
                r.lanes_range = range(s);
                for (auto* lc : s->laneCount()) {
                    ast::LaneCount n;
                    n.count = std::strtoll(lc->INT()->getText().c_str(), nullptr, 10);
                    n.count_range = range(lc->INT());
                    n.direction = ident(lc->ident());
                    n.range = range(lc);
                    r.lanes.push_back(n);
                }
            } else if (auto* s2 = dynamic_cast<SdvParser::RoadLaneWidthContext*>(st)) {
                r.settings.push_back(setting(s2->LANE_WIDTH(), {s2->value()}, s2));
            } else if (auto* s3 = dynamic_cast<SdvParser::RoadSpeedLimitContext*>(st)) {
                r.settings.push_back(setting(s3->SPEED_LIMIT(), {s3->value()}, s3));
            } else if (auto* s4 = dynamic_cast<SdvParser::RoadStraightContext*>(st)) {
                ast::Segment seg;
                seg.length = value(s4->value());
                seg.range = range(s4);
                r.segments.push_back(std::move(seg));
            } else if (auto* s5 = dynamic_cast<SdvParser::RoadArcContext*>(st)) {
                ast::Segment seg;
                seg.arc = true;
                seg.length = value(s5->value(0));
                seg.radius = value(s5->value(1));
                if (s5->LEFT()) seg.side = ast::Ident{"left", range(s5->LEFT())};
                if (s5->RIGHT()) seg.side = ast::Ident{"right", range(s5->RIGHT())};
                seg.range = range(s5);
                r.segments.push_back(std::move(seg));
            } else if (auto* s6 = dynamic_cast<SdvParser::RoadOriginContext*>(st)) {
                r.settings.push_back(setting(s6->ORIGIN(), {s6->value(0), s6->value(1)}, s6));
                if (s6->HEADING()) {
                    r.settings.push_back(setting(s6->HEADING(), {s6->value(2)}, s6));
                }
            } else if (auto* s7 = dynamic_cast<SdvParser::RoadCrosswalkContext*>(st)) {
                r.crosswalks.push_back(crosswalk(s7->crosswalk()));
            }
        }
        return r;
    }

    ast::JunctionDecl junction(SdvParser::JunctionDeclContext* c) {
        ast::JunctionDecl j;
        j.name = ident(c->ident());
        j.range = range(c);
        for (auto* st : c->junctionStmt()) {
            if (auto* s = dynamic_cast<SdvParser::JunctionLanesContext*>(st)) {
                ast::Setting set;
                set.key = {"lanes", range(s->LANES())};
                ast::Value v;
                v.lo.kind = ast::Primary::Kind::quantity;
                v.lo.quantity.value = static_cast<double>(std::strtoll(s->INT()->getText().c_str(), nullptr, 10));
                v.lo.quantity.text = s->INT()->getText();
                v.lo.quantity.is_integer = true;
                v.lo.range = v.range = range(s->INT());
                set.values.push_back(std::move(v));
                set.range = range(s);
                j.settings.push_back(std::move(set));
            } else if (auto* s2 = dynamic_cast<SdvParser::JunctionLaneWidthContext*>(st)) {
                j.settings.push_back(setting(s2->LANE_WIDTH(), {s2->value()}, s2));
            } else if (auto* s3 = dynamic_cast<SdvParser::JunctionSpeedLimitContext*>(st)) {
                j.settings.push_back(setting(s3->SPEED_LIMIT(), {s3->value()}, s3));
            } else if (auto* s4 = dynamic_cast<SdvParser::JunctionArmLengthContext*>(st)) {
                j.settings.push_back(setting(s4->ARM_LENGTH(), {s4->value()}, s4));
            } else if (auto* s5 = dynamic_cast<SdvParser::JunctionControlContext*>(st)) {
                ast::Setting set;
                set.key = {"control", range(s5->CONTROL())};
                ast::Value v;
                v.lo.kind = ast::Primary::Kind::name;
                v.lo.name.parts.push_back(ident(s5->ident()));
                v.lo.name.range = v.lo.range = v.range = range(s5->ident());
                set.values.push_back(std::move(v));
                set.range = range(s5);
                j.settings.push_back(std::move(set));
            } else if (auto* s6 = dynamic_cast<SdvParser::JunctionCrosswalkContext*>(st)) {
                j.crosswalks.push_back(crosswalk(s6->crosswalk()));
            }
        }
        return j;
    }

    ast::CrosswalkDecl crosswalk(SdvParser::CrosswalkContext* c) {
        ast::CrosswalkDecl x;
        x.name = ident(c->ident(0));
        if (c->ON()) x.arm = ident(c->ident(1));
        // The values in order: `at` first when both are written.
        size_t next = 0;
        if (c->AT()) x.at = value(c->value(next++));
        if (c->WIDTH()) x.width = value(c->value(next++));
        if (c->SIGNALISED()) x.signalised = range(c->SIGNALISED());
        x.range = range(c);
        return x;
    }

    ast::MapDecl map(SdvParser::MapDeclContext* c) {
        ast::MapDecl m;
        m.name = ident(c->ident());
        m.range = range(c);
        for (auto* st : c->mapStmt()) {
            if (auto* s = dynamic_cast<SdvParser::MapFileContext*>(st)) {
                ast::Setting set;
                set.key = {"file", range(s->FILE())};
                ast::Value v;
                v.lo.kind = ast::Primary::Kind::string;
                v.lo.string = unescape(s->STRING()->getText());
                v.lo.range = v.range = range(s->STRING());
                set.values.push_back(std::move(v));
                set.range = range(s);
                m.settings.push_back(std::move(set));
            } else if (auto* s2 = dynamic_cast<SdvParser::MapOriginContext*>(st)) {
                m.settings.push_back(setting(s2->ORIGIN(), s2->value(), s2));
            }
        }
        return m;
    }

    std::unique_ptr<ast::Node> node(SdvParser::NodeContext* c) {
        auto n = std::make_unique<ast::Node>();
        if (c->ident()) n->label = ident(c->ident());
        n->range = range(c);
        auto* body = c->nodeBody();
        if (auto* comp = dynamic_cast<SdvParser::CompositeNodeContext*>(body)) {
            auto* k = comp->compositeKind();
            n->keyword_range = range(k);
            if (k->FALLBACK()) n->kind = ast::NodeKind::fallback;
            else if (k->SEQUENCE()) n->kind = ast::NodeKind::sequence;
            else if (k->REACTIVE_SEQUENCE()) n->kind = ast::NodeKind::reactive_sequence;
            else n->kind = ast::NodeKind::parallel;
            n->args = args(comp->argList());
            for (auto* child : comp->node()) n->children.push_back(node(child));
        } else if (auto* cond = dynamic_cast<SdvParser::ConditionNodeContext*>(body)) {
            n->kind = ast::NodeKind::condition;
            n->keyword_range = range(cond->CONDITION());
            n->callee.parts.push_back(ident(cond->ident()));
            n->callee.range = range(cond->ident());
            n->args = args(cond->argList());
        } else if (auto* man = dynamic_cast<SdvParser::ManeuverNodeContext*>(body)) {
            n->kind = ast::NodeKind::maneuver;
            n->keyword_range = range(man->MANEUVER());
            n->callee.parts.push_back(ident(man->ident()));
            n->callee.range = range(man->ident());
            n->args = args(man->argList());
        } else if (auto* sub = dynamic_cast<SdvParser::SubtreeNodeContext*>(body)) {
            n->kind = ast::NodeKind::subtree;
            n->keyword_range = range(sub->SUBTREE());
            n->callee = qual(sub->qualName());
            n->args = args(sub->argList());
        } else if (auto* dec = dynamic_cast<SdvParser::DecoratorNodeContext*>(body)) {
            n->kind = dec->decorator()->NOT()    ? ast::NodeKind::not_
                      : dec->decorator()->ONCE() ? ast::NodeKind::once
                                                 : ast::NodeKind::latch;
            n->keyword_range = range(dec->decorator());
            n->children.push_back(node(dec->node()));
        }
        return n;
    }

    ast::TreeDecl tree(SdvParser::TreeDeclContext* c) {
        ast::TreeDecl t;
        t.name = ident(c->ident());
        t.range = range(c);
        for (auto* p : c->paramDecl()) {
            ast::Param param;
            param.name = ident(p->ident(0));
            param.type = ident(p->ident(1));
            if (p->value()) param.def = value(p->value());
            param.range = range(p);
            t.params.push_back(std::move(param));
        }
        for (auto* n : c->node()) t.body.push_back(node(n));
        return t;
    }

    ast::LaneRef lane_ref(SdvParser::LaneRefContext* c) {
        ast::LaneRef l;
        l.range = range(c);
        if (auto* li = c->laneIndex()) {
            l.kind = ast::LaneRef::Kind::index;
            l.index = std::strtoll(li->INT()->getText().c_str(), nullptr, 10);
            if (li->sign != nullptr) l.index = -l.index;
        } else if (auto* q = c->qualName()) {
            l.kind = ast::LaneRef::Kind::name;
            l.name = qual(q);
        } else {
            l.kind = ast::LaneRef::Kind::string;
            l.string = unescape(c->STRING()->getText());
        }
        return l;
    }

    ast::Position position(SdvParser::PositionContext* c) {
        ast::Position p;
        p.range = range(c);
        if (auto* lp = dynamic_cast<SdvParser::LanePositionContext*>(c)) {
            p.lane = lane_ref(lp->laneRef());
            p.s = value(lp->value(0));
            if (lp->OFFSET()) p.offset = value(lp->value(1));
        } else if (auto* xp = dynamic_cast<SdvParser::XyPositionContext*>(c)) {
            p.xy = true;
            p.x = value(xp->value(0));
            p.y = value(xp->value(1));
            if (xp->HEADING()) p.heading = value(xp->value(2));
        }
        return p;
    }

    ast::VehicleDecl vehicle(std::vector<SdvParser::VehicleStmtContext*> stmts, ast::VehicleDecl v) {
        for (auto* st : stmts) {
            if (auto* s = dynamic_cast<SdvParser::VehStartContext*>(st)) {
                v.starts.push_back(position(s->position()));
            } else if (auto* s2 = dynamic_cast<SdvParser::VehSpeedContext*>(st)) {
                v.settings.push_back(setting(s2->SPEED(), {s2->value()}, s2));
            } else if (auto* s3 = dynamic_cast<SdvParser::VehLengthContext*>(st)) {
                v.settings.push_back(setting(s3->LENGTH(), {s3->value()}, s3));
            } else if (auto* s4 = dynamic_cast<SdvParser::VehWidthContext*>(st)) {
                v.settings.push_back(setting(s4->WIDTH(), {s4->value()}, s4));
            } else if (auto* s5 = dynamic_cast<SdvParser::VehGoalContext*>(st)) {
                v.goals.push_back(position(s5->position()));
                v.goal_ends_run = v.goal_ends_run || s5->ENDS() != nullptr;
            } else if (auto* s6 = dynamic_cast<SdvParser::VehRouteContext*>(st)) {
                std::vector<ast::LaneRef> route;
                for (auto* l : s6->laneRef()) route.push_back(lane_ref(l));
                v.routes.push_back(std::move(route));
            } else if (auto* s7 = dynamic_cast<SdvParser::VehTreeContext*>(st)) {
                v.trees.push_back({qual(s7->qualName()), args(s7->argList()), range(s7)});
            } else if (auto* s8 = dynamic_cast<SdvParser::VehTrajectoryContext*>(st)) {
                std::vector<ast::Waypoint> wps;
                for (auto* w : s8->waypoint()) {
                    ast::Waypoint wp;
                    wp.time = single(primary(w->time));
                    wp.position = position(w->position());
                    if (w->SPEED()) wp.speed = value(w->value());
                    wp.range = range(w);
                    wps.push_back(std::move(wp));
                }
                v.trajectories.push_back(std::move(wps));
            } else if (auto* s9 = dynamic_cast<SdvParser::VehPathContext*>(st)) {
                std::vector<ast::PathPoint> pts;
                for (auto* w : s9->pathPoint()) {
                    ast::PathPoint pp;
                    pp.position = position(w->position());
                    if (w->SPEED()) pp.speed = value(w->value());
                    pp.range = range(w);
                    pts.push_back(std::move(pp));
                }
                v.paths.push_back(std::move(pts));
            } else if (auto* s10 = dynamic_cast<SdvParser::VehMeetContext*>(st)) {
                v.meets.push_back(ident(s10->ident()));
            }
        }
        return v;
    }

    std::unique_ptr<ast::Expr> expr(SdvParser::ExprContext* c) {
        auto e = std::make_unique<ast::Expr>();
        e->range = range(c);
        if (auto* n = dynamic_cast<SdvParser::NotExprContext*>(c)) {
            e->kind = ast::Expr::Kind::not_;
            e->lhs = expr(n->expr());
        } else if (auto* a = dynamic_cast<SdvParser::AndExprContext*>(c)) {
            e->kind = ast::Expr::Kind::and_;
            e->lhs = expr(a->expr(0));
            e->rhs = expr(a->expr(1));
        } else if (auto* o = dynamic_cast<SdvParser::OrExprContext*>(c)) {
            e->kind = ast::Expr::Kind::or_;
            e->lhs = expr(o->expr(0));
            e->rhs = expr(o->expr(1));
        } else if (auto* p = dynamic_cast<SdvParser::ParenExprContext*>(c)) {
            return expr(p->expr());
        } else if (auto* call = dynamic_cast<SdvParser::CallExprContext*>(c)) {
            e->kind = ast::Expr::Kind::call;
            auto ids = call->call()->ident();
            e->function = ident(ids[0]);
            for (size_t i = 1; i < ids.size(); ++i) e->args.push_back(ident(ids[i]));
            if (call->cmp != nullptr) {
                e->cmp = call->cmp->getText();
                e->bound = value(call->value());
            }
        }
        return e;
    }

    ast::VehicleDecl::Repeat repeat(SdvParser::RepeatContext* c, const ast::Ident& name) {
        ast::VehicleDecl::Repeat r;
        if (auto* id = c->ident()) r.var = ident(id);
        r.lo = primary(c->primary(0));
        r.hi = primary(c->primary(1));
        r.range = {name.range.begin, range(c).end};
        return r;
    }

    ast::ScenarioDecl scenario(SdvParser::ScenarioDeclContext* c) {
        ast::ScenarioDecl s;
        s.name = ident(c->ident());
        s.range = range(c);
        for (auto* st : c->scenarioStmt()) {
            if (auto* r = dynamic_cast<SdvParser::ScenarioRoadContext*>(st)) {
                ast::Setting set;
                set.key = {"road", range(r->ROAD())};
                ast::Value v;
                v.lo.kind = ast::Primary::Kind::name;
                v.lo.name = qual(r->qualName());
                v.lo.range = v.range = range(r->qualName());
                set.values.push_back(std::move(v));
                set.range = range(r);
                s.settings.push_back(std::move(set));
            } else if (auto* t = dynamic_cast<SdvParser::ScenarioTimeoutContext*>(st)) {
                s.settings.push_back(setting(t->TIMEOUT(), {t->value()}, t));
            } else if (auto* sd = dynamic_cast<SdvParser::ScenarioSeedContext*>(st)) {
                ast::Setting set;
                set.key = {"seed", range(sd->SEED())};
                ast::Value v;
                v.lo.kind = ast::Primary::Kind::quantity;
                v.lo.quantity.text = sd->INT()->getText();
                v.lo.quantity.value = std::strtod(v.lo.quantity.text.c_str(), nullptr);
                v.lo.quantity.is_integer = true;
                v.lo.range = v.range = range(sd->INT());
                set.values.push_back(std::move(v));
                set.range = range(sd);
                s.settings.push_back(std::move(set));
            } else if (auto* rt = dynamic_cast<SdvParser::ScenarioRateContext*>(st)) {
                ast::Setting set;
                set.key = {"rate " + spelling(rt->ident()), range(rt->ident())};
                set.values.push_back(value(rt->value()));
                set.range = range(rt);
                s.settings.push_back(std::move(set));
            } else if (auto* vh = dynamic_cast<SdvParser::ScenarioVehicleContext*>(st)) {
                ast::VehicleDecl v;
                v.is_ego = vh->EGO() != nullptr;
                v.is_pedestrian = vh->PEDESTRIAN() != nullptr;
                v.name = ident(vh->ident(0));
                v.kind = ident(vh->ident(1));
                v.range = range(vh);
                if (auto* rp = vh->repeat()) v.repeat = repeat(rp, v.name);
                s.vehicles.push_back(vehicle(vh->vehicleStmt(), std::move(v)));
            } else if (auto* ob = dynamic_cast<SdvParser::ScenarioObjectContext*>(st)) {
                ast::VehicleDecl v;
                v.is_object = true;
                v.name = ident(ob->ident());
                v.kind = {"static", range(ob->OBJECT())};
                v.range = range(ob);
                if (auto* rp = ob->repeat()) v.repeat = repeat(rp, v.name);
                s.vehicles.push_back(vehicle(ob->vehicleStmt(), std::move(v)));
            } else if (auto* li = dynamic_cast<SdvParser::ScenarioLightContext*>(st)) {
                ast::LightDecl l;
                l.name = qual(li->qualName());
                l.range = range(li);
                for (auto* ls : li->lightStmt()) {
                    if (auto* off = dynamic_cast<SdvParser::LightOffsetContext*>(ls)) {
                        l.offset = value(off->value());
                    } else if (auto* ph = dynamic_cast<SdvParser::LightPhaseContext*>(ls)) {
                        ast::Setting set;
                        set.key = ident(ph->ident());
                        ast::Value duration = single(primary(ph->leadPrimary()));
                        duration.range = {range(ph->leadPrimary()).begin, range(ph).end};
                        if (ph->DOTDOT()) {
                            duration.kind = ast::Value::Kind::interval;
                            duration.hi = primary(ph->primary());
                        }
                        if (auto* sp = ph->spread()) duration.spread = primary(sp->primary());
                        if (auto* sm = ph->samples()) duration.samples = samples(sm);
                        set.values.push_back(std::move(duration));
                        set.range = range(ph);
                        l.phases.push_back(std::move(set));
                    }
                }
                s.lights.push_back(std::move(l));
            } else if (auto* ex = dynamic_cast<SdvParser::ScenarioExpectContext*>(st)) {
                auto e = expr(ex->expr());
                if (auto* w = ex->window()) {
                    ast::Expr::Window win;
                    Token* k = w->getStart();
                    win.kind = w->DURING() ? ast::Expr::Window::Kind::during
                               : w->AFTER() ? ast::Expr::Window::Kind::after
                                            : ast::Expr::Window::Kind::before;
                    win.keyword = {k->getText(), range(k)};
                    win.value = value(w->value());
                    win.range = range(w);
                    e->window = std::move(win);
                }
                s.expects.push_back(std::move(e));
            } else if (auto* va = dynamic_cast<SdvParser::ScenarioVaryContext*>(st)) {
                s.varies.push_back(vary(va));
            }
        }
        return s;
    }

    static std::optional<int64_t> int_token(antlr4::tree::TerminalNode* t) {
        errno = 0;
        const long long n = std::strtoll(t->getText().c_str(), nullptr, 10);
        return errno == ERANGE ? -1 : n;  // the checker reports out-of-range counts
    }

    ast::VaryDecl vary(SdvParser::ScenarioVaryContext* c) {
        ast::VaryDecl out;
        out.keyword_range = range(c->VARY());
        out.range = range(c);
        for (auto* st : c->varyStmt()) {
            if (auto* p = dynamic_cast<SdvParser::VaryParamContext*>(st)) {
                ast::VaryParam vp;
                vp.path = qual(p->qualName());
                vp.range = range(p);
                vp.domain_range = range(p->varyDomain());
                if (auto* set = dynamic_cast<SdvParser::VarySetContext*>(p->varyDomain())) {
                    vp.kind = ast::VaryParam::Kind::set;
                    for (auto* x : set->primary()) vp.values.push_back(primary(x));
                } else if (auto* r = dynamic_cast<SdvParser::VaryRangeContext*>(p->varyDomain())) {
                    vp.kind = ast::VaryParam::Kind::range;
                    vp.values.push_back(primary(r->primary(0)));
                    vp.values.push_back(primary(r->primary(1)));
                    if (r->COUNT()) {
                        vp.count = int_token(r->INT());
                        vp.count_range = range(r->INT());
                    }
                } else if (auto* d = dynamic_cast<SdvParser::VaryDistributionContext*>(p->varyDomain())) {
                    vp.kind = ast::VaryParam::Kind::distribution;
                    vp.distribution = ident(d->ident());
                    vp.values.push_back(primary(d->primary(0)));
                    vp.values.push_back(primary(d->primary(1)));
                }
                out.params.push_back(std::move(vp));
            } else if (auto* sm = dynamic_cast<SdvParser::VarySampleContext*>(st)) {
                ast::Setting set;
                set.key = {"sample", range(sm->SAMPLE())};
                ast::Value method;
                method.lo.kind = ast::Primary::Kind::name;
                method.lo.name.parts.push_back(ident(sm->ident()));
                method.lo.name.range = method.lo.range = method.range = range(sm->ident());
                set.values.push_back(std::move(method));
                if (sm->INT() != nullptr) set.values.push_back(int_value(sm->INT()));
                set.range = range(sm);
                out.settings.push_back(std::move(set));
            } else if (auto* sd = dynamic_cast<SdvParser::VarySeedContext*>(st)) {
                ast::Setting set;
                set.key = {"seed", range(sd->SEED())};
                set.values.push_back(int_value(sd->INT()));
                set.range = range(sd);
                out.settings.push_back(std::move(set));
            }
        }
        return out;
    }

    ast::Value int_value(antlr4::tree::TerminalNode* t) {
        ast::Value v;
        v.lo.kind = ast::Primary::Kind::quantity;
        v.lo.quantity.text = t->getText();
        v.lo.quantity.value = std::strtod(v.lo.quantity.text.c_str(), nullptr);
        v.lo.quantity.is_integer = true;
        v.lo.range = v.range = range(t);
        return v;
    }

    diag::FileId file_;
    const CodePoints& offs_;
    std::vector<diag::Diagnostic>& pending_;
};

// A token as the pre-pass and the parser need it: 12 bytes instead of a 112-byte CommonToken
// behind its own allocation, which for a 10 MB file (millions of tokens) was most of the
// memory and a good part of the time.
struct Lexeme {
    uint32_t type;
    uint32_t start;  // code points, as ANTLR counts them
    uint32_t stop;   // inclusive
};

// The generated lexer, recording the default-channel tokens as lexemes instead of emitting
// CommonTokens; hidden tokens (white space, comments) are dropped as they come.
class LexemeLexer : public SdvLexer {
public:
    using SdvLexer::SdvLexer;

    // Lexes the whole input; returns the start index of the end of file.
    size_t lex_all() {
        for (;;) {
            if (auto eof = nextToken()) return eof->getStartIndex();  // only EOF is emitted
        }
    }

    Token* emit() override {
        if (type == Token::EOF) return Lexer::emit();  // an empty input's EOF comes this way
        if (channel == Token::DEFAULT_CHANNEL) {
            lexemes.push_back({static_cast<uint32_t>(type),
                               static_cast<uint32_t>(tokenStartCharIndex),
                               static_cast<uint32_t>(getCharIndex() - 1)});
        }
        return nullptr;
    }

    std::vector<Lexeme> lexemes;
};

// A CommonTokenStream whose buffer is sized for its tokens up front, instead of growing one
// token at a time as the parser pulls them.
class SizedTokenStream : public antlr4::CommonTokenStream {
public:
    SizedTokenStream(antlr4::TokenSource* source, size_t tokens) : CommonTokenStream(source) {
        _tokens.reserve(tokens);
    }
};

// Items are parsed and built in chunks of at least this many tokens, so that only one chunk's
// tokens and parse tree exist at a time.
constexpr size_t kChunkTokens = 4096;

bool starts_item(size_t type) {
    return type == SdvLexer::IMPORT || type == SdvLexer::ROAD || type == SdvLexer::JUNCTION ||
           type == SdvLexer::MAP || type == SdvLexer::TREE || type == SdvLexer::SCENARIO;
}

// A lexeme's source range, in bytes.
diag::SourceRange range_of(diag::FileId file, const CodePoints& offs, const Lexeme& t) {
    const size_t b = std::min<size_t>(t.start, offs.size() - 1);
    const size_t e = std::min<size_t>(t.stop + size_t{1}, offs.size() - 1);
    return {{file, offs[b]}, {file, offs[std::max(b, e)]}};
}

// A lexeme's text: the text is valid UTF-8, so its bytes are what ANTLR would decode them to.
std::string spelling(std::string_view text, const CodePoints& offs, const Lexeme& t) {
    return std::string(text.substr(offs[t.start], offs[t.stop + 1] - offs[t.start]));
}

// E0001 at the first byte of `text` that is not UTF-8; false then.
bool check_utf8(diag::FileId file, std::string_view text, diag::DiagnosticEngine& diags) {
    const size_t bad = find_invalid_utf8(text);
    if (bad == std::string_view::npos) return true;
    const auto off = static_cast<uint32_t>(bad);
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02X", static_cast<unsigned char>(text[bad]));
    diags.error("E0001", {{file, off}, {file, off + 1}},
                std::string("file is not valid UTF-8 text (byte ") + hex + ")")
        .notes.push_back({{}, ".sdv files are UTF-8 text; is this a binary file?"});
    return false;
}

// What the pre-parse pass leaves for the parser: the lexemes it keeps, where chunks end, and how
// many trees the file declares at least.
struct Prepared {
    std::vector<Lexeme> lexemes;
    std::vector<size_t> chunk_ends;
    size_t trees = 0;
};

// The pre-parse pass: reports stray characters and unterminated strings once each, drops them
// from the stream, and refuses pathological nesting before the recursive parser sees it. It
// also marks where chunks may start: at an item keyword after a closing brace at depth 0, once
// the chunk has kChunkTokens tokens. False when the file cannot be parsed (reported).
bool prepare(diag::FileId file, std::string_view text, const CodePoints& offs, std::vector<Lexeme> lexemes,
             Prepared& out, diag::DiagnosticEngine& diags) {
    size_t kept = 0;
    std::vector<size_t>& chunk_ends = out.chunk_ends;
    int depth = 0;
    int decorators = 0;
    int operators = 0;  // `and` / `or` since the last `expect`: each one nests the expression
    bool lexical_errors = false;
    bool after_close = false;
    for (size_t i = 0; i < lexemes.size(); ++i) {
        const Lexeme t = lexemes[i];
        if (t.type == SdvLexer::ERROR_CHAR) {
            size_t j = i;
            while (j + 1 < lexemes.size() && lexemes[j + 1].type == SdvLexer::ERROR_CHAR &&
                   lexemes[j + 1].start == lexemes[j].stop + 1) {
                ++j;
            }
            diag::SourceRange r{range_of(file, offs, t).begin, range_of(file, offs, lexemes[j]).end};
            diags.error("E0001", r, "unexpected character '" + spelling(text, offs, t) + "'");
            lexical_errors = true;
            if (diags.limit_reached()) return false;
            i = j;
            continue;
        }
        if (t.type == SdvLexer::UNTERMINATED_STRING) {
            diags.error("E0002", range_of(file, offs, t), "unterminated string")
                .notes.push_back({{}, "add the closing '\"' on the same line"});
            lexical_errors = true;
            continue;
        }
        if (depth == 0 && after_close && starts_item(t.type) &&
            kept - (chunk_ends.empty() ? 0 : chunk_ends.back()) >= kChunkTokens) {
            chunk_ends.push_back(kept);
        }
        if (depth == 0 && t.type == SdvLexer::TREE) ++out.trees;
        // Brackets are one character; the first byte of a longer code point is not ASCII.
        const char bracket = t.stop == t.start ? text[offs[t.start]] : '\0';
        if (bracket == '{' || bracket == '(' || bracket == '[') ++depth;
        if (bracket == '}' || bracket == ')' || bracket == ']') depth = std::max(0, depth - 1);
        after_close = bracket == '}';
        const bool decorator = t.type == SdvLexer::NOT || t.type == SdvLexer::ONCE ||
                               t.type == SdvLexer::LATCH;
        decorators = decorator ? decorators + 1 : 0;
        if (depth + decorators > kMaxNesting) {
            diags.error("E0004", range_of(file, offs, t),
                        "nesting is too deep (more than " + std::to_string(kMaxNesting) + " levels)")
                .notes.push_back({{}, "split the tree into named subtrees"});
            return false;
        }
        if (t.type == SdvLexer::EXPECT || bracket == '}') operators = 0;
        if ((t.type == SdvLexer::AND || t.type == SdvLexer::OR) && ++operators > kMaxOperators) {
            diags.error("E0004", range_of(file, offs, t),
                        "expression is too long (more than " + std::to_string(kMaxOperators) +
                            " 'and' / 'or')")
                .notes.push_back({{}, "write it as several expect statements: they must all hold"});
            return false;
        }
        lexemes[kept++] = t;
    }
    if (lexical_errors) return false;
    if (kept == 0) {
        diags.error("E0008", {{file, 0}, {file, 0}}, "the file declares nothing")
            .notes.push_back({{}, "a .sdv file holds imports, roads, trees and scenarios"});
        return false;
    }
    lexemes.resize(kept);
    lexemes.shrink_to_fit();  // they stay until the last chunk, next to the whole AST
    chunk_ends.push_back(kept);
    out.lexemes = std::move(lexemes);
    return true;
}

}  // namespace

bool check_encoding(diag::FileId file, const diag::SourceManager& sm, diag::DiagnosticEngine& diags) {
    return check_utf8(file, sm.contents(file), diags);
}

bool precheck(diag::FileId file, const diag::SourceManager& sm, const std::vector<Token*>& tokens,
              diag::DiagnosticEngine& diags) {
    const std::string_view text = sm.contents(file);
    const CodePoints offs(text);
    std::vector<Lexeme> lexemes;
    lexemes.reserve(tokens.size());
    for (const Token* t : tokens) {
        if (t->getChannel() != Token::DEFAULT_CHANNEL || t->getType() == Token::EOF) continue;
        lexemes.push_back({static_cast<uint32_t>(t->getType()),
                           static_cast<uint32_t>(t->getStartIndex()),
                           static_cast<uint32_t>(t->getStopIndex())});
    }
    Prepared prepared;
    return prepare(file, text, offs, std::move(lexemes), prepared, diags);
}

void add_parse_stats(antlr4::atn::ParseInfo info, ParseStats& stats) {
    for (const auto& d : info.getDecisionInfo()) {
        stats.decisions += d.invocations;
        stats.lookahead += d.SLL_TotalLook + d.LL_TotalLook;
        stats.max_lookahead = std::max({stats.max_lookahead, d.SLL_MaxLook, d.LL_MaxLook});
        stats.full_context += d.LL_Fallback;
    }
}

std::unique_ptr<ast::File> parse(diag::FileId file, const diag::SourceManager& sm,
                                 diag::DiagnosticEngine& diags, ParseStats* stats) {
    const std::string_view text = sm.contents(file);
    if (!check_utf8(file, text, diags)) return nullptr;
    const CodePoints offs(text);

    try {
        Utf8Stream input(text, offs);
        LexemeLexer lexer(&input);
        lexer.removeErrorListeners();
        const size_t eof = lexer.lex_all();
        Prepared prepared;
        if (!prepare(file, text, offs, std::move(lexer.lexemes), prepared, diags)) return nullptr;
        const std::vector<Lexeme>& lexemes = prepared.lexemes;
        const std::vector<size_t>& chunk_ends = prepared.chunk_ends;
        const size_t kept = lexemes.size();

        // The ANTLR tokens of lexemes [begin, end) and an end of file. Their text is set from
        // the source, so reading it (the unit predicate, the builder) is a copy. Their line and
        // column are not kept: everything here places tokens by code point index.
        const std::pair<antlr4::TokenSource*, antlr4::CharStream*> origin{&lexer, &input};
        auto tokens = [&](size_t begin, size_t end) {
            std::vector<std::unique_ptr<Token>> out;
            out.reserve(end - begin + 1);
            for (size_t i = begin; i < end; ++i) {
                const Lexeme& l = lexemes[i];
                auto t = std::make_unique<antlr4::CommonToken>(
                    origin, l.type, Token::DEFAULT_CHANNEL, l.start, l.stop);
                t->setText(spelling(text, offs, l));
                out.push_back(std::move(t));
            }
            out.push_back(std::make_unique<antlr4::CommonToken>(
                origin, Token::EOF, Token::DEFAULT_CHANNEL, eof, eof - 1));
            return out;
        };

        auto ast = std::make_unique<ast::File>();
        ast->file = file;
        ast->trees.reserve(prepared.trees);
        std::vector<diag::Diagnostic> pending;
        Builder builder(file, offs, pending);
        SdvParser parser(nullptr);
        parser.removeErrorListeners();
        if (stats != nullptr) parser.setProfile(true);
        // Counted however the parse ends (a syntax error cancels it by throwing).
        struct Count {
            SdvParser& parser;
            ParseStats* stats;
            ~Count() {
                if (stats == nullptr) return;
                try {
                    add_parse_stats(parser.getParseInfo(), *stats);
                } catch (...) {  // a count lost, never a second exception while unwinding
                }
            }
        } count{parser, stats};
        auto* interpreter = parser.getInterpreter<antlr4::atn::ParserATNSimulator>();
        // Two stages, as ANTLR recommends: SLL prediction bailing out at the first error (fast,
        // and exact for every input it accepts), chunk by chunk, each chunk's tree built and
        // freed before the next. A chunk that parses is a sequence of whole items (an item
        // cannot run on into an item keyword), so it parses as it would inside the whole file.
        interpreter->setPredictionMode(antlr4::atn::PredictionMode::SLL);
        parser.setErrorHandler(std::make_shared<antlr4::BailErrorStrategy>());
        size_t begin = 0;
        for (size_t end : chunk_ends) {
            antlr4::ListTokenSource source(tokens(begin, end));
            SizedTokenStream stream(&source, end - begin + 1);
            parser.setTokenStream(&stream);
            SdvParser::FileContext* tree = nullptr;
            try {
                tree = parser.file();
            } catch (const antlr4::ParseCancellationException&) {
                break;
            }
            builder.add(tree, *ast);
            begin = end;
        }
        // Then, from the first chunk SLL rejects to the end, full LL with error reporting and
        // recovery. The chunks before it had no errors, so this reports what one parse of the
        // whole file would: it starts where that parse would stand, at the start of an item
        // (the listener only compares token indexes with each other).
        if (begin < kept) {
            antlr4::ListTokenSource source(tokens(begin, kept));
            SizedTokenStream stream(&source, kept - begin + 1);
            parser.setTokenStream(&stream);
            parser.setErrorHandler(std::make_shared<antlr4::DefaultErrorStrategy>());
            interpreter->setPredictionMode(antlr4::atn::PredictionMode::LL);
            ErrorListener listener(file, offs, diags);
            parser.addErrorListener(&listener);
            SdvParser::FileContext* tree = nullptr;
            try {
                tree = parser.file();
            } catch (const CancelParse&) {
                diags.error("E0003", listener.last_range(),
                            "too many syntax errors (" + std::to_string(kMaxSyntaxErrors) + "); stopping here");
                return nullptr;
            }
            if (listener.count() > 0 || parser.getNumberOfSyntaxErrors() > 0) return nullptr;
            builder.add(tree, *ast);
        }
        for (auto& d : pending) diags.report(std::move(d));
        return ast;
    } catch (const std::exception& e) {
        diags.error("E0003", {{file, 0}, {file, 0}},
                    std::string("the parser failed on this file: ") + e.what());
        return nullptr;
    }
}

std::string dump_tokens(diag::FileId file, const diag::SourceManager& sm) {
    const std::string_view text = sm.contents(file);
    if (find_invalid_utf8(text) != std::string_view::npos) return "";
    const CodePoints offs(text);
    Utf8Stream input(text, offs);
    SdvLexer lexer(&input);
    lexer.removeErrorListeners();
    std::string out;
    const auto& vocab = lexer.getVocabulary();
    for (auto& t : lexer.getAllTokens()) {
        if (t->getChannel() != Token::DEFAULT_CHANNEL) continue;
        // The lexer counts lines at '\n' and columns in code points, as SourceManager::line_col
        // does, without a lookup per token (a long line has many tokens).
        std::string name = vocab.getSymbolicName(t->getType());
        if (name.empty()) name = vocab.getLiteralName(t->getType());
        out += std::to_string(t->getLine()) + ":" + std::to_string(t->getCharPositionInLine() + 1) +
               " " + name + " '" + t->getText() + "'\n";
    }
    return out;
}

}  // namespace sdv::compiler::syntax
