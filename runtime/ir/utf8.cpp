#include "runtime/ir/utf8.h"

#include <cstdint>

namespace sdv::ir {

size_t utf8_sequence_length(std::string_view s, size_t i) {
    const auto c = static_cast<unsigned char>(s[i]);
    size_t n = 0;
    uint32_t cp = 0;
    if (c < 0x80) {
        return 1;
    } else if ((c & 0xE0) == 0xC0) {
        n = 1;
        cp = c & 0x1Fu;
    } else if ((c & 0xF0) == 0xE0) {
        n = 2;
        cp = c & 0x0Fu;
    } else if ((c & 0xF8) == 0xF0) {
        n = 3;
        cp = c & 0x07u;
    } else {
        return 0;
    }
    for (size_t k = 1; k <= n; ++k) {
        if (i + k >= s.size()) return 0;
        const auto cc = static_cast<unsigned char>(s[i + k]);
        if ((cc & 0xC0) != 0x80) return 0;
        cp = (cp << 6) | (cc & 0x3Fu);
    }
    // Overlong forms, surrogates and values beyond Unicode are invalid too.
    if ((n == 1 && cp < 0x80) || (n == 2 && cp < 0x800) || (n == 3 && cp < 0x10000) ||
        (cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF) {
        return 0;
    }
    return n + 1;
}

size_t find_invalid_utf8(std::string_view s) {
    for (size_t i = 0; i < s.size();) {
        const size_t n = utf8_sequence_length(s, i);
        if (n == 0) return i;
        i += n;
    }
    return std::string_view::npos;
}

}  // namespace sdv::ir
