// Writing and reading the IR as canonical JSON. Writing is deterministic (same Program, same
// bytes); reading validates everything (format, version, content hash, every field's type,
// catalog names, index ranges, tree shape) and never crashes on bad input.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "runtime/ir/ir.h"

namespace sdv::ir {

// The IR file text: {"format":"sdvir","version":1,"compiler":...,"hash":...,"program":{...}}.
std::string write_ir(const Program& program);

// 64-bit FNV-1a of the canonical program text, as 16 hex digits: names the exact behavior a
// run executed.
std::string program_hash(const Program& program);

struct ReadResult {
    std::optional<Program> program;
    std::string error;  // one line, when program is empty
};

ReadResult read_ir(std::string_view text);

// The deepest nesting of arrays and objects in JSON text (brackets inside strings skipped), in
// one pass. Readers of JSON refuse text deeper than they need before parsing it: nlohmann's
// parser is iterative, but writing a value back (dump) recurses once per level.
int json_depth(std::string_view text);

}  // namespace sdv::ir
