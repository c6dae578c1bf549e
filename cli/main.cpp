// The `sdv` executable: parses the command line (CLI11), calls the libraries, prints, and
// decides the exit code: 0 ok, 1 user-level failure (diagnostics, failed expectations),
// 2 usage error, 3 internal error. No verb logic lives here beyond wiring.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <optional>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "compiler/ast/ast.h"
#include "compiler/diff/diff.h"
#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/render.h"
#include "compiler/gss/scenario.h"
#include "runtime/ir/ir_io.h"
#include "compiler/sema/compile.h"
#include "compiler/syntax/format.h"
#include "compiler/syntax/parser.h"
#include "compiler/sema/std_trees.h"
#include "runtime/catalog/catalog.h"
#include "runtime/cosim/replay.h"
#include "runtime/cosim/server.h"
#include "runtime/cosim/sha256.h"
#include "runtime/io/gss_outputs.h"
#include "runtime/io/outputs.h"
#include "runtime/io/plot.h"
#include "runtime/io/reuse.h"
#include "runtime/io/run_diff.h"
#include "runtime/io/view.h"
#include "runtime/sim/simulation.h"

#include <unistd.h>

#include "cli/campaign.h"
#include "cli/realism.h"
#include "cli/common.h"
#include "runtime/campaign/variants.h"
#include "runtime/io/junit.h"
#include "runtime/io/sweep_report.h"
#include "runtime/ir/bindings.h"

