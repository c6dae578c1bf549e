#include "runtime/road/reader_text.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace sdv::road {

bool read_file(const std::string& path, std::string& out) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::stringstream ss;
    ss << in.rdbuf();
    out = ss.str();
    return true;
}

std::optional<double> parse_number(const char* text) {
    auto space = [](char c) { return c == ' ' || c == '\n' || c == '\t' || c == '\r'; };
    while (space(*text)) ++text;
    if (*text == '\0') return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    if (end == text) return std::nullopt;
    while (space(*end)) ++end;
    if (*end != '\0' || !std::isfinite(v)) return std::nullopt;
    return v;
}

XmlLines::XmlLines(const std::string& text) {
    for (size_t i = 0; i < text.size(); ++i)
        if (text[i] == '\n') ends_.push_back(i);
}

int XmlLines::line(const pugi::xml_node& n) const {
    const ptrdiff_t off = n.offset_debug();
    if (off < 0) return 0;
    return static_cast<int>(std::upper_bound(ends_.begin(), ends_.end(), static_cast<size_t>(off)) - ends_.begin()) + 1;
}

}  // namespace sdv::road
