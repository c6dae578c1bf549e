// `sdv compile --emit tokens` (compiler::syntax::dump_tokens): every token's `line:col` is where
// its text starts in the source, as SourceManager::line_col counts it (lines at '\n', columns in
// code points, a tab or a '\r' one column). Checked on random texts of every token kind, with
// multi-byte characters, tabs, CRLF line ends, comments and blank lines.
#include <doctest/doctest.h>

#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/diag/source_manager.h"
#include "compiler/syntax/parser.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace tokens_test {

using namespace sdv;

namespace {

// Pieces a line is made of: keywords, names, numbers, units, strings (some with multi-byte
// characters or escapes), operators, characters the lexer does not know, and comments.
const std::vector<std::string> kPieces = {
    "scenario", "vehicle",  "road",     "expect", "and",     "speed_1", "x",      "42",
    "1_000",    "3.5e2",    "0.25",     "m/s²",   "±",       "+-",      "%",      "..",
    "<=",       ">",        "{",        "}",      "(",       ")",       ",",      ":",
    "\"s\"",    "\"é ü\"",  "\"a\\\"b\"", "\"∞ → ∑\"", "\"",   "@",       "é",      "→",
    "# a comment ü", "#",   "\t",       "  ",     "\r",      "µ",       "³",      "=",
};

std::string random_text(std::mt19937& rng) {
    std::uniform_int_distribution<int> lines(1, 12), pieces(0, 8), pick(0, int(kPieces.size()) - 1),
        space(0, 3), crlf(0, 4);
    std::string text;
    const int n = lines(rng);
    for (int l = 0; l < n; ++l) {
        const int k = pieces(rng);
        for (int p = 0; p < k; ++p) {
            const std::string& piece = kPieces[static_cast<size_t>(pick(rng))];
            text += piece;
            // A comment runs to the line end.
            if (piece[0] == '#') break;
            text += std::string(static_cast<size_t>(space(rng)), ' ');
        }
        text += crlf(rng) == 0 ? "\r\n" : "\n";
    }
    return text;
}

// The offset of the first byte of code point `col` (1-based) of line `line`.
size_t offset_of(const diag::SourceManager& sm, diag::FileId id, uint32_t line, uint32_t col) {
    const std::string_view text = sm.contents(id);
    const std::string_view l = sm.line_text(id, line);
    size_t off = static_cast<size_t>(l.data() - text.data());
    for (uint32_t c = 1; c < col && off < text.size(); ++c) {
        ++off;
        while (off < text.size() && (static_cast<unsigned char>(text[off]) & 0xC0) == 0x80) ++off;
    }
    return off;
}

}  // namespace

TEST_CASE("--emit tokens: every token's line:col is where its text starts") {
    std::mt19937 rng(22);
    int tokens = 0, after_multibyte = 0;
    for (int round = 0; round < 300; ++round) {
        const std::string text = random_text(rng);
        diag::SourceManager sm;
        const auto id = sm.add_file("t.sdv", text);
        const std::string dump = compiler::syntax::dump_tokens(id, sm);
        std::istringstream in(dump);
        std::string row;
        size_t last = 0;
        while (std::getline(in, row)) {
            CAPTURE(text);
            CAPTURE(row);
            uint32_t line = 0, col = 0;
            char colon = 0;
            std::istringstream fields(row);
            fields >> line >> colon >> col;
            REQUIRE(colon == ':');
            // `line:col NAME 'text'`: a NAME has no space (a literal one is quoted: '{').
            const size_t name = row.find(' ');
            REQUIRE(name != std::string::npos);
            const size_t q = row.find(' ', name + 1) + 1;
            REQUIRE(q > 0);
            REQUIRE(row[q] == '\'');
            REQUIRE(row.back() == '\'');
            const std::string token = row.substr(q + 1, row.size() - q - 2);
            const size_t off = offset_of(sm, id, line, col);
            CHECK(text.compare(off, token.size(), token) == 0);
            CHECK(off >= last);
            const auto lc = sm.line_col({id, static_cast<uint32_t>(off)});
            CHECK(lc.line == line);
            CHECK(lc.col == col);
            const auto line_start = static_cast<size_t>(sm.line_text(id, line).data() - text.data());
            if (off - line_start + 1 != col) ++after_multibyte;
            last = off + token.size();
            ++tokens;
        }
    }
    // The texts reach tokens after multi-byte characters on their line.
    CHECK(tokens > 3000);
    CHECK(after_multibyte > 500);
}

}  // namespace tokens_test
