// The .btree parser's work is bounded by the input's size: every prediction the grammar makes
// looks at most two tokens ahead, whatever the file, well formed or not. Before the fix of fuzz
// finding 34 a name followed by '(' could open a call or be a name followed by a tuple, and ANTLR
// looked ahead to the matching ')' to decide: calls nested a hundred deep took it seconds (904
// bytes, 2.8 s). Counted with the parser's profiler (BtreeParseStats), never with a clock: over
// generated nestings of calls, tuples and both, with names and spaces between arguments, each
// cut short at many points; every .btree of the project and ../shared/data; and the fuzz
// campaign's reproducers.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/source_manager.h"
#include "compiler/gss/btree.h"
#include "compiler/syntax/parser.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace btree_parse_cost_test {

namespace {

namespace fs = std::filesystem;
using namespace sdv;
using compiler::gss::BtreeParseStats;

// Tokens one prediction may examine: the grammar is LL(2) (`NAME '='` against a NAME value,
// `NAME CALL_OPEN` against a name), and a prediction counts the token it stops at.
constexpr long long kMaxLookahead = 2;

struct Parsed {
    bool ok = false;
    BtreeParseStats stats;
};

Parsed parse(const std::string& text) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    const auto file = sm.add_file("t.btree", text);
    Parsed p;
    p.ok = compiler::gss::parse_btree(file, sm, diags, &p.stats).has_value();
    return p;
}

std::string tree(const std::string& value) { return "behaviortree t:\n    maneuver m(MConfig(" + value + "))\n"; }

// A value nested `depth` deep, each level one of: a call `MP(...)`, a named argument in a call
// `MP(vel=...)`, a call whose arguments are separated by spaces `MP(1 ... 2)`, a tuple
// `(..., 1)`, and a call written with a space before its '(' (`MP (...)`, a call as in Python).
std::string nested(int depth, int shape) {
    static const char* const kOpen[] = {"MP(", "MP(vel=", "MP(1 ", "(", "MP ("};
    static const char* const kClose[] = {")", ")", " 2)", ", 1)", ")"};
    std::string open, close;
    for (int level = 0; level < depth; ++level) {
        const int s = shape < 5 ? shape : (level * 7 + shape) % 5;  // 5..: the shapes mixed
        open += kOpen[s];
        close = kClose[s] + close;
    }
    return open + "14" + close;
}

void check(const std::string& what, const std::string& text, bool must_parse) {
    const Parsed p = parse(text);
    INFO(what << " (" << text.size() << " bytes)");
    if (must_parse) CHECK(p.ok);
    CHECK(p.stats.max_lookahead <= kMaxLookahead);
    if (p.ok) CHECK(p.stats.full_context == 0);
}

std::vector<fs::path> btree_files(const fs::path& root) {
    std::vector<fs::path> out;
    if (!fs::is_directory(root)) return out;
    for (const auto& e : fs::recursive_directory_iterator(root)) {
        if (e.is_regular_file() && e.path().extension() == ".btree") out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace

TEST_CASE("nested calls and tuples parse with bounded lookahead at every depth") {
    // Up to the bracket limit (the maneuver's and MConfig's brackets count): one more '(' is
    // refused before the parser runs.
    const int limit = compiler::syntax::kMaxNesting - 2;
    for (int shape = 0; shape < 8; ++shape) {
        for (int depth : {1, 2, 3, 8, 32, limit}) {
            check("shape " + std::to_string(shape) + " depth " + std::to_string(depth), tree(nested(depth, shape)),
                  true);
        }
    }
}

TEST_CASE("cut short anywhere, nested values still cost bounded lookahead") {
    // Each prefix of a deep value, and each with its last ')' dropped or doubled: the error paths
    // (recovery included) predict like the rest.
    for (int shape = 0; shape < 8; ++shape) {
        const std::string full = tree(nested(100, shape));
        for (size_t cut = 20; cut < full.size(); cut += 37) {
            check("shape " + std::to_string(shape) + " cut at " + std::to_string(cut), full.substr(0, cut) + "\n",
                  false);
        }
        const size_t last = full.rfind(')');
        check("shape " + std::to_string(shape) + " one ')' short", full.substr(0, last) + full.substr(last + 1), false);
        check("shape " + std::to_string(shape) + " one ')' over", full.substr(0, last) + ")" + full.substr(last), false);
    }
}

TEST_CASE("long argument lists and many leaves parse with bounded lookahead") {
    std::string args;
    for (int i = 0; i < 2000; ++i) args += (i % 3 == 0 ? "p" + std::to_string(i) + "=" : std::string()) + "MP(1,2,3) ";
    check("2000 arguments", tree(args), true);
    std::string leaves = "behaviortree t:\n    ->\n";
    for (int i = 0; i < 500; ++i) leaves += "        condition c" + std::to_string(i) + "(sim_time(tmin=" + std::to_string(i) + "))\n";
    leaves += "        maneuver m(MStopConfig(type=GOAL_POINT))\n";
    check("500 leaves", leaves, true);
}

TEST_CASE("every .btree of the project, ../shared/data and the fuzz reproducers") {
    std::vector<fs::path> files = btree_files(fs::path(SDV_SOURCE_DIR) / "examples");
    for (const char* dir : {"docs", "stdlib", "tests/golden", "tests/fuzz/regressions/btree"}) {
        auto more = btree_files(fs::path(SDV_SOURCE_DIR) / dir);
        files.insert(files.end(), more.begin(), more.end());
    }
    auto shared = btree_files(fs::path(SDV_SHARED_DIR) / "data");
    REQUIRE(!shared.empty());
    files.insert(files.end(), shared.begin(), shared.end());
    size_t parsed = 0;
    for (const auto& f : files) {
        const Parsed p = parse(read(f));
        INFO(f.string());
        CHECK(p.stats.max_lookahead <= kMaxLookahead);
        if (p.ok) {
            CHECK(p.stats.full_context == 0);
            ++parsed;
        }
    }
    // The reference's own trees all parse.
    CHECK(parsed >= shared.size());
}

}  // namespace btree_parse_cost_test
