// The parser's unit predicate: an identifier right after a number is read as a unit only
// when it is a unit word of the catalog's table. Included by the generated parser, which is
// C++17, so it declares the catalog function instead of including its C++20 header.
#pragma once

#include <string_view>

namespace sdv::catalog {
bool is_unit_atom(std::string_view word);  // runtime/catalog/units.h
}  // namespace sdv::catalog

namespace sdv::compiler::syntax {

inline bool is_unit_word(std::string_view word) { return catalog::is_unit_atom(word); }

}  // namespace sdv::compiler::syntax
