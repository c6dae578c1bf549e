// Replays, through every fuzz target (targets/targets.h), each file of the committed corpus
// (corpus/NAME/) and the reproducer of each finding (regressions/NAME/), so that a fixed finding
// stays fixed in every build, without libFuzzer. A crash, a sanitizer report or a broken
// property aborts with the file named (doctest prints the INFO context on a crash). Slowness is
// not checked here (a test's verdict must not depend on how busy the machine is): the fuzzers'
// own -timeout finds slow inputs (scripts/fuzz.sh), and their reproducers bound the work by size.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/targets/targets.h"

namespace fs = std::filesystem;

namespace {

using Target = int (*)(const uint8_t*, size_t);

// Every regular file under tests/fuzz/{corpus,regressions}/<name>/, in a stable order.
std::vector<fs::path> inputs(const std::string& name) {
    std::vector<fs::path> out;
    for (const char* kind : {"corpus", "regressions"}) {
        const fs::path dir = fs::path(SDV_FUZZ_DIR) / kind / name;
        std::error_code ec;
        if (!fs::is_directory(dir, ec)) continue;
        for (const auto& e : fs::recursive_directory_iterator(dir)) {
            if (e.is_regular_file() && e.path().filename().string()[0] != '.') out.push_back(e.path());
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

void replay(const std::string& name, Target target) {
    const auto files = inputs(name);
    CHECK_MESSAGE(!files.empty(), "no corpus or regressions for fuzz target " << name);
    for (const auto& f : files) {
        INFO("fuzz target ", name, ": ", f.string());
        std::ifstream in(f, std::ios::binary);
        REQUIRE(in);
        const std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
        CHECK(target(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()) == 0);
    }
    MESSAGE(name << ": " << files.size() << " inputs replayed");
}

}  // namespace

TEST_CASE("sdv_frontend") { replay("sdv_frontend", sdv_fuzz_sdv_frontend); }
TEST_CASE("ir_reader") { replay("ir_reader", sdv_fuzz_ir_reader); }
TEST_CASE("btree") { replay("btree", sdv_fuzz_btree); }
TEST_CASE("gss_scenario") { replay("gss_scenario", sdv_fuzz_gss_scenario); }
TEST_CASE("lanelet2") { replay("lanelet2", sdv_fuzz_lanelet2); }
TEST_CASE("cosim_frame") { replay("cosim_frame", sdv_fuzz_cosim_frame); }
TEST_CASE("sweep_results") { replay("sweep_results", sdv_fuzz_sweep_results); }
TEST_CASE("recording") { replay("recording", sdv_fuzz_recording); }
TEST_CASE("run_dir") { replay("run_dir", sdv_fuzz_run_dir); }
TEST_CASE("run_diff") { replay("run_diff", sdv_fuzz_run_diff); }
TEST_CASE("sweep_rows") { replay("sweep_rows", sdv_fuzz_sweep_rows); }
