// Sweeps: variants run on a pool of threads, rows appended as they finish, results gathered
// and summarised from the rows alone (see sweep.h).
#include "runtime/campaign/sweep.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <string_view>
#include <thread>

#include <nlohmann/json.hpp>

#include "runtime/campaign/variants.h"
#include "runtime/catalog/catalog.h"
#include "runtime/io/junit.h"
#include "runtime/io/outputs.h"
#include "runtime/io/recorder.h"
#include "runtime/io/text.h"
#include "runtime/io/view.h"
#include "runtime/ir/bindings.h"
#include "runtime/ir/ir_io.h"
#include "runtime/sim/road_cache.h"

namespace sdv::campaign {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

constexpr const char* kFormat = "sdv-sweep/1";

// What printf's "%.6g" writes (to_chars with a precision is specified so), without its cost:
// rows are read back by writing them again (read_row_of).
std::string num(double v) {
    if (!std::isfinite(v)) return "";
    char buf[32];
    const auto end = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6).ptr;
    const std::string_view text(buf, static_cast<size_t>(end - buf));
    return text == "-0" ? std::string("0") : std::string(text);
}

std::string csv_quote(const std::string& s) {
    if (s.empty()) return "";
    std::string out = "\"";
    for (char c : s) {
        if (c == '"') out += "\"\"";
        else if (c == '\n' || c == '\r') out += ' ';
        else out += c;
    }
    return out + "\"";
}

// Splits one CSV line (RFC 4180 quotes); false when the quoting is broken.
bool split_csv(const std::string& line, std::vector<std::string>& out) {
    out.clear();
    std::string cell;
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
                cell += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                cell += c;
            }
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            out.push_back(std::move(cell));
            cell.clear();
        } else {
            cell += c;
        }
    }
    out.push_back(std::move(cell));
    return !quoted;
}

std::string expect_unit(const ir::Scenario& s, size_t root) {
    const auto& e = s.expects[static_cast<size_t>(s.expect_roots[root])];
    if (e.kind != ir::Expect::Kind::call || e.function < 0) return "";
    const auto& def = catalog::expectations()[static_cast<size_t>(e.function)];
    return def.boolean ? "" : std::string(catalog::si_unit(def.result));
}

std::string with_unit(const std::string& name, const std::string& unit) {
    return unit.empty() ? name : name + "[" + unit + "]";
}

std::string slice_file(const std::string& dir, int slice, int slices) {
    return dir + "/rows/slice-" + std::to_string(slice) + "-of-" + std::to_string(slices) + ".csv";
}

std::string manifest_text(const ir::Program& program, int scenario, int64_t variants) {
    Json j;
    j["format"] = kFormat;
    j["scenario"] = program.scenarios[static_cast<size_t>(scenario)].name;
    j["ir_hash"] = ir::program_hash(program);
    j["variants"] = variants;
    j["columns"] = columns(program.scenarios[static_cast<size_t>(scenario)]);
    return j.dump(1) + "\n";
}

