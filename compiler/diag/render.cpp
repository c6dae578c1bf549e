#include "compiler/diag/render.h"

#include <algorithm>

namespace sdv::diag {
namespace {

const char* severity_word(Severity s) {
    switch (s) {
        case Severity::error: return "error";
        case Severity::warning: return "warning";
        case Severity::note: return "note";
    }
    return "error";
}

size_t code_points(std::string_view s) {
    size_t n = 0;
    for (char c : s) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
    return n;
}

// The source line under a location with a caret line below it.
std::string snippet(SourceRange r, const SourceManager& sm) {
    const auto b = sm.line_col(r.begin);
    if (b.line == 0) return "";
    const std::string_view text = sm.line_text(r.begin.file, b.line);
    // Long lines (generated files) are shown as a window around the caret, found from the
    // caret's byte rather than from the line's start: a line of a megabyte costs no more than a
    // short one, however many diagnostics it has (a .btree call with 4,000 arguments had one
    // warning per argument, each of which scanned the line up to its caret).
    constexpr size_t kBefore = 60, kMaxShown = 160;
    const size_t first = b.col > kBefore + 20 ? b.col - kBefore : 1;  // first column shown
    size_t col = b.col - first + 1;
    std::string shown = first > 1 ? "..." : "";
    if (first > 1) col += 3;
    const auto continuation = [](char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; };
    size_t start = 0;  // byte of the line where the window starts
    if (first > 1) {
        // From the caret's byte (as line_col clamps it), walking back over the first bytes of
        // kBefore code points reaches the first byte of column `first`.
        const std::string_view all = sm.contents(r.begin.file);
        const auto line_start = static_cast<size_t>(text.data() - all.data());
        size_t at = std::min<size_t>(r.begin.offset, all.size());
        for (size_t back = b.col - first; back > 0 && at > line_start;) {
            if (!continuation(all[--at])) --back;
        }
        start = at - line_start;
    }
    size_t cp = 0;  // code points shown
    for (size_t i = start; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (!continuation(text[i])) {
            if (cp == kMaxShown) {
                shown += "...";
                break;
            }
            ++cp;
        } else if (cp == 0) {
            continue;  // bytes that continue no code point before the window
        }
        shown += (c == '\t' || c < 0x20) ? ' ' : static_cast<char>(c);
    }
    // Width of the underline: the range on this line, at least one.
    size_t width = 1;
    const auto e = sm.line_col(r.end);
    if (r.end.file == r.begin.file && r.end.offset > r.begin.offset) {
        const size_t line_end = code_points(shown) + 1;
        width = e.line == b.line ? std::max<size_t>(1, e.col - b.col)
                                 : std::max<size_t>(1, line_end > col ? line_end - col : 1);
        width = std::min(width, std::max<size_t>(1, line_end > col ? line_end - col : 1));
    }
    const std::string num = std::to_string(b.line);
    const size_t gutter = std::max<size_t>(4, num.size());
    std::string out = std::string(gutter - num.size() + 1, ' ') + num + " | " + shown + "\n";
    out += std::string(gutter + 1, ' ') + " | " + std::string(col - 1, ' ') + "^" +
           std::string(width - 1, '~') + "\n";
    return out;
}

std::string location(SourceRange r, const SourceManager& sm) {
    const auto lc = sm.line_col(r.begin);
    return sm.path(r.begin.file) + ":" + std::to_string(lc.line) + ":" + std::to_string(lc.col);
}

}  // namespace

std::string render_text(const Diagnostic& d, const SourceManager& sm) {
    std::string out;
    std::string flag;
    if (!d.warning_name.empty()) {
        flag = d.severity == Severity::warning ? " [-W" + d.warning_name + "]"
                                               : " [-Werror,-W" + d.warning_name + "]";
    }
    const std::string head =
        std::string(severity_word(d.severity)) + "[" + d.code + "]: " + d.message + flag;
    if (d.range.valid()) {
        out = location(d.range, sm) + ": " + head + "\n" + snippet(d.range, sm);
    } else {
        out = "sdv: " + head + "\n";
    }
    for (const auto& n : d.notes) {
        if (n.range.valid()) {
            out += location(n.range, sm) + ": note: " + n.message + "\n" + snippet(n.range, sm);
        } else {
            out += "note: " + n.message + "\n";
        }
    }
    return out;
}

namespace {

struct Counts {
    size_t errors = 0;
    size_t warnings = 0;
};

Counts count(const std::vector<Diagnostic>& ds) {
    Counts n;
    for (const auto& d : ds) {
        n.errors += d.severity == Severity::error;
        n.warnings += d.severity == Severity::warning;
    }
    return n;
}

std::string all_text(const std::vector<Diagnostic>& ds, Counts n, const SourceManager& sm) {
    std::string out;
    for (const auto& d : ds) out += render_text(d, sm);
    if (n.errors + n.warnings > 0) {
        std::string summary;
        if (n.errors) summary = std::to_string(n.errors) + (n.errors == 1 ? " error" : " errors");
        if (n.warnings) {
            summary += (summary.empty() ? "" : ", ") + std::to_string(n.warnings) +
                       (n.warnings == 1 ? " warning" : " warnings");
        }
        out += summary + " generated.\n";
    }
    return out;
}

std::string all_json(const std::vector<Diagnostic>& ds, Counts n, const SourceManager& sm) {
    nlohmann::ordered_json j;
    j["diagnostics"] = nlohmann::ordered_json::array();
    for (const auto& d : ds) j["diagnostics"].push_back(to_json(d, sm));
    j["errors"] = n.errors;
    j["warnings"] = n.warnings;
    return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);  // a message may quote invalid UTF-8 from a file
}

}  // namespace

std::string render_all_text(const DiagnosticEngine& diags, const SourceManager& sm) {
    return all_text(diags.sorted(), {diags.error_count(), diags.warning_count()}, sm);
}

std::string render_all_text(const std::vector<Diagnostic>& ds, const SourceManager& sm) {
    return all_text(ds, count(ds), sm);
}

nlohmann::ordered_json to_json(const Diagnostic& d, const SourceManager& sm) {
    nlohmann::ordered_json j;
    j["severity"] = severity_word(d.severity);
    j["code"] = d.code;
    if (!d.warning_name.empty()) j["name"] = d.warning_name;
    j["message"] = d.message;
    if (d.range.valid()) {
        const auto b = sm.line_col(d.range.begin);
        const auto e = sm.line_col(d.range.end.file != 0 ? d.range.end : d.range.begin);
        j["file"] = sm.path(d.range.begin.file);
        j["line"] = b.line;
        j["column"] = b.col;
        j["end_line"] = e.line;
        j["end_column"] = e.col;
    }
    j["notes"] = nlohmann::ordered_json::array();
    for (const auto& n : d.notes) {
        nlohmann::ordered_json nj;
        nj["message"] = n.message;
        if (n.range.valid()) {
            const auto b = sm.line_col(n.range.begin);
            nj["file"] = sm.path(n.range.begin.file);
            nj["line"] = b.line;
            nj["column"] = b.col;
        }
        j["notes"].push_back(nj);
    }
    return j;
}

std::string render_all_json(const DiagnosticEngine& diags, const SourceManager& sm) {
    return all_json(diags.sorted(), {diags.error_count(), diags.warning_count()}, sm);
}

std::string render_all_json(const std::vector<Diagnostic>& ds, const SourceManager& sm) {
    return all_json(ds, count(ds), sm);
}

}  // namespace sdv::diag
