// Co-simulation step cost (issue 15): N SDVs on a straight road with an external ego that keeps
// its lane at 13 m/s, stepped through the C API (libsdv.so) for 2 simulated minutes, against the
// same scenario run without co-simulation (the ego a trajectory vehicle on the same path).
// Reports steps/s and the per-step time percentiles of both, and the difference of the medians:
// the co-simulation overhead per step (state exchange, claims, events) in process.
//   build/bench/bench/cosim_bench [N] [--repeat R]
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "compiler/sema/compile.h"
#include "include/sdv/sdv.h"
#include "runtime/sim/simulation.h"

namespace {

std::string scenario(int n, bool external) {
    std::string s = "import \"std/drive.sdv\"\nroad r {\n lanes 3 forward\n speed_limit 60 km/h\n straight 4000 m\n}\n";
    s += "scenario bench {\n road r\n timeout 120 s\n";
    if (external) {
        s += " ego ego: external { start lane 2 at 400 m speed 13 m/s }\n";
    } else {
        s += " ego ego: trajectory { trajectory { 0 s: lane 2 at 400 m  120 s: lane 2 at 1960 m } }\n";
    }
    for (int i = 0; i < n; ++i) {
        s += " vehicle v" + std::to_string(i) + ": sdv { start lane " + std::to_string(1 + 2 * (i % 2)) + " at " +
             std::to_string(20 + 30 * (i / 2)) + " m speed 12 m/s tree std.drive(speed = 14 m/s) }\n";
    }
    s += "}\n";
    return s;
}

double pct(std::vector<double> v, double p) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size())))];
}

using Clock = std::chrono::steady_clock;
double us_since(Clock::time_point t0) { return std::chrono::duration<double, std::micro>(Clock::now() - t0).count(); }

// Per-step times of the C API run: set the ego's state, step, read every state and the events.
std::vector<double> run_capi(const std::string& path) {
    sdv_config cfg{};
    cfg.struct_size = sizeof cfg;
    cfg.scenario_path = path.c_str();
    cfg.threads = 1;
    sdv_sim* h = nullptr;
    uint64_t ego = 0;
    if (sdv_create(&cfg, &h) != SDV_OK || sdv_claim(h, "ego", SDV_CONTROL_POSE, &ego) != SDV_OK) {
        std::fprintf(stderr, "cosim_bench: %s\n", sdv_last_error(h));
        std::exit(1);
    }
    std::vector<sdv_actor_state> states(256);
    std::vector<sdv_event> events(64);
    std::vector<double> step_us;
    sdv_run_state rs = SDV_RUNNING;
    size_t n = 0, m = 0;
    sdv_get_actor_states(h, states.data(), states.size(), &n);
    sdv_actor_state me = states[ego - 1];
    while (rs == SDV_RUNNING) {
        const auto t0 = Clock::now();
        me.x += 13.0 / 30;
        me.speed = 13;
        sdv_set_external_state(h, &me);
        if (sdv_step(h, &rs) != SDV_OK) break;
        sdv_get_actor_states(h, states.data(), states.size(), &n);
        sdv_poll_events(h, events.data(), events.size(), &m);
        step_us.push_back(us_since(t0));
    }
    sdv_finish(h);
    sdv_destroy(h);
    return step_us;
}

std::vector<double> run_plain(const sdv::ir::Program& p) {
    sdv::sim::RunOptions opts;
    sdv::sim::Simulation sim(p, 0, opts);
    sim.start();
    std::vector<double> step_us;
    for (;;) {
        const auto t0 = Clock::now();
        if (!sim.step()) break;
        step_us.push_back(us_since(t0));
    }
    sim.finish();
    return step_us;
}

}  // namespace

int main(int argc, char** argv) {
    int n = 20, repeat = 3;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--repeat" && i + 1 < argc) repeat = std::atoi(argv[++i]);
        else n = std::atoi(a.c_str());
    }
    const std::string path = "/tmp/sdv_cosim_bench_" + std::to_string(::getpid()) + ".sdv";
    std::ofstream(path) << scenario(n, true);
    sdv::diag::SourceManager sm;
    sdv::diag::DiagnosticEngine diags(sm);
    auto plain = sdv::compiler::compile_source("plain.sdv", scenario(n, false), sm, diags);
    if (!plain.program) {
        std::fprintf(stderr, "cosim_bench: the plain scenario does not compile\n");
        return 1;
    }
    std::printf("%d SDVs + 1 external ego, 120 s at 30 Hz, one thread, best of %d runs by median\n", n, repeat);
    std::printf("%-26s %10s %10s %10s %12s\n", "run", "steps/s", "p50 us", "p99 us", "steps");
    std::vector<double> best_c, best_p;
    for (int r = 0; r < repeat; ++r) {
        auto c = run_capi(path);
        auto p = run_plain(*plain.program);
        if (best_c.empty() || pct(c, 0.5) < pct(best_c, 0.5)) best_c = c;
        if (best_p.empty() || pct(p, 0.5) < pct(best_p, 0.5)) best_p = p;
    }
    auto row = [](const char* name, const std::vector<double>& v) {
        double total = 0;
        for (double x : v) total += x;
        std::printf("%-26s %10.0f %10.1f %10.1f %12zu\n", name, static_cast<double>(v.size()) / (total * 1e-6), pct(v, 0.5), pct(v, 0.99), v.size());
    };
    row("without co-simulation", best_p);
    row("C API (in process)", best_c);
    std::printf("added per step (p50): %.1f us\n", pct(best_c, 0.5) - pct(best_p, 0.5));
    std::remove(path.c_str());
    return 0;
}
