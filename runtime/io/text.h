// Text that the reports write from what they read (names and cells of a run directory, a
// sweep's columns): escaped for the format they go into, whatever bytes they hold; and the
// numbers they read from cells.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace sdv::io {

// `j` as compact JSON; bytes that are not UTF-8 in its strings become U+FFFD (nlohmann's dump
// throws on them otherwise).
std::string json_text(const nlohmann::json& j);

// `s` as XML character data or a double-quoted attribute value: & < > " escaped, tabs and line
// breaks as character references, the other control characters (not allowed in XML 1.0) left
// out, bytes that are not UTF-8 as U+FFFD.
std::string xml_text(std::string_view s);

// A whole cell as a finite number: what std::to_chars and printf("%g") write; no spaces, no
// '+', no hex, no "nan" or "inf". False (v unchanged) for anything else.
bool finite_number(std::string_view cell, double& v);

}  // namespace sdv::io
