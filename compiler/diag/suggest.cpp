#include "compiler/diag/suggest.h"

#include <algorithm>
#include <vector>

namespace sdv::diag {

size_t edit_distance(std::string_view a, std::string_view b) {
    // Optimal string alignment distance with three rolling rows (one allocation).
    const size_t m = b.size();
    std::vector<size_t> rows(3 * (m + 1));
    size_t* prev2 = rows.data();
    size_t* prev = prev2 + (m + 1);
    size_t* cur = prev + (m + 1);
    for (size_t j = 0; j <= m; ++j) prev[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (size_t j = 1; j <= m; ++j) {
            const size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
                cur[j] = std::min(cur[j], prev2[j - 2] + 1);
            }
        }
        std::swap(prev2, prev);
        std::swap(prev, cur);
    }
    return prev[m];
}

std::optional<std::string> closest_match(std::string_view word,
                                         std::span<const std::string> candidates) {
    if (word.size() > 64) return std::nullopt;
    const size_t limit = std::max<size_t>(word.size() >= 6 ? 2 : 1, word.size() / 3);
    std::optional<std::string> best;
    size_t best_d = limit + 1;
    for (const auto& c : candidates) {
        if (c == word || c.size() > 64) continue;
        // The distance is at least the difference in length: most candidates cost nothing.
        const size_t gap = c.size() > word.size() ? c.size() - word.size() : word.size() - c.size();
        if (gap >= best_d) continue;
        const size_t dist = edit_distance(word, c);
        if (dist < best_d) {
            best_d = dist;
            best = c;
        }
    }
    return best;
}

std::string alternatives(std::span<const std::string> names) {
    if (names.empty() || names.size() > 8) return "";
    std::string out;
    for (size_t i = 0; i < names.size(); ++i) {
        if (i) out += (i + 1 == names.size()) ? " or " : ", ";
        out += names[i];
    }
    return out;
}

}  // namespace sdv::diag
