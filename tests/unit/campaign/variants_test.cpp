// The variants of a campaign: grid order, the Latin hypercube's one-per-stratum property,
// random draws inside their domains, and that a variant depends only on (vary block, index).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "runtime/campaign/variants.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace variants_test {

using namespace sdv;

namespace {

ir::VaryParam range(double lo, double hi, int count = 0) {
    ir::VaryParam p;
    p.kind = ir::VaryParam::Kind::range;
    p.lo = lo;
    p.hi = hi;
    p.count = count;
    return p;
}

ir::VaryParam set(std::vector<double> v) {
    ir::VaryParam p;
    p.kind = ir::VaryParam::Kind::set;
    p.values = std::move(v);
    return p;
}

}  // namespace

TEST_CASE("a grid enumerates every combination, the last parameter fastest") {
    ir::Vary v;
    v.params = {range(2, 6, 3), set({-1, -3})};
    campaign::VariantSpace space(v);
    REQUIRE(space.size() == 6);
    std::set<std::vector<double>> seen;
    for (int64_t i = 0; i < space.size(); ++i) seen.insert(space.values(i));
    CHECK(seen.size() == 6);
    CHECK(space.values(0) == std::vector<double>{2, -1});
    CHECK(space.values(1) == std::vector<double>{2, -3});
    CHECK(space.values(2) == std::vector<double>{4, -1});
    CHECK(space.values(5) == std::vector<double>{6, -3});
}

TEST_CASE("a Latin hypercube puts exactly one variant in each stratum of every parameter") {
    for (uint64_t seed : {0ULL, 1ULL, 77ULL}) {
        for (int64_t n : {1, 7, 100, 1000}) {
            ir::Vary v;
            v.sample = ir::Vary::Sample::latin;
            v.count = n;
            v.seed = seed;
            ir::VaryParam normal;
            normal.kind = ir::VaryParam::Kind::normal;
            normal.mean = 10;
            normal.sd = 2;
            normal.lo = 4;
            normal.hi = 16;
            v.params = {range(0, 1), range(-5, 5), normal};
            campaign::VariantSpace space(v);
            REQUIRE(space.size() == n);
            std::vector<std::vector<int>> strata(3, std::vector<int>(static_cast<size_t>(n), 0));
            for (int64_t i = 0; i < n; ++i) {
                const auto x = space.values(i);
                const int a = std::min<int>(static_cast<int>(n - 1), static_cast<int>(x[0] * static_cast<double>(n)));
                const int b = std::min<int>(static_cast<int>(n - 1), static_cast<int>((x[1] + 5) / 10 * static_cast<double>(n)));
                strata[0][static_cast<size_t>(a)]++;
                strata[1][static_cast<size_t>(b)]++;
                CHECK(x[2] >= 4 - 1e-9);
                CHECK(x[2] <= 16 + 1e-9);
            }
            for (size_t k = 0; k < 2; ++k) {
                CHECK(std::all_of(strata[k].begin(), strata[k].end(), [](int c) { return c == 1; }));
            }
        }
    }
}

TEST_CASE("random draws stay in their domain, hit every level of a set, and depend only on (seed, index)") {
    ir::Vary v;
    v.sample = ir::Vary::Sample::random;
    v.count = 2000;
    v.seed = 5;
    ir::VaryParam seeds = range(1, 10);
    seeds.integer = true;
    v.params = {range(3, 4), set({1, 2, 3}), seeds, range(0, 10, 3)};
    campaign::VariantSpace a(v), b(v);
    std::set<double> levels, ints, grid;
    double lo = 1e9, hi = -1e9;
    for (int64_t i = 0; i < v.count; ++i) {
        const auto x = a.values(i);
        CHECK(x == b.values(i));
        lo = std::min(lo, x[0]);
        hi = std::max(hi, x[0]);
        levels.insert(x[1]);
        ints.insert(x[2]);
        CHECK(x[2] == std::round(x[2]));
        grid.insert(x[3]);
    }
    CHECK(lo >= 3);
    CHECK(hi <= 4);
    CHECK(hi - lo > 0.99);
    CHECK(levels == std::set<double>{1, 2, 3});
    CHECK(ints.size() == 10);
    CHECK(*ints.begin() == 1);
    CHECK(*ints.rbegin() == 10);
    CHECK(grid == std::set<double>{0, 5, 10});
    ir::Vary w = v;
    w.seed = 6;
    campaign::VariantSpace c(w);
    CHECK(c.values(0) != a.values(0));
}

TEST_CASE("the normal quantile inverts the normal distribution") {
    for (double p : {1e-10, 0.001, 0.02, 0.3, 0.5, 0.8, 0.99, 1 - 1e-9}) {
        const double x = campaign::normal_quantile(p);
        CHECK(0.5 * std::erfc(-x / std::sqrt(2.0)) == doctest::Approx(p).epsilon(1e-9));
    }
}

}  // namespace variants_test
