// Binary payloads are serialized with deterministic serialization switched on, so equal messages
// give equal bytes whatever protobuf's internal choices; JSON is printed by protobuf's own
// proto3-JSON printer (field order = field numbers, doubles in their shortest exact form).
#include "runtime/cosim/codec.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <google/protobuf/util/json_util.h>

#include <climits>

namespace sdv::cosim {

std::optional<Encoding> parse_encoding(std::string_view name) {
    if (name == "binary") return Encoding::binary;
    if (name == "json") return Encoding::json;
    return std::nullopt;
}

const char* encoding_name(Encoding e) { return e == Encoding::json ? "json" : "binary"; }

std::string encode(const v1::Envelope& message, Encoding encoding) {
    std::string out;
    if (encoding == Encoding::json) {
        google::protobuf::util::JsonPrintOptions opts;
        opts.preserve_proto_field_names = true;
        opts.always_print_primitive_fields = true;
        // Only fails on invalid UTF-8 in a string field, which decode() never lets in and sdv's
        // own strings (names from the scenario) do not contain.
        (void)google::protobuf::util::MessageToJsonString(message, &out, opts);
        return out;
    }
    {
        google::protobuf::io::StringOutputStream stream(&out);
        google::protobuf::io::CodedOutputStream coded(&stream);
        coded.SetSerializationDeterministic(true);
        message.SerializeToCodedStream(&coded);
    }  // the coded stream flushes into `out` here
    return out;
}

bool decode(std::string_view payload, Encoding encoding, v1::Envelope& message,
            std::string& error) {
    message.Clear();
    if (encoding == Encoding::json) {
        google::protobuf::util::JsonParseOptions opts;
        opts.ignore_unknown_fields = true;
        const auto status = google::protobuf::util::JsonStringToMessage(
            google::protobuf::StringPiece(payload.data(), payload.size()), &message, opts);
        if (!status.ok()) {
            error = "not a JSON Envelope: " + std::string(status.message());
            message.Clear();
            return false;
        }
        return true;
    }
    if (payload.size() > static_cast<size_t>(INT_MAX) ||
        !message.ParseFromArray(payload.data(), static_cast<int>(payload.size()))) {
        error = "not a binary Envelope (" + std::to_string(payload.size()) +
                " bytes that do not parse)";
        message.Clear();
        return false;
    }
    return true;
}

}  // namespace sdv::cosim
