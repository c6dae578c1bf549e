// `sdv fmt` (compiler::syntax::format) lexes and parses a file itself, once, after the checks
// parse() makes before parsing (syntax::check_encoding, then syntax::precheck on the tokens it
// lexed). Pinned on mutants of every example and std/ tree file: format gives a text exactly
// when parse() gives an AST; when it does not, it reports what parse() reports, diagnostic for
// diagnostic; and the text it gives is a fixed point that parses.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/diag/render.h"
#include "compiler/syntax/format.h"
#include "compiler/syntax/parser.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace format_test {

using namespace sdv;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> sources() {
    std::vector<std::string> out;
    for (const char* dir : {"examples", "stdlib-trees"}) {
        std::vector<fs::path> paths;
        for (const auto& e : fs::directory_iterator(fs::path(SDV_SOURCE_DIR) / dir)) {
            if (e.path().extension() == ".sdv") paths.push_back(e.path());
        }
        std::sort(paths.begin(), paths.end());
        for (const auto& p : paths) {
            std::ifstream in(p, std::ios::binary);
            std::stringstream ss;
            ss << in.rdbuf();
            out.push_back(ss.str());
        }
    }
    return out;
}

// Edits that break a file in the ways the pre-parse checks and the parser tell apart: stray
// bytes, deletions, duplications, tokens dropped in, truncation, deep nesting, long `and`
// chains, an unterminated string.
std::string mutate(std::string text, std::mt19937& rng) {
    const std::vector<std::string> tokens = {"{", "}", "(", ")", ",", "=", "m/s", "±", "..", "tree",
                                             "maneuver", "1e999", "\"", "#", "@", "\xff", "not ",
                                             " and x > 1", "vehicle", "expect"};
    std::uniform_int_distribution<int> edits(1, 3), op(0, 7);
    for (int k = edits(rng); k > 0; --k) {
        const size_t i = text.empty() ? 0 : std::uniform_int_distribution<size_t>(0, text.size() - 1)(rng);
        switch (op(rng)) {
            case 0: if (!text.empty()) text[i] = static_cast<char>(rng() % 256); break;
            case 1: text.erase(i, rng() % 20); break;
            case 2: text.insert(i, text.substr(rng() % (text.size() + 1), rng() % 40)); break;
            case 3:
            case 4: text.insert(i, tokens[rng() % tokens.size()]); break;
            case 5: text.resize(i); break;
            case 6: {
                std::string deep;
                const size_t n = rng() % 2 == 0 ? 140 : 20;  // past the nesting limit, or not
                for (size_t d = 0; d < n; ++d) deep += "sequence { ";
                text.insert(i, deep);
                break;
            }
            default: {
                std::string chain;
                const size_t n = rng() % 2 == 0 ? 300 : 10;  // past the `and` limit, or not
                for (size_t d = 0; d < n; ++d) chain += " and x > 1";
                text.insert(i, chain);
                break;
            }
        }
    }
    return text;
}

struct Outcome {
    bool ok = false;
    std::string diagnostics;
    std::string text;
};

Outcome run_format(const std::string& text) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    const auto id = sm.add_file("m.sdv", text);
    auto formatted = compiler::syntax::format(id, sm, diags);
    return {formatted.has_value(), formatted ? "" : diag::render_all_text(diags, sm),
            formatted.value_or("")};
}

Outcome run_parse(const std::string& text) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    const auto id = sm.add_file("m.sdv", text);
    const bool ok = compiler::syntax::parse(id, sm, diags) != nullptr;
    return {ok, ok ? "" : diag::render_all_text(diags, sm), ""};
}

}  // namespace

TEST_CASE("format parses exactly what parse accepts and reports what parse reports") {
    const auto files = sources();
    REQUIRE(files.size() >= 10);
    std::mt19937 rng(20261125);
    int refused = 0, formatted = 0;
    for (size_t f = 0; f < files.size(); ++f) {
        for (int k = 0; k < 40; ++k) {
            const std::string text = k == 0 ? files[f] : mutate(files[f], rng);
            CAPTURE(f);
            CAPTURE(k);
            const Outcome fmt = run_format(text);
            const Outcome parsed = run_parse(text);
            REQUIRE(fmt.ok == parsed.ok);
            if (!fmt.ok) {
                ++refused;
                CHECK(!fmt.diagnostics.empty());
                CHECK(fmt.diagnostics == parsed.diagnostics);
                continue;
            }
            ++formatted;
            const Outcome again = run_format(fmt.text);
            REQUIRE(again.ok);
            CHECK(again.text == fmt.text);
        }
    }
    // Both sides of the property are exercised (339 and 101 of 440 with the files of 2026-11-25).
    CHECK(refused > 150);
    CHECK(formatted > 50);
}

}  // namespace format_test
