#include "compiler/syntax/utf8.h"

namespace sdv::compiler::syntax {

std::vector<uint32_t> code_point_offsets(std::string_view s) {
    std::vector<uint32_t> offs;
    offs.reserve(s.size() + 1);
    for (size_t i = 0; i < s.size(); ++i) {
        if ((static_cast<unsigned char>(s[i]) & 0xC0) != 0x80) offs.push_back(static_cast<uint32_t>(i));
    }
    offs.push_back(static_cast<uint32_t>(s.size()));
    return offs;
}

}  // namespace sdv::compiler::syntax