namespace {

using namespace sdv;

using namespace sdv::cli;

std::string summary(const ir::Program& p, const std::string& hash) {
    std::ostringstream out;
    for (const auto& s : p.scenarios) {
        out << "scenario " << s.name;
        if (s.road >= 0) {
            const auto& r = p.roads[static_cast<size_t>(s.road)];
            out << " on " << (r.kind == ir::RoadKind::road       ? "road "
                              : r.kind == ir::RoadKind::junction ? "junction "
                                                                 : "map ")
                << r.name;
        }
        out << ": " << s.vehicles.size() << " vehicle" << (s.vehicles.size() == 1 ? "" : "s")
            << ", timeout " << s.timeout << " s, seed " << s.seed << ", " << s.expect_roots.size()
            << " expectation" << (s.expect_roots.size() == 1 ? "" : "s") << "\n";
        for (const auto& v : s.vehicles) {
            // The kind as the source declares it (a simulated pedestrian is an sdp).
            const char* kind = v.kind == ir::VehicleKind::sdv             ? (v.pedestrian ? "sdp" : "sdv")
                               : v.kind == ir::VehicleKind::trajectory    ? "trajectory"
                               : v.kind == ir::VehicleKind::path          ? "path"
                               : v.kind == ir::VehicleKind::static_object ? (v.object ? "object" : "static")
                                                                          : "external";
            out << "  " << (v.is_ego ? "ego " : "    ") << v.name << ": " << (v.pedestrian ? "pedestrian, " : "") << kind;
            if (!v.start.xy) out << ", starts on " << v.start.lane << " at " << v.start.s << " m";
            if (v.tree >= 0) {
                const auto& inst = p.instances[static_cast<size_t>(v.tree)];
                int maneuvers = 0;
                for (const auto& n : inst.nodes) maneuvers += n.kind == ir::NodeKind::maneuver;
                out << ", tree of " << inst.nodes.size() << " nodes (" << maneuvers
                    << " maneuver" << (maneuvers == 1 ? "" : "s") << ")";
            }
            out << "\n";
        }
        for (int32_t root : s.expect_roots) {
            out << "  expect " << s.expects[static_cast<size_t>(root)].text << "\n";
        }
        if (!s.vary.empty()) {
            const char* methods[] = {"grid", "random", "latin"};
            out << "  vary " << s.vary.params.size() << " parameter" << (s.vary.params.size() == 1 ? "" : "s") << " ("
                << methods[static_cast<int>(s.vary.sample)] << "): " << campaign::VariantSpace(s.vary).size()
                << " variants\n";
            for (const auto& vp : s.vary.params) out << "    " << vp.name << " in " << vp.domain << "\n";
        }
    }
    if (p.scenarios.empty()) out << p.trees.size() << " trees, no scenario\n";
    out << "IR hash " << hash << "\n";
    return out.str();
}

int cmd_lint(const std::vector<std::string>& files, const Common& c, const WarningFlags& w, bool quiet) {
    bool errors = false;
    size_t warnings = 0;
    for (const auto& f : files) {
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        diags.set_policy(w.policy);
        compile_input(f, c, sm, diags);
        warnings += diags.warning_count();
        errors = report(diags, sm, c) || errors;
    }
    // On success a one-line summary on a terminal (as compilers do), so a user sees it ran;
    // nothing with -q, with --format json or into a pipe.
    if (!errors && !quiet && c.format == "text" && isatty(STDOUT_FILENO) != 0) {
        std::cout << (files.size() == 1 ? files[0] : std::to_string(files.size()) + " files") << ": no errors"
                  << (warnings ? ", " + std::to_string(warnings) + " warning" + (warnings == 1 ? "" : "s") : "") << "\n";
    }
    return errors ? kFailure : kOk;
}

int cmd_compile(const std::string& file, const std::string& out, const std::string& emit,
                const Common& c, const WarningFlags& w) {
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    diags.set_policy(w.policy);
    if (emit == "tokens") {
        std::ifstream in(file, std::ios::binary);
        if (!in) {
            std::cerr << "sdv: error: cannot read '" << file << "'\n";
            return kFailure;
        }
        std::stringstream ss;
        ss << in.rdbuf();
        const auto id = sm.add_file(file, ss.str());
        std::cout << compiler::syntax::dump_tokens(id, sm);
        return kOk;
    }
    auto result = compile_input(file, c, sm, diags);
    if (emit == "ast") {
        if (!result.files.empty() && result.files[0]) {
            std::cout << compiler::ast::dump(*result.files[0], sm);
        }
        return report(diags, sm, c) ? kFailure : kOk;
    }
    if (report(diags, sm, c) || !result.program) return kFailure;
    const std::string text = ir::write_ir(*result.program);
    if (emit == "ir" || out.empty() || out == "-") {
        std::cout << text;
        return kOk;
    }
    if (!write_file(out, text)) return kFailure;
    std::cout << summary(*result.program, ir::program_hash(*result.program)) << "wrote " << out
              << "\n";
    return kOk;
}

struct RunArgs {
    std::string file, out, scenario;
    std::optional<uint64_t> seed;
    int threads = 1;
    bool trace = false, realtime = false, gss_outputs = false, view = false;
    std::string junit;               // JUnit XML of the expectations
    std::optional<int64_t> variant;  // run this variant of the scenario's vary block
    // Co-simulation (docs/cosim.md): sdv serves one client at this endpoint.
    std::string cosim, cosim_port_file, cosim_encoding = "binary", cosim_record;
    double cosim_step_timeout = 0, cosim_connect_timeout = 60;
};

// The extras of a finished run directory (--gss-outputs, --view); an exit code.
int write_extras(const RunArgs& args, const std::string& dir, const ir::Program& program, int index,
                 const sim::RunResult& r) {
    if (args.gss_outputs) {
        std::ifstream csv(std::filesystem::path(dir) / "trajectories.csv", std::ios::binary);
        if (auto e = io::write_gss_outputs(dir, program, index, r, csv); !e.empty()) {
            std::cerr << "sdv: error: " << e << "\n";
            return kFailure;
        }
    }
    if (!args.junit.empty()) {
        if (!write_file(args.junit, io::run_junit(program, index, r, args.file))) return kFailure;
        std::cout << "JUnit report in " << args.junit << "\n";
    }
    if (args.view) {
        std::string error;
        const std::string html = io::view_report(dir, error);
        const std::string path = (std::filesystem::path(dir) / "report.html").string();
        if (!error.empty()) {
            std::cerr << "sdv: error: " << error << "\n";
            return kFailure;
        }
        if (!write_file(path, html)) return kFailure;
        std::cout << "report in " << path << "\n";
    }
    return kOk;
}

// `sdv run --cosim`: the scenario as a co-simulation server (runtime/cosim/server.h). The run
// writes the same outputs and prints the same report as `sdv run`; the exit status is the
// session's (cosim::kExit*: 0/1 the verdict after Bye, 4 client gone, 5 Error sent, 6 time-out).
int cmd_run_cosim(const RunArgs& args, ir::Program program, int index, const std::string& file_text) {
    std::string error;
    const auto endpoint = cosim::parse_endpoint(args.cosim, error);
    if (!endpoint) {
        std::cerr << "sdv: error: --cosim: " << error << "\n";
        return kUsage;
    }
    if (args.realtime) {
        std::cerr << "sdv: error: --realtime does not apply to --cosim: the client drives the clock\n";
        return kUsage;
    }
    if (args.cosim_step_timeout < 0 || args.cosim_connect_timeout < 0) {
        std::cerr << "sdv: error: co-simulation time-outs are seconds >= 0 (0: wait forever)\n";
        return kUsage;
    }
    auto shared = std::make_shared<const ir::Program>(std::move(program));
    const ir::Scenario& sc = shared->scenarios[static_cast<size_t>(index)];
    const std::string dir = args.out.empty() ? "out/" + sc.name : args.out;
    cosim::SessionOptions so;
    so.seed = args.seed;
    so.threads = args.threads;
    so.trace = args.trace;
    so.output_dir = dir;
    auto session = cosim::Session::create(shared, index, so, error);
    if (!session) {
        std::cerr << error << "\n";
        return kFailure;
    }
    cosim::WelcomeInfo info = cosim::welcome_info(*shared, index);
    info.sdv_version = compiler::kCompilerVersion;
    info.scenario = args.file;
    info.scenario_sha256 = cosim::sha256_hex(file_text);
    cosim::ServerOptions opts;
    opts.encoding = *cosim::parse_encoding(args.cosim_encoding);
    opts.connect_timeout_s = args.cosim_connect_timeout;
    opts.step_timeout_s = args.cosim_step_timeout;
    opts.port_file = args.cosim_port_file;
    opts.record_path = args.cosim_record;
    cosim::RecordHeader header;
    std::error_code ec;
    header.scenario = std::filesystem::absolute(args.file, ec).string();
    header.scenario_name = sc.name;
    header.sdv_version = info.sdv_version;
    auto server = cosim::Server::listen(*endpoint, opts, header, error);
    if (!server) {
        std::cerr << "sdv: error: " << error << "\n";
        return kFailure;
    }
    // A client (or its test) reads this line, or the --cosim-port-file, to know where to connect.
    std::cout << "listening on " << server->address() << std::endl;
    const cosim::ServeResult res = server->serve(*session, info);
    using Kind = cosim::Protocol::Outcome::Kind;
    const std::string who = res.client_name.empty() ? "the client" : "client '" + res.client_name + "'";
    switch (res.outcome.kind) {
        case Kind::bye:
            std::cout << who << " said Bye after " << res.steps << " step" << (res.steps == 1 ? "" : "s")
                      << (res.outcome.message.empty() ? "" : " (" + res.outcome.message + ")") << "\n";
            break;
        case Kind::disconnected:
            std::cerr << "sdv: error: co-simulation aborted after " << res.steps << " steps: " << res.outcome.message << "\n";
            break;
        case Kind::client_error:
            std::cerr << "sdv: error: co-simulation aborted after " << res.steps << " steps: " << who << " sent Error "
                      << res.outcome.message << "\n";
            break;
        case Kind::error:
        case Kind::timeout:
            std::cerr << "sdv: error: co-simulation aborted after " << res.steps << " steps: sent Error "
                      << cosim::code_name(res.outcome.code) << ": " << res.outcome.message << "\n";
            break;
        case Kind::open: break;
    }
    if (!res.finish_error.empty()) std::cerr << "sdv: error: " << res.finish_error << "\n";
    if (const sim::RunResult* r = session->result()) {
        std::cout << io::report(*shared, index, *r) << "outputs in " << dir << "\n";
        if (res.finish_error.empty() && write_extras(args, dir, *shared, index, *r) != kOk && res.exit_status == kOk) {
            return kFailure;
        }
    }
    return res.exit_status;
}

int run_one(const RunArgs& args, Loaded& loaded);

// `sdv run`: one scenario, or each scenario of a file that has several, into OUT/<scenario>
// (default out/<scenario>); the exit status is 0 when every one passed.
int cmd_run(const RunArgs& args, const Common& c, const WarningFlags& w) {
    Loaded loaded;
    const bool single_only = args.variant || !args.cosim.empty() || !args.junit.empty();
    if (const int e = load_scenario(args.file, args.scenario, c, w, loaded, !single_only); e != kOk) return e;
    if (loaded.index >= 0) return run_one(args, loaded);
    int status = kOk;
    const auto count = loaded.program.scenarios.size();
    for (size_t i = 0; i < count; ++i) {
        RunArgs one = args;
        one.scenario = loaded.program.scenarios[i].name;
        one.out = (std::filesystem::path(args.out.empty() ? "out" : args.out) / one.scenario).string();
        Loaded copy{loaded.program, static_cast<int>(i), loaded.text};
        const int e = run_one(one, copy);
        if (e != kOk && status == kOk) status = e;
    }
    std::cout << count << " scenarios run\n";
    return status;
}

int run_one(const RunArgs& args, Loaded& loaded) {
    if (args.variant) {
        ir::Scenario& vs = loaded.program.scenarios[static_cast<size_t>(loaded.index)];
        const campaign::VariantSpace space(vs.vary);
        if (*args.variant < 0 || *args.variant >= space.size()) {
            std::cerr << "sdv: error: scenario '" << vs.name << "' has "
                      << (vs.vary.empty() ? std::string("no vary block") : std::to_string(space.size()) + " variants (0 to " +
                                                                              std::to_string(space.size() - 1) + ")")
                      << "; there is no variant " << *args.variant << "\n";
            return kUsage;
        }
        const auto values = space.values(*args.variant);
        const auto base = ir::scenario_number_values(loaded.program, loaded.index);
        if (auto e = ir::apply_variant(loaded.program, loaded.index, base, values); !e.empty()) {
            std::cerr << "sdv: error: " << e << "\n";
            return kFailure;
        }
        std::cout << "variant " << *args.variant << ": " << campaign::describe(vs.vary, values) << "\n";
    }
    std::optional<ir::Program> program = std::move(loaded.program);
    const int index = loaded.index;
    const std::string& text = loaded.text;
    const ir::Scenario& sc = program->scenarios[static_cast<size_t>(index)];
    if (!args.cosim.empty()) return cmd_run_cosim(args, std::move(*program), index, text);
    for (const auto& v : sc.vehicles) {
        if (v.kind != ir::VehicleKind::external) continue;
        std::cerr << "sdv: error: vehicle '" << v.name << "' of scenario '" << sc.name
                  << "' is external: a co-simulation client drives it. Run with --cosim tcp://127.0.0.1:0 "
                     "(or --cosim unix:PATH) and connect the client (docs/cosim.md)\n";
        return kUsage;
    }
    sim::RunOptions opts;
    opts.seed = args.seed;
    opts.threads = args.threads;
    opts.trace = args.trace;
    opts.realtime = args.realtime;
    const bool tty = isatty(STDERR_FILENO) != 0;
    if (tty) {
        // On a terminal: the simulated time and real-time factor on one line, and each event
        // (but fallbacks, summed up in the report) as it happens above it.
        const auto wall0 = std::chrono::steady_clock::now();
        opts.progress = [&sc, wall0, shown = size_t{0}, drawn = -1.0](double t, double, const std::vector<sim::Event>& events) mutable {
            bool printed = false;
            for (; shown < events.size(); ++shown) {
                if (events[shown].kind == "fallback" || events[shown].kind == "timeout") continue;
                std::fprintf(stderr, "\r\033[K%s\n", io::event_line(sc, events[shown]).c_str());
                printed = true;
            }
            const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
            if (!printed && drawn >= 0 && wall - drawn < 0.1) return;  // at most ten redraws a second
            drawn = wall;
            std::fprintf(stderr, "\r\033[K%s: %.1f / %.1f s simulated, %.0fx real time", sc.name.c_str(), t, sc.timeout,
                         wall > 0 ? t / wall : 0.0);
            std::fflush(stderr);
        };
    }
    const std::string dir = args.out.empty() ? "out/" + sc.name : args.out;
    {
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec) {
            std::cerr << "sdv: error: cannot create '" << dir << "': " << ec.message() << "\n";
            return kFailure;
        }
    }
    // Trajectories and decisions stream into the output directory as the run goes.
    io::Recorder recorder;
    if (auto e = recorder.open(dir, args.trace); !e.empty()) {
        std::cerr << "sdv: error: " << e << "\n";
        return kFailure;
    }
    sim::RunResult r = sim::simulate(*program, index, opts, &recorder);
    if (tty) std::fprintf(stderr, "\r\033[K");
    if (!r.error.empty()) {
        recorder.discard();
        std::cerr << r.error << "\n";
        return kFailure;
    }
    if (auto e = recorder.commit(); !e.empty()) {
        std::cerr << "sdv: error: " << e << "\n";
        return kFailure;
    }
    const io::Recording rec = recorder.take();
    io::RunInfo info;
    info.ir_hash = ir::program_hash(*program);
    info.seed = args.seed.value_or(sc.seed);
    info.trace = args.trace;
    info.threads = args.threads;
    if (auto e = io::write_outputs(dir, *program, index, r, rec, info); !e.empty()) {
        std::cerr << "sdv: error: " << e << "\n";
        return kFailure;
    }
    std::cout << io::report(*program, index, r) << "outputs in " << dir << "\n";
    if (const int e = write_extras(args, dir, *program, index, r); e != kOk) return e;
    return r.passed() ? kOk : kFailure;
}