std::string read_text(const std::string& path, bool& ok) {
    std::ifstream in(path, std::ios::binary);
    ok = static_cast<bool>(in);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Writes `text` to `path` through a temporary file and a rename. The temporary name is the
// writer's own (process and a per-process counter): the array tasks of one Slurm sweep write the
// same manifest at the same moment, and a shared ".part" would let one task rename the other's
// file away from under it.
bool write_atomic(const std::string& path, const std::string& text) {
    static std::atomic<uint64_t> counter{0};
    const std::string part = path + "." + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".part";
    {
        std::ofstream o(part, std::ios::binary);
        o << text;
        if (!o) return false;
    }
    std::error_code ec;
    fs::rename(part, path, ec);
    if (!ec) return true;
    fs::remove(part, ec);
    return false;
}

// A whole cell as a count: decimal digits, at most 18 of them, no leading zero.
bool parse_count(const std::string& cell, int64_t& v) {
    if (cell.empty() || cell.size() > 18 || (cell.size() > 1 && cell[0] == '0')) return false;
    const auto [p, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
    return ec == std::errc() && p == cell.data() + cell.size() && v >= 0;
}

std::string cell_shown(const std::string& s) {
    return "'" + (s.size() > 40 ? s.substr(0, 40) + "..." : s) + "'";
}

// The value cell of parameter `k` as `row` writes it.
std::string param_text(const ir::Scenario& s, size_t k, double v) {
    return s.vary.params[k].integer ? std::to_string(std::llround(v)) : num(v);
}

bool read_row_of(const ir::Scenario& s, const std::vector<std::string>& cols, const VariantSpace& space,
                 const std::string& line, Row& out, std::string& why);

// The rows of one rows/*.csv file (`text`, named `name` in messages) that read back as sdv
// writes them, by variant (the first row of a variant is kept). A torn last line, from a sweep
// killed while writing, is dropped; every other line that is not a row of this campaign counts
// in `out.damaged`, so its variant runs again on a resume.
void read_rows(const ir::Scenario& s, const VariantSpace& space, const std::string& text, const std::string& name,
               RowFiles& out) {
    const auto cols = columns(s);
    size_t at = 0, line_no = 0;
    while (at < text.size()) {
        const size_t nl = text.find('\n', at);
        if (nl == std::string::npos) break;
        ++line_no;
        std::string line = text.substr(at, nl - at);
        at = nl + 1;
        if (line.empty()) continue;
        Row r;
        std::string why;
        if (!read_row_of(s, cols, space, line, r, why)) {
            if (out.damaged++ == 0) out.damage = name + ":" + std::to_string(line_no) + ": " + why;
            continue;
        }
        const int64_t v = r.variant;
        if (!out.rows.count(v)) out.rows.emplace(v, StoredRow{std::move(r), std::move(line)});
    }
}

// Metrics of the pairs that involve the ego (all pairs without one).
struct PairMins {
    double ttc = INFINITY, gap = INFINITY, clearance = INFINITY;
};

PairMins pair_mins(const ir::Scenario& s, const sim::RunResult& r) {
    int ego = -1;
    for (size_t i = 0; i < s.vehicles.size(); ++i) {
        if (s.vehicles[i].is_ego) ego = static_cast<int>(i);
    }
    PairMins m;
    for (const auto& p : r.pairs) {
        if (ego >= 0 && p.a != ego && p.b != ego) continue;
        m.ttc = std::min(m.ttc, p.min_ttc);
        m.gap = std::min(m.gap, p.min_gap);
        m.clearance = std::min(m.clearance, p.min_clearance);
    }
    return m;
}

}  // namespace

std::vector<std::string> columns(const ir::Scenario& s) {
    std::vector<std::string> out = {"variant"};
    for (const auto& p : s.vary.params) out.push_back(with_unit(p.name, p.unit));
    for (const char* c : {"passed", "error", "collisions", "min_ttc[s]", "min_gap[m]", "min_clearance[m]",
                          "fallback_share", "duration[s]"}) {
        out.emplace_back(c);
    }
    for (size_t k = 0; k < s.expect_roots.size(); ++k) {
        const std::string id = "e" + std::to_string(k + 1);
        out.push_back(with_unit(id, expect_unit(s, k)));
        out.push_back(id + "_passed");
    }
    return out;
}

Row run_row(const ir::Scenario& s, int64_t index, const std::vector<double>& values, const sim::RunResult& r) {
    Row out;
    out.variant = index;
    out.values = values;
    out.passed = r.passed();
    out.error = r.error;
    out.expect_values.assign(s.expect_roots.size(), std::nullopt);
    out.expect_passed.assign(s.expect_roots.size(), false);
    if (!r.error.empty()) return out;
    for (const auto& e : r.events) out.collisions += e.kind == "collision" ? 1 : 0;
    const PairMins m = pair_mins(s, r);
    auto finite = [](double v) { return std::isfinite(v) ? std::optional<double>(v) : std::nullopt; };
    out.min_ttc = finite(m.ttc);
    out.min_gap = finite(m.gap);
    out.min_clearance = finite(m.clearance);
    long long plans = 0, fallback = 0;
    for (const auto& v : r.vehicles) {
        plans += v.plans;
        fallback += v.fallback_plans;
    }
    out.fallback_share = plans > 0 ? static_cast<double>(fallback) / static_cast<double>(plans) : 0.0;
    out.duration = r.duration;
    for (size_t k = 0; k < s.expect_roots.size() && k < r.expectations.size(); ++k) {
        const sim::ExpectResult& e = r.expectations[k];
        if (e.value) out.expect_values[k] = finite(*e.value);
        out.expect_passed[k] = e.passed;
    }
    return out;
}

std::string row_text(const ir::Scenario& s, const Row& r) {
    auto opt = [](const std::optional<double>& v) { return v ? num(*v) : std::string(); };
    std::string out = std::to_string(r.variant);
    for (size_t k = 0; k < r.values.size(); ++k) out += "," + param_text(s, k, r.values[k]);
    out += std::string(",") + (r.passed ? "1" : "0") + "," + csv_quote(r.error);
    if (!r.error.empty()) {
        out += ",,,,,,";
        for (size_t k = 0; k < s.expect_roots.size(); ++k) out += ",,0";
        return out;
    }
    out += "," + std::to_string(r.collisions) + "," + opt(r.min_ttc) + "," + opt(r.min_gap) + "," +
           opt(r.min_clearance) + "," + num(r.fallback_share) + "," + num(r.duration);
    for (size_t k = 0; k < s.expect_roots.size(); ++k) {
        out += "," + (k < r.expect_values.size() ? opt(r.expect_values[k]) : std::string()) + "," +
               (k < r.expect_passed.size() && r.expect_passed[k] ? "1" : "0");
    }
    return out;
}

std::string row(const ir::Scenario& s, int64_t index, const std::vector<double>& values, const sim::RunResult& r) {
    return row_text(s, run_row(s, index, values, r));
}

bool read_row(const ir::Scenario& s, const VariantSpace& space, const std::string& line, Row& out,
              std::string& why) {
    return read_row_of(s, columns(s), space, line, out, why);
}

namespace {

bool read_row_of(const ir::Scenario& s, const std::vector<std::string>& cols, const VariantSpace& space,
                 const std::string& line, Row& out, std::string& why) {
    std::vector<std::string> cells;
    if (!split_csv(line, cells)) {
        why = "a quote is not closed";
        return false;
    }
    if (cells.size() != cols.size()) {
        why = std::to_string(cells.size()) + " cells, not the campaign's " + std::to_string(cols.size());
        return false;
    }
    size_t c = 0;
    auto fail = [&](const std::string& what) {
        why = "'" + cols[c] + "' " + cell_shown(cells[c]) + " " + what;
        return false;
    };
    Row r;
    if (!parse_count(cells[c], r.variant)) return fail("is not a variant index");
    if (r.variant >= space.size()) {
        return fail("is not a variant of this campaign (it has " + std::to_string(space.size()) + ")");
    }
    const std::vector<double> expected = space.values(r.variant);
    for (size_t k = 0; k < s.vary.params.size(); ++k) {
        ++c;
        double v = 0;
        if (!io::finite_number(cells[c], v)) return fail("is not a number");
        const std::string want = param_text(s, k, expected[k]);
        if (cells[c] != want) return fail("is not variant " + std::to_string(r.variant) + "'s value (" + want + ")");
        r.values.push_back(v);
    }
    auto flag = [&](bool& f) {
        if (cells[c] != "0" && cells[c] != "1") return fail("is not 1 or 0");
        f = cells[c] == "1";
        return true;
    };
    ++c;
    if (!flag(r.passed)) return false;
    r.error = cells[++c];
    const bool failed_run = !r.error.empty();
    r.expect_values.assign(s.expect_roots.size(), std::nullopt);
    r.expect_passed.assign(s.expect_roots.size(), false);
    auto measure = [&](std::optional<double>& v) {
        if (cells[c].empty()) return true;
        if (failed_run) return fail("is a measure of a run that did not run (its error is set)");
        double x = 0;
        if (!io::finite_number(cells[c], x)) return fail("is not a number");
        v = x;
        return true;
    };
    ++c;
    if (failed_run) {
        if (!cells[c].empty()) return fail("is a measure of a run that did not run (its error is set)");
    } else {
        int64_t n = 0;
        if (!parse_count(cells[c], n) || n > 1000000000) return fail("is not a count");
        r.collisions = static_cast<int>(n);
    }
    for (std::optional<double>* m : {&r.min_ttc, &r.min_gap, &r.min_clearance}) {
        ++c;
        if (!measure(*m)) return false;
    }
    for (double* m : {&r.fallback_share, &r.duration}) {
        ++c;
        std::optional<double> v;
        if (!measure(v)) return false;
        if (!failed_run && !v) return fail("is empty");
        *m = v.value_or(0);
    }
    for (size_t k = 0; k < s.expect_roots.size(); ++k) {
        ++c;
        if (!measure(r.expect_values[k])) return false;
        ++c;
        bool passed = false;
        if (!flag(passed)) return false;
        r.expect_passed[k] = passed;
    }
    // Every cell read; what is left is the form: the row must be the very text sdv writes for it
    // (no "1.0" for "1", no unquoted error), so a row read back writes back to the same bytes.
    const std::string canonical = row_text(s, r);
    if (canonical != line) {
        why = "not the text sdv writes for this row (" + cell_shown(canonical) + ")";
        return false;
    }
    out = std::move(r);
    return true;
}

}  // namespace

std::string clear_sweep(const std::string& dir) {
    std::error_code ec;
    for (const char* name : {"rows", "runs", "slurm"}) fs::remove_all(dir + "/" + name, ec);
    for (const char* name : {"results.csv", "summary.json", "timing.json", "report.html", "junit.xml"}) {
        fs::remove(dir + "/" + name, ec);
    }
    return ec ? "cannot clear '" + dir + "': " + ec.message() : "";
}

SweepOutcome run_sweep(const ir::Program& program, int scenario, const SweepOptions& o) {
    SweepOutcome out;
    const auto t0 = std::chrono::steady_clock::now();
    const ir::Scenario& sc = program.scenarios[static_cast<size_t>(scenario)];
    const VariantSpace space(sc.vary);
    out.variants = space.size();
    if (o.slices < 1 || o.slice < 0 || o.slice >= o.slices) {
        out.error = "invalid slice " + std::to_string(o.slice) + "/" + std::to_string(o.slices);
        return out;
    }
    const int64_t n = space.size();
    const int64_t begin = n * o.slice / o.slices, end = n * (o.slice + 1) / o.slices;
    std::error_code ec;
    fs::create_directories(o.dir + "/rows", ec);
    if (ec) {
        out.error = "cannot create '" + o.dir + "/rows': " + ec.message();
        return out;
    }
    // The manifest ties the rows to one campaign: a resume of another scenario must not mix.
    const std::string manifest = manifest_text(program, scenario, n);
    const std::string manifest_path = o.dir + "/rows/manifest.json";
    bool have = false;
    const std::string existing = read_text(manifest_path, have);
    if (have && existing != manifest) {
        out.error = "'" + o.dir + "' holds the rows of another campaign (a different scenario, vary block or sdv); "
                    "use a new directory, or run without --resume to start afresh";
        return out;
    }
    if (!have && !write_atomic(manifest_path, manifest)) {
        out.error = "cannot write '" + manifest_path + "'";
        return out;
    }
    const RowFiles files = read_row_files(sc, o.dir);
    const auto& done = files.rows;
    out.damaged = files.damaged;
    out.damage = files.damage;
    // Our own slice file: cut a torn last line, then append.
    const std::string own = slice_file(o.dir, o.slice, o.slices);
    {
        bool ok = false;
        const std::string text = read_text(own, ok);
        if (ok && !text.empty() && text.back() != '\n') fs::resize_file(own, text.rfind('\n') + 1, ec);
    }
    const int fd = ::open(own.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) {
        out.error = "cannot write '" + own + "'";
        return out;
    }
    std::vector<int64_t> todo;
    for (int64_t i = begin; i < end; ++i) {
        if (done.count(i)) {
            ++out.skipped;
        } else {
            todo.push_back(i);
        }
    }
    const std::vector<double> base = ir::scenario_number_values(program, scenario);
    // Every variant runs on the same road: build it once.
    sim::RunOptions run_options;
    run_options.roads = std::make_shared<sim::RoadCache>();
    std::atomic<size_t> next{0};
    std::mutex mu;
    int64_t finished = out.skipped, failed = 0;
    for (const auto& [i, read] : done) {
        if (i >= begin && i < end && !read.row.passed) ++failed;
    }
    std::string first_error;
    auto run_one = [&](ir::Program& variant, int64_t i) {
        const auto values = space.values(i);
        ir::reset_variant(variant, scenario, program);
        std::string err = ir::apply_variant(variant, scenario, base, values);
        sim::RunResult r;
        if (!err.empty()) {
            r.error = err;
        } else if (o.keep == Keep::runs) {
            r = run_kept(variant, scenario, o.dir, i, err, run_options);
        } else {
            r = sim::simulate(variant, scenario, run_options);
            if (o.keep == Keep::failed && !r.passed()) r = run_kept(variant, scenario, o.dir, i, err, run_options);
        }
        const std::string line = row(sc, i, values, r) + "\n";
        std::lock_guard<std::mutex> lock(mu);
        if (!err.empty() && first_error.empty()) first_error = err;
        if (::write(fd, line.data(), line.size()) != static_cast<ssize_t>(line.size()) && first_error.empty()) {
            first_error = "cannot write '" + own + "'";
        }
        ++finished;
        ++out.ran;
        failed += r.passed() ? 0 : 1;
    };
    const int jobs = std::max(1, std::min<int>(o.jobs, static_cast<int>(std::max<size_t>(1, todo.size()))));
    std::vector<std::thread> pool;
    std::atomic<int64_t> reported{-1};
    auto worker = [&]() {
        ir::Program variant = program;
        for (;;) {
            const size_t k = next.fetch_add(1);
            if (k >= todo.size()) break;
            run_one(variant, todo[k]);
        }
    };
    for (int j = 1; j < jobs; ++j) pool.emplace_back(worker);
    // The calling thread works too, and reports progress between its own variants.
    {
        ir::Program variant = program;
        for (;;) {
            if (o.progress) {
                int64_t f = 0, fl = 0;
                {
                    std::lock_guard<std::mutex> lock(mu);
                    f = finished;
                    fl = failed;
                }
                if (f != reported.exchange(f)) o.progress(f, end - begin, fl);
            }
            const size_t k = next.fetch_add(1);
            if (k >= todo.size()) break;
            run_one(variant, todo[k]);
        }
    }
    for (auto& t : pool) t.join();
    ::close(fd);
    if (o.progress) o.progress(finished, end - begin, failed);
    out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!first_error.empty()) out.error = first_error;
    return out;
}

