// Every diagnostic a user sees has a code, a message and a place within its file (docs/
// diagnostics.md), whatever the input: checked on every cut of every example .sdv, .btree and
// GeoScenario scenario (the project's and those of ../shared/data), which stops the text anywhere
// (inside a string, a tag, an attribute, a block), and on files of more syntax errors than the
// parser reports. The notes about the limits (E0007, W0001) are the only diagnostics without one.
// The fuzz targets check the same on every input they try (tests/fuzz/targets/scratch.h).
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/diag/render.h"
#include "compiler/gss/btree.h"
#include "compiler/gss/scenario.h"
#include "compiler/sema/compile.h"
#include "compiler/syntax/parser.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace diagnostic_places_test {

using namespace sdv;
namespace fs = std::filesystem;

namespace {

// Cuts of each file: the text stopped at this many places spread over it.
constexpr size_t kCuts = 24;

std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// The files under the project's and the shared data's directories whose names end in `ext`,
// sorted (a stable order of failures).
std::vector<fs::path> files(const std::string& ext) {
    std::vector<fs::path> out;
    for (const fs::path& root : {fs::path(SDV_SOURCE_DIR) / "examples", fs::path(SDV_SOURCE_DIR) / "stdlib-trees",
                                fs::path(SDV_SHARED_DIR) / "data"}) {
        if (!fs::is_directory(root)) continue;
        for (const auto& e : fs::recursive_directory_iterator(root)) {
            const std::string name = e.path().filename().string();
            if (e.is_regular_file() && name.size() > ext.size() && name.ends_with(ext)) out.push_back(e.path());
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

// The cuts of `text`: kCuts prefixes at evenly spread lengths, the whole text last.
std::vector<std::string> cuts(const std::string& text) {
    std::vector<std::string> out;
    for (size_t k = 1; k < kCuts; ++k) out.push_back(text.substr(0, text.size() * k / kCuts));
    out.push_back(text);
    return out;
}

// What is wrong with the diagnostics, or "" when each has its code, message and place.
std::string misplaced(const diag::SourceManager& sm, const diag::DiagnosticEngine& diags) {
    for (const auto& d : diags.sorted()) {
        const bool code = d.code.size() == 5 && (d.code[0] == 'E' || d.code[0] == 'W') &&
                          std::all_of(d.code.begin() + 1, d.code.end(), [](char c) { return c >= '0' && c <= '9'; });
        if (!code || d.message.empty()) return "a diagnostic without a code or a message: '" + d.code + "' " + d.message;
        if (d.code == "E0007" || d.code == "W0001") continue;
        const auto& r = d.range;
        if (r.begin.file == 0 || r.begin.file > sm.file_count() || r.end.file != r.begin.file ||
            r.begin.offset > r.end.offset || r.end.offset > sm.contents(r.begin.file).size())
            return d.code + " (" + d.message + ") has no place within its file";
    }
    return "";
}

}  // namespace

TEST_CASE("every diagnostic of a cut .sdv file has a code, a message and a place in the file") {
    const auto sdv = files(".sdv");
    REQUIRE(sdv.size() >= 10);
    size_t with_errors = 0;
    for (const auto& p : sdv) {
        for (const auto& text : cuts(read(p))) {
            diag::SourceManager sm;
            diag::DiagnosticEngine diags;
            (void)compiler::compile_source(p.string(), text, sm, diags);
            with_errors += diags.has_errors();
            INFO(p.string() << " cut at " << text.size() << " bytes");
            CHECK(misplaced(sm, diags) == "");
        }
    }
    CHECK(with_errors > sdv.size());  // the cuts do break files: the property is not vacuous
}

TEST_CASE("every diagnostic of a cut .btree file has a code, a message and a place in the file") {
    const auto trees = files(".btree");
    REQUIRE(trees.size() >= 10);
    size_t with_errors = 0;
    for (const auto& p : trees) {
        for (const auto& text : cuts(read(p))) {
            diag::SourceManager sm;
            diag::DiagnosticEngine diags;
            (void)compiler::gss::parse_btree(sm.add_file(p.string(), text), sm, diags);
            with_errors += diags.has_errors();
            INFO(p.string() << " cut at " << text.size() << " bytes");
            CHECK(misplaced(sm, diags) == "");
        }
    }
    CHECK(with_errors > trees.size());
}

TEST_CASE("every diagnostic of a cut GeoScenario scenario has a code, a message and a place in the file") {
    const auto scenarios = files(".osm");
    REQUIRE(scenarios.size() >= 5);
    size_t with_errors = 0;
    for (const auto& p : scenarios) {
        for (const auto& text : cuts(read(p))) {
            diag::SourceManager sm;
            diag::DiagnosticEngine diags;
            (void)compiler::gss::read_geoscenario(sm.add_file(p.string(), text), sm, diags);
            with_errors += diags.has_errors();
            INFO(p.string() << " cut at " << text.size() << " bytes");
            CHECK(misplaced(sm, diags) == "");
        }
    }
    CHECK(with_errors > scenarios.size());
}

TEST_CASE("the parser stops after 20 syntax errors at the place of the last") {
    std::string text;
    for (int i = 0; i < 30; ++i) text += "road r" + std::to_string(i) + " { lanes }\n";
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    (void)compiler::compile_source("many.sdv", text, sm, diags);
    const auto all = diags.sorted();
    REQUIRE(all.size() == static_cast<size_t>(compiler::syntax::kMaxSyntaxErrors) + 1);
    CHECK(misplaced(sm, diags) == "");
    // Sorted by place, the note comes right after the error it stops at, on its line.
    const auto stop = std::find_if(all.begin(), all.end(), [](const auto& d) { return d.message.find("too many") != std::string::npos; });
    REQUIRE(stop != all.end());
    CHECK(stop->code == "E0003");
    CHECK(stop->message == "too many syntax errors (20); stopping here");
    CHECK(sm.line_col(stop->range.begin).line == static_cast<uint32_t>(compiler::syntax::kMaxSyntaxErrors));
}

}  // namespace diagnostic_places_test
