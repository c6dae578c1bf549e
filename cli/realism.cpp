// `sdv replay`, `sdv calibrate` and the conversion of recordings (docs/realism.md).
#include "cli/realism.h"

#include <nlopt.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "compiler/recorded/replay.h"
#include "compiler/sema/std_trees.h"
#include "runtime/catalog/units.h"
#include "runtime/io/outputs.h"
#include "runtime/io/recorder.h"
#include "runtime/ir/ir_io.h"
#include "runtime/realism/metrics.h"
#include "runtime/realism/recording.h"
#include "runtime/road/commonroad_reader.h"
#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"

namespace sdv::cli {
namespace fs = std::filesystem;
namespace {

// What a replay needs of its recording: the tracks and the prepared road network.
struct Source {
    realism::Recording rec;
    road::RoadNetwork net;
};

bool load_source(const std::string& file, const std::string& map, Source& out) {
    out.rec = realism::read_recording(file, map);
    for (const auto& w : out.rec.warnings) std::cerr << "sdv: warning: " << w << "\n";
    if (!out.rec.errors.empty()) {
        for (const auto& e : out.rec.errors) std::cerr << "sdv: error: " << e << "\n";
        return false;
    }
    std::optional<road::GeoOrigin> origin;
    if (out.rec.format == "interaction") origin = road::GeoOrigin{0, 0, 0};
    auto net = road::load_map(out.rec.map_path, origin);
    if (!net.errors.empty()) {
        std::cerr << "sdv: error: map '" << out.rec.map_path << "': " << net.errors.front() << "\n";
        return false;
    }
    out.net = std::move(*net.network);
    out.net.prepare();
    return true;
}

// The tracks named by a --sdv list ("all": every vehicle; pedestrians are never replaced).
bool select_tracks(const realism::Recording& rec, const std::string& list, std::vector<std::string>& ids) {
    if (list == "all") {
        for (const auto& t : rec.tracks)
            if (!t.pedestrian() && t.states.size() > 1) ids.push_back(t.id);
        return true;
    }
    std::stringstream ss(list);
    std::string id;
    while (std::getline(ss, id, ',')) {
        if (id.empty()) continue;
        if (rec.find(id) == nullptr) {
            std::string known;
            size_t n = 0;
            for (const auto& t : rec.tracks)
                if (n++ < 10) known += (known.empty() ? "" : ", ") + t.id;
            std::cerr << "sdv: error: the recording has no agent '" << id << "' (its agents: " << known
                      << (rec.tracks.size() > 10 ? ", ..." : "") << ")\n";
            return false;
        }
        ids.push_back(id);
    }
    if (ids.empty()) std::cerr << "sdv: error: --sdv names no agent\n";
    return !ids.empty();
}

// Records the run's outputs and the SDV's states at every tick (in the recording's time).
class Sampler final : public sim::RunObserver {
public:
    Sampler(io::Recorder* recorder, std::string name, double t0) : recorder_(recorder), name_(std::move(name)), t0_(t0) {}
    void start(const sim::World& w) override {
        if (recorder_ != nullptr) recorder_->start(w);
        for (const auto& a : w.agents)
            if (a.v->name == name_) index_ = a.index;
        sample(w, 0);
    }
    void tick(const sim::World& w, int tick, double time) override {
        if (recorder_ != nullptr) recorder_->tick(w, tick, time);
        sample(w, time);
    }
    void plan(const sim::World& w, const sim::Agent& a) override {
        if (recorder_ != nullptr) recorder_->plan(w, a);
    }
    std::vector<realism::State> states;

private:
    void sample(const sim::World& w, double time) {
        if (index_ < 0) return;
        const sim::Agent& a = w.agents[static_cast<size_t>(index_)];
        if (!a.active) return;
        states.push_back({t0_ + time, a.x, a.y, a.yaw, a.speed});
    }
    io::Recorder* recorder_;
    std::string name_;
    double t0_;
    int index_ = -1;
};

// One replaced vehicle.
struct Replayed {
    std::string id, name;
    std::optional<realism::Comparison> cmp;
    std::string outcome;  // completed | collision | left road | error: ...
    double duration = 0;  // of the recorded span
};

struct Job {
    std::string id;
    compiler::recorded::ReplaySource src;
    std::optional<ir::Program> program;
    std::string error;
};

// Generates and compiles the replay of each track (on this thread: the compiler is not shared
// between threads).
std::vector<Job> prepare(const Source& s, const std::vector<std::string>& ids, const compiler::recorded::ReplaySpec& base,
                         const std::string& runs_dir, const Common& c) {
    std::vector<Job> jobs;
    for (const auto& id : ids) {
        Job j;
        j.id = id;
        auto spec = base;
        spec.sdv = id;
        j.src = compiler::recorded::replay_source(s.rec, s.net, spec);
        if (!j.src.error.empty()) {
            j.error = j.src.error;
            jobs.push_back(std::move(j));
            continue;
        }
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        const std::string display =
            runs_dir.empty() ? j.src.sdv_name + ".sdv" : (fs::path(runs_dir) / j.src.sdv_name / "scenario.sdv").string();
        if (!runs_dir.empty()) {
            std::error_code ec;
            fs::create_directories(fs::path(display).parent_path(), ec);
            std::ofstream(display, std::ios::binary) << j.src.text;
        }
        auto comp = compiler::compile_source(display, j.src.text, sm, diags, compiler::CompileOptions{c.import_dirs});
        if (!comp.program) {
            std::ostringstream msg;
            for (const auto& d : diags.sorted()) {
                if (d.severity != diag::Severity::error) continue;
                msg << display << ": [" << d.code << "] " << d.message;
                break;
            }
            j.error = "the replay does not compile: " + msg.str();
        } else {
            j.program = std::move(comp.program);
        }
        jobs.push_back(std::move(j));
    }
    return jobs;
}

Replayed run_job(const Source& s, const Job& j, const std::string& dir) {
    Replayed out;
    out.id = j.id;
    out.name = j.src.sdv_name;
    const realism::Track& tr = *s.rec.find(j.id);
    out.duration = tr.end() - tr.start();
    if (!j.program) {
        out.outcome = "error: " + j.error;
        return out;
    }
    std::optional<io::Recorder> recorder;
    if (!dir.empty()) {
        recorder.emplace();
        if (auto e = recorder->open(dir, false); !e.empty()) {
            out.outcome = "error: " + e;
            return out;
        }
    }
    Sampler sampler(recorder ? &*recorder : nullptr, j.src.sdv_name, j.src.start);
    sim::RunOptions opts;
    opts.threads = 1;
    const sim::RunResult r = sim::simulate(*j.program, 0, opts, &sampler);
    if (!r.error.empty()) {
        if (recorder) recorder->discard();
        out.outcome = "error: " + r.error;
        return out;
    }
    if (recorder) {
        recorder->commit();
        const io::Recording rec = recorder->take();
        io::RunInfo info;
        info.ir_hash = ir::program_hash(*j.program);
        info.seed = j.program->scenarios[0].seed;
        io::write_outputs(dir, *j.program, 0, r, rec, info);
        std::ofstream rc(dir + "/recorded.csv", std::ios::binary);
        rc << "vehicle,t,x,y,heading,speed\n";
        char buf[160];
        for (const auto& st : tr.states) {
            std::snprintf(buf, sizeof buf, "%s,%.3f,%.3f,%.3f,%.4f,%.3f\n", out.name.c_str(), st.t - j.src.start, st.x, st.y,
                          st.heading, st.speed);
            rc << buf;
        }
    }
    out.outcome = "completed";
    int sdv = -1;
    const auto& vehicles = j.program->scenarios[0].vehicles;
    for (size_t i = 0; i < vehicles.size(); ++i)
        if (vehicles[i].name == out.name) sdv = static_cast<int>(i);
    for (const auto& e : r.events) {
        if (std::find(e.vehicles.begin(), e.vehicles.end(), sdv) == e.vehicles.end()) continue;
        if (e.kind == "collision" && out.outcome == "completed") out.outcome = "collision";
        if (e.kind == "left_road" && out.outcome == "completed") out.outcome = "left road";
    }
    out.cmp = realism::compare(sampler.states, tr.states);
    return out;
}

// Runs the jobs on `threads` threads; results in job order.
std::vector<Replayed> run_jobs(const Source& s, const std::vector<Job>& jobs, const std::string& runs_dir, int threads) {
    std::vector<Replayed> out(jobs.size());
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t i = next++; i < jobs.size(); i = next++) {
            const std::string dir = runs_dir.empty() ? "" : (fs::path(runs_dir) / jobs[i].src.sdv_name).string();
            out[i] = run_job(s, jobs[i], dir);
        }
    };
    std::vector<std::thread> pool;
    const int n = std::max(1, std::min<int>(threads, static_cast<int>(jobs.size())));
    for (int k = 1; k < n; ++k) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    return out;
}