sim::RunResult run_kept(const ir::Program& variant, int scenario, const std::string& dir, int64_t index,
                        std::string& error, const sim::RunOptions& options) {
    const std::string run_dir = dir + "/runs/" + std::to_string(index);
    std::error_code ec;
    fs::create_directories(run_dir, ec);
    io::Recorder recorder;
    sim::RunResult r;
    if (auto e = recorder.open(run_dir, false); !e.empty()) {
        error = e;
        return sim::simulate(variant, scenario, options);
    }
    r = sim::simulate(variant, scenario, options, &recorder);
    if (!r.error.empty()) {
        recorder.discard();
        return r;
    }
    if (auto e = recorder.commit(); !e.empty()) {
        error = e;
        return r;
    }
    const io::Recording rec = recorder.take();
    io::RunInfo info;
    info.ir_hash = ir::program_hash(variant);
    info.seed = variant.scenarios[static_cast<size_t>(scenario)].seed;
    if (auto e = io::write_outputs(run_dir, variant, scenario, r, rec, info); !e.empty()) {
        error = e;
        return r;
    }
    std::string view_error;
    const std::string html = io::view_report(run_dir, view_error);
    if (!html.empty()) write_atomic(run_dir + "/view.html", html);
    return r;
}

RowFiles read_row_files(const ir::Scenario& s, const std::string& dir) {
    const VariantSpace space(s.vary);
    std::vector<std::string> files;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir + "/rows", ec)) {
        if (entry.path().extension() == ".csv") files.push_back(entry.path().filename().string());
    }
    std::sort(files.begin(), files.end());
    RowFiles out;
    for (const auto& f : files) {
        bool ok = false;
        const std::string path = dir + "/rows/" + f;
        read_rows(s, space, read_text(path, ok), path, out);
    }
    return out;
}

