// UTF-8, the encoding of every text sdv reads and writes: sources, the IR, outputs and the
// co-simulation protocol's messages. The one check of it, shared by the compiler's readers and
// the runtime (which may not include compiler/).
#pragma once

#include <cstddef>
#include <string_view>

namespace sdv::ir {

// The length in bytes of the UTF-8 sequence at byte `i` of `s` (i < s.size()), 1 to 4; 0 when it
// is not valid UTF-8 (a stray or truncated byte, an overlong form, a surrogate, beyond U+10FFFF;
// RFC 3629).
size_t utf8_sequence_length(std::string_view s, size_t i);

// Returns the byte offset of the first invalid UTF-8 sequence, or npos.
size_t find_invalid_utf8(std::string_view s);

}  // namespace sdv::ir
