// AST helpers and the `--emit ast` dump: an indented outline, one node per line, with the
// line:col of each node so that the dump can be read next to the source.
#include "compiler/ast/ast.h"

#include <sstream>

namespace sdv::compiler::ast {

std::string QualName::str() const {
    std::string s;
    for (size_t i = 0; i < parts.size(); ++i) s += (i ? "." : "") + parts[i].text;
    return s;
}

std::string LaneRef::str() const {
    switch (kind) {
        case Kind::index: return std::to_string(index);
        case Kind::name: return name.str();
        case Kind::string: return "\"" + string + "\"";
    }
    return "";
}

const char* to_string(NodeKind kind) {
    switch (kind) {
        case NodeKind::fallback: return "fallback";
        case NodeKind::sequence: return "sequence";
        case NodeKind::reactive_sequence: return "reactive_sequence";
        case NodeKind::parallel: return "parallel";
        case NodeKind::condition: return "condition";
        case NodeKind::maneuver: return "maneuver";
        case NodeKind::subtree: return "subtree";
        case NodeKind::not_: return "not";
        case NodeKind::once: return "once";
        case NodeKind::latch: return "latch";
    }
    return "?";
}

namespace {

class Dumper {
public:
    Dumper(const diag::SourceManager& sm) : sm_(sm) {}

    void crosswalk(const CrosswalkDecl& x) {
        std::string t = "crosswalk " + x.name.text;
        if (x.arm) t += " on " + x.arm->text;
        if (x.at) t += " at " + value(*x.at);
        if (x.width) t += " width " + value(*x.width);
        if (x.signalised) t += " signalised";
        line(1, x.range, t);
    }

    std::string run(const File& f) {
        for (const auto& i : f.imports) {
            line(0, i.range, "import \"" + i.path + "\"" + (i.alias ? " as " + i.alias->text : ""));
        }
        for (const auto& r : f.roads) {
            line(0, r.range, "road " + r.name.text);
            for (const auto& l : r.lanes) {
                line(1, l.range, "lanes " + std::to_string(l.count) + " " + l.direction.text);
            }
            for (const auto& s : r.settings) setting(1, s);
            for (const auto& seg : r.segments) {
                std::string t = seg.arc ? "arc " : "straight ";
                t += value(seg.length);
                if (seg.radius) t += " radius " + value(*seg.radius);
                if (seg.side) t += " " + seg.side->text;
                line(1, seg.range, t);
            }
            for (const auto& x : r.crosswalks) crosswalk(x);
        }
        for (const auto& j : f.junctions) {
            line(0, j.range, "junction " + j.name.text);
            for (const auto& s : j.settings) setting(1, s);
            for (const auto& x : j.crosswalks) crosswalk(x);
        }
        for (const auto& m : f.maps) {
            line(0, m.range, "map " + m.name.text);
            for (const auto& s : m.settings) setting(1, s);
        }
        for (const auto& t : f.trees) {
            std::string head = "tree " + t.name.text + "(";
            for (size_t i = 0; i < t.params.size(); ++i) {
                const auto& p = t.params[i];
                head += (i ? ", " : "") + p.name.text + ": " + p.type.text;
                if (p.def) head += " = " + value(*p.def);
            }
            line(0, t.range, head + ")");
            for (const auto& n : t.body) node(1, *n);
        }
        for (const auto& s : f.scenarios) {
            line(0, s.range, "scenario " + s.name.text);
            for (const auto& st : s.settings) setting(1, st);
            for (const auto& v : s.vehicles) {
                line(1, v.range, std::string(v.is_object ? "object " : v.is_ego ? "ego " : v.is_pedestrian ? "pedestrian " : "vehicle ") +
                                     v.name.text + repeat(v) + ": " + v.kind.text);
                for (const auto& p : v.starts) line(2, p.range, "start " + position(p));
                for (const auto& st : v.settings) setting(2, st);
                for (const auto& p : v.goals) line(2, p.range, "goal " + position(p) + (v.goal_ends_run ? " ends run" : ""));
                for (const auto& r : v.routes) {
                    std::string t = "route";
                    for (const auto& l : r) t += " " + l.str();
                    line(2, r.empty() ? v.range : r.front().range, t);
                }
                for (const auto& t : v.trees) line(2, t.range, "tree " + t.name.str() + args(t.args));
                for (const auto& tr : v.trajectories) {
                    for (const auto& w : tr) {
                        line(2, w.range, "waypoint " + value(w.time) + ": " + position(w.position));
                    }
                }
                for (const auto& pa : v.paths) {
                    for (const auto& w : pa) {
                        line(2, w.range, "path point " + position(w.position) + (w.speed ? " speed " + value(*w.speed) : ""));
                    }
                }
                for (const auto& m : v.meets) line(2, m.range, "meet " + m.text);
            }
            for (const auto& l : s.lights) {
                line(1, l.range, "light " + l.name.str());
                for (const auto& p : l.phases) setting(2, p);
                if (l.offset) line(2, l.offset->range, "offset " + value(*l.offset));
            }
            for (const auto& e : s.expects) {
                std::string t = "expect " + expr(*e);
                if (e->window) t += " " + e->window->keyword.text + " " + value(e->window->value);
                line(1, e->range, t);
            }
            for (const auto& va : s.varies) {
                line(1, va.range, "vary");
                for (const auto& p : va.params) {
                    std::string t = p.path.str() + " in ";
                    if (p.kind == VaryParam::Kind::set) {
                        t += "[";
                        for (size_t i = 0; i < p.values.size(); ++i) t += (i ? ", " : "") + primary(p.values[i]);
                        t += "]";
                    } else if (p.kind == VaryParam::Kind::range) {
                        t += primary(p.values[0]) + " .. " + primary(p.values[1]);
                        if (p.count) t += " count " + std::to_string(*p.count);
                    } else {
                        t += p.distribution.text + "(" + primary(p.values[0]) + ", " + primary(p.values[1]) + ")";
                    }
                    line(2, p.range, t);
                }
                for (const auto& st : va.settings) setting(2, st);
            }
        }
        return out_.str();
    }

private:
    void line(int depth, SourceRange r, const std::string& text) {
        auto lc = sm_.line_col(r.begin);
        out_ << std::string(static_cast<size_t>(depth) * 2, ' ') << text << "  @" << lc.line << ":"
             << lc.col << "\n";
    }

