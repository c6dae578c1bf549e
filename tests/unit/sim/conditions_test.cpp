// The runtime answers every condition of the catalog with its own function.
#include <doctest/doctest.h>

#include "runtime/catalog/catalog.h"
#include "runtime/sim/leaves.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace conditions_test {

using namespace sdv;

TEST_CASE("the condition table has one function per catalog condition, in catalog order") {
    const auto table = sim::condition_table();
    const auto conditions = catalog::conditions();
    REQUIRE(table.size() == conditions.size());
    for (size_t i = 0; i < table.size(); ++i) {
        CAPTURE(conditions[i].name);
        CHECK(table[i].kind == conditions[i].kind);
        CHECK(static_cast<bool>(table[i].fn));
    }
}

}  // namespace conditions_test
