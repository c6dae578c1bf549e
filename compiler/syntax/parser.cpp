// The ANTLR adapter: lexing, the pre-parse checks (encoding, stray characters, unterminated
// strings, nesting depth), the parse with capped error recovery, and the parse-tree → AST
// builder. ANTLR counts positions in code points; the builder maps them to byte offsets.
#include "compiler/syntax/parser.h"

#include "compiler/diag/suggest.h"
#include "compiler/syntax/utf8.h"
#include "runtime/catalog/units.h"

#include <SdvLexer.h>
#include <SdvParser.h>
#include <antlr4-runtime.h>

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

// Reports syntax errors as diagnostics and stops the parse after kMaxSyntaxErrors.
class ErrorListener : public antlr4::BaseErrorListener {
public:
    ErrorListener(diag::FileId file, const std::vector<uint32_t>& offs,
                  diag::DiagnosticEngine& diags)
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
        diag::SourceRange range{};
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
        auto& d = diags_.error("E0003", range, "syntax error: unexpected " + found);
        if (!expected.empty()) {
            d.notes.push_back({{}, "expected " + expected});
        } else if (msg.rfind("no viable alternative", 0) != 0 && !msg.empty()) {
            d.notes.push_back({{}, msg});
        }
        if (count_ >= kMaxSyntaxErrors) throw CancelParse{};
    }

    int count() const { return count_; }

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
                names.push_back(sym);
            }
        }
        if (name_like) names.insert(names.begin(), "a name");
        return diag::alternatives(names);
    }

    diag::FileId file_;
    const std::vector<uint32_t>& offs_;
    diag::DiagnosticEngine& diags_;
    int count_ = 0;
    long last_ = -1;
};

// Builds the owned AST from a parse tree that had no syntax errors.
class Builder {
public:
    Builder(diag::FileId file, const std::vector<uint32_t>& offs, diag::DiagnosticEngine& diags)
        : file_(file), offs_(offs), diags_(diags) {}

    std::unique_ptr<ast::File> build(SdvParser::FileContext* ctx) {
        auto f = std::make_unique<ast::File>();
        f->file = file_;
        for (auto* item : ctx->item()) {
            if (auto* c = item->importDecl()) f->imports.push_back(import_decl(c));
            if (auto* c = item->roadDecl()) f->roads.push_back(road(c));
            if (auto* c = item->junctionDecl()) f->junctions.push_back(junction(c));
            if (auto* c = item->mapDecl()) f->maps.push_back(map(c));
            if (auto* c = item->treeDecl()) f->trees.push_back(tree(c));
            if (auto* c = item->scenarioDecl()) f->scenarios.push_back(scenario(c));
        }
        return f;
    }

private:
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

