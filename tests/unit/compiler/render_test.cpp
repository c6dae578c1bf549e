// The text rendering of a diagnostic (compiler/diag/render.h): its source snippet shows a window
// of a long line around the caret. The window is found from the caret's byte; this test holds it
// to the straightforward definition (count code points from the line's start), kept here as the
// reference, on random files of ASCII, tabs, multi-byte UTF-8, stray continuation bytes and
// CRLF line ends, with carets anywhere (inside a code point, on a line break, at the end).
#include <doctest/doctest.h>

#include <random>
#include <string>

#include "compiler/diag/diagnostic.h"
#include "compiler/diag/render.h"
#include "compiler/diag/source_manager.h"

using namespace sdv::diag;

namespace {

size_t count_code_points(std::string_view s) {
    size_t n = 0;
    for (char c : s) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
    return n;
}

// The snippet as first written: every code point of the line counted up to the window.
std::string reference_snippet(SourceRange r, const SourceManager& sm) {
    const auto b = sm.line_col(r.begin);
    if (b.line == 0) return "";
    const std::string_view text = sm.line_text(r.begin.file, b.line);
    constexpr size_t kBefore = 60, kMaxShown = 160;
    const size_t first = b.col > kBefore + 20 ? b.col - kBefore : 1;
    size_t col = b.col - first + 1;
    std::string shown = first > 1 ? "..." : "";
    if (first > 1) col += 3;
    size_t cp = 0;
    for (size_t i = 0; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if ((c & 0xC0) != 0x80) ++cp;
        if (cp < first) continue;
        if (cp >= first + kMaxShown) {
            if ((c & 0xC0) != 0x80) {
                shown += "...";
                break;
            }
            continue;
        }
        shown += (c == '\t' || c < 0x20) ? ' ' : static_cast<char>(c);
    }
    size_t width = 1;
    const auto e = sm.line_col(r.end);
    if (r.end.file == r.begin.file && r.end.offset > r.begin.offset) {
        const size_t line_end = count_code_points(shown) + 1;
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

std::string random_file(std::mt19937& rng) {
    static const char* const pieces[] = {"a", "z", " ", "\t", "\xC3\xA9", "\xE2\x82\xAC", "\xF0\x9F\x9A\x97",
                                         "\x80", "\xBF", "\xC3", "\r\n", "\n", "\x01", "("};
    std::uniform_int_distribution<int> lines(1, 4), len(0, 1), piece(0, 13), kind(0, 9);
    std::string file;
    for (int l = lines(rng); l > 0; --l) {
        // Short lines, lines about as long as the window, and long ones.
        const int k = kind(rng);
        const size_t n = k < 3 ? std::uniform_int_distribution<size_t>(0, 90)(rng)
                       : k < 7 ? std::uniform_int_distribution<size_t>(60, 260)(rng)
                               : std::uniform_int_distribution<size_t>(200, 3000)(rng);
        for (size_t i = 0; i < n; ++i) {
            const int p = piece(rng);
            if (p >= 10 && p <= 11 && i + 1 < n) continue;  // line breaks only at the end
            file += pieces[p];
        }
        if (l > 1) file += len(rng) ? "\r\n" : "\n";
    }
    return file;
}

}  // namespace

TEST_CASE("a diagnostic's snippet shows the window a scan from the line's start shows") {
    std::mt19937 rng(2026);
    for (int round = 0; round < 3000; ++round) {
        SourceManager sm;
        const std::string text = random_file(rng);
        const FileId id = sm.add_file("f.sdv", text);
        std::uniform_int_distribution<uint32_t> at(0, static_cast<uint32_t>(text.size()) + 2);
        for (int k = 0; k < 8; ++k) {
            uint32_t a = at(rng), b = at(rng);
            if (b < a) std::swap(a, b);
            Diagnostic d;
            d.severity = Severity::warning;
            d.code = "W0000";
            d.message = "m";
            d.range = {{id, a}, {id, b}};
            const auto lc = sm.line_col(d.range.begin);
            const std::string expected = "f.sdv:" + std::to_string(lc.line) + ":" + std::to_string(lc.col) +
                                         ": warning[W0000]: m\n" + reference_snippet(d.range, sm);
            INFO("round " << round << ", range " << a << ".." << b << " of " << text.size() << " bytes");
            REQUIRE(render_text(d, sm) == expected);
        }
    }
}

TEST_CASE("a snippet of a long line is a window of it") {
    SourceManager sm;
    const std::string line(1'000'000, 'x');
    const FileId id = sm.add_file("long.btree", line + "\n");
    Diagnostic d;
    d.severity = Severity::error;
    d.code = "E0000";
    d.message = "m";
    d.range = {{id, 900'000}, {id, 900'003}};
    const std::string out = render_text(d, sm);
    CHECK(out.rfind("long.btree:1:900001: error[E0000]: m\n", 0) == 0);
    CHECK(out.size() < 600);
    CHECK(out.find("| ..." + std::string(60, 'x') + std::string(100, 'x') + "...\n") != std::string::npos);
    CHECK(out.find(std::string(64, ' ') + "^~~\n") != std::string::npos);
}
