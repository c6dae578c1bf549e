// The diagnostic engine's policy and limits (compiler/diag/diagnostic_engine.h), held to a
// reference model written the straightforward way: apply the policy to every diagnostic
// reported, then keep the first 100 errors (E0007 once after them) and the first 100 warnings
// (the rest counted in one W0001 note). Random streams of errors and named warnings under random
// policies (-w, -Wno-NAME, -Werror=NAME, -Werror) and limits.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/render.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace diagnostic_engine_test {

using namespace sdv::diag;

namespace {

struct Reported {
    bool is_warning = false;
    std::string name;  // warnings: one of a few names
    uint32_t offset = 0;
};

struct Expected {
    std::vector<Diagnostic> shown;  // in report order, severity after the policy
    size_t errors = 0;              // error_count(): shown errors, E0007 included
    size_t warnings = 0;            // warning_count(): every warning the policy keeps as one
    size_t unshown = 0;
};

Expected model(const std::vector<Reported>& in, const DiagnosticEngine::WarningPolicy& p,
               size_t error_limit, size_t warning_limit) {
    Expected e;
    size_t errors = 0, warnings = 0;
    bool noted = false;
    for (const auto& r : in) {
        bool as_error = !r.is_warning;
        if (r.is_warning) {
            const bool promoted = p.promoted.count(r.name) > 0;
            if (!promoted && (p.disable_all || p.disabled.count(r.name))) continue;
            as_error = promoted || p.all_errors;
        }
        Diagnostic d;
        d.code = r.is_warning ? "W0101" : "E0101";
        d.warning_name = r.is_warning ? r.name : "";
        d.range.begin = {1, r.offset};
        d.severity = as_error ? Severity::error : Severity::warning;
        if (as_error) {
            if (errors < error_limit) {
                ++errors;
                e.shown.push_back(d);
            } else if (!noted) {
                noted = true;
                Diagnostic limit;
                limit.code = "E0007";
                e.shown.push_back(limit);
            }
        } else if (warnings < warning_limit) {
            ++warnings;
            e.shown.push_back(d);
        } else {
            ++e.unshown;
        }
    }
    e.errors = errors + (noted ? 1 : 0);
    e.warnings = warnings + e.unshown;
    return e;
}

const std::vector<std::string> kNames = {"unused-tree", "unused-parameter", "gss-ignored-parameter"};

}  // namespace