    ast::Ident ident(SdvParser::IdentContext* c) { return {c->getText(), range(c)}; }

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
        std::string text;
        for (char ch : c->getText()) {
            if (ch != '_') text += ch;
        }
        errno = 0;
        double v = std::strtod(text.c_str(), nullptr);
        if (errno == ERANGE || !std::isfinite(v)) {
            if (std::isinf(v) || std::fabs(v) > 1.0) {
                diags_.error("E0005", range(c), "number '" + c->getText() + "' is out of range")
                    .notes.push_back({{}, "numbers must be finite double-precision values "
                                          "(magnitude below 1.8e308)"});
                v = 0.0;
            } else {
                v = 0.0;  // underflow to zero is harmless
            }
        }
        return v;
    }

    ast::Quantity quantity(SdvParser::QuantityContext* c) {
        ast::Quantity q;
        q.value = number(c->number());
        q.text = c->number()->getText();
        q.is_integer = c->number()->INT() != nullptr;
        if (c->sign != nullptr && c->sign->getText() == "-") {
            q.value = -q.value;
            q.text = "-" + q.text;
        }
        if (auto* u = c->unit()) {
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
            std::string t = child->getText();
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
        if (auto* q = c->quantity()) {
            p.kind = ast::Primary::Kind::quantity;
            p.quantity = quantity(q);
        } else if (auto* n = c->qualName()) {
            p.kind = ast::Primary::Kind::name;
            p.name = qual(n);
        } else {
            p.kind = ast::Primary::Kind::string;
            p.string = unescape(c->STRING()->getText());
        }
        return p;
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
                auto* sv = dynamic_cast<SdvParser::SingleValueContext*>(v);
                if (sv != nullptr && !sv->spread() && !sv->samples()) {
                    s.method_arg = primary(sv->primary());
                } else {
                    diags_.error("E0003", range(v), "syntax error: expected a single quantity "
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
        if (auto* s = dynamic_cast<SdvParser::SingleValueContext*>(c)) {
            v.kind = ast::Value::Kind::single;
            v.lo = primary(s->primary());
            if (auto* sp = s->spread()) v.spread = primary(sp->primary());
            if (auto* sm = s->samples()) v.samples = samples(sm);
        } else if (auto* iv = dynamic_cast<SdvParser::IntervalValueContext*>(c)) {
            v.kind = ast::Value::Kind::interval;
            v.lo = primary(iv->primary(0));
            v.hi = primary(iv->primary(1));
            if (auto* sm = iv->samples()) v.samples = samples(sm);
        } else if (auto* lv = dynamic_cast<SdvParser::ListValueContext*>(c)) {
            v.kind = ast::Value::Kind::list;
            for (auto* item : lv->value()) v.items.push_back(value(item));
        }
        return v;
    }

    std::vector<ast::Arg> args(SdvParser::ArgListContext* c) {
        std::vector<ast::Arg> out;
        if (c == nullptr) return out;
        for (auto* a : c->arg()) out.push_back({qual(a->qualName()), value(a->value()), range(a)});
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
                    diags_.error("E0504", range(s), "duplicate 'lanes' in road '" + r.name.text + "'");
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
            }
        }
        return j;
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
                    wp.time = value(w->value(0));
                    wp.position = position(w->position());
                    if (w->SPEED()) wp.speed = value(w->value(1));
                    wp.range = range(w);
                    wps.push_back(std::move(wp));
                }
                v.trajectories.push_back(std::move(wps));
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
                set.key = {"rate " + rt->ident()->getText(), range(rt->ident())};
                set.values.push_back(value(rt->value()));
                set.range = range(rt);
                s.settings.push_back(std::move(set));
            } else if (auto* vh = dynamic_cast<SdvParser::ScenarioVehicleContext*>(st)) {
                ast::VehicleDecl v;
                v.is_ego = vh->EGO() != nullptr;
                v.name = ident(vh->ident(0));
                v.kind = ident(vh->ident(1));
                v.range = range(vh);
                s.vehicles.push_back(vehicle(vh->vehicleStmt(), std::move(v)));
            } else if (auto* ob = dynamic_cast<SdvParser::ScenarioObjectContext*>(st)) {
                ast::VehicleDecl v;
                v.is_object = true;
                v.name = ident(ob->ident());
                v.kind = {"static", range(ob->OBJECT())};
                v.range = range(ob);
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
                        set.values.push_back(value(ph->value()));
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
            }
        }
        return s;
    }

    diag::FileId file_;
    const std::vector<uint32_t>& offs_;
    diag::DiagnosticEngine& diags_;
};

}  // namespace