int jobs_of(int j) { return j > 0 ? j : static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }

std::string fixed(double v, int digits = 3) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

std::string realism_csv(const std::vector<Replayed>& rows) {
    std::string csv = "vehicle,sted_m,max_distance_m,final_displacement_m,speed_rmse_mps,duration_s,outcome\n";
    for (const auto& r : rows) {
        csv += r.id + ",";
        if (r.cmp) {
            csv += fixed(r.cmp->sted) + "," + fixed(r.cmp->max_distance) + "," + fixed(r.cmp->final_displacement) + "," +
                   fixed(r.cmp->speed_rmse) + ",";
        } else {
            csv += ",,,,";
        }
        std::string outcome = r.outcome;
        std::replace(outcome.begin(), outcome.end(), ',', ';');
        std::replace(outcome.begin(), outcome.end(), '\n', ' ');
        csv += fixed(r.duration, 1) + ",\"" + outcome + "\"\n";
    }
    return csv;
}

nlohmann::ordered_json distribution_json(const realism::Distribution& d) {
    nlohmann::ordered_json j;
    j["n"] = d.n;
    j["mean"] = std::round(d.mean * 1000) / 1000;
    j["p10"] = std::round(d.p10 * 1000) / 1000;
    j["median"] = std::round(d.median * 1000) / 1000;
    j["p90"] = std::round(d.p90 * 1000) / 1000;
    j["max"] = std::round(d.max * 1000) / 1000;
    return j;
}

