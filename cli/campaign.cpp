// `sdv sweep` and `sdv search`: the campaign subcommands (docs/campaigns.md). Argument handling,
// progress on a terminal, and exit codes; the work is in runtime/campaign.
#include "cli/campaign.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <thread>

#include "runtime/campaign/slurm.h"
#include "runtime/campaign/sweep.h"
#include "runtime/campaign/variants.h"
#include "runtime/io/sweep_report.h"

namespace sdv::cli {
namespace fs = std::filesystem;

namespace {

// A one-line progress bar on stderr when it is a terminal; nothing otherwise.
class ProgressBar {
public:
    explicit ProgressBar(std::string what) : what_(std::move(what)), tty_(isatty(STDERR_FILENO) != 0) {}
    ~ProgressBar() { clear(); }

    void update(int64_t done, int64_t total, int64_t failed) {
        if (!tty_ || total <= 0) return;
        const auto now = std::chrono::steady_clock::now();
        if (done < total && now - last_ < std::chrono::milliseconds(100)) return;
        last_ = now;
        if (first_done_ < 0) {
            first_done_ = done;
            start_ = now;
        }
        const double elapsed = std::chrono::duration<double>(now - start_).count();
        const double rate = elapsed > 0 ? static_cast<double>(done - first_done_) / elapsed : 0;
        constexpr int kWidth = 30;
        const int filled = static_cast<int>(kWidth * done / total);
        std::string bar(static_cast<size_t>(filled), '#');
        bar += std::string(static_cast<size_t>(kWidth - filled), '.');
        char eta[32] = "--:--";
        if (rate > 0) {
            const auto s = static_cast<long long>(static_cast<double>(total - done) / rate);
            std::snprintf(eta, sizeof eta, "%lld:%02lld", s / 60, s % 60);
        }
        std::fprintf(stderr, "\r\033[K%s [%s] %lld/%lld, %lld failed, %.0f/s, ETA %s", what_.c_str(), bar.c_str(),
                     static_cast<long long>(done), static_cast<long long>(total), static_cast<long long>(failed),
                     rate, eta);
        std::fflush(stderr);
        shown_ = true;
    }

