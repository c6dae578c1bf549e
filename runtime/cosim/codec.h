// The two encodings of an Envelope (docs/cosim.md "Encodings"): binary protobuf, the reference,
// and the proto3-JSON mapping of the same schema for stdlib-only clients and debugging. A session
// uses one encoding for every frame in both directions. Encoding is deterministic (the same
// message always gives the same bytes), which record/replay relies on.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "runtime/cosim/sdv_cosim.pb.h"

namespace sdv::cosim {

enum class Encoding { binary, json };

// "binary" or "json".
std::optional<Encoding> parse_encoding(std::string_view name);
const char* encoding_name(Encoding e);

// The payload of a frame. JSON prints the schema's field names (preserve_proto_field_names)
// and every field, defaults included (always_print_primitive_fields).
std::string encode(const v1::Envelope& message, Encoding encoding);

// Parses a payload; false with `error` for bytes that are no Envelope. JSON ignores unknown
// fields, as binary protobuf does (minor versions only add).
bool decode(std::string_view payload, Encoding encoding, v1::Envelope& message, std::string& error);

}  // namespace sdv::cosim