TEST_CASE("the engine applies the policy and the limits as the reference model does") {
    std::mt19937 rng(20261129);
    for (int round = 0; round < 400; ++round) {
        DiagnosticEngine::WarningPolicy p;
        p.disable_all = rng() % 8 == 0;
        p.all_errors = rng() % 6 == 0;
        for (const auto& n : kNames) {
            if (rng() % 4 == 0) p.disabled.insert(n);
            if (rng() % 5 == 0) p.promoted.insert(n);
        }
        const size_t error_limit = 1 + rng() % 120;
        const size_t warning_limit = 1 + rng() % 120;
        const size_t count = rng() % 400;
        std::vector<Reported> in;
        for (size_t k = 0; k < count; ++k) {
            Reported r;
            r.is_warning = rng() % 3 != 0;
            r.name = kNames[rng() % kNames.size()];
            r.offset = static_cast<uint32_t>(rng() % 1000);
            in.push_back(r);
        }

        DiagnosticEngine diags;
        diags.set_policy(p);
        diags.set_error_limit(error_limit);
        diags.set_warning_limit(warning_limit);
        for (const auto& r : in) {
            const SourceRange range{{1, r.offset}, {1, r.offset}};
            if (r.is_warning) {
                diags.warning("W0101", r.name, range, "w").notes.push_back({{}, "a note"});
            } else {
                diags.error("E0101", range, "e").notes.push_back({{}, "a note"});
            }
        }

        const Expected want = model(in, p, error_limit, warning_limit);
        CAPTURE(round);
        CHECK(diags.error_count() == want.errors);
        CHECK(diags.warning_count() == want.warnings);
        CHECK(diags.has_errors() == (want.errors > 0));

        // The shown ones, sorted by offset (stable: report order at one offset), E0007 then
        // W0001 last.
        std::vector<Diagnostic> sorted_want;
        for (const auto& d : want.shown) {
            if (d.code != "E0007") sorted_want.push_back(d);
        }
        std::stable_sort(sorted_want.begin(), sorted_want.end(), [](const auto& a, const auto& b) {
            return a.range.begin.offset < b.range.begin.offset;
        });
        const auto got = diags.sorted();
        size_t k = 0;
        for (; k < sorted_want.size() && k < got.size(); ++k) {
            CHECK(got[k].code == sorted_want[k].code);
            CHECK(got[k].severity == sorted_want[k].severity);
            CHECK(got[k].warning_name == sorted_want[k].warning_name);
            CHECK(got[k].range.begin.offset == sorted_want[k].range.begin.offset);
            CHECK(got[k].notes.size() == 1);
        }
        const bool noted = want.errors > 0 && want.errors > error_limit;
        REQUIRE(got.size() == sorted_want.size() + (noted ? 1 : 0) + (want.unshown ? 1 : 0));
        if (noted) {
            CHECK(got[k].code == "E0007");
            CHECK(got[k].severity == Severity::error);
            CHECK(got[k].message == "too many errors (" + std::to_string(error_limit) + "); stopping");
            ++k;
        }
        if (want.unshown) {
            CHECK(got[k].code == "W0001");
            CHECK(got[k].severity == Severity::note);
            CHECK(!got[k].range.valid());
            CHECK(got[k].message.rfind(std::to_string(want.unshown) + " more warning", 0) == 0);
        }

        // What sdv prints: the listed diagnostics, and counts that include the unlisted
        // warnings (a tool reading "warnings" learns how many there were).
        SourceManager sm;
        REQUIRE(sm.add_file("t.sdv", std::string(1000, 'x') + "\n") == 1);
        const auto json = nlohmann::json::parse(render_all_json(diags, sm));
        CHECK(json["diagnostics"].size() == got.size());
        CHECK(json["errors"] == want.errors);
        CHECK(json["warnings"] == want.warnings);
        const std::string text = render_all_text(diags, sm);
        std::string summary;
        if (want.errors) summary = std::to_string(want.errors) + (want.errors == 1 ? " error" : " errors");
        if (want.warnings) {
            summary += (summary.empty() ? "" : ", ") + std::to_string(want.warnings) +
                       (want.warnings == 1 ? " warning" : " warnings");
        }
        if (summary.empty()) {
            CHECK(text.find("generated.") == std::string::npos);
        } else {
            const std::string tail = summary + " generated.\n";
            REQUIRE(text.size() >= tail.size());
            CHECK(text.substr(text.size() - tail.size()) == tail);
        }
    }
}

TEST_CASE("a warning past the limit or disabled is a scratch diagnostic, never reported") {
    DiagnosticEngine diags;
    diags.set_warning_limit(2);
    DiagnosticEngine::WarningPolicy p;
    p.disabled.insert("unused-tree");
    diags.set_policy(p);
    diags.warning("W0101", "unused-tree", {}, "disabled").message = "changed";
    for (int k = 0; k < 5; ++k) {
        diags.warning("W0102", "unused-parameter", {{1, 10u + k}, {1, 10u + k}}, "w" + std::to_string(k))
            .notes.push_back({{}, "n"});
    }
    const auto got = diags.sorted();
    REQUIRE(got.size() == 3);
    CHECK(got[0].message == "w0");
    CHECK(got[1].message == "w1");
    CHECK(got[2].message == "3 more warnings not shown (the first 2 are); -Wno-NAME silences a kind");
    CHECK(diags.warning_count() == 5);
    CHECK(!diags.has_errors());
}

}  // namespace diagnostic_engine_test