std::vector<double> steds(const std::vector<Replayed>& rows) {
    std::vector<double> v;
    for (const auto& r : rows)
        if (r.cmp) v.push_back(r.cmp->sted);
    return v;
}

// The objective of a calibration: a replay that could not run counts as far off.
constexpr double kFailedSted = 50.0;

double mean_sted(const std::vector<Replayed>& rows) {
    if (rows.empty()) return 0;
    double sum = 0;
    for (const auto& r : rows) sum += r.cmp ? std::min(r.cmp->sted, kFailedSted) : kFailedSted;
    return sum / static_cast<double>(rows.size());
}

bool write_text(const std::string& path, const std::string& text) {
    std::ofstream o(path, std::ios::binary);
    o << text;
    if (!o) std::cerr << "sdv: error: cannot write '" << path << "'\n";
    return static_cast<bool>(o);
}

compiler::recorded::ReplaySpec spec_of(const std::string& tree, const std::vector<std::string>& imports) {
    compiler::recorded::ReplaySpec spec;
    spec.tree = tree;
    for (const auto& imp : imports) spec.imports.push_back(fs::absolute(imp).lexically_normal().string());
    return spec;
}

}  // namespace

bool is_recording_path(const std::string& file) {
    const std::string ext = fs::path(file).extension().string();
    if (ext == ".csv") return true;
    if (ext != ".xml") return false;
    std::ifstream in(file, std::ios::binary);
    std::string head(4096, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<size_t>(in.gcount()));
    return road::is_commonroad(head);
}

