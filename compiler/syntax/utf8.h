// UTF-8 helpers shared by the front ends that hand text to ANTLR (which counts positions in
// code points while diagnostics count bytes).
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace sdv::compiler::syntax {

// The length in bytes of the UTF-8 sequence at byte `i` of `s` (i < s.size()), 1 to 4; 0 when it
// is not valid UTF-8 (a stray or truncated byte, an overlong form, a surrogate, beyond U+10FFFF).
size_t utf8_sequence_length(std::string_view s, size_t i);

// Returns the byte offset of the first invalid UTF-8 sequence, or npos.
size_t find_invalid_utf8(std::string_view s);

// Byte offset of every code point, plus one entry for the end of the text.
std::vector<uint32_t> code_point_offsets(std::string_view s);

}  // namespace sdv::compiler::syntax