std::unique_ptr<ast::File> parse(diag::FileId file, const diag::SourceManager& sm,
                                 diag::DiagnosticEngine& diags) {
    const std::string_view text = sm.contents(file);
    if (size_t bad = find_invalid_utf8(text); bad != std::string_view::npos) {
        const auto off = static_cast<uint32_t>(bad);
        char hex[8];
        std::snprintf(hex, sizeof hex, "0x%02X", static_cast<unsigned char>(text[bad]));
        diags.error("E0001", {{file, off}, {file, off + 1}},
                    std::string("file is not valid UTF-8 text (byte ") + hex + ")")
            .notes.push_back({{}, ".sdv files are UTF-8 text; is this a binary file?"});
        return nullptr;
    }
    const std::vector<uint32_t> offs = code_point_offsets(text);
    auto range_of = [&](Token* t) -> diag::SourceRange {
        const size_t b = std::min(t->getStartIndex(), offs.size() - 1);
        const size_t e = std::min(t->getStopIndex() + 1, offs.size() - 1);
        return {{file, offs[b]}, {file, offs[std::max(b, e)]}};
    };

    try {
        antlr4::ANTLRInputStream input(text.data(), text.size());
        SdvLexer lexer(&input);
        lexer.removeErrorListeners();
        std::vector<std::unique_ptr<Token>> tokens = lexer.getAllTokens();

        // Pre-parse pass: report stray characters and unterminated strings once each, drop
        // them from the stream, and refuse pathological nesting before the recursive parser
        // sees it.
        std::vector<std::unique_ptr<Token>> kept;
        kept.reserve(tokens.size() + 1);
        int depth = 0;
        int decorators = 0;
        bool lexical_errors = false;
        for (size_t i = 0; i < tokens.size(); ++i) {
            auto& t = tokens[i];
            const size_t type = t->getType();
            if (type == SdvLexer::ERROR_CHAR) {
                size_t j = i;
                while (j + 1 < tokens.size() && tokens[j + 1]->getType() == SdvLexer::ERROR_CHAR &&
                       tokens[j + 1]->getStartIndex() == tokens[j]->getStopIndex() + 1) {
                    ++j;
                }
                diag::SourceRange r{range_of(t.get()).begin, range_of(tokens[j].get()).end};
                std::string shown = t->getText();
                diags.error("E0001", r, "unexpected character '" + shown + "'");
                lexical_errors = true;
                if (diags.limit_reached()) return nullptr;
                i = j;
                continue;
            }
            if (type == SdvLexer::UNTERMINATED_STRING) {
                diags.error("E0002", range_of(t.get()), "unterminated string")
                    .notes.push_back({{}, "add the closing '\"' on the same line"});
                lexical_errors = true;
                continue;
            }
            if (t->getChannel() != Token::DEFAULT_CHANNEL) continue;
            if (t->getStopIndex() == t->getStartIndex()) {  // brackets are one character
                const std::string tx = t->getText();
                if (tx == "{" || tx == "(" || tx == "[") ++depth;
                if (tx == "}" || tx == ")" || tx == "]") depth = std::max(0, depth - 1);
            }
            decorators = (type == SdvLexer::NOT || type == SdvLexer::ONCE || type == SdvLexer::LATCH) ? decorators + 1 : 0;
            if (depth + decorators > kMaxNesting) {
                diags.error("E0004", range_of(t.get()),
                            "nesting is too deep (more than " + std::to_string(kMaxNesting) +
                                " levels)")
                    .notes.push_back({{}, "split the tree into named subtrees"});
                return nullptr;
            }
            kept.push_back(std::move(t));
        }
        if (lexical_errors) return nullptr;
        if (kept.empty()) {
            diags.error("E0008", {{file, 0}, {file, 0}}, "the file declares nothing")
                .notes.push_back({{}, "a .sdv file holds imports, roads, trees and scenarios"});
            return nullptr;
        }
        kept.push_back(lexer.nextToken());  // EOF, which getAllTokens() leaves out

        antlr4::ListTokenSource source(std::move(kept));
        antlr4::CommonTokenStream stream(&source);
        SdvParser parser(&stream);
        parser.removeErrorListeners();
        ErrorListener listener(file, offs, diags);
        SdvParser::FileContext* tree = nullptr;
        // Two stages, as ANTLR recommends: SLL prediction bailing out at the first error (fast,
        // and exact for every input it accepts), then full LL with error reporting and
        // recovery only for a file SLL rejects.
        parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(antlr4::atn::PredictionMode::SLL);
        parser.setErrorHandler(std::make_shared<antlr4::BailErrorStrategy>());
        try {
            tree = parser.file();
        } catch (const antlr4::ParseCancellationException&) {
            tree = nullptr;
        }
        if (tree == nullptr) {
            stream.seek(0);
            parser.reset();
            parser.setErrorHandler(std::make_shared<antlr4::DefaultErrorStrategy>());
            parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(antlr4::atn::PredictionMode::LL);
        }
        parser.addErrorListener(&listener);
        try {
            if (tree == nullptr) tree = parser.file();
        } catch (const CancelParse&) {
            diags.error("E0003", {}, "too many syntax errors in " + std::string(sm.path(file)) +
                                         "; stopping");
            return nullptr;
        }
        if (listener.count() > 0 || parser.getNumberOfSyntaxErrors() > 0) return nullptr;
        Builder builder(file, offs, diags);
        return builder.build(tree);
    } catch (const std::exception& e) {
        diags.error("E0003", {{file, 0}, {file, 0}},
                    std::string("the parser failed on this file: ") + e.what());
        return nullptr;
    }
}

std::string dump_tokens(diag::FileId file, const diag::SourceManager& sm) {
    const std::string_view text = sm.contents(file);
    if (find_invalid_utf8(text) != std::string_view::npos) return "";
    const std::vector<uint32_t> offs = code_point_offsets(text);
    antlr4::ANTLRInputStream input(text.data(), text.size());
    SdvLexer lexer(&input);
    lexer.removeErrorListeners();
    std::string out;
    const auto& vocab = lexer.getVocabulary();
    for (auto& t : lexer.getAllTokens()) {
        if (t->getChannel() != Token::DEFAULT_CHANNEL) continue;
        const size_t b = std::min(t->getStartIndex(), offs.size() - 1);
        auto lc = sm.line_col({file, offs[b]});
        std::string name = vocab.getSymbolicName(t->getType());
        if (name.empty()) name = vocab.getLiteralName(t->getType());
        out += std::to_string(lc.line) + ":" + std::to_string(lc.col) + " " + name + " '" +
               t->getText() + "'\n";
    }
    return out;
}

}  // namespace sdv::compiler::syntax
