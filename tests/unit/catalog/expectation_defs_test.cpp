// The expectation functions: the IR stores a function as its index in expectations(), so the
// table follows ExpectKind; every quantity says what its missing value means.
#include <doctest/doctest.h>

#include <set>
#include <string>

#include "runtime/catalog/catalog.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace expectation_defs_test {

using namespace sdv::catalog;

TEST_CASE("expectation kinds index the table in order") {
    const auto defs = expectations();
    for (size_t i = 0; i < defs.size(); ++i) CHECK(static_cast<size_t>(defs[i].kind) == i);
    CHECK(static_cast<size_t>(ExpectKind::timeout) == defs.size() - 1);
}

TEST_CASE("every expectation names its metric, and min_gap is the same-lane bumper gap") {
    std::set<std::string> names;
    for (const auto& d : expectations()) {
        CHECK(names.insert(d.name).second);
        CHECK_FALSE(d.label.empty());
        CHECK_FALSE(d.doc.empty());
        if (!d.boolean && d.result != Dim::ratio) CHECK_FALSE(d.none.empty());
    }
    CHECK(find_expectation("min_gap")->label == "same-lane bumper gap");
    CHECK(find_expectation("min_clearance")->label == "outline clearance");
    CHECK(find_expectation("min_ttc")->none == "never closing");
    CHECK_FALSE(find_expectation("fallback_share")->windowed);
    CHECK(find_expectation("min_acc")->windowed);
}

}  // namespace expectation_defs_test
