// The sweep report: reads a sweep directory (summary.json, results.csv, runs/<i>/view.html),
// checks results.csv against the columns summary.json announces, and inlines both into the
// embedded page as columnar JSON. Every reading problem becomes one error line naming the file
// and, for results.csv and JSON syntax, the line and column.
#include "runtime/io/sweep_report.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>
#include <vector>

#include "runtime/io/text.h"
#include "runtime/ir/ir_io.h"

namespace sdv::io {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr const char* kSweepFormat = "sdv-sweep/1";
constexpr const char* kReportFormat = "sdv-sweep-report/1";

bool read(const fs::path& p, std::string& out) {
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) return false;
    std::ifstream in(p, std::ios::binary);
    if (!in) return false;
    std::stringstream ss;
    ss << in.rdbuf();
    out = ss.str();
    return true;
}

// ---- results.csv: RFC 4180 records with the line and column of every field ----------------

struct Field {
    std::string text;
    size_t col = 1;  // 1-based column of the field's first character on its line
};

struct Record {
    size_t line = 1;  // 1-based line where the record starts
    std::vector<Field> fields;
};

// Splits `text` into records. Quoted fields may hold commas, doubled quotes and line breaks;
// "\r\n" line ends are accepted; blank lines are skipped. On a syntax error returns false with
// `error` = "line:col: message".
bool parse_csv(std::string_view text, std::vector<Record>& out, std::string& error) {
    const size_t n = text.size();
    size_t i = 0, line = 1, line_start = 0;
    auto where = [&](size_t at_line, size_t at_col) {
        return std::to_string(at_line) + ":" + std::to_string(at_col) + ": ";
    };
    while (i < n) {
        Record rec;
        rec.line = line;
        for (;;) {
            Field f;
            f.col = i - line_start + 1;
            if (i < n && text[i] == '"') {
                const size_t open_line = line, open_col = f.col;
                ++i;
                for (;;) {
                    if (i >= n) {
                        error = where(open_line, open_col) + "unterminated quoted field";
                        return false;
                    }
                    const char c = text[i];
                    if (c == '"') {
                        if (i + 1 < n && text[i + 1] == '"') {
                            f.text += '"';
                            i += 2;
                            continue;
                        }
                        ++i;
                        break;
                    }
                    if (c == '\n') {
                        ++line;
                        line_start = i + 1;
                    }
                    f.text += c;
                    ++i;
                }
                const bool crlf = i + 1 < n && text[i] == '\r' && text[i + 1] == '\n';
                if (i < n && text[i] != ',' && text[i] != '\n' && !crlf) {
                    error = where(line, i - line_start + 1) +
                            "unexpected character after a quoted field";
                    return false;
                }
            } else {
                const size_t start = i;
                while (i < n && text[i] != ',' && text[i] != '\n') {
                    if (text[i] == '"') {
                        error = where(line, i - line_start + 1) +
                                "quote inside an unquoted field (quote the whole field)";
                        return false;
                    }
                    ++i;
                }
                size_t end = i;
                if (end > start && text[end - 1] == '\r') --end;
                f.text.assign(text.substr(start, end - start));
            }
            rec.fields.push_back(std::move(f));
            if (i < n && text[i] == ',') {
                ++i;
                continue;
            }
            if (i < n && text[i] == '\r') ++i;
            if (i < n && text[i] == '\n') {
                ++i;
                ++line;
                line_start = i;
            }
            break;
        }
        const bool blank = rec.fields.size() == 1 && rec.fields[0].text.empty();
        if (!blank) out.push_back(std::move(rec));
    }
    return true;
}

