// `sdv sweep` and `sdv search`: the campaign subcommands (docs/campaigns.md). Argument handling,
// progress on a terminal, and exit codes; the work is in runtime/campaign.
#include "cli/campaign.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <thread>

#include "runtime/campaign/search.h"
#include "runtime/campaign/slurm.h"
#include "runtime/campaign/sweep.h"
#include "runtime/campaign/variants.h"
#include "runtime/io/sweep_report.h"
#include "runtime/ir/bindings.h"

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
    // The scenario is compiled from its absolute path, with absolute import directories, as the
    // Slurm tasks compile it (sweep_on_slurm): the program's file names are part of the IR hash
    // that ties rows to their campaign, and they appear in the rows' error messages, so a resume
    // or merge from any directory, naming the file any way, meets the same campaign and writes
    // the same bytes.
    Common abs = c;
    for (auto& d : abs.import_dirs) d = absolute(d);
    Loaded l;
    if (const int e = load_scenario(absolute(a.file), a.scenario, abs, w, l); e != kOk) return e;
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
    if (outcome.damaged > 0) {
        const bool one = outcome.damaged == 1;
        std::cerr << "sdv: warning: " << outcome.damaged << (one ? " line of " : " lines of ") << o.dir << "/rows "
                  << (one ? "is not a row as sdv writes it; it was" : "are not rows as sdv writes them; they were")
                  << " skipped, and every variant without a row ran again (" << (one ? "" : "first: ")
                  << outcome.damage << ")\n";
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

namespace sdv::cli {
namespace {

std::string number_text(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

}  // namespace

int cmd_search(const SearchArgs& a, const Common& c, const WarningFlags& w) {
    Loaded l;
    if (const int e = load_scenario(a.file, a.scenario, c, w, l); e != kOk) return e;
    if (const int e = check_campaign(l, a.file); e != kOk) return e;
    const ir::Scenario& sc = l.program.scenarios[static_cast<size_t>(l.index)];
    if (a.minimize.empty() == a.maximize.empty()) {
        std::cerr << "sdv: error: give the metric to search for with --minimize or --maximize (one of them), "
                     "e.g. --minimize 'min_ttc(ego, v2)'\n";
        return kUsage;
    }
    campaign::SearchOptions o;
    o.maximize = !a.maximize.empty();
    std::string error;
    auto metric = campaign::parse_metric(sc, o.maximize ? a.maximize : a.minimize, error);
    if (!metric) {
        std::cerr << "sdv: error: " << error << "\n";
        return kUsage;
    }
    o.metric = *metric;
    o.budget = a.budget;
    o.seed = a.seed;
    const std::string dir = a.out.empty() ? "out/" + sc.name + "-search" : a.out;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) {
        std::cerr << "sdv: error: cannot create '" << dir << "': " << ec.message() << "\n";
        return kFailure;
    }
    ProgressBar bar("search " + sc.name);
    o.progress = [&](int runs, int budget, double) { bar.update(runs, budget, 0); };
    const auto result = campaign::search(l.program, l.index, o);
    bar.clear();
    if (!result.error.empty()) {
        std::cerr << "sdv: error: " << result.error << "\n";
        return kFailure;
    }
    // Every run, in order: what the optimiser tried.
    std::string csv = "run";
    for (const auto& p : sc.vary.params) csv += "," + (p.unit.empty() ? p.name : p.name + "[" + p.unit + "]");
    csv += ",\"" + o.metric.text + (o.metric.unit.empty() ? "" : "[" + o.metric.unit + "]") + "\",error\n";
    for (size_t i = 0; i < result.runs.size(); ++i) {
        const auto& r = result.runs[i];
        csv += std::to_string(i);
        for (double v : r.values) csv += "," + number_text(v);
        csv += "," + (std::isfinite(r.metric) ? number_text(r.metric) : std::string()) + ",";
        if (!r.error.empty()) {
            std::string q = r.error;
            for (auto& ch : q) ch = ch == '"' || ch == '\n' ? '\'' : ch;
            csv += "\"" + q + "\"";
        }
        csv += "\n";
    }
    if (!write_file(dir + "/search.csv", csv)) return kFailure;
    const auto& best = result.runs[result.best];
    if (!best.error.empty()) {
        std::cerr << "sdv: error: every run of the search failed; the first: " << result.runs.front().error << "\n";
        return kFailure;
    }
    const std::string values = campaign::describe(sc.vary, best.values);
    std::cout << "search " << sc.name << ": " << result.runs.size() << " runs, " << (o.maximize ? "maximum " : "minimum ")
              << o.metric.text << " = "
              << (std::isfinite(best.metric) ? number_text(best.metric) + (o.metric.unit.empty() ? "" : " " + o.metric.unit)
                                             : std::string("never measured"))
              << " at run " << result.best << "\n  " << values << "\n";
    // The worst case as a plain scenario, and its run with the outputs of `sdv run`.
    const bool is_sdv = a.file.size() > 4 && a.file.compare(a.file.size() - 4, 4, ".sdv") == 0;
    if (is_sdv) {
        std::vector<std::pair<std::string, std::string>> placed;
        for (size_t k = 0; k < sc.vary.params.size(); ++k) {
            const auto& p = sc.vary.params[k];
            const std::string v = p.integer ? std::to_string(std::llround(best.values[k])) : number_text(best.values[k]);
            placed.emplace_back(p.name, p.unit.empty() ? v : v + " " + p.unit);
        }
        const std::string comment = "The " + std::string(o.maximize ? "maximum" : "minimum") + " of " + o.metric.text +
                                    " found by `sdv search` (" + std::to_string(result.runs.size()) + " runs, seed " +
                                    std::to_string(o.seed) + "): " + values;
        auto text = compiler::concretize(a.file, l.text, sc.name, placed, comment, error);
        const std::string out = a.write.empty() ? dir + "/worst.sdv" : a.write;
        if (!text) {
            std::cerr << "sdv: warning: no concrete scenario written: " << error << "\n";
        } else if (write_file(out, *text)) {
            std::cout << "worst case written to " << out << "\n";
        }
    }
    ir::Program variant = l.program;
    const auto base = ir::scenario_number_values(l.program, l.index);
    if (auto e = ir::apply_variant(variant, l.index, base, best.values); !e.empty()) {
        std::cerr << "sdv: error: " << e << "\n";
        return kFailure;
    }
    std::string run_error;
    campaign::run_kept(variant, l.index, dir, 0, run_error);
    std::error_code rename_ec;
    fs::remove_all(dir + "/worst", rename_ec);
    fs::rename(dir + "/runs/0", dir + "/worst", rename_ec);
    fs::remove(dir + "/runs", rename_ec);
    if (!run_error.empty()) std::cerr << "sdv: warning: " << run_error << "\n";
    std::cout << "its run in " << dir << "/worst (sdv view " << dir << "/worst)\n";
    return kOk;
}

}  // namespace sdv::cli