std::string gather(const ir::Program& program, int scenario, const std::string& dir, Results& out) {
    const ir::Scenario& sc = program.scenarios[static_cast<size_t>(scenario)];
    const int64_t n = VariantSpace(sc.vary).size();
    bool have = false;
    const std::string manifest = read_text(dir + "/rows/manifest.json", have);
    if (!have) return "'" + dir + "' holds no sweep rows (no rows/manifest.json)";
    if (manifest != manifest_text(program, scenario, n)) {
        return "the rows in '" + dir + "' belong to another campaign (a different scenario, vary block or sdv)";
    }
    return gather_rows(sc, dir, out);
}

std::string gather_rows(const ir::Scenario& sc, const std::string& dir, Results& out) {
    const int64_t n = VariantSpace(sc.vary).size();
    out.header = columns(sc);
    RowFiles files = read_row_files(sc, dir);
    auto& rows = files.rows;
    std::vector<int64_t> missing;
    for (int64_t i = 0; i < n && missing.size() < 6; ++i) {
        if (!rows.count(i)) missing.push_back(i);
    }
    if (!missing.empty()) {
        std::string list;
        for (size_t k = 0; k < missing.size() && k < 5; ++k) list += (k ? ", " : "") + std::to_string(missing[k]);
        if (missing.size() > 5) list += ", ...";
        std::string damaged;
        if (files.damaged > 0) {
            damaged = files.damaged == 1 ? "; 1 line is not a row as sdv writes it (" + files.damage + ")"
                                         : "; " + std::to_string(files.damaged) +
                                               " lines are not rows as sdv writes them (first: " + files.damage + ")";
        }
        return "the sweep in '" + dir + "' is incomplete: " + std::to_string(n - static_cast<int64_t>(rows.size())) +
               " of " + std::to_string(n) + " variants have no row (" + list + ")" + damaged +
               "; run it again with --resume";
    }
    for (auto& [i, read] : rows) {
        out.rows.push_back(std::move(read.row));
        out.lines.push_back(std::move(read.line));
    }
    return "";
}

