// What the readers of map and recording files share: whole files read at once, strict numbers
// from element text, and the line of an XML element for error messages.
#pragma once

#include <optional>
#include <pugixml.hpp>
#include <string>
#include <vector>

namespace sdv::road {

// The file's bytes; false when it cannot be read.
bool read_file(const std::string& path, std::string& out);

// A finite number that is all of `text` but surrounding whitespace ("1e3", " -2.5\n"); nullopt
// for anything else (empty, "nan", "inf", "3 m").
std::optional<double> parse_number(const char* text);

// Line numbers of the elements of a document parsed from `text` (pugixml's byte offsets).
class XmlLines {
public:
    explicit XmlLines(const std::string& text);
    int line(const pugi::xml_node& n) const;  // 0 when unknown

private:
    std::vector<size_t> ends_;
};

}  // namespace sdv::road
