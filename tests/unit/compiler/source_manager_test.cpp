// The line table of compiler/diag/source_manager.h: every offset's line and column, and every
// line's text, held to their definitions (count line breaks and code points from the start of
// the file, byte by byte), kept here as the reference, on random files of every length around
// the table's blocks (256 bytes) and words (8 bytes): ASCII, multi-byte UTF-8 across those
// boundaries, stray and dangling continuation bytes, bytes 0xF8-0xFF, NUL, CR, LF and CRLF.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "compiler/diag/source_manager.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace source_manager_test {

using namespace sdv::diag;

namespace {

bool starts_code_point(unsigned char c) { return (c & 0xC0) != 0x80; }

// The line and column of every offset of `text`, 0 to its end, by one scan from its start: a line
// break starts a line, and the column counts the code points that start before the offset on its
// line, plus one.
std::vector<SourceManager::LineCol> reference_line_cols(const std::string& text) {
    std::vector<SourceManager::LineCol> at;
    uint32_t line = 1, col = 1;
    for (const char c : text) {
        at.push_back({line, col});
        if (c == '\n') {
            ++line;
            col = 1;
        } else if (starts_code_point(static_cast<unsigned char>(c))) {
            ++col;
        }
    }
    at.push_back({line, col});
    return at;
}

// The text of 1-based line `line` without its line break and a CR that ends it (the last line's
// too); empty past the last line.
std::string reference_line_text(const std::string& text, uint32_t line) {
    size_t start = 0;
    for (uint32_t l = 1; l < line; ++l) {
        const size_t nl = text.find('\n', start);
        if (nl == std::string::npos) return "";
        start = nl + 1;
    }
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    if (end > start && text[end - 1] == '\r') --end;
    return text.substr(start, end - start);
}

std::string random_text(std::mt19937& rng, size_t size) {
    static const std::string_view pieces[] = {"a", " ", "\t", "\xC3\xA9", "\xE2\x82\xAC", "\xF0\x9F\x9A\x97",
                                              "\x80", "\xBF", "\xC3", "\xFF", "\xF8", std::string_view("\0", 1),
                                              "\r", "\n", "\r\n"};
    std::uniform_int_distribution<int> piece(0, 14), one_in_four(0, 3);
    const bool one_line = one_in_four(rng) == 0;  // one long line now and then: no CR or LF
    std::string text;
    while (text.size() < size) {
        const int p = piece(rng);
        if (one_line && p >= 12) continue;
        text += pieces[p];
    }
    text.resize(size);  // may cut a code point: a dangling lead byte at the end
    return text;
}

}  // namespace

TEST_CASE("every offset's line and column and every line's text are those of a scan from the start") {
    std::mt19937 rng(2026);
    // Lengths around the word and block boundaries, and random ones up to a few blocks.
    std::vector<size_t> sizes = {0, 1, 7, 8, 9, 15, 16, 17, 255, 256, 257, 511, 512, 513, 1031};
    for (int k = 0; k < 60; ++k) sizes.push_back(std::uniform_int_distribution<size_t>(0, 1400)(rng));
    for (const size_t size : sizes) {
        for (int round = 0; round < 4; ++round) {
            const std::string text = random_text(rng, size);
            SourceManager sm;
            const FileId id = sm.add_file("f.sdv", text);
            REQUIRE(sm.contents(id) == text);
            INFO("file of " << size << " bytes, round " << round);
            const auto positions = reference_line_cols(text);
            for (uint32_t offset = 0; offset <= text.size() + 2; ++offset) {
                // Past the end: the end.
                const auto expected = positions[std::min<size_t>(offset, text.size())];
                const auto got = sm.line_col({id, offset});
                INFO("offset " << offset);
                REQUIRE(got.line == expected.line);
                REQUIRE(got.col == expected.col);
            }
            for (uint32_t line = 0; line <= positions.back().line + 1; ++line) {
                INFO("line " << line);
                REQUIRE(std::string(sm.line_text(id, line)) == (line == 0 ? "" : reference_line_text(text, line)));
            }
        }
    }
}

TEST_CASE("a file that is one long line has its columns in code points") {
    // 3 bytes a code point over 40 blocks: a column far into the line counts every block before it.
    std::string text;
    for (int i = 0; i < 3'500; ++i) text += "\xE2\x82\xAC";
    text += "x\n";
    SourceManager sm;
    const FileId id = sm.add_file("one_line.sdv", text);
    CHECK(sm.line_col({id, 10'500}).col == 3'501);
    CHECK(sm.line_col({id, 10'501}).col == 3'502);  // the line break
    CHECK(sm.line_col({id, 10'502}).line == 2);
    CHECK(sm.line_col({id, 10'502}).col == 1);
    CHECK(sm.line_col({id, 3 * 1'000}).col == 1'001);
    CHECK(sm.line_col({id, 3 * 1'000 + 1}).col == 1'002);  // inside a code point: past it, as the scan says
}

}  // namespace source_manager_test
