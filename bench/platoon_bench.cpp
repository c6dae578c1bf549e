// The paper's scalability scenario (SPEC §9): a platoon of N SDVs on one lane for 2 simulated
// minutes, without and with a static obstacle that they steer around (into a free second lane).
// Reports real-time factor, vehicle updates/s, plans/s, candidates/s, tick and plan time
// percentiles, the paper's TRC / TPRC (share of ticks within 33 ms, of plans within 333 ms),
// peak memory, and whether any collision happened.
//   build/bench/bench/platoon_bench [N...] [--threads T]
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "compiler/diag/render.h"
#include "compiler/sema/compile.h"
#include "runtime/sim/simulation.h"

namespace {

// Up to 3,000 vehicles form one platoon in lane 1 (lane 2 free); more fill `loaded` lanes side by
// side (at most 3,000 each: a straight is at most 100 km) with one free lane on the left.
std::string platoon(int n, bool obstacle) {
    const int loaded = n <= 3000 ? 1 : (n + 2999) / 3000;
    const int per_lane = (n + loaded - 1) / loaded;
    std::string s = "import \"std/drive.sdv\"\nimport \"std/lane_change.sdv\"\n";
    s += "road r {\n lanes " + std::to_string(loaded + 1) + " forward\n speed_limit 60 km/h\n straight " +
         std::to_string(1600 + 25 * per_lane) + " m\n}\n";
    s += "tree passer() {\n fallback {\n  sequence {\n   condition lane_occupied(lane = current, distance = 40 m)\n"
         "   condition vehicle_stopped(vehicle = front)\n   subtree std.lane_change(lane = left, gap = 15 m)\n  }\n"
         "  subtree std.drive(speed = 12 m/s)\n }\n}\n";
    s += "scenario platoon {\n road r\n timeout 120 s\n";
    if (obstacle) s += " object block { start lane 1 at " + std::to_string(25 * per_lane + 300) + " m }\n";
    for (int i = 0; i < n; ++i) {
        s += " vehicle v" + std::to_string(i) + ": sdv { start lane " + std::to_string(1 + i % loaded) + " at " +
             std::to_string(10 + 25 * (i / loaded)) + " m speed 12 m/s tree passer() }\n";
    }
    s += " expect no_collision()\n}\n";
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> sizes;
    int threads = 1;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
        else sizes.push_back(std::atoi(a.c_str()));
    }
    if (sizes.empty()) sizes = {10, 20, 50, 100};
    std::printf("| N | obstacle | threads | RTF | vehicle-updates/s | plans/s | candidates/s | tick p50 / p99 (µs) | "
                "plan p50 / p99 (µs) | TRC | TPRC | peak RSS (MB) | collisions |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int n : sizes) {
        for (bool obstacle : {false, true}) {
            sdv::diag::SourceManager sm;
            sdv::diag::DiagnosticEngine diags;
            auto comp = sdv::compiler::compile_source("platoon.sdv", platoon(n, obstacle), sm, diags);
            if (!comp.program) {
                std::fprintf(stderr, "%s", sdv::diag::render_all_text(diags.sorted(), sm).c_str());
                return 1;
            }
            sdv::sim::RunOptions opt;
            opt.threads = threads;
            const auto r = sdv::sim::simulate(*comp.program, 0, opt);
            if (!r.error.empty()) {
                std::fprintf(stderr, "%s\n", r.error.c_str());
                return 1;
            }
            int collisions = 0;
            for (const auto& e : r.events) collisions += e.kind == "collision";
            rusage ru{};
            getrusage(RUSAGE_SELF, &ru);
            const double wall = r.timing.wall_s;
            const double updates = static_cast<double>(r.ticks + 1) * (n + (obstacle ? 1 : 0));
            std::printf("| %d | %s | %d | %.3g× | %.3g | %.3g | %.3g | %.0f / %.0f | %.0f / %.0f | %.4f | %.4f | %.0f | %d |\n", n,
                        obstacle ? "yes" : "no", threads, r.duration / wall, updates / wall,
                        static_cast<double>(r.timing.plan_us.count()) / wall, static_cast<double>(r.timing.candidates) / wall,
                        r.timing.tick_us.percentile(0.5), r.timing.tick_us.percentile(0.99), r.timing.plan_us.percentile(0.5),
                        r.timing.plan_us.percentile(0.99), r.timing.tick_us.share_below(33333), r.timing.plan_us.share_below(333333),
                        static_cast<double>(ru.ru_maxrss) / 1024.0, collisions);
            std::fflush(stdout);
        }
    }
    return 0;
}
