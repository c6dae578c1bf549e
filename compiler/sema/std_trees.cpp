#include "compiler/sema/std_trees.h"

#include <nlohmann/json.hpp>

#include <sstream>

#include "compiler/syntax/parser.h"
#include "stdlib-trees/stdlib.h"

namespace sdv::compiler {
namespace {

std::string text_of(std::string_view src, const diag::SourceRange& r) {
    if (!r.valid() || r.begin.offset > r.end.offset || r.end.offset > src.size()) return "";
    return std::string(src.substr(r.begin.offset, r.end.offset - r.begin.offset));
}

// The `#` lines directly above offset `at` (the tree's first line), without their '#'.
std::string doc_above(std::string_view src, uint32_t at) {
    size_t line_start = src.rfind('\n', at == 0 ? 0 : at - 1);
    line_start = line_start == std::string_view::npos ? 0 : line_start + 1;
    std::vector<std::string> lines;
    while (line_start > 0) {
        const size_t prev_end = line_start - 1;  // the '\n' ending the line above
        const size_t prev_start_nl = prev_end == 0 ? std::string_view::npos : src.rfind('\n', prev_end - 1);
        const size_t prev_start = prev_start_nl == std::string_view::npos ? 0 : prev_start_nl + 1;
        std::string_view line = src.substr(prev_start, prev_end - prev_start);
        const size_t first = line.find_first_not_of(" \t");
        if (first == std::string_view::npos || line[first] != '#') break;
        line.remove_prefix(first + 1);
        if (!line.empty() && line.front() == ' ') line.remove_prefix(1);
        lines.emplace_back(line);
        line_start = prev_start;
    }
    std::string out;
    for (auto it = lines.rbegin(); it != lines.rend(); ++it) out += (out.empty() ? "" : "\n") + *it;
    return out;
}

std::string signature(const StdTree& t) {
    std::string s = t.name + "(";
    for (size_t i = 0; i < t.params.size(); ++i) {
        const auto& p = t.params[i];
        s += (i ? ", " : "") + p.name + ": " + p.type + (p.def.empty() ? "" : " = " + p.def);
    }
    return s + ")";
}

}  // namespace

std::vector<StdTree> std_trees() {
    std::vector<StdTree> out;
    for (const stdlib::File& f : stdlib::files()) {
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        const diag::FileId id = sm.add_file(std::string(f.path), std::string(f.contents));
        auto file = syntax::parse(id, sm, diags);
        if (!file) continue;
        const std::string_view src = sm.contents(id);
        for (const auto& t : file->trees) {
            StdTree st;
            st.name = "std." + t.name.text;
            st.file = std::string(f.path);
            st.doc = doc_above(src, t.range.begin.offset);
            for (const auto& p : t.params) st.params.push_back({p.name.text, p.type.text, p.def ? text_of(src, p.def->range) : ""});
            out.push_back(std::move(st));
        }
    }
    return out;
}

std::string render_std_trees_text(const std::vector<StdTree>& trees) {
    std::ostringstream out;
    for (const auto& t : trees) {
        out << signature(t) << "    (import \"" << t.file << "\")\n";
        std::istringstream doc(t.doc);
        for (std::string line; std::getline(doc, line);) out << "    " << line << "\n";
        out << "\n";
    }
    return out.str();
}

std::string render_std_trees_markdown(const std::vector<StdTree>& trees) {
    std::ostringstream out;
    out << "## Standard trees\n\n"
        << "The trees of the standard library (`sdv catalog --trees`), with their parameters and the "
           "comment written above each in its file. Import the file, then `tree std.NAME(param = value)`; "
           "node fields are overridden as `node.field = value`.\n\n";
    for (const auto& t : trees) {
        out << "### `" << t.name << "`\n\n`import \"" << t.file << "\"`\n\n";
        if (!t.doc.empty()) {
            out << "```\n" << t.doc << "\n```\n\n";
        }
        if (t.params.empty()) {
            out << "No parameters.\n\n";
            continue;
        }
        out << "| parameter | type | default |\n|---|---|---|\n";
        for (const auto& p : t.params) out << "| `" << p.name << "` | " << p.type << " | " << (p.def.empty() ? "(required)" : p.def) << " |\n";
        out << "\n";
    }
    return out.str();
}

std::string render_std_trees_json(const std::vector<StdTree>& trees) {
    nlohmann::ordered_json j = nlohmann::ordered_json::array();
    for (const auto& t : trees) {
        nlohmann::ordered_json jt;
        jt["name"] = t.name;
        jt["file"] = t.file;
        jt["doc"] = t.doc;
        jt["params"] = nlohmann::ordered_json::array();
        for (const auto& p : t.params) {
            nlohmann::ordered_json jp;
            jp["name"] = p.name;
            jp["type"] = p.type;
            if (!p.def.empty()) jp["default"] = p.def;
            jt["params"].push_back(jp);
        }
        j.push_back(jt);
    }
    return j.dump(2) + "\n";
}

}  // namespace sdv::compiler