std::string write_results(const ir::Program& program, int scenario, const SweepOptions& o, const Results& res) {
    const ir::Scenario& sc = program.scenarios[static_cast<size_t>(scenario)];
    std::string csv;
    for (size_t k = 0; k < res.header.size(); ++k) csv += (k ? "," : "") + res.header[k];
    csv += "\n";
    for (const auto& l : res.lines) csv += l + "\n";
    if (!write_atomic(o.dir + "/results.csv", csv)) return "cannot write '" + o.dir + "/results.csv'";

    const VariantSpace space(sc.vary);
    Json j;
    j["format"] = kFormat;
    j["file"] = o.file;
    j["scenario"] = sc.name;
    j["ir_hash"] = ir::program_hash(program);
    const char* methods[] = {"grid", "random", "latin"};
    j["sample"] = {{"method", methods[static_cast<int>(sc.vary.sample)]},
                   {"count", sc.vary.sample == ir::Vary::Sample::grid ? 0 : sc.vary.count},
                   {"seed", sc.vary.seed}};
    j["parameters"] = Json::array();
    for (size_t k = 0; k < sc.vary.params.size(); ++k) {
        const auto& p = sc.vary.params[k];
        const auto lv = space.levels(k);
        Json pj;
        pj["name"] = p.name;
        pj["unit"] = p.unit;
        pj["column"] = with_unit(p.name, p.unit);
        pj["domain"] = p.domain;
        pj["values"] = lv.empty() ? Json(nullptr) : Json(lv);
        j["parameters"].push_back(pj);
    }
    j["expectations"] = Json::array();
    for (size_t k = 0; k < sc.expect_roots.size(); ++k) {
        const auto& e = sc.expects[static_cast<size_t>(sc.expect_roots[k])];
        const std::string id = "e" + std::to_string(k + 1), u = expect_unit(sc, k);
        j["expectations"].push_back({{"id", id}, {"text", e.text}, {"column", with_unit(id, u)},
                                     {"unit", u.empty() ? Json(nullptr) : Json(u)}, {"line", e.loc.line}});
    }
    int64_t passed = 0, errors = 0, with_collision = 0;
    std::vector<int64_t> expect_failures(sc.expect_roots.size(), 0);
    struct Worst {
        std::optional<double> value;
        int64_t variant = -1;
    } ttc, gap, clearance;
    auto track = [](Worst& w, const std::optional<double>& v, int64_t i) {
        if (v && (!w.value || *v < *w.value)) {
            w.value = v;
            w.variant = i;
        }
    };
    for (const auto& r : res.rows) {
        passed += r.passed ? 1 : 0;
        errors += r.error.empty() ? 0 : 1;
        with_collision += r.collisions > 0 ? 1 : 0;
        if (r.error.empty()) {
            for (size_t k = 0; k < r.expect_passed.size(); ++k) expect_failures[k] += r.expect_passed[k] ? 0 : 1;
        }
        track(ttc, r.min_ttc, r.variant);
        track(gap, r.min_gap, r.variant);
        track(clearance, r.min_clearance, r.variant);
    }
    const auto total = static_cast<int64_t>(res.rows.size());
    j["variants"] = total;
    j["passed"] = passed;
    j["failed"] = total - passed - errors;
    j["errors"] = errors;
    j["with_collision"] = with_collision;
    j["expectation_failures"] = Json::object();
    for (size_t k = 0; k < expect_failures.size(); ++k) {
        j["expectation_failures"]["e" + std::to_string(k + 1)] = expect_failures[k];
    }
    auto worst = [&](const Worst& w) -> Json {
        if (!w.value) return nullptr;
        return {{"variant", w.variant}, {"value", std::stod(num(*w.value))},
                {"parameters", describe(sc.vary, res.rows[static_cast<size_t>(w.variant)].values)}};
    };
    j["worst"] = {{"min_ttc", worst(ttc)}, {"min_gap", worst(gap)}, {"min_clearance", worst(clearance)}};
    const char* keeps[] = {"none", "failed", "runs"};
    j["kept"] = keeps[static_cast<int>(o.keep)];
    if (!write_atomic(o.dir + "/summary.json", j.dump(2) + "\n")) return "cannot write '" + o.dir + "/summary.json'";
    return "";
}

