// UTF-8 helpers shared by the front ends that hand text to ANTLR (which counts positions in
// code points while diagnostics count bytes).
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "runtime/ir/utf8.h"

namespace sdv::compiler::syntax {

// The validity check itself is the runtime's (runtime/ir/utf8.h), shared with the co-simulation
// protocol.
using sdv::ir::find_invalid_utf8;
using sdv::ir::utf8_sequence_length;

// Byte offset of every code point, plus one entry for the end of the text.
std::vector<uint32_t> code_point_offsets(std::string_view s);

}  // namespace sdv::compiler::syntax