// Formats files in place (default), to stdout, or only checks them (exit 1 when one would change).
int cmd_fmt(const std::vector<std::string>& files, bool check, bool to_stdout, const Common& c) {
    bool changed = false, failed = false;
    for (const auto& f : files) {
        std::ifstream in(f, std::ios::binary);
        if (!in) {
            std::cerr << "sdv: error: cannot read '" << f << "'\n";
            failed = true;
            continue;
        }
        std::stringstream ss;
        ss << in.rdbuf();
        const std::string original = ss.str();
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        const auto id = sm.add_file(f, original);
        auto formatted = compiler::syntax::format(id, sm, diags);
        if (!formatted) {
            report(diags, sm, c);
            failed = true;
            continue;
        }
        if (to_stdout) {
            std::cout << *formatted;
        } else if (*formatted != original) {
            changed = true;
            if (check) {
                std::cerr << f << ": not formatted (run sdv fmt " << f << ")\n";
            } else {
                if (!write_file(f, *formatted)) failed = true;
            }
        }
    }
    return failed || (check && changed) ? kFailure : kOk;
}

// Loads a program from .sdv (compiled) or .sdvir (read and validated).
std::optional<ir::Program> load_program(const std::string& file, const Common& c) {
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        std::cerr << "sdv: error: cannot read '" << file << "'\n";
        return std::nullopt;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    if (file.size() > 6 && file.compare(file.size() - 6, 6, ".sdvir") == 0) {
        auto r = ir::read_ir(ss.str());
        if (!r.program) std::cerr << file << ": error: " << r.error << "\n";
        return std::move(r.program);
    }
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    compiler::CompileOptions opts{c.import_dirs};
    auto result = compiler::compile_source(file, ss.str(), sm, diags, opts);
    if (diags.has_errors() || !result.program) {
        Common text = c;
        text.format = "text";
        report(diags, sm, text);
        return std::nullopt;
    }
    return std::move(result.program);
}

