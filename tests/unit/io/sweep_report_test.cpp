// The sweep report (issue 16, test campaigns): the data inlined into the page from a sweep
// directory (results.csv, summary.json, runs/<i>/view.html), and every way a directory can fail
// to be a readable sweep: a missing file, an unknown format, a header that does not follow
// summary.json, a wrong field count, a cell that is not a number, broken quoting or JSON. Each
// is one error line naming the file (and the line and column), never a crash.
#include "runtime/io/sweep_report.h"

#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

// This file's tests and helpers, apart from the other files of its unity batch.
namespace sweep_report_test {

using namespace sdv;
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// A fresh directory under the system temp directory, removed at the end of the test.
struct TempDir {
    fs::path path;
    TempDir() {
        static int n = 0;
        path = fs::temp_directory_path() /
               ("sdv_sweep_report_test_" + std::to_string(::getpid()) + "_" + std::to_string(n++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

void write(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
}

// One parameter `a` [m] on a grid, one expectation with a value in seconds.
std::string summary(const std::string& format = "sdv-sweep/1", int variants = 2) {
    Json s = Json::parse(R"({
        "file": "t.sdv", "scenario": "t", "ir_hash": "0", "sample": {"method": "grid", "count": 0, "seed": 1},
        "parameters": [{"name": "a", "unit": "m", "column": "a[m]", "domain": "1 m .. 2 m count 2", "values": [1, 2]}],
        "expectations": [{"id": "e1", "text": "min_ttc(ego, v2) > 1.5 s", "column": "e1[s]", "unit": "s", "line": 3}],
        "passed": 1, "failed": 0, "errors": 1, "with_collision": 0, "expectation_failures": {"e1": 0}, "kept": "runs"})");
    s["format"] = format;
    s["variants"] = variants;
    return s.dump(2);
}

const std::string kHeader =
    "variant,a[m],passed,error,collisions,min_ttc[s],min_gap[m],min_clearance[m],fallback_share,"
    "duration[s],e1[s],e1_passed\n";
const std::string kRows = "0,1,1,,0,2.5,3,1,0,10,2.5,1\n1,2,0,\"boom, \"\"bad\"\"\",,,,,,,,\n";

// The JSON inlined into the page.
Json data_of(const std::string& html) {
    const std::string open = "<script id=\"sdv-data\" type=\"application/json\">";
    const size_t a = html.find(open);
    REQUIRE(a != std::string::npos);
    const size_t b = html.find("</script>", a);
    REQUIRE(b != std::string::npos);
    return Json::parse(html.substr(a + open.size(), b - a - open.size()));
}

// The report of a directory with these files; the error (empty when it worked).
std::string error_of(const std::string& summary_text, const std::string& csv_text) {
    TempDir d;
    write(d.path / "summary.json", summary_text);
    write(d.path / "results.csv", csv_text);
    std::string error;
    const std::string html = io::sweep_report(d.path.string(), error);
    CHECK(html.empty() == !error.empty());
    return error;
}

bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("sweep report: the grid fixture's data, kept runs with a view.html only") {
    std::string error;
    const std::string html =
        io::sweep_report(std::string(SDV_SOURCE_DIR) + "/tests/browser/data/sweep_grid", error);
    REQUIRE(error.empty());
    CHECK(html.find("__SDV_DATA__") == std::string::npos);
    const Json d = data_of(html);
    CHECK(d["format"] == "sdv-sweep-report/1");
    CHECK(d["summary"]["scenario"] == "cut_in_table");
    CHECK(d["columns"].size() == 15);
    CHECK(d["columns"][1] == "v2.tree.accept_gap[m]");
    CHECK(d["values"][0].size() == 15);
    CHECK(d["kept"] == Json::array({4, 11}));  // runs/1 holds no view.html
    // the quoted error (a comma and doubled quotes) and its empty metric cells
    CHECK(d["values"][4][7] ==
          "planner: no feasible candidate for v2 at t=3.2 s, \"cut_in\" aborted");
    CHECK(d["values"][4][0].is_null());
    CHECK(d["values"][6][7].is_null());
    CHECK(d["values"][6][6].is_null());  // min_ttc never measured
    CHECK(d["values"][6][0] == 2.41);
    CHECK(d["values"][9][1] == doctest::Approx(0.0833333));
}

TEST_CASE("sweep report: the random fixture (three continuous parameters)") {
    std::string error;
    const std::string html =
        io::sweep_report(std::string(SDV_SOURCE_DIR) + "/tests/browser/data/sweep_random", error);
    REQUIRE(error.empty());
    const Json d = data_of(html);
    CHECK(d["summary"]["parameters"].size() == 3);
    CHECK(d["summary"]["parameters"][0]["values"].is_null());
    CHECK(d["values"][0].size() == 12);
    CHECK(d["kept"] == Json::array({2}));
}

TEST_CASE("sweep report: reading a small directory; quoting, CRLF, '<' in messages") {
    TempDir dir;
    write(dir.path / "summary.json", summary());
    write(dir.path / "results.csv",
          kHeader +
              "0,1,1,,0,2.5,3,1,0,10,2.5,1\r\n1,2,0,\"</script><!-- line\nbreak\",,,,,,,,\r\n\n");
    write(dir.path / "runs" / "1" / "view.html", "<html></html>");
    write(dir.path / "runs" / "7" / "view.html", "<html></html>");  // not a variant of results.csv
    write(dir.path / "runs" / "x" / "view.html", "<html></html>");
    std::string error;
    const std::string html = io::sweep_report(dir.path.string(), error);
    REQUIRE(error.empty());
    const Json d = data_of(html);
    CHECK(d["values"][3][1] == "</script><!-- line\nbreak");
    CHECK(d["values"][3][0].is_null());
    CHECK(d["values"][5][0] == 2.5);
    CHECK(d["values"][11][0] == 1);
    CHECK(d["values"][11][1].is_null());
    CHECK(d["kept"] == Json::array({1}));
    // inside the page's <script>, no '<' of the data survives unescaped
    const size_t a = html.find("application/json\">");
    CHECK(html.find("</script><!--", a) == std::string::npos);
}

TEST_CASE("sweep report: missing directory or files") {
    std::string error;
    CHECK(io::sweep_report("/nonexistent/sweep", error).empty());
    CHECK(contains(error, "'/nonexistent/sweep' is not a directory"));

    TempDir dir;
    write(dir.path / "summary.json", summary());
    CHECK(io::sweep_report(dir.path.string(), error).empty());
    CHECK(contains(error, (dir.path / "results.csv").string() + ": cannot read it"));

    fs::remove(dir.path / "summary.json");
    write(dir.path / "results.csv", kHeader + kRows);
    CHECK(io::sweep_report(dir.path.string(), error).empty());
    CHECK(contains(error, (dir.path / "summary.json").string() + ": cannot read it"));

    CHECK(io::sweep_report((dir.path / "results.csv").string(), error).empty());
    CHECK(contains(error, "is not a directory"));
}

TEST_CASE("sweep report: summary.json errors") {
    CHECK(contains(error_of(summary("sdv-sweep/2"), kHeader + kRows),
                   "summary.json: unknown format \"sdv-sweep/2\" (expected \"sdv-sweep/1\")"));
    CHECK(contains(error_of(R"({"file": "x"})", kHeader + kRows), "summary.json: no \"format\""));
    CHECK(contains(error_of("[1, 2]", kHeader + kRows), "summary.json: expected a JSON object"));
    const std::string broken = "{\n  \"format\": \"sdv-sweep/1\",\n  \"file\": x\n}";
    CHECK(contains(error_of(broken, kHeader + kRows), "summary.json:3:11: not valid JSON"));
    CHECK(contains(error_of(R"({"format": "sdv-sweep/1", "expectations": []})", kHeader + kRows),
                   "summary.json: no \"parameters\" array"));
    CHECK(contains(
        error_of(R"({"format": "sdv-sweep/1", "parameters": [{"name": "a"}], "expectations": []})",
                 kHeader + kRows),
        "summary.json: parameters[0]: expected an object with string \"name\" and \"column\""));
    Json bad_values = Json::parse(summary());
    bad_values["parameters"][0]["values"] = Json::array({1, "x"});
    CHECK(contains(error_of(bad_values.dump(), kHeader + kRows),
                   "summary.json: parameters[0].values: expected null or an array of numbers"));
    CHECK(contains(error_of(summary("sdv-sweep/1", 3), kHeader + kRows),
                   "results.csv: 2 variants, but summary.json says 3"));
}

TEST_CASE("sweep report: results.csv errors name the line and column") {
    CHECK(contains(error_of(summary(), ""), "results.csv: empty (expected a header line)"));
    // a header that does not follow summary.json
    std::string header = kHeader;
    header.replace(header.find("a[m]"), 4, "b[m]");
    CHECK(contains(
        error_of(summary(), header + kRows),
        "results.csv:1:9: column 2 is 'b[m]', expected 'a[m]' (the columns follow summary.json)"));
    CHECK(contains(
        error_of(summary(), "variant,a[m],passed\n"),
        "results.csv:1: 3 columns, expected 12 (from summary.json: 1 parameters, 1 expectations)"));
    // wrong column count in a row
    CHECK(contains(error_of(summary(), kHeader + "0,1,1,,0,2.5,3,1,0,10,2.5\n"),
                   "results.csv:2: 11 fields, expected 12"));
    // non-numeric cells
    CHECK(contains(
        error_of(summary(), kHeader + "0,1,1,,0,abc,3,1,0,10,2.5,1\n1,2,1,,0,,,,,,,\n"),
        "results.csv:2:10: 'min_ttc[s]': 'abc' is not a number (or empty when never measured)"));
    CHECK(contains(error_of(summary(), kHeader + "0,1,1,,0,2.5,3,1,0,10,2.5,1\n1,x,1,,0,,,,,,,\n"),
                   "results.csv:3:3: 'a[m]': 'x' is not a number"));
    CHECK(contains(error_of(summary(), kHeader + "0,,1,,0,,,,,,,\n1,2,1,,0,,,,,,,\n"),
                   "results.csv:2:3: 'a[m]': '' is not a number"));
    CHECK(contains(error_of(summary(), kHeader + "0,1,1,,0,inf,3,1,0,10,2.5,1\n1,2,1,,0,,,,,,,\n"),
                   "'inf' is not a number"));
    CHECK(contains(error_of(summary(), kHeader + "0,1,1,,0, 2.5,3,1,0,10,2.5,1\n1,2,1,,0,,,,,,,\n"),
                   "' 2.5' is not a number"));
    CHECK(contains(error_of(summary(), kHeader + "0,1,2,,0,,,,,,,\n1,2,1,,0,,,,,,,\n"),
                   "results.csv:2:5: 'passed': '2' is not 1 or 0"));
    CHECK(contains(error_of(summary(), kHeader + "0,1,1,,0.5,,,,,,,\n1,2,1,,0,,,,,,,\n"),
                   "'collisions': '0.5' is not a count"));
    CHECK(contains(error_of(summary(), kHeader + "0,1,1,,0,,,,,,,yes\n1,2,1,,0,,,,,,,\n"),
                   "'e1_passed': 'yes' is not 1, 0 or empty"));
    CHECK(contains(error_of(summary(), kHeader + "-1,1,1,,0,,,,,,,\n1,2,1,,0,,,,,,,\n"),
                   "results.csv:2:1: 'variant': '-1' is not a variant index"));
    CHECK(contains(error_of(summary(), kHeader + "1,1,1,,0,,,,,,,\n0,2,1,,0,,,,,,,\n"),
                   "results.csv:3:1: 'variant': variant 0 after variant 1 (rows are sorted by "
                   "variant, each once)"));
    // broken quoting
    CHECK(contains(error_of(summary(), kHeader + "0,1,1,\"open,0,,,,,,,\n"),
                   "results.csv:2:7: unterminated quoted field"));
    CHECK(contains(error_of(summary(), kHeader + "0,1,1,\"a\"b,0,,,,,,,\n"),
                   "results.csv:2:10: unexpected character after a quoted field"));
    CHECK(contains(error_of(summary(), kHeader + "0,1,1,a\"b,0,,,,,,,\n"),
                   "results.csv:2:8: quote inside an unquoted field"));
}

TEST_CASE("sweep report: never crashes on a truncated or corrupted directory") {
    const std::string csv = kHeader + kRows, json = summary();
    for (size_t n = 0; n < csv.size(); ++n) error_of(json, csv.substr(0, n));
    for (size_t n = 0; n < json.size(); n += 3) error_of(json.substr(0, n), csv);
    // bytes that are not UTF-8 in an error message are replaced, not fatal
    CHECK(error_of(json, kHeader + "0,1,1,,0,2.5,3,1,0,10,2.5,1\n1,2,0,\"\xff\xfe bad\",,,,,,,,\n")
              .empty());
}

TEST_CASE("sweep report: 10,000 variants") {
    TempDir dir;
    std::string s = summary("sdv-sweep/1", 10000), csv = kHeader;
    for (int i = 0; i < 10000; ++i) {
        csv += std::to_string(i) + "," + std::to_string(1 + i % 2) + "," + (i % 7 ? "1,," : "0,,") +
               std::to_string(i % 3) + "," + std::to_string(0.5 + i * 1e-4) +
               ",3.25,1.5,0.0416667,30," + (i % 11 ? "2.5" : "") + "," + (i % 7 ? "1" : "0") + "\n";
    }
    write(dir.path / "summary.json", s);
    write(dir.path / "results.csv", csv);
    std::string error;
    const std::string html = io::sweep_report(dir.path.string(), error);
    REQUIRE(error.empty());
    const Json d = data_of(html);
    CHECK(d["values"][0].size() == 10000);
    CHECK(d["values"][0][9999] == 9999);
    CHECK(d["values"][10][11].is_null());
    CHECK(d["values"][5][9999] == doctest::Approx(1.4999));
}

}  // namespace sweep_report_test