std::string sweep_junit(const ir::Program& program, int scenario, const Results& res) {
    const ir::Scenario& sc = program.scenarios[static_cast<size_t>(scenario)];
    std::vector<io::JUnitSuite> suites;
    for (const auto& r : res.rows) {
        io::JUnitSuite s;
        const std::string params = describe(sc.vary, r.values);
        s.name = sc.name + "[" + std::to_string(r.variant) + "] " + params;
        s.properties = {{"variant", std::to_string(r.variant)}, {"parameters", params}};
        for (size_t k = 0; k < sc.expect_roots.size(); ++k) {
            const auto& e = sc.expects[static_cast<size_t>(sc.expect_roots[k])];
            io::JUnitCase c;
            c.name = e.text;
            c.classname = sc.name + "." + std::to_string(r.variant);
            c.time = r.duration;
            const std::string u = expect_unit(sc, k);
            const std::string measured = r.expect_values[k] ? "measured " + num(*r.expect_values[k]) + (u.empty() ? "" : " " + u)
                                                            : "measured no value";
            if (!r.error.empty()) {
                c.error = "not evaluated: " + r.error;
            } else if (!r.expect_passed[k]) {
                c.failure = measured + "; expected " + e.text + " (" + params + ")";
            } else {
                c.output = measured;
            }
            s.cases.push_back(std::move(c));
        }
        if (sc.expect_roots.empty()) {
            io::JUnitCase c;
            c.name = "run";
            c.classname = sc.name + "." + std::to_string(r.variant);
            c.time = r.duration;
            if (!r.error.empty()) c.error = r.error;
            s.cases.push_back(std::move(c));
        }
        suites.push_back(std::move(s));
    }
    return io::junit_xml(suites);
}

