// The text rendering of a diagnostic (compiler/diag/render.h): its source snippet shows a window
// of a long line around the caret. The window is found from the caret's byte; this test holds it
// (what is shown of the line, and where the caret is) to the straightforward definition (count
// code points from the line's start), kept here as the reference, on random files of ASCII,
// tabs, multi-byte UTF-8, stray continuation bytes and CRLF line ends, with carets anywhere
// (inside a code point, on a line break, at the end).
#include <doctest/doctest.h>

#include <random>
#include <string>

#include "compiler/diag/diagnostic.h"
#include "compiler/diag/render.h"
#include "compiler/diag/source_manager.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace render_test {

using namespace sdv::diag;

namespace {

// The window as first written: every code point of the line counted up to it. What the
// snippet shows of the line, and the caret's column in that.
struct Window {
    std::string shown;
    size_t caret = 0;
};

Window reference_window(SourceRange r, const SourceManager& sm) {
    const auto b = sm.line_col(r.begin);
    const std::string_view text = sm.line_text(r.begin.file, b.line);
    constexpr size_t kBefore = 60, kMaxShown = 160;
    const size_t first = b.col > kBefore + 20 ? b.col - kBefore : 1;
    Window w{first > 1 ? "..." : "", b.col - first + 1 + (first > 1 ? 3 : 0)};
    size_t cp = 0;
    for (size_t i = 0; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if ((c & 0xC0) != 0x80) ++cp;
        if (cp < first) continue;
        if (cp >= first + kMaxShown) {
            if ((c & 0xC0) != 0x80) {
                w.shown += "...";
                break;
            }
            continue;
        }
        w.shown += (c == '\t' || c < 0x20) ? ' ' : static_cast<char>(c);
    }
    return w;
}

// The window of a rendered diagnostic: its snippet's two lines after the gutter ("  12 | ").
Window rendered_window(const std::string& out) {
    const size_t l1 = out.find('\n') + 1, l2 = out.find('\n', l1) + 1, l3 = out.find('\n', l2);
    const size_t bar1 = out.find(" | ", l1) + 3, bar2 = out.find(" | ", l2) + 3;
    Window w{out.substr(bar1, l2 - 1 - bar1), 0};
    w.caret = out.find('^', bar2) - bar2 + 1;
    REQUIRE(w.caret <= l3 - bar2);
    return w;
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
            INFO("round " << round << ", range " << a << ".." << b << " of " << text.size() << " bytes");
            const Window expected = reference_window(d.range, sm), got = rendered_window(render_text(d, sm));
            REQUIRE(got.shown == expected.shown);
            REQUIRE(got.caret == expected.caret);
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

}  // namespace render_test
