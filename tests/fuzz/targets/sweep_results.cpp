// Fuzz target of the sweep directory reader: what `sdv view SWEEP_DIR` and `sdv sweep --report`
// read (runtime/io/sweep_report.h sweep_report). The input is the directory's two files: the
// bytes before the first NUL are results.csv, those after it summary.json (no NUL: a directory
// without summary.json). Property: a sweep that is refused says why.
#include <string>
#include <string_view>

#include "runtime/io/sweep_report.h"
#include "tests/fuzz/targets/scratch.h"
#include "tests/fuzz/targets/targets.h"

using namespace sdv;

int sdv_fuzz_sweep_results(const uint8_t* data, size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const std::string dir = fuzz::fresh_dir("sweep_results");
    const size_t nul = bytes.find('\0');
    fuzz::write_file(dir + "/results.csv", bytes.substr(0, nul));
    if (nul != std::string_view::npos) fuzz::write_file(dir + "/summary.json", bytes.substr(nul + 1));
    std::string error;
    const std::string html = io::sweep_report(dir, error);
    if (html.empty() && error.empty()) fuzz::fail("sweep_results", "no report and no error");
    return 0;
}
