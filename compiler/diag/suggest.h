// "Did you mean": the closest candidate by edit distance, if it is close enough.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace sdv::diag {

// Optimal-string-alignment distance (Levenshtein plus adjacent transpositions).
size_t edit_distance(std::string_view a, std::string_view b);

// The candidate closest to `word`, when its distance is at most max(1, |word| / 3) (2 for
// words of 6 or more characters); ties go to the earlier candidate.
std::optional<std::string> closest_match(std::string_view word,
                                         std::span<const std::string> candidates);

// "a, b or c" for the alternatives of an "expected ..." note; "" when there are none or too many
// (more than 8) to be helpful.
std::string alternatives(std::span<const std::string> names);

}  // namespace sdv::diag