int cmd_replay(const ReplayArgs& a, const Common& c) {
    Source s;
    if (!load_source(a.recording, a.map, s)) return kFailure;
    std::vector<std::string> ids;
    if (!select_tracks(s.rec, a.sdv, ids)) return kUsage;
    const std::string out = a.out.empty() ? "out/" + fs::path(a.recording).stem().string() + "-replay" : a.out;
    std::error_code ec;
    fs::create_directories(out + "/runs", ec);
    if (ec) {
        std::cerr << "sdv: error: cannot create '" << out << "/runs': " << ec.message() << "\n";
        return kFailure;
    }
    const auto wall0 = std::chrono::steady_clock::now();
    const auto jobs = prepare(s, ids, spec_of(a.tree, a.imports), out + "/runs", c);
    const auto rows = run_jobs(s, jobs, out + "/runs", jobs_of(a.jobs));
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    if (!write_text(out + "/realism.csv", realism_csv(rows))) return kFailure;
    const auto dist = realism::distribution(steds(rows));
    nlohmann::ordered_json j;
    j["recording"] = fs::path(a.recording).filename().string();
    j["format"] = s.rec.format;
    j["tree"] = a.tree.empty() ? "std.drive(speed = the start lane's speed limit)" : a.tree;
    j["vehicles"] = rows.size();
    size_t failed = 0;
    std::map<std::string, int> outcomes;
    for (const auto& r : rows) {
        ++outcomes[r.outcome.rfind("error", 0) == 0 ? "error" : r.outcome];
        if (!r.cmp) ++failed;
    }
    j["outcomes"] = outcomes;
    j["sted_m"] = distribution_json(dist);
    if (!write_text(out + "/realism.json", j.dump(2) + "\n")) return kFailure;
    std::cout << "replayed " << rows.size() << " vehicle" << (rows.size() == 1 ? "" : "s") << " of " << a.recording << ": STED mean "
              << fixed(dist.mean, 2) << " m, median " << fixed(dist.median, 2) << " m, p90 " << fixed(dist.p90, 2) << " m";
    if (failed > 0) std::cout << " (" << failed << " not compared)";
    std::cout << "; " << fixed(wall > 0 ? static_cast<double>(rows.size()) / wall : 0, 1) << " vehicles/s\n";
    for (const auto& r : rows)
        if (r.outcome.rfind("error", 0) == 0) std::cout << "  " << r.id << ": " << r.outcome << "\n";
    std::cout << "outputs in " << out << " (realism.csv, realism.json, runs/<vehicle>)\n";
    return kOk;
}

namespace {

struct FitParam {
    std::string name;
    catalog::Dim dim = catalog::Dim::none;
    std::string unit;  // as written in the tree call
    double lo = 0, hi = 1, start = 0;
};

// Bounds of a parameter by its type, when the user gives none.
bool default_bounds(catalog::Dim d, double& lo, double& hi) {
    switch (d) {
        case catalog::Dim::speed: lo = 1; hi = 40; return true;
        case catalog::Dim::time: lo = 0.2; hi = 5; return true;
        case catalog::Dim::length: lo = 1; hi = 200; return true;
        case catalog::Dim::accel: lo = 0.3; hi = 8; return true;
        default: return false;
    }
}

// A default as written ("14 m/s", "2 s", "50 km/h") in SI.
std::optional<double> si_value(const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str()) return std::nullopt;
    std::string unit(end);
    unit.erase(std::remove(unit.begin(), unit.end(), ' '), unit.end());
    if (unit.empty()) return v;
    if (auto u = catalog::find_unit(unit)) return v * u->to_si;
    return std::nullopt;
}

// The parameters of the tree being fitted: a standard tree, or one of the imported files'.
bool tree_params(const std::string& call, const std::vector<std::string>& imports, const Common& c,
                 std::vector<std::pair<std::string, std::pair<std::string, std::string>>>& out, std::string& error) {
    std::string name = call.substr(0, call.find('('));
    name.erase(std::remove(name.begin(), name.end(), ' '), name.end());
    for (const auto& t : compiler::std_trees()) {
        if (t.name != name) continue;
        for (const auto& p : t.params) out.push_back({p.name, {p.type, p.def}});
        return true;
    }
    for (const auto& file : imports) {
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        auto comp = compiler::compile_file(file, sm, diags, compiler::CompileOptions{c.import_dirs});
        for (const auto& f : comp.files) {
            if (!f) continue;
            for (const auto& t : f->trees) {
                if (t.name.text != name && name.substr(name.rfind('.') + 1) != t.name.text) continue;
                for (const auto& p : t.params) {
                    std::string def;
                    if (p.def && p.def->lo.kind == compiler::ast::Primary::Kind::quantity)
                        def = p.def->lo.quantity.text + (p.def->lo.quantity.unit.empty() ? "" : " " + p.def->lo.quantity.unit);
                    out.push_back({p.name.text, {p.type.text, def}});
                }
                return true;
            }
        }
    }
    error = "no tree '" + name + "' among the standard trees" + (imports.empty() ? "" : " and the --import files");
    return false;
}

catalog::Dim dim_of(const std::string& type) {
    if (type == "speed") return catalog::Dim::speed;
    if (type == "time") return catalog::Dim::time;
    if (type == "length") return catalog::Dim::length;
    if (type == "acceleration" || type == "accel") return catalog::Dim::accel;
    return catalog::Dim::none;
}

