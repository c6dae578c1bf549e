#include "runtime/io/text.h"

#include <charconv>
#include <cmath>

#include "runtime/ir/utf8.h"

namespace sdv::io {

std::string json_text(const nlohmann::json& j) {
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string xml_text(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (size_t i = 0; i < s.size();) {
        const size_t n = ir::utf8_sequence_length(s, i);
        if (n == 0) {
            out += "\xEF\xBF\xBD";  // U+FFFD
            ++i;
            continue;
        }
        if (n > 1) {
            out.append(s, i, n);
            i += n;
            continue;
        }
        const char c = s[i++];
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\n': out += "&#10;"; break;
            case '\t': out += "&#9;"; break;
            default:
                if (static_cast<unsigned char>(c) >= 0x20) out += c;  // else not allowed in XML 1.0
        }
    }
    return out;
}

bool finite_number(std::string_view cell, double& v) {
    double x = 0;
    const char* b = cell.data();
    const char* e = b + cell.size();
    const auto [p, ec] = std::from_chars(b, e, x, std::chars_format::general);
    if (cell.empty() || ec != std::errc() || p != e || !std::isfinite(x)) return false;
    v = x;
    return true;
}

}  // namespace sdv::io