int cmd_diff(const std::string& a, const std::string& b, bool runs, const Common& c) {
    if (runs) {
        const io::RunDiff d = io::diff_runs(a, b);
        if (!d.error.empty()) {
            std::cerr << "sdv: error: " << d.error << "\n";
            return kFailure;
        }
        std::cout << (c.format == "json" ? io::render_json(d) : io::render_text(d));
        return d.equal ? kOk : kFailure;
    }
    auto pa = load_program(a, c);
    auto pb = load_program(b, c);
    if (!pa || !pb) return kFailure;
    const auto changes = diff::diff_programs(*pa, *pb);
    std::cout << (c.format == "json" ? diff::render_json(changes) : diff::render_text(changes));
    return changes.empty() ? kOk : kFailure;
}

int cmd_reuse(const std::vector<std::string>& files, const Common& c) {
    std::vector<ir::Program> programs;
    programs.reserve(files.size());
    for (const auto& f : files) {
        auto p = load_program(f, c);
        if (!p) return kFailure;
        programs.push_back(std::move(*p));
    }
    std::vector<io::ReuseInput> inputs;
    for (size_t i = 0; i < files.size(); ++i) {
        for (size_t s = 0; s < programs[i].scenarios.size(); ++s) inputs.push_back({files[i], &programs[i], static_cast<int>(s)});
    }
    if (inputs.size() < 2) {
        std::cerr << "sdv: error: reuse needs at least two scenarios\n";
        return kUsage;
    }
    const io::ReuseReport r = io::reuse(inputs);
    if (!r.error.empty()) {
        std::cerr << r.error << "\n";
        return kFailure;
    }
    std::cout << io::render_reuse(r);
    return kOk;
}

// `sdv convert`: the .sdv text of a GeoScenario input, formatted, checked before it is written.
int cmd_convert(const std::string& file, const std::string& out, const Common& c, const WarningFlags& w) {
    if (!compiler::gss::is_btree_path(file) && !compiler::gss::is_geoscenario_path(file)) {
        std::cerr << "sdv: error: '" << file << "' is neither a GeoScenario scenario (.osm) nor a .btree file\n";
        return kUsage;
    }
    diag::SourceManager sm;
    diag::DiagnosticEngine diags;
    diags.set_policy(w.policy);
    const bool to_stdout = out.empty() || out == "-";
    std::error_code ec;
    const std::string out_dir = to_stdout ? std::filesystem::current_path(ec).string()
                                          : std::filesystem::absolute(out, ec).parent_path().string();
    auto text = convert_input(file, c, out_dir, sm, diags);
    if (!text || diags.has_errors()) {
        report(diags, sm, c);
        return kFailure;
    }
    // The canonical layout, then a check of the result as it will be read back.
    const std::string display =
        to_stdout ? (std::filesystem::path(out_dir) / (std::filesystem::path(file).filename().string() + ".sdv")).string() : out;
    const auto id = sm.add_file(display, *text);
    if (auto formatted = compiler::syntax::format(id, sm, diags)) *text = *formatted;
    compiler::CompileOptions opts{c.import_dirs};
    if (!to_stdout) opts.import_dirs.push_back(out_dir);
    auto result = compiler::compile_source(display, *text, sm, diags, opts);
    if (report(diags, sm, c) || !result.program) return kFailure;
    if (to_stdout) {
        std::cout << *text;
        return kOk;
    }
    if (!write_file(out, *text)) return kFailure;
    std::cout << "wrote " << out << "\n";
    return kOk;
}