std::string unit_of(catalog::Dim d) {
    switch (d) {
        case catalog::Dim::speed: return "m/s";
        case catalog::Dim::time: return "s";
        case catalog::Dim::length: return "m";
        case catalog::Dim::accel: return "m/s^2";
        default: return "";
    }
}

// A reproducible permutation (Fisher-Yates over splitmix64), the same on every platform.
std::vector<std::string> shuffled(std::vector<std::string> v, uint64_t seed) {
    uint64_t state = seed;
    auto next = [&state] {
        uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    };
    for (size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[next() % i]);
    return v;
}

struct Fit {
    const Source* source = nullptr;
    const Common* common = nullptr;
    compiler::recorded::ReplaySpec base;
    std::vector<FitParam> params;
    std::vector<std::string> training;
    int threads = 1;
    int evaluations = 0;
    std::string log;  // calibration.csv rows
    double best = INFINITY;
    std::vector<double> best_x;

    compiler::recorded::ReplaySpec spec(const std::vector<double>& x) const {
        auto s = base;
        for (size_t i = 0; i < params.size(); ++i) s.params.push_back({params[i].name, fixed(x[i], 4) + " " + params[i].unit});
        return s;
    }
    std::vector<Replayed> replay(const std::vector<std::string>& ids, const std::vector<double>& x) const {
        const auto jobs = prepare(*source, ids, spec(x), "", *common);
        return run_jobs(*source, jobs, "", threads);
    }
    static double thunk(unsigned n, const double* u, double*, void* data) {
        auto* f = static_cast<Fit*>(data);
        std::vector<double> x(n);
        for (unsigned i = 0; i < n; ++i) x[i] = f->params[i].lo + u[i] * (f->params[i].hi - f->params[i].lo);
        const double v = mean_sted(f->replay(f->training, x));
        ++f->evaluations;
        f->log += std::to_string(f->evaluations);
        for (double xi : x) f->log += "," + fixed(xi, 4);
        f->log += "," + fixed(v, 4) + "\n";
        if (v < f->best) {
            f->best = v;
            f->best_x = x;
        }
        return v;
    }
};

}  // namespace

