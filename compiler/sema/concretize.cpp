// One variant of a campaign written back as a plain scenario: the source with the scenario's
// vary block removed and each varied value written where the scenario states it (or added
// where it would be written: a vehicle setting before the vehicle's closing brace, a tree
// argument at the end of the call, a position's offset or heading after the position, a
// scenario setting where the vary block was). Everything else, comments included, is kept.
#include <algorithm>

#include "compiler/sema/compile.h"
#include "compiler/syntax/parser.h"

namespace sdv::compiler {
namespace {

struct Edit {
    uint32_t begin = 0, end = 0;  // bytes replaced
    std::string text;
};

}  // namespace

std::optional<std::string> concretize(const std::string& display, const std::string& text, const std::string& scenario,
                                      const std::vector<std::pair<std::string, std::string>>& values,
                                      const std::string& comment, std::string& error) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    const auto id = sm.add_file(display, text);
    auto file = syntax::parse(id, sm, diags);
    if (file == nullptr || diags.has_errors()) {
        error = "'" + display + "' does not parse";
        return std::nullopt;
    }
    const ast::ScenarioDecl* s = nullptr;
    for (const auto& sc : file->scenarios) {
        if (sc.name.text == scenario) s = &sc;
    }
    if (s == nullptr || s->varies.empty()) {
        error = "'" + display + "' has no scenario '" + scenario + "' with a vary block";
        return std::nullopt;
    }
    const ast::VaryDecl& vary = s->varies[0];
    std::vector<Edit> edits;
    // Where the vary block was: the comment, then any scenario settings that had no line.
    std::string at_vary = "# " + comment;
    auto replace_value = [&](const ast::Value& v, const std::string& t) {
        edits.push_back({v.lo.range.begin.offset, v.lo.range.end.offset, t});
    };
    auto insert = [&](uint32_t at, const std::string& t) { edits.push_back({at, at, t}); };
    for (const auto& entry : values) {
        const std::string& path = entry.first;  // not a structured binding: clang 14 cannot capture those
        const std::string& value = entry.second;
        std::vector<std::string> parts;
        for (size_t from = 0;;) {
            const size_t dot = path.find('.', from);
            parts.push_back(path.substr(from, dot == std::string::npos ? std::string::npos : dot - from));
            if (dot == std::string::npos) break;
            from = dot + 1;
        }
        auto scenario_setting = [&](const std::string& key, const std::string& line) {
            for (const auto& st : s->settings) {
                if (st.key.text == key && !st.values.empty()) {
                    replace_value(st.values[0], value);
                    return;
                }
            }
            at_vary += "\n    " + line;
        };
        if (parts.size() == 1 && (parts[0] == "seed" || parts[0] == "timeout")) {
            scenario_setting(parts[0], parts[0] + " " + value);
            continue;
        }
        if (parts.size() == 2 && parts[0] == "rate") {
            scenario_setting("rate " + parts[1], "rate " + parts[1] + " " + value);
            continue;
        }
        const ast::VehicleDecl* v = nullptr;
        for (const auto& x : s->vehicles) {
            if (x.name.text == parts[0]) v = &x;
        }
        if (v == nullptr || parts.size() < 2) {
            error = "cannot place '" + path + "' in scenario '" + scenario + "'";
            return std::nullopt;
        }
        const std::string& what = parts[1];
        if (what == "speed" || what == "length" || what == "width") {
            const ast::Setting* found = nullptr;
            for (const auto& st : v->settings) {
                if (st.key.text == what && !st.values.empty()) found = &st;
            }
            if (found != nullptr) {
                replace_value(found->values[0], value);
            } else {
                insert(v->range.end.offset - 1, "    " + what + " " + value + "\n    ");
            }
        } else if ((what == "start" || what == "goal") && parts.size() <= 3) {
            const auto& ps = what == "start" ? v->starts : v->goals;
            if (ps.empty()) {
                error = "vehicle '" + v->name.text + "' has no " + what;
                return std::nullopt;
            }
            const ast::Position& p = ps[0];
            const std::string field = parts.size() == 3 ? parts[2] : p.xy ? "" : "s";
            const std::optional<ast::Value>* f = field == "s"        ? &p.s
                                                 : field == "offset" ? &p.offset
                                                 : field == "x"      ? &p.x
                                                 : field == "y"      ? &p.y
                                                 : field == "heading" ? &p.heading
                                                                      : nullptr;
            if (f == nullptr) {
                error = "cannot place '" + path + "'";
                return std::nullopt;
            }
            if (*f) {
                replace_value(**f, value);
            } else {
                insert(p.range.end.offset, " " + field + " " + value);
            }
        } else if (what == "tree" && parts.size() >= 3 && !v->trees.empty()) {
            const ast::TreeRef& t = v->trees[0];
            std::string arg = parts[2];
            for (size_t k = 3; k < parts.size(); ++k) arg += "." + parts[k];
            const ast::Arg* found = nullptr;
            for (const auto& a : t.args) {
                if (a.name.str() == arg) found = &a;
            }
            if (found != nullptr) {
                replace_value(found->value, value);
            } else {
                insert(t.range.end.offset - 1, (t.args.empty() ? "" : ", ") + arg + " = " + value);
            }
        } else {
            error = "cannot place '" + path + "' in scenario '" + scenario + "'";
            return std::nullopt;
        }
    }
    // The vary block (and the indentation before it) becomes the comment and settings.
    uint32_t begin = vary.range.begin.offset;
    while (begin > 0 && (text[begin - 1] == ' ' || text[begin - 1] == '\t')) --begin;
    edits.push_back({begin, vary.range.end.offset, "    " + at_vary});
    std::sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.begin > b.begin; });
    std::string out = text;
    for (const auto& e : edits) out.replace(e.begin, e.end - e.begin, e.text);
    return out;
}

}  // namespace sdv::compiler
