// Fuzz target of the reader of a sweep's rows: what `sdv sweep --resume` and the merge of a
// Slurm sweep read from DIR/rows (runtime/campaign/sweep.h: read_row, run_sweep, gather). The
// input is one rows/*.csv file of the campaign in sweep_rows.sdv (embedded). It is read three
// ways that must agree:
//   - line by line (read_row): a line read back writes back to the same bytes (row_text), is a
//     variant of the campaign with that variant's values, and a refused line says why;
//   - as a resume reads it (read_row_files, what run_sweep skips and warns about): the first row
//     of each variant kept, exactly the complete lines read_row refuses counted as damaged, and
//     the first of them named with its file and line;
//   - by the merge (gather_rows: gather after its manifest check, which compares one file's
//     bytes): it succeeds exactly when every variant has a row, with the first row of each
//     variant, in variant order; otherwise it says how many variants have none.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "compiler/sema/compile.h"
#include "runtime/campaign/sweep.h"
#include "tests/fuzz/targets/scratch.h"
#include "tests/fuzz/targets/targets.h"

using namespace sdv;

namespace sdv::fuzz {
std::string_view sweep_rows_scenario_text();  // targets/sweep_rows.sdv, embedded (CMakeLists.txt)
}

namespace {

constexpr const char* kTarget = "sweep_rows";

const ir::Program& campaign_program() {
    static const ir::Program program = [] {
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        auto c = compiler::compile_source("sweep_rows.sdv", std::string(fuzz::sweep_rows_scenario_text()), sm, diags);
        if (!c.program) fuzz::fail(kTarget, "the target's campaign (sweep_rows.sdv) does not compile");
        return std::move(*c.program);
    }();
    return program;
}

}  // namespace

int sdv_fuzz_sweep_rows(const uint8_t* data, size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const ir::Program& program = campaign_program();
    const ir::Scenario& s = program.scenarios[0];
    const campaign::VariantSpace space(s.vary);
    const int64_t n = space.size();

    // Line by line. Only lines that end in '\n' are rows; a torn last line is no row and no damage.
    std::vector<std::string> first_line(static_cast<size_t>(n));
    std::vector<bool> has(static_cast<size_t>(n), false);
    int64_t refused = 0;
    size_t first_refused = 0;
    size_t at = 0, line_no = 0;
    while (at < bytes.size()) {
        const size_t nl = bytes.find('\n', at);
        if (nl == std::string_view::npos) break;
        ++line_no;
        const std::string line(bytes.substr(at, nl - at));
        at = nl + 1;
        if (line.empty()) continue;
        campaign::Row row;
        std::string why;
        if (!campaign::read_row(s, space, line, row, why)) {
            if (why.empty()) fuzz::fail(kTarget, "a refused row without a reason");
            if (refused++ == 0) first_refused = line_no;
            continue;
        }
        if (row.variant < 0 || row.variant >= n) fuzz::fail(kTarget, "a row read of no variant of the campaign");
        if (campaign::row_text(s, row) != line) fuzz::fail(kTarget, "a row read back writes other text");
        campaign::Row exact = row;
        exact.values = space.values(row.variant);
        if (campaign::row_text(s, exact) != line) fuzz::fail(kTarget, "a row read with another variant's values");
        const auto v = static_cast<size_t>(row.variant);
        if (!has[v]) {
            has[v] = true;
            first_line[v] = line;
        }
    }

    // What a resume reads (run_sweep: the variants it need not run, the lines it warns about).
    const std::string dir = fuzz::fresh_dir(kTarget);
    std::filesystem::create_directories(dir + "/rows");
    fuzz::write_file(dir + "/rows/slice-0-of-1.csv", bytes);
    const campaign::RowFiles files = campaign::read_row_files(s, dir);
    if (files.damaged != refused) {
        fuzz::fail(kTarget, "the resume counts " + std::to_string(files.damaged) + " damaged lines, read_row refuses " +
                                std::to_string(refused));
    }
    const std::string where = dir + "/rows/slice-0-of-1.csv:" + std::to_string(first_refused) + ": ";
    if (refused > 0 && files.damage.rfind(where, 0) != 0) {
        fuzz::fail(kTarget, "the first damaged line is not named: " + files.damage);
    }
    for (const auto& [v, stored] : files.rows) {
        if (v < 0 || v >= n || !has[static_cast<size_t>(v)] || stored.line != first_line[static_cast<size_t>(v)]) {
            fuzz::fail(kTarget, "the resume keeps another row of variant " + std::to_string(v));
        }
    }

    // The merge.
    campaign::Results results;
    const std::string error = campaign::gather_rows(s, dir, results);
    int64_t missing = 0;
    for (const bool h : has) missing += h ? 0 : 1;
    if (missing > 0) {
        if (error.find("is incomplete: " + std::to_string(missing) + " of " + std::to_string(n)) == std::string::npos) {
            fuzz::fail(kTarget, "the merge of rows missing " + std::to_string(missing) + " variants says: " + error);
        }
        return 0;
    }
    if (!error.empty()) fuzz::fail(kTarget, "the merge of a whole campaign failed: " + error);
    if (results.lines.size() != static_cast<size_t>(n) || results.rows.size() != static_cast<size_t>(n)) {
        fuzz::fail(kTarget, "the merge does not give one row per variant");
    }
    for (int64_t v = 0; v < n; ++v) {
        const auto k = static_cast<size_t>(v);
        if (results.rows[k].variant != v || results.lines[k] != first_line[k]) {
            fuzz::fail(kTarget, "the merge's row of variant " + std::to_string(v) + " is not the first one read");
        }
    }
    return 0;
}