// The shortest text that reads back as the same double (valid JSON).
void put_number(std::string& out, double v) {
    char buf[40];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

bool all_digits(std::string_view s) {
    return !s.empty() && s.size() <= 9 &&
           std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// What a column may hold.
enum class Kind {
    Variant,  // non-negative integer, strictly increasing
    Param,    // number
    Passed,   // 0 or 1
    Error,    // any text (empty = no error)
    Count,    // non-negative integer or empty
    Number,   // number or empty (empty = never measured / not applicable)
    Verdict,  // 0, 1 or empty
};

struct Column {
    std::string name;
    Kind kind;
};

// ---- summary.json ---------------------------------------------------------------------------

// "line:col" of a byte offset.
std::string line_col(std::string_view text, size_t offset) {
    offset = std::min(offset, text.size());
    size_t line = 1, start = 0;
    for (size_t i = 0; i < offset; ++i) {
        if (text[i] == '\n') {
            ++line;
            start = i + 1;
        }
    }
    return std::to_string(line) + ":" + std::to_string(offset - start + 1);
}

// The columns results.csv must have, in order, from summary.json; false with `error` when
// summary.json does not describe them.
bool expected_columns(const Json& s, std::vector<Column>& cols, std::string& error) {
    cols.push_back({"variant", Kind::Variant});
    if (!s.contains("parameters") || !s["parameters"].is_array()) {
        error = "no \"parameters\" array";
        return false;
    }
    for (size_t i = 0; i < s["parameters"].size(); ++i) {
        const Json& p = s["parameters"][i];
        const std::string at = "parameters[" + std::to_string(i) + "]";
        if (!p.is_object() || !p.contains("column") || !p["column"].is_string() ||
            !p.contains("name") || !p["name"].is_string()) {
            error = at + ": expected an object with string \"name\" and \"column\"";
            return false;
        }
        if (p.contains("values") && !p["values"].is_null()) {
            const Json& v = p["values"];
            if (!v.is_array() ||
                !std::all_of(v.begin(), v.end(), [](const Json& x) { return x.is_number(); })) {
                error = at + ".values: expected null or an array of numbers";
                return false;
            }
        }
        cols.push_back({p["column"].get<std::string>(), Kind::Param});
    }
    cols.push_back({"passed", Kind::Passed});
    cols.push_back({"error", Kind::Error});
    cols.push_back({"collisions", Kind::Count});
    for (const char* name :
         {"min_ttc[s]", "min_gap[m]", "min_clearance[m]", "fallback_share", "duration[s]"}) {
        cols.push_back({name, Kind::Number});
    }
    if (!s.contains("expectations") || !s["expectations"].is_array()) {
        error = "no \"expectations\" array";
        return false;
    }
    for (size_t i = 0; i < s["expectations"].size(); ++i) {
        const Json& e = s["expectations"][i];
        if (!e.is_object() || !e.contains("id") || !e["id"].is_string() || !e.contains("column") ||
            !e["column"].is_string()) {
            error = "expectations[" + std::to_string(i) +
                    "]: expected an object with string \"id\" and \"column\"";
            return false;
        }
        cols.push_back({e["column"].get<std::string>(), Kind::Number});
        cols.push_back({e["id"].get<std::string>() + "_passed", Kind::Verdict});
    }
    return true;
}

std::string in_quotes(const std::string& s) { return "'" + s + "'"; }

std::string report(const std::string& dir_text, std::string& error) {
    const fs::path dir(dir_text);
    const std::string summary_file = (dir / "summary.json").string();
    const std::string csv_file = (dir / "results.csv").string();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        error = "'" + dir_text +
                "' is not a directory (a sweep directory is written by `sdv sweep -o DIR`)";
        return "";
    }
    std::string summary_text, csv;
    if (!read(dir / "summary.json", summary_text)) {
        error = summary_file +
                ": cannot read it (a sweep directory has summary.json and results.csv, written by "
                "`sdv sweep -o DIR`)";
        return "";
    }
    if (!read(dir / "results.csv", csv)) {
        error = csv_file +
                ": cannot read it (a sweep directory has summary.json and results.csv, written by "
                "`sdv sweep -o DIR`)";
        return "";
    }

    // summary.json (sdv sweep writes 3 levels; deeper text would make writing it into the report
    // recurse once per level)
    if (ir::json_depth(summary_text) > 64) {
        error = summary_file + ": JSON nested more than 64 levels deep";
        return "";
    }
    Json summary;
    try {
        summary = Json::parse(summary_text);
    } catch (const Json::parse_error& e) {
        std::string what = e.what();
        // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error ..."
        const size_t colon = what.find(": ", what.find("parse error"));
        error = summary_file + ":" + line_col(summary_text, e.byte == 0 ? 0 : e.byte - 1) +
                ": not valid JSON" +
                (colon == std::string::npos ? "" : " (" + what.substr(colon + 2) + ")");
        return "";
    }
    if (!summary.is_object()) {
        error = summary_file + ": expected a JSON object";
        return "";
    }
    if (!summary.contains("format") || !summary["format"].is_string()) {
        error = summary_file + ": no \"format\" (expected \"" + kSweepFormat + "\")";
        return "";
    }
    if (summary["format"] != kSweepFormat) {
        error = summary_file + ": unknown format \"" + summary["format"].get<std::string>() +
                "\" (expected \"" + kSweepFormat + "\")";
        return "";
    }
    std::vector<Column> cols;
    std::string why;
    if (!expected_columns(summary, cols, why)) {
        error = summary_file + ": " + why;
        return "";
    }

    // results.csv
    std::vector<Record> records;
    if (!parse_csv(csv, records, why)) {
        error = csv_file + ":" + why;
        return "";
    }
    if (records.empty()) {
        error = csv_file + ": empty (expected a header line)";
        return "";
    }
    const Record& header = records[0];
    for (size_t c = 0; c < std::min(header.fields.size(), cols.size()); ++c) {
        if (header.fields[c].text != cols[c].name) {
            error = csv_file + ":" + std::to_string(header.line) + ":" +
                    std::to_string(header.fields[c].col) + ": column " + std::to_string(c + 1) +
                    " is " + in_quotes(header.fields[c].text) + ", expected " +
                    in_quotes(cols[c].name) + " (the columns follow summary.json)";
            return "";
        }
    }
    if (header.fields.size() != cols.size()) {
        error = csv_file + ":" + std::to_string(header.line) + ": " +
                std::to_string(header.fields.size()) + " columns, expected " +
                std::to_string(cols.size()) +
                " (from summary.json: " + std::to_string(summary["parameters"].size()) +
                " parameters, " + std::to_string(summary["expectations"].size()) + " expectations)";
        return "";
    }

    // Columnar JSON text of the rows, checked cell by cell.
    const size_t rows = records.size() - 1;
    std::vector<std::string> out(cols.size());
    std::vector<long> variants;
    variants.reserve(rows);
    for (auto& o : out) o.reserve(rows * 6 + 2);
    for (size_t r = 1; r < records.size(); ++r) {
        const Record& rec = records[r];
        if (rec.fields.size() != cols.size()) {
            error = csv_file + ":" + std::to_string(rec.line) + ": " +
                    std::to_string(rec.fields.size()) + " fields, expected " +
                    std::to_string(cols.size());
            return "";
        }
        for (size_t c = 0; c < cols.size(); ++c) {
            const Field& f = rec.fields[c];
            std::string& o = out[c];
            if (r > 1) o += ',';
            auto fail = [&](const std::string& what) {
                error = csv_file + ":" + std::to_string(rec.line) + ":" + std::to_string(f.col) +
                        ": " + in_quotes(cols[c].name) + ": " + what;
                return std::string();
            };
            double v = 0;
            switch (cols[c].kind) {
                case Kind::Variant: {
                    if (!all_digits(f.text))
                        return fail(in_quotes(f.text) +
                                    " is not a variant index (a non-negative integer)");
                    const long idx = std::stol(f.text);
                    if (!variants.empty() && idx <= variants.back()) {
                        return fail("variant " + std::to_string(idx) + " after variant " +
                                    std::to_string(variants.back()) +
                                    " (rows are sorted by variant, each once)");
                    }
                    variants.push_back(idx);
                    o += std::to_string(idx);
                    break;
                }
                case Kind::Param:
                    if (!finite_number(f.text, v))
                        return fail(in_quotes(f.text) + " is not a number");
                    put_number(o, v);
                    break;
                case Kind::Passed:
                    if (f.text != "0" && f.text != "1")
                        return fail(in_quotes(f.text) + " is not 1 or 0");
                    o += f.text;
                    break;
                case Kind::Error:
                    o += f.text.empty() ? std::string("null") : json_text(Json(f.text));
                    break;
                case Kind::Count:
                    if (f.text.empty())
                        o += "null";
                    else if (!all_digits(f.text))
                        return fail(in_quotes(f.text) + " is not a count (a non-negative integer)");
                    else
                        o += std::to_string(std::stol(f.text));
                    break;
                case Kind::Number:
                    if (f.text.empty())
                        o += "null";
                    else if (!finite_number(f.text, v))
                        return fail(in_quotes(f.text) +
                                    " is not a number (or empty when never measured)");
                    else
                        put_number(o, v);
                    break;
                case Kind::Verdict:
                    if (f.text.empty())
                        o += "null";
                    else if (f.text != "0" && f.text != "1")
                        return fail(in_quotes(f.text) + " is not 1, 0 or empty");
                    else
                        o += f.text;
                    break;
            }
        }
    }
    if (summary.contains("variants") && summary["variants"].is_number_integer() &&
        summary["variants"].get<long long>() != static_cast<long long>(rows)) {
        error = csv_file + ": " + std::to_string(rows) + " variants, but summary.json says " +
                std::to_string(summary["variants"].get<long long>());
        return "";
    }

    // Kept runs with a report of their own: runs/<variant>/view.html.
    std::vector<long> kept;
    const fs::path runs = dir / "runs";
    if (fs::is_directory(runs, ec)) {
        for (fs::directory_iterator it(runs, ec), end; !ec && it != end; it.increment(ec)) {
            const std::string name = it->path().filename().string();
            if (!all_digits(name)) continue;
            const long idx = std::stol(name);
            std::error_code ec2;
            if (std::binary_search(variants.begin(), variants.end(), idx) &&
                fs::is_regular_file(it->path() / "view.html", ec2)) {
                kept.push_back(idx);
            }
        }
        std::sort(kept.begin(), kept.end());
    }

    std::string data = std::string("{\"format\":\"") + kReportFormat +
                       "\",\"summary\":" + json_text(summary) + ",\"columns\":[";
    for (size_t c = 0; c < cols.size(); ++c) data += (c ? "," : "") + json_text(Json(cols[c].name));
    data += "],\"values\":[";
    for (size_t c = 0; c < cols.size(); ++c) data += (c ? ",[" : "[") + out[c] + "]";
    data += "],\"kept\":[";
    for (size_t k = 0; k < kept.size(); ++k) data += (k ? "," : "") + std::to_string(kept[k]);
    data += "]}";

    // Inside <script>, "</script>" or "<!--" in a string would end or confuse the element: '<'
    // is written as its JSON escape, which JSON.parse reads back unchanged.
    std::string safe;
    safe.reserve(data.size() + 64);
    for (char c : data) {
        if (c == '<')
            safe += "\\u003c";
        else
            safe += c;
    }
    std::string html(sweep_report_template());
    const std::string marker = "__SDV_DATA__";
    const size_t at = html.find(marker);
    if (at == std::string::npos) {
        error = "the embedded sweep report has no data placeholder (a build problem)";
        return "";
    }
    html.replace(at, marker.size(), safe);
    return html;
}

}  // namespace

std::string sweep_report(const std::string& dir, std::string& error) {
    error.clear();
    try {
        return report(dir, error);
    } catch (const std::exception& e) {  // e.g. out of memory: the API never throws
        error = "'" + dir + "': cannot build the sweep report: " + e.what();
        return "";
    }
}

}  // namespace sdv::io
