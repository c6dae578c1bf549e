// Campaign throughput (issue 16): the cut-in of examples/sweeps/cut_in_search.sdv (30 s, two
// SDVs) as a Latin hypercube of N variants (default 1,000), run (a) bare as `sdv run` runs a
// scenario: every variant applied beforehand and simulated in a loop on one thread, its road
// built by each run, no rows, no files; (a') the same with the road shared between the runs
// (sim::RoadCache, as the sweep does); (b) as `sdv sweep` does it with 1 job and (c) with 2 jobs
// (rows appended to a directory, results and summary written). Reports variants per second, the
// per-variant run time percentiles of (a) and (a'), the sweep's share of (a') per core (what the
// sweep itself costs) and of (a), and checks that (b) and (c) wrote identical results.
//   build/bench/bench/sweep_bench [N] [--repeat R] [--source DIR]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/sema/compile.h"
#include "runtime/campaign/sweep.h"
#include "runtime/campaign/variants.h"
#include "runtime/ir/bindings.h"
#include "runtime/sim/road_cache.h"
#include "runtime/sim/simulation.h"

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double pct(std::vector<double> v, double p) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size())))];
}

double median(std::vector<double> v) { return pct(std::move(v), 0.5); }

std::string read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace

int main(int argc, char** argv) {
    int64_t n = 1000;
    int repeat = 3;
    std::string source = SDV_SOURCE_DIR;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--repeat" && i + 1 < argc) {
            repeat = std::atoi(argv[++i]);
        } else if (a == "--source" && i + 1 < argc) {
            source = argv[++i];
        } else {
            n = std::atoll(argv[i]);
        }
    }
    const std::string file = source + "/examples/sweeps/cut_in_search.sdv";
    sdv::diag::SourceManager sm;
    sdv::diag::DiagnosticEngine diags;
    auto c = sdv::compiler::compile_file(file, sm, diags);
    if (!c.program) {
        std::fprintf(stderr, "cannot compile %s\n", file.c_str());
        return 1;
    }
    sdv::ir::Program program = std::move(*c.program);
    program.scenarios[0].vary.sample = sdv::ir::Vary::Sample::latin;
    program.scenarios[0].vary.count = n;
    const sdv::campaign::VariantSpace space(program.scenarios[0].vary);
    const auto base = sdv::ir::scenario_number_values(program, 0);
    std::vector<sdv::ir::Program> variants;
    for (int64_t i = 0; i < n; ++i) {
        variants.push_back(program);
        sdv::ir::apply_variant(variants.back(), 0, base, space.values(i));
    }
    const auto tmp = std::filesystem::temp_directory_path() / "sdv-sweep-bench";
    std::vector<double> bare_rate, shared_rate, rate1, rate2, run_ms, shared_ms;
    bool identical = true;
    for (int r = 0; r < repeat; ++r) {
        // (a) bare runs
        const auto t0 = Clock::now();
        for (const auto& v : variants) {
            const auto t = Clock::now();
            const auto result = sdv::sim::simulate(v, 0, sdv::sim::RunOptions{});
            run_ms.push_back(seconds_since(t) * 1e3);
            if (!result.error.empty()) {
                std::fprintf(stderr, "run error: %s\n", result.error.c_str());
                return 1;
            }
        }
        bare_rate.push_back(static_cast<double>(n) / seconds_since(t0));
        // (a') bare runs sharing the road
        sdv::sim::RunOptions shared;
        shared.roads = std::make_shared<sdv::sim::RoadCache>();
        const auto t1 = Clock::now();
        for (const auto& v : variants) {
            const auto t = Clock::now();
            sdv::sim::simulate(v, 0, shared);
            shared_ms.push_back(seconds_since(t) * 1e3);
        }
        shared_rate.push_back(static_cast<double>(n) / seconds_since(t1));
        // (b), (c) sweeps
        std::string results[2];
        for (int jobs : {1, 2}) {
            const std::string dir = (tmp / ("j" + std::to_string(jobs))).string();
            sdv::campaign::clear_sweep(dir);
            sdv::campaign::SweepOptions o;
            o.dir = dir;
            o.file = file;
            o.jobs = jobs;
            const auto t = Clock::now();
            const auto out = sdv::campaign::run_sweep(program, 0, o);
            sdv::campaign::Results res;
            const std::string e1 = sdv::campaign::gather(program, 0, dir, res);
            const std::string e2 = e1.empty() ? sdv::campaign::write_results(program, 0, o, res) : e1;
            const double s = seconds_since(t);
            if (!out.error.empty() || !e2.empty()) {
                std::fprintf(stderr, "sweep error: %s%s\n", out.error.c_str(), e2.c_str());
                return 1;
            }
            (jobs == 1 ? rate1 : rate2).push_back(static_cast<double>(n) / s);
            results[jobs - 1] = read(dir + "/results.csv") + read(dir + "/summary.json");
        }
        identical = identical && results[0] == results[1];
    }
    std::filesystem::remove_all(tmp);
    const double bare = median(bare_rate), shared_road = median(shared_rate), one = median(rate1), two = median(rate2);
    std::printf("sweep_bench: %lld variants of %s (Latin hypercube), %d repeats, medians\n", static_cast<long long>(n),
                "examples/sweeps/cut_in_search.sdv", repeat);
    std::printf("  bare runs, 1 thread:  %7.1f variants/s   run time p50 %.2f ms  p90 %.2f ms  p99 %.2f ms  max %.2f ms\n",
                bare, pct(run_ms, 0.5), pct(run_ms, 0.9), pct(run_ms, 0.99), pct(run_ms, 1.0));
    std::printf("  bare, shared road:    %7.1f variants/s   run time p50 %.2f ms  p90 %.2f ms  p99 %.2f ms  max %.2f ms\n",
                shared_road, pct(shared_ms, 0.5), pct(shared_ms, 0.9), pct(shared_ms, 0.99), pct(shared_ms, 1.0));
    std::printf("  sdv sweep, 1 job:     %7.1f variants/s   %.1f %% of the bare runs with a shared road, %.1f %% of sdv run's\n",
                one, 100 * one / shared_road, 100 * one / bare);
    std::printf("  sdv sweep, 2 jobs:    %7.1f variants/s   %.1f %% of the shared-road throughput per core (speed-up %.2fx)\n",
                two, 100 * two / (2 * shared_road), two / one);
    std::printf("  results.csv and summary.json identical for 1 and 2 jobs: %s\n", identical ? "yes" : "NO");
    return identical ? 0 : 1;
}