    void setting(int depth, const Setting& s) {
        std::string t = s.key.text;
        for (const auto& v : s.values) t += " " + value(v);
        line(depth, s.range, t);
    }

    static std::string repeat(const VehicleDecl& v) {
        if (!v.repeat) return "";
        return "[" + (v.repeat->var ? v.repeat->var->text + " = " : std::string()) + primary(v.repeat->lo) + " .. " +
               primary(v.repeat->hi) + "]";
    }

    static std::string arith(const Arith& a) {
        switch (a.kind) {
            case Arith::Kind::quantity:
                return a.quantity.text + (a.quantity.unit.empty() ? "" : " " + a.quantity.unit);
            case Arith::Kind::name: return (a.negate ? "-" : "") + a.name.str();
            case Arith::Kind::sum:
            case Arith::Kind::product: {
                std::string s = "(";
                for (size_t i = 0; i < a.operands.size(); ++i) {
                    if (i > 0) s += std::string(" ") + a.ops[i - 1] + " ";
                    s += arith(a.operands[i]);
                }
                return s + ")";
            }
            case Arith::Kind::group:
                return (a.negate ? "-" : "") + arith(a.operands[0]) + (a.unit.empty() ? "" : " " + a.unit);
        }
        return "";
    }

    static std::string primary(const Primary& p) {
        switch (p.kind) {
            case Primary::Kind::quantity:
                return p.quantity.text + (p.quantity.unit.empty() ? "" : " " + p.quantity.unit);
            case Primary::Kind::name: return p.name.str();
            case Primary::Kind::string: return "\"" + p.string + "\"";
            case Primary::Kind::expr: return p.expr ? arith(*p.expr) : "";
        }
        return "";
    }

    static std::string value(const Value& v) {
        std::string s;
        switch (v.kind) {
            case Value::Kind::single:
                s = primary(v.lo);
                if (v.spread) s += " +- " + primary(*v.spread);
                break;
            case Value::Kind::interval: s = primary(v.lo) + " .. " + primary(*v.hi); break;
            case Value::Kind::list:
                s = "[";
                for (size_t i = 0; i < v.items.size(); ++i) s += (i ? ", " : "") + value(v.items[i]);
                return s + "]";
        }
        if (v.samples) {
            s += " samples " + std::to_string(v.samples->count);
            if (v.samples->method) s += " " + v.samples->method->text;
            if (v.samples->method_arg) s += "(" + primary(*v.samples->method_arg) + ")";
        }
        return s;
    }

    static std::string args(const std::vector<Arg>& as) {
        std::string s = "(";
        for (size_t i = 0; i < as.size(); ++i) {
            s += (i ? ", " : "") + as[i].name.str() + " = " + value(as[i].value);
        }
        return s + ")";
    }

    static std::string position(const Position& p) {
        if (p.xy) {
            std::string s = "at (" + value(*p.x) + ", " + value(*p.y) + ")";
            if (p.heading) s += " heading " + value(*p.heading);
            return s;
        }
        std::string s = "lane " + p.lane.str() + " at " + value(*p.s);
        if (p.offset) s += " offset " + value(*p.offset);
        return s;
    }

    static std::string expr(const Expr& e) {
        switch (e.kind) {
            case Expr::Kind::not_: return "not (" + expr(*e.lhs) + ")";
            case Expr::Kind::and_: return "(" + expr(*e.lhs) + " and " + expr(*e.rhs) + ")";
            case Expr::Kind::or_: return "(" + expr(*e.lhs) + " or " + expr(*e.rhs) + ")";
            case Expr::Kind::call: {
                std::string s = e.function.text + "(";
                for (size_t i = 0; i < e.args.size(); ++i) s += (i ? ", " : "") + e.args[i].text;
                s += ")";
                if (!e.cmp.empty()) s += " " + e.cmp + " " + value(*e.bound);
                return s;
            }
        }
        return "";
    }

    void node(int depth, const Node& n) {
        std::string t = n.label ? n.label->text + ": " : "";
        t += to_string(n.kind);
        if (!n.callee.parts.empty()) t += " " + n.callee.str();
        if (!n.args.empty() || n.kind == NodeKind::condition || n.kind == NodeKind::maneuver ||
            n.kind == NodeKind::subtree) {
            t += args(n.args);
        }
        line(depth, n.range, t);
        for (const auto& c : n.children) node(depth + 1, *c);
    }

    const diag::SourceManager& sm_;
    std::ostringstream out_;
};

}  // namespace

std::string dump(const File& file, const diag::SourceManager& sm) { return Dumper(sm).run(file); }

}  // namespace sdv::compiler::ast