// `sdv replay-cosim RECORD`: plays a recorded co-simulation back against a fresh session of
// the same scenario and seed; exit 0 when sdv answers every recorded request with the recorded
// bytes, 1 at the first difference (or an unreadable record).
int cmd_replay_cosim(const std::string& record, const std::string& out, const Common& c) {
    std::string error;
    const auto summary = cosim::summarize_record(record, error);
    if (!summary) {
        std::cerr << "sdv: error: " << error << "\n";
        return kFailure;
    }
    const std::string& file = summary->header.scenario;
    std::ifstream in(file, std::ios::binary);
    if (!in) {
        std::cerr << "sdv: error: cannot read the recorded scenario '" << file << "'\n";
        return kFailure;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    std::optional<ir::Program> program;
    if (compiler::gss::is_geoscenario_path(file)) {
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        auto result = compile_input(file, c, sm, diags);
        if (report(diags, sm, c) || !result.program) return kFailure;
        program = std::move(result.program);
    } else {
        program = load_program(file, c);
        if (!program) return kFailure;
    }
    int index = -1;
    for (size_t i = 0; i < program->scenarios.size(); ++i) {
        if (program->scenarios[i].name == summary->header.scenario_name) index = static_cast<int>(i);
    }
    if (index < 0) {
        std::cerr << "sdv: error: no scenario '" << summary->header.scenario_name << "' in '" << file << "' any more\n";
        return kFailure;
    }
    const std::string sha = cosim::sha256_hex(text);
    if (summary->welcome && summary->welcome->scenario_sha256() != sha) {
        std::cout << "note: '" << file << "' changed since the recording; comparing behaviour with the changed scenario\n";
    }
    auto shared = std::make_shared<const ir::Program>(std::move(*program));
    cosim::SessionOptions so;
    if (summary->welcome) so.seed = summary->welcome->seed();
    so.output_dir = out;
    auto session = cosim::Session::create(shared, index, so, error);
    if (!session) {
        std::cerr << error << "\n";
        return kFailure;
    }
    cosim::WelcomeInfo info = cosim::welcome_info(*shared, index);
    info.sdv_version = compiler::kCompilerVersion;
    info.scenario = summary->welcome ? summary->welcome->scenario() : file;
    info.scenario_sha256 = summary->welcome ? summary->welcome->scenario_sha256() : sha;
    const cosim::ReplayResult r = cosim::replay(record, *session, info);
    if (!r.error.empty()) std::cerr << "sdv: error: " << r.error << "\n";
    if (!r.finish_error.empty()) std::cerr << "sdv: error: " << r.finish_error << "\n";
    if (r.identical) {
        std::cout << "replayed " << r.steps << " step" << (r.steps == 1 ? "" : "s") << " of " << record << ": all "
                  << r.compared << " replies identical\n";
    } else {
        std::cout << "replayed " << r.steps << " step" << (r.steps == 1 ? "" : "s") << " of " << record << ": "
                  << r.differing << " of " << r.compared << " replies differ; " << r.first_difference;
        if (!r.first_difference.empty() && r.first_difference.back() != '\n') std::cout << "\n";
    }
    if (!out.empty() && session->result()) {
        std::cout << io::report(*shared, index, *session->result()) << "outputs in " << out << "\n";
    }
    return r.identical && r.finish_error.empty() ? kOk : kFailure;
}

// The leaves (maneuvers, conditions, expectations) or, with --trees, the standard trees; the
// markdown (docs/catalog.md) has both.
int cmd_catalog(const std::string& format, bool trees) {
    if (trees) {
        const auto std_trees = compiler::std_trees();
        std::cout << (format == "json"       ? compiler::render_std_trees_json(std_trees)
                      : format == "markdown" ? compiler::render_std_trees_markdown(std_trees)
                                             : compiler::render_std_trees_text(std_trees));
    } else if (format == "json") {
        std::cout << catalog::to_json().dump(2) << "\n";
    } else if (format == "markdown") {
        std::cout << catalog::render_markdown() << "\n" << compiler::render_std_trees_markdown(compiler::std_trees());
    } else {
        std::cout << catalog::render_text() << "\nThe standard trees and their parameters: sdv catalog --trees\n";
    }
    return kOk;
}

int run(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    WarningFlags warnings = extract_warning_flags(args);
    if (!warnings.unknown.empty()) {
        std::string list;
        for (const auto& n : kWarningNames) list += (list.empty() ? "" : ", ") + n;
        std::cerr << "sdv: error: unknown warning '" << warnings.unknown[0]
                  << "' (known: " << list << ")\n";
        return kUsage;
    }
    CLI::App app{"sdv: scenario DSL compiler and runtime for the Simulated Driver-Vehicle model"};
    app.set_version_flag("--version", std::string(compiler::kCompilerVersion) + " (IR format " +
                                          std::to_string(ir::kFormatVersion) + ")");
    app.require_subcommand(1);
    Common common;
    auto add_common = [&](CLI::App* sub) {
        sub->add_option("--format", common.format, "diagnostics format")
            ->check(CLI::IsMember({"text", "json"}));
        sub->add_option("-I,--import-dir", common.import_dirs,
                        "extra directory searched for relative imports");
        sub->add_option("--btree-path", common.btree_path,
                        "GeoScenario input: directory searched first for .btree files, NAME.btree "
                        "then sdv/ or sp/NAME.btree (repeatable; then the scenario's directory and "
                        "btrees/ in it and its parents, the reference's layout)");
        sub->add_option("--map-dir", common.map_dirs, "GeoScenario input: directory searched for the map (repeatable)");
    };

    std::vector<std::string> lint_files;
    auto* lint = app.add_subcommand("lint", "parse and check .sdv files; all diagnostics at once. "
                                            "Warnings: -Wno-NAME, -Werror, -Werror=NAME");
    lint->add_option("files", lint_files, ".sdv files")->required();
    bool lint_quiet = false;
    lint->add_flag("-q,--quiet", lint_quiet, "no summary line on success");
    add_common(lint);

    std::string compile_file, compile_out, emit;
    auto* compile = app.add_subcommand("compile", "check a .sdv file and write its IR (.sdvir)");
    compile->add_option("file", compile_file, ".sdv file")->required();
    compile->add_option("-o,--output", compile_out, "output .sdvir file ('-' for stdout)");
    compile->add_option("--emit", emit, "print an intermediate stage instead")
        ->check(CLI::IsMember({"tokens", "ast", "ir"}));
    add_common(compile);

    std::string catalog_format = "text";
    auto* cat = app.add_subcommand("catalog", "every maneuver, condition and expectation with its "
                                              "parameters, units, defaults and meaning");
    cat->add_option("--format", catalog_format, "text, json or markdown")
        ->check(CLI::IsMember({"text", "json", "markdown"}));
    bool catalog_trees = false;
    cat->add_flag("--trees", catalog_trees, "the standard trees instead: parameters, types, defaults and doc comments");

    RunArgs run_args;
    uint64_t seed_value = 0;
    auto* run_cmd = app.add_subcommand("run", "simulate a scenario (.sdv or .sdvir) headless; outputs in -o DIR; "
                                              "exit 1 when an expectation fails");
    run_cmd->add_option("file", run_args.file, ".sdv or .sdvir file")->required();
    run_cmd->add_option("-o,--output", run_args.out, "output directory (default out/<scenario>)");
    auto* seed_opt = run_cmd->add_option("--seed", seed_value, "random seed (overrides the scenario's)");
    run_cmd->add_option("--threads", run_args.threads, "planning threads (results do not depend on it)")
        ->check(CLI::Range(1, 256));
    run_cmd->add_option("--scenario", run_args.scenario, "which scenario of the file");
    run_cmd->add_flag("--trace", run_args.trace, "write decisions.jsonl (every planning decision)");
    run_cmd->add_flag("--realtime", run_args.realtime, "pace the run to the wall clock");
    run_cmd->add_flag("--view", run_args.view, "also write DIR/report.html (see `sdv view`)");
    run_cmd->add_option("--junit", run_args.junit, "also write the expectations as JUnit XML to this file");
    int64_t variant_value = 0;
    auto* variant_opt = run_cmd->add_option("--variant", variant_value,
                                            "run variant K of the scenario's vary block (as `sdv sweep` numbers them)");
    run_cmd->add_flag("--gss-outputs", run_args.gss_outputs,
                      "also write GeoScenario's violations.json and trajectory_v<id>.csv");
    auto* cosim_opt = run_cmd->add_option("--cosim", run_args.cosim,
                                          "co-simulation: serve one client at tcp://HOST:PORT (port 0: any free port; "
                                          "loopback by default) or unix:PATH (docs/cosim.md)");
    run_cmd->add_option("--cosim-port-file", run_args.cosim_port_file,
                        "write the chosen TCP port (or the Unix socket path) to this file once listening")
        ->needs(cosim_opt);
    run_cmd->add_option("--cosim-encoding", run_args.cosim_encoding, "frame payloads: binary protobuf (default) or proto3-JSON")
        ->check(CLI::IsMember({"binary", "json"}))
        ->needs(cosim_opt);
    run_cmd->add_option("--cosim-step-timeout", run_args.cosim_step_timeout,
                        "seconds to wait for each request before aborting with Error TIMEOUT (0: forever, the default)")
        ->needs(cosim_opt);
    run_cmd->add_option("--cosim-connect-timeout", run_args.cosim_connect_timeout,
                        "seconds for the client to connect and send Hello (default 60; 0: forever)")
        ->needs(cosim_opt);
    run_cmd->add_option("--cosim-record", run_args.cosim_record,
                        "record every frame of the session to this file (replay with `sdv replay-cosim`)")
        ->needs(cosim_opt);
    add_common(run_cmd);

    std::string replay_file, replay_out;
    auto* replay_cmd = app.add_subcommand("replay-cosim", "play a recorded co-simulation (--cosim-record) back against a fresh "
                                                          "run; exit 0 when every reply is identical");
    replay_cmd->add_option("file", replay_file, "the record")->required();
    replay_cmd->add_option("-o,--output", replay_out, "also write the run's outputs to this directory");
    add_common(replay_cmd);

    std::vector<std::string> fmt_files;
    bool fmt_check = false, fmt_stdout = false;
    auto* fmt = app.add_subcommand("fmt", "rewrite .sdv files in the canonical layout (comments kept)");
    fmt->add_option("files", fmt_files, ".sdv files")->required();
    fmt->add_flag("--check", fmt_check, "change nothing; exit 1 when a file is not formatted");
    fmt->add_flag("--stdout", fmt_stdout, "print the formatted text instead of rewriting the file");
    add_common(fmt);

    std::string diff_a, diff_b;
    bool diff_runs = false;
    auto* diff_cmd = app.add_subcommand("diff", "semantic difference of two scenarios (.sdv/.sdvir), or with --runs of two "
                                                "run directories; exit 0 equal, 1 different");
    diff_cmd->add_option("a", diff_a, "first .sdv, .sdvir or run directory")->required();
    diff_cmd->add_option("b", diff_b, "second")->required();
    diff_cmd->add_flag("--runs", diff_runs, "compare two run output directories");
    add_common(diff_cmd);

    std::vector<std::string> reuse_files;
    auto* reuse_cmd = app.add_subcommand("reuse", "the paper's internal reuse level (IRL) of a set of scenarios, over all "
                                                  "tree nodes and over the nodes executed in their runs");
    reuse_cmd->add_option("files", reuse_files, ".sdv or .sdvir files")->required();
    add_common(reuse_cmd);

    std::string plot_dir, plot_out = "-";
    auto* plot_cmd = app.add_subcommand("plot", "a static SVG of a run: paths over the road and speed profiles");
    plot_cmd->add_option("run_dir", plot_dir, "a run output directory (sdv run -o)")->required();
    plot_cmd->add_option("-o,--output", plot_out, "SVG file ('-' for stdout)");

    std::string check_file;
    std::string view_dir, view_out;
    SweepArgs sweep_args;
    auto* sweep_cmd = app.add_subcommand("sweep", "run every variant of a scenario's vary block in parallel; one row per "
                                                  "variant in DIR/results.csv, counts in DIR/summary.json; exit 1 when a "
                                                  "variant fails");
    sweep_cmd->add_option("file", sweep_args.file, ".sdv or .sdvir file with a vary block")->required();
    sweep_cmd->add_option("-o,--output", sweep_args.out, "output directory (default out/<scenario>-sweep)");
    sweep_cmd->add_option("--scenario", sweep_args.scenario, "which scenario of the file");
    sweep_cmd->add_option("-j,--jobs", sweep_args.jobs, "variants run at once (default: every core; results do not depend on it)")
        ->check(CLI::Range(1, 1024));
    sweep_cmd->add_flag("--resume", sweep_args.resume, "keep the rows already in DIR and run only the missing variants");
    sweep_cmd->add_option("--keep", sweep_args.keep, "which variants keep a run directory DIR/runs/<variant> with view.html: "
                                                     "none (default), failed or runs (all)")
        ->check(CLI::IsMember({"none", "failed", "runs"}));
    sweep_cmd->add_flag("--report", sweep_args.report, "also write DIR/report.html (heat map, scatter or parallel coordinates)");
    sweep_cmd->add_option("--junit", sweep_args.junit, "also write JUnit XML: a test suite per variant, a case per expectation");
    sweep_cmd->add_option("--slice", sweep_args.slice, "run only slice I of K (I/K), as a Slurm array task does; "
                                                       "results are written once every slice is in (--resume)");
    auto* slurm_opt = sweep_cmd->add_flag("--slurm", sweep_args.slurm, "run the slices as one Slurm job array, wait, and merge");
    sweep_cmd->add_option("--array-tasks", sweep_args.array_tasks, "Slurm array tasks (default 4)")
        ->check(CLI::Range(1, 10000))
        ->needs(slurm_opt);
    sweep_cmd->add_option("--partition", sweep_args.partition, "Slurm partition (default: the cluster's)")->needs(slurm_opt);
    sweep_cmd->add_flag("--slurm-script-only", sweep_args.slurm_script_only,
                        "write DIR/slurm/sweep.sbatch and stop (submit it yourself, then --resume to merge)")
        ->needs(slurm_opt);
    add_common(sweep_cmd);

    SearchArgs search_args;
    auto* search_cmd = app.add_subcommand("search", "find the variant of a scenario's vary block that minimises (or "
                                                    "maximises) a metric, with NLopt within a budget of runs");
    search_cmd->add_option("file", search_args.file, ".sdv or .sdvir file with a vary block")->required();
    search_cmd->add_option("-o,--output", search_args.out, "output directory (default out/<scenario>-search)");
    search_cmd->add_option("--scenario", search_args.scenario, "which scenario of the file");
    search_cmd->add_option("--minimize", search_args.minimize, "the metric to minimise, as an expectation names it: "
                                                               "'min_ttc(ego, v2)'");
    search_cmd->add_option("--maximize", search_args.maximize, "the metric to maximise: 'max_jerk(ego)'");
    search_cmd->add_option("--budget", search_args.budget, "runs at most (default 200)")->check(CLI::Range(1, 1000000));
    search_cmd->add_option("--seed", search_args.seed, "seed of the optimiser's global phase (default 1)");
    search_cmd->add_option("--write", search_args.write, "the worst case as a .sdv file (default OUT/worst.sdv)");
    add_common(search_cmd);

    auto* view_cmd = app.add_subcommand("view", "one self-contained HTML report of a run (map, playback, charts, "
                                                "timeline, expectations, decisions); opens offline");
    view_cmd->add_option("run_dir", view_dir, "a run output directory (sdv run -o; --trace adds the decisions), or a sweep's (sdv sweep -o)")->required();
    view_cmd->add_option("-o,--output", view_out, "HTML file (default RUN_DIR/report.html; '-' for stdout)");

    std::string convert_file, convert_out, convert_map, convert_sdv;
    auto* convert_cmd = app.add_subcommand("convert", "convert a GeoScenario scenario (.osm), behavior tree (.btree) or "
                                                      "recorded traffic (CommonRoad .xml, INTERACTION .csv) into .sdv source");
    convert_cmd->add_option("file", convert_file, ".gs.osm scenario, .btree file or recording")->required();
    convert_cmd->add_option("-o,--output", convert_out, "output .sdv file ('-' for stdout, the default)");
    convert_cmd->add_option("--map", convert_map, "a recording's Lanelet2 map (INTERACTION tracks)");
    convert_cmd->add_option("--sdv", convert_sdv, "a recording: replace this recorded vehicle by an SDV");
    add_common(convert_cmd);

    ReplayArgs replay_args;
    auto* realism_replay = app.add_subcommand("replay", "replace recorded vehicles by SDVs one at a time, everything else as "
                                                        "recorded, and measure how far each drives from its recording (STED)");
    realism_replay->add_option("recording", replay_args.recording, "CommonRoad scenario (.xml) or INTERACTION track file (.csv)")
        ->required();
    realism_replay->add_option("--map", replay_args.map, "the Lanelet2 map of INTERACTION tracks (local metres)");
    realism_replay->add_option("--sdv", replay_args.sdv, "the recorded vehicles replaced: an id, a comma-separated list, or all (default)");
    realism_replay->add_option("--tree", replay_args.tree,
                               "the SDVs' tree call, e.g. 'std.drive(speed = 12 m/s, time_gap = 1.5 s)' (default std.drive at the "
                               "start lane's speed limit)");
    realism_replay->add_option("--import", replay_args.imports, "a .sdv file the tree comes from (repeatable)");
    realism_replay->add_option("-j,--jobs", replay_args.jobs, "replays run at once (default: every core; results do not depend on it)")
        ->check(CLI::Range(1, 1024));
    realism_replay->add_option("-o,--output", replay_args.out, "output directory (default out/<recording>-replay)");
    add_common(realism_replay);

    CalibrateArgs calib_args;
    auto* calibrate_cmd = app.add_subcommand("calibrate", "fit driving-style parameters (a tree's arguments) to a recording: "
                                                          "minimise mean STED on training vehicles, report held-out STED");
    calibrate_cmd->add_option("recording", calib_args.recording, "CommonRoad scenario (.xml) or INTERACTION track file (.csv)")
        ->required();
    calibrate_cmd->add_option("--params", calib_args.params, "the parameters fitted: NAME or NAME=LO..HI, comma-separated")->required();
    calibrate_cmd->add_option("--map", calib_args.map, "the Lanelet2 map of INTERACTION tracks (local metres)");
    calibrate_cmd->add_option("--sdv", calib_args.sdv, "the recorded vehicles used: ids, comma-separated, or all (default)");
    calibrate_cmd->add_option("--tree", calib_args.tree, "the tree whose parameters are fitted, as a call (default std.drive())");
    calibrate_cmd->add_option("--import", calib_args.imports, "a .sdv file the tree comes from (repeatable)");
    calibrate_cmd->add_option("--split", calib_args.split, "the share of vehicles used for training (default 0.7); the rest are held out");
    calibrate_cmd->add_option("--seed", calib_args.seed, "seed of the training/held-out split and the optimiser (default 1)");
    calibrate_cmd->add_option("--budget", calib_args.budget, "objective evaluations (default 60)");
    calibrate_cmd->add_option("-j,--jobs", calib_args.jobs, "replays run at once (default: every core)")->check(CLI::Range(1, 1024));
    calibrate_cmd->add_option("-o,--output", calib_args.out, "output directory (default out/<recording>-calibrate)");
    add_common(calibrate_cmd);

    auto* check_ir = app.add_subcommand("check-ir", "validate a .sdvir file (format, version, hash, "
                                                    "structure)");
    check_ir->add_option("file", check_file, ".sdvir file")->required();

    // `sdv` alone and `sdv help [SUBCOMMAND]`: the subcommands (or one's options), not only
    // "a subcommand is required".
    if (args.empty() || args[0] == "help") {
        CLI::App* which = &app;
        if (args.size() > 1) {
            try {
                which = app.get_subcommand(args[1]);
            } catch (const CLI::OptionNotFound&) {
                std::cerr << "sdv: error: no subcommand '" << args[1] << "'\n" << app.help();
                return kUsage;
            }
        }
        (args.empty() ? std::cerr : std::cout) << which->help();
        return args.empty() ? kUsage : kOk;
    }
    std::vector<const char*> cargv;
    cargv.push_back(argv[0]);
    for (const auto& a : args) cargv.push_back(a.c_str());
    try {
        app.parse(static_cast<int>(cargv.size()), const_cast<char**>(cargv.data()));
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return kUsage;
    }

    if (lint->parsed()) return cmd_lint(lint_files, common, warnings, lint_quiet);
    if (compile->parsed()) return cmd_compile(compile_file, compile_out, emit, common, warnings);
    if (cat->parsed()) return cmd_catalog(catalog_format, catalog_trees);
    if (convert_cmd->parsed()) {
        if (is_recording_path(convert_file)) return cmd_convert_recording(convert_file, convert_map, convert_sdv, convert_out, common);
        return cmd_convert(convert_file, convert_out, common, warnings);
    }
    if (realism_replay->parsed()) return cmd_replay(replay_args, common);
    if (calibrate_cmd->parsed()) return cmd_calibrate(calib_args, common);
    if (sweep_cmd->parsed()) return cmd_sweep(sweep_args, common, warnings);
    if (search_cmd->parsed()) return cmd_search(search_args, common, warnings);
    if (view_cmd->parsed()) {
        std::string error;
        // A sweep directory gets the sweep's report; a run directory the run's.
        const bool sweep = std::filesystem::exists(std::filesystem::path(view_dir) / "results.csv");
        const std::string html = sweep ? io::sweep_report(view_dir, error) : io::view_report(view_dir, error);
        const std::string out = view_out.empty() ? (std::filesystem::path(view_dir) / "report.html").string() : view_out;
        return emit_report(html, error, out, true);
    }
    if (fmt->parsed()) return cmd_fmt(fmt_files, fmt_check, fmt_stdout, common);
    if (diff_cmd->parsed()) return cmd_diff(diff_a, diff_b, diff_runs, common);
    if (reuse_cmd->parsed()) return cmd_reuse(reuse_files, common);
    if (plot_cmd->parsed()) {
        std::string error;
        const std::string svg = io::plot_run(plot_dir, error);
        return emit_report(svg, error, plot_out, false);
    }
    if (replay_cmd->parsed()) return cmd_replay_cosim(replay_file, replay_out, common);
    if (run_cmd->parsed()) {
        if (seed_opt->count() > 0) run_args.seed = seed_value;
        if (variant_opt->count() > 0) run_args.variant = variant_value;
        return cmd_run(run_args, common, warnings);
    }
    if (check_ir->parsed()) {
        std::ifstream in(check_file, std::ios::binary);
        if (!in) {
            std::cerr << "sdv: error: cannot read '" << check_file << "'\n";
            return kFailure;
        }
        std::stringstream ss;
        ss << in.rdbuf();
        auto r = ir::read_ir(ss.str());
        if (!r.program) {
            std::cerr << check_file << ": error: " << r.error << "\n";
            return kFailure;
        }
        std::cout << summary(*r.program, ir::program_hash(*r.program));
        return kOk;
    }
    return kUsage;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "sdv: internal error: " << e.what() << "\n";
        return kInternal;
    } catch (...) {
        std::cerr << "sdv: internal error\n";
        return kInternal;
    }
}