    void clear() {
        if (shown_) std::fprintf(stderr, "\r\033[K");
        shown_ = false;
    }

private:
    std::string what_;
    bool tty_;
    bool shown_ = false;
    int64_t first_done_ = -1;
    std::chrono::steady_clock::time_point start_, last_;
};

bool parse_slice(const std::string& text, int& slice, int& slices) {
    const auto slash = text.find('/');
    if (slash == std::string::npos) return false;
    char* end = nullptr;
    const long a = std::strtol(text.c_str(), &end, 10);
    if (end != text.c_str() + slash) return false;
    const long b = std::strtol(text.c_str() + slash + 1, &end, 10);
    if (*end != '\0' || b < 1 || b > 100000 || a < 0 || a >= b) return false;
    slice = static_cast<int>(a);
    slices = static_cast<int>(b);
    return true;
}

std::string absolute(const std::string& p) {
    std::error_code ec;
    auto a = fs::absolute(p, ec);
    return ec ? p : a.lexically_normal().string();
}

std::string self_exe() {
    std::error_code ec;
    auto p = fs::read_symlink("/proc/self/exe", ec);
    return ec ? "sdv" : p.string();
}

// A campaign that can run: it has a vary block and no vehicle waits for a co-simulation client.
int check_campaign(const Loaded& l, const std::string& file) {
    const ir::Scenario& sc = l.program.scenarios[static_cast<size_t>(l.index)];
    if (sc.vary.empty()) {
        std::cerr << "sdv: error: scenario '" << sc.name << "' of '" << file
                  << "' has no vary block: nothing to sweep (add one, see docs/campaigns.md; `sdv run` runs the "
                     "scenario as written)\n";
        return kFailure;
    }
    for (const auto& v : sc.vehicles) {
        if (v.kind != ir::VehicleKind::external) continue;
        std::cerr << "sdv: error: vehicle '" << v.name << "' of scenario '" << sc.name
                  << "' is external; a campaign runs without a co-simulation client\n";
        return kUsage;
    }
    return kOk;
}

// results.csv, summary.json and the extras of a sweep whose rows are all in DIR.
int finish_sweep(const Loaded& l, const SweepArgs& a, const campaign::SweepOptions& o) {
    campaign::Results results;
    if (auto e = campaign::gather(l.program, l.index, o.dir, results); !e.empty()) {
        std::cerr << "sdv: error: " << e << "\n";
        return kFailure;
    }
    if (auto e = campaign::write_results(l.program, l.index, o, results); !e.empty()) {
        std::cerr << "sdv: error: " << e << "\n";
        return kFailure;
    }
    std::cout << campaign::sweep_report_text(l.program, l.index, results);
    if (!a.junit.empty()) {
        if (!write_file(a.junit, campaign::sweep_junit(l.program, l.index, results))) return kFailure;
        std::cout << "JUnit report in " << a.junit << "\n";
    }
    if (a.report) {
        std::string error;
        const std::string html = io::sweep_report(o.dir, error);
        if (!error.empty()) {
            std::cerr << "sdv: error: " << error << "\n";
            return kFailure;
        }
        if (!write_file(o.dir + "/report.html", html)) return kFailure;
        std::cout << "report in " << o.dir << "/report.html\n";
    }
    std::cout << "results in " << o.dir << "/results.csv\n";
    bool all_passed = true;
    for (const auto& r : results.rows) all_passed = all_passed && r.passed;
    return all_passed ? kOk : kFailure;
}

int sweep_on_slurm(const Loaded& l, const SweepArgs& a, const campaign::SweepOptions& o, const Common& c) {
    const ir::Scenario& sc = l.program.scenarios[static_cast<size_t>(l.index)];
    campaign::SlurmJob job;
    job.work_dir = absolute(o.dir);
    job.command = {self_exe(), "sweep", absolute(a.file), "-o", job.work_dir, "--jobs", "1", "--scenario", sc.name};
    for (const auto& d : c.import_dirs) {
        job.command.push_back("-I");
        job.command.push_back(absolute(d));
    }
    job.array_tasks = a.array_tasks;
    job.partition = a.partition;
    job.job_name = "sdv-" + sc.name;
    if (a.slurm_script_only) {
        const std::string path = job.work_dir + "/slurm/sweep.sbatch";
        std::error_code ec;
        fs::create_directories(job.work_dir + "/slurm", ec);
        if (!write_file(path, campaign::slurm_script(job))) return kFailure;
        std::cout << "wrote " << path << "\nsubmit it with `sbatch " << path << "`; once every task has finished, "
                  << "`sdv sweep " << a.file << " -o " << o.dir << " --resume` merges the slices\n";
        return kOk;
    }
    ProgressBar bar("slurm " + sc.name + " (tasks)");
    const auto outcome = campaign::slurm_run(job, [&](int done, int total) { bar.update(done, total, 0); });
    bar.clear();
    if (!outcome.error.empty()) {
        std::cerr << "sdv: error: " << outcome.error << "\n";
        return kFailure;
    }
    std::cout << "slurm job " << outcome.job_id << ": " << a.array_tasks << " tasks finished\n";
    return finish_sweep(l, a, o);
}

}  // namespace

int cmd_sweep(const SweepArgs& a, const Common& c, const WarningFlags& w) {
    Loaded l;
    if (const int e = load_scenario(a.file, a.scenario, c, w, l); e != kOk) return e;
    if (const int e = check_campaign(l, a.file); e != kOk) return e;
    const ir::Scenario& sc = l.program.scenarios[static_cast<size_t>(l.index)];
    campaign::SweepOptions o;
    o.dir = a.out.empty() ? "out/" + sc.name + "-sweep" : a.out;
    o.file = a.file;
    o.jobs = a.jobs > 0 ? a.jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    o.resume = a.resume;
    o.keep = a.keep == "runs" ? campaign::Keep::runs : a.keep == "failed" ? campaign::Keep::failed : campaign::Keep::none;
    const bool sliced = !a.slice.empty();
    if (sliced && !parse_slice(a.slice, o.slice, o.slices)) {
        std::cerr << "sdv: error: --slice takes I/K with 0 <= I < K, e.g. --slice 0/4\n";
        return kUsage;
    }
    if (sliced && a.slurm) {
        std::cerr << "sdv: error: --slice runs one slice of a sweep; --slurm submits them all: use one of them\n";
        return kUsage;
    }
    std::error_code ec;
    fs::create_directories(o.dir, ec);
    if (ec) {
        std::cerr << "sdv: error: cannot create '" << o.dir << "': " << ec.message() << "\n";
        return kFailure;
    }
    // A fresh sweep starts from nothing; a slice (a Slurm task) always continues its rows.
    if (!a.resume && !sliced) {
        if (auto e = campaign::clear_sweep(o.dir); !e.empty()) {
            std::cerr << "sdv: error: " << e << "\n";
            return kFailure;
        }
    }
    if (a.slurm) return sweep_on_slurm(l, a, o, c);
    const int64_t total = campaign::VariantSpace(sc.vary).size();
    ProgressBar bar(sc.name);
    o.progress = [&](int64_t done, int64_t n, int64_t failed) { bar.update(done, n, failed); };
    const auto outcome = campaign::run_sweep(l.program, l.index, o);
    bar.clear();
    if (!outcome.error.empty()) {
        std::cerr << "sdv: error: " << outcome.error << "\n";
        return kFailure;
    }
    {
        const double rate = outcome.wall_s > 0 ? static_cast<double>(outcome.ran) / outcome.wall_s : 0;
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "{\n  \"jobs\": %d,\n  \"slice\": \"%d/%d\",\n  \"ran\": %lld,\n  \"skipped\": %lld,\n"
                      "  \"wall_s\": %.3f,\n  \"variants_per_second\": %.1f\n}\n",
                      o.jobs, o.slice, o.slices, static_cast<long long>(outcome.ran),
                      static_cast<long long>(outcome.skipped), outcome.wall_s, rate);
        const std::string name = sliced ? "/rows/timing-" + std::to_string(o.slice) + ".json" : "/timing.json";
        write_file(o.dir + name, buf);
    }
    if (sliced) {
        std::cout << sc.name << " slice " << o.slice << "/" << o.slices << ": ran " << outcome.ran << " variants"
                  << (outcome.skipped ? ", " + std::to_string(outcome.skipped) + " were already done" : "") << "\n";
        return kOk;
    }
    if (outcome.skipped > 0) std::cout << "resumed: " << outcome.skipped << " of " << total << " variants were done\n";
    return finish_sweep(l, a, o);
}

}  // namespace sdv::cli