std::string sweep_report_text(const ir::Program& program, int scenario, const Results& res) {
    const ir::Scenario& sc = program.scenarios[static_cast<size_t>(scenario)];
    int64_t passed = 0, errors = 0, collided = 0;
    std::vector<int64_t> failures(sc.expect_roots.size(), 0);
    for (const auto& r : res.rows) {
        passed += r.passed ? 1 : 0;
        errors += r.error.empty() ? 0 : 1;
        collided += r.collisions > 0 ? 1 : 0;
        if (!r.error.empty()) continue;
        for (size_t k = 0; k < failures.size(); ++k) failures[k] += r.expect_passed[k] ? 0 : 1;
    }
    const auto n = static_cast<int64_t>(res.rows.size());
    std::string out = sc.name + ": " + std::to_string(n) + " variants, " + std::to_string(passed) + " passed, " +
                      std::to_string(n - passed - errors) + " failed" +
                      (errors ? ", " + std::to_string(errors) + " with a runtime error" : "") + "; " +
                      std::to_string(collided) + " with a collision\n";
    for (size_t k = 0; k < failures.size(); ++k) {
        const auto& e = sc.expects[static_cast<size_t>(sc.expect_roots[k])];
        out += "  e" + std::to_string(k + 1) + " " + e.text + ": failed in " + std::to_string(failures[k]) + "\n";
    }
    return out;
}

}  // namespace sdv::campaign