int cmd_calibrate(const CalibrateArgs& a, const Common& c) {
    if (!(a.split > 0 && a.split <= 1)) {
        std::cerr << "sdv: error: --split must be in (0, 1] (the share of vehicles used for training)\n";
        return kUsage;
    }
    if (a.budget < 2 || a.budget > 100000) {
        std::cerr << "sdv: error: --budget must be between 2 and 100000 evaluations\n";
        return kUsage;
    }
    Source s;
    if (!load_source(a.recording, a.map, s)) return kFailure;
    std::vector<std::string> ids;
    if (!select_tracks(s.rec, a.sdv, ids)) return kUsage;
    const std::string tree = a.tree.empty() ? "std.drive()" : a.tree;
    std::vector<std::pair<std::string, std::pair<std::string, std::string>>> declared;
    std::string error;
    if (!tree_params(tree, a.imports, c, declared, error)) {
        std::cerr << "sdv: error: " << error << "\n";
        return kUsage;
    }
    // --params: NAME or NAME=LO..HI, in the parameter's own unit (m/s, s, m, m/s^2).
    Fit fit;
    {
        std::stringstream ss(a.params);
        std::string item;
        while (std::getline(ss, item, ',')) {
            if (item.empty()) continue;
            FitParam p;
            p.name = item.substr(0, item.find('='));
            auto it = std::find_if(declared.begin(), declared.end(), [&](const auto& d) { return d.first == p.name; });
            if (it == declared.end()) {
                std::string names;
                for (const auto& d : declared) names += (names.empty() ? "" : ", ") + d.first;
                std::cerr << "sdv: error: tree '" << tree.substr(0, tree.find('(')) << "' has no parameter '" << p.name
                          << "' (its parameters: " << (names.empty() ? "none" : names) << ")\n";
                return kUsage;
            }
            p.dim = dim_of(it->second.first);
            p.unit = unit_of(p.dim);
            const bool bounded = default_bounds(p.dim, p.lo, p.hi);
            if (item.find('=') != std::string::npos) {
                const std::string range = item.substr(item.find('=') + 1);
                const size_t dots = range.find("..");
                char* e1 = nullptr;
                char* e2 = nullptr;
                const std::string lo = range.substr(0, dots), hi = dots == std::string::npos ? "" : range.substr(dots + 2);
                p.lo = std::strtod(lo.c_str(), &e1);
                p.hi = std::strtod(hi.c_str(), &e2);
                if (dots == std::string::npos || e1 == lo.c_str() || e2 == hi.c_str() || !(p.lo < p.hi)) {
                    std::cerr << "sdv: error: --params " << item << ": write NAME=LO..HI with LO < HI (in " << (p.unit.empty() ? "its unit" : p.unit)
                              << ")\n";
                    return kUsage;
                }
            } else if (!bounded) {
                std::cerr << "sdv: error: parameter '" << p.name << "' (" << it->second.first
                          << ") has no default range: give one, e.g. --params " << p.name << "=0..1\n";
                return kUsage;
            }
            const auto def = si_value(it->second.second);
            p.start = std::clamp(def.value_or(0.5 * (p.lo + p.hi)), p.lo, p.hi);
            fit.params.push_back(p);
        }
    }
    if (fit.params.empty()) {
        std::cerr << "sdv: error: --params names no parameter (e.g. --params time_gap,speed)\n";
        return kUsage;
    }
    const auto order = shuffled(ids, a.seed);
    const size_t n_train = std::clamp<size_t>(static_cast<size_t>(std::llround(a.split * static_cast<double>(order.size()))), 1, order.size());
    fit.training.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(n_train));
    std::vector<std::string> held(order.begin() + static_cast<std::ptrdiff_t>(n_train), order.end());
    std::sort(fit.training.begin(), fit.training.end());
    std::sort(held.begin(), held.end());
    fit.source = &s;
    fit.common = &c;
    fit.base = spec_of(a.tree, a.imports);
    fit.threads = jobs_of(a.jobs);
    const std::string out = a.out.empty() ? "out/" + fs::path(a.recording).stem().string() + "-calibrate" : a.out;
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) {
        std::cerr << "sdv: error: cannot create '" << out << "': " << ec.message() << "\n";
        return kFailure;
    }
    // Before: the replay's own defaults (the tree as given, no parameter set).
    auto before_spec = fit.base;
    const auto before_jobs_train = prepare(s, fit.training, before_spec, "", c);
    const double train_before = mean_sted(run_jobs(s, before_jobs_train, "", fit.threads));
    const double held_before = held.empty() ? 0 : mean_sted(run_jobs(s, prepare(s, held, before_spec, "", c), "", fit.threads));
    // The fit, in the unit cube: a subplex search from the defaults.
    const unsigned n = static_cast<unsigned>(fit.params.size());
    std::vector<double> u(n), lo(n, 0.0), hi(n, 1.0), step(n, 0.25);
    for (unsigned i = 0; i < n; ++i) u[i] = (fit.params[i].start - fit.params[i].lo) / (fit.params[i].hi - fit.params[i].lo);
    nlopt_srand(static_cast<unsigned long>(a.seed));
    nlopt_opt opt = nlopt_create(NLOPT_LN_SBPLX, n);
    nlopt_set_lower_bounds(opt, lo.data());
    nlopt_set_upper_bounds(opt, hi.data());
    nlopt_set_min_objective(opt, &Fit::thunk, &fit);
    nlopt_set_maxeval(opt, a.budget);
    nlopt_set_initial_step(opt, step.data());
    nlopt_set_xtol_abs1(opt, 1e-3);
    double fmin = 0;
    nlopt_optimize(opt, u.data(), &fmin);
    nlopt_destroy(opt);
    const std::vector<double> x = fit.best_x;
    const double train_after = fit.best;
    const double held_after = held.empty() ? 0 : mean_sted(fit.replay(held, x));
    // Outputs: calibration.json, calibration.csv (every evaluation), calibrated.sdv.
    nlohmann::ordered_json j;
    j["recording"] = fs::path(a.recording).filename().string();
    j["tree"] = tree;
    j["seed"] = a.seed;
    j["split"] = a.split;
    j["evaluations"] = fit.evaluations;
    auto round3 = [](double v) { return std::round(v * 1000) / 1000; };
    for (size_t i = 0; i < fit.params.size(); ++i) {
        const auto& p = fit.params[i];
        nlohmann::ordered_json pj;
        pj["name"] = p.name;
        pj["unit"] = p.unit;
        pj["lo"] = p.lo;
        pj["hi"] = p.hi;
        pj["start"] = round3(p.start);
        pj["fitted"] = round3(x[i]);
        j["params"].push_back(pj);
    }
    j["training"] = {{"vehicles", fit.training}, {"sted_before_m", round3(train_before)}, {"sted_after_m", round3(train_after)}};
    j["held_out"] = {{"vehicles", held},
                     {"sted_before_m", held.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(round3(held_before))},
                     {"sted_after_m", held.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(round3(held_after))}};
    if (!write_text(out + "/calibration.json", j.dump(2) + "\n")) return kFailure;
    std::string header = "evaluation";
    for (const auto& p : fit.params) header += "," + p.name;
    if (!write_text(out + "/calibration.csv", header + ",mean_sted_m\n" + fit.log)) return kFailure;
    // The fitted values as the defaults of a tree that calls the fitted one.
    const std::string call = tree.substr(0, tree.find('('));
    std::string sdv = "# Calibrated on " + fs::path(a.recording).filename().string() + " by sdv calibrate (seed " + std::to_string(a.seed) +
                      "): mean STED on " + std::to_string(fit.training.size()) + " training vehicles " + fixed(train_before, 2) + " m -> " +
                      fixed(train_after, 2) + " m";
    if (!held.empty()) sdv += ",\n# on " + std::to_string(held.size()) + " held-out vehicles " + fixed(held_before, 2) + " m -> " + fixed(held_after, 2) + " m";
    sdv += ".\nimport \"std/drive.sdv\"\n";
    for (const auto& imp : fit.base.imports) sdv += "import \"" + imp + "\"\n";
    sdv += "\ntree calibrated(";
    std::string args;
    for (size_t i = 0; i < fit.params.size(); ++i) {
        const auto& p = fit.params[i];
        const auto it = std::find_if(declared.begin(), declared.end(), [&](const auto& d) { return d.first == p.name; });
        sdv += (i ? ", " : "") + p.name + ": " + it->second.first + " = " + fixed(x[i], 3) + (p.unit.empty() ? "" : " " + p.unit);
        args += (i ? ", " : "") + p.name + " = " + p.name;
    }
    std::string inner = tree;
    const size_t close = inner.rfind(')');
    const bool empty = inner.find_first_not_of(" \t", inner.find('(') + 1) == close;
    inner.insert(close, (empty ? "" : ", ") + args);
    sdv += ") {\n    subtree " + inner + "\n}\n";
    if (!write_text(out + "/calibrated.sdv", sdv)) return kFailure;
    std::cout << "calibrated";
    for (size_t i = 0; i < fit.params.size(); ++i) std::cout << (i ? "," : "") << " " << fit.params[i].name << " = " << fixed(x[i], 3) << " " << fit.params[i].unit;
    std::cout << " in " << fit.evaluations << " evaluations\n";
    std::cout << "  training (" << fit.training.size() << " vehicles): mean STED " << fixed(train_before, 2) << " m -> " << fixed(train_after, 2)
              << " m\n";
    if (!held.empty())
        std::cout << "  held out (" << held.size() << " vehicles): mean STED " << fixed(held_before, 2) << " m -> " << fixed(held_after, 2)
                  << " m\n";
    std::cout << "outputs in " << out << " (calibration.json, calibration.csv, calibrated.sdv)\n";
    return kOk;
}

int cmd_convert_recording(const std::string& recording, const std::string& map, const std::string& sdv, const std::string& out,
                          const Common& c) {
    Source s;
    if (!load_source(recording, map, s)) return kFailure;
    compiler::recorded::ReplaySpec spec;
    spec.sdv = sdv;
    const auto src = compiler::recorded::replay_source(s.rec, s.net, spec);
    if (!src.error.empty()) {
        std::cerr << "sdv: error: " << src.error << "\n";
        return kFailure;
    }
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    const bool to_stdout = out.empty() || out == "-";
    auto comp = compiler::compile_source(to_stdout ? fs::path(recording).stem().string() + ".sdv" : out, src.text, sm, diags,
                                         compiler::CompileOptions{c.import_dirs});
    if (report(diags, sm, c) || !comp.program) return kFailure;
    if (to_stdout) {
        std::cout << src.text;
        return kOk;
    }
    if (!write_file(out, src.text)) return kFailure;
    std::cout << "wrote " << out << "\n";
    return kOk;
}

}  // namespace sdv::cli
