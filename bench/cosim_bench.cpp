// Co-simulation step cost (issue 15): N SDVs on a straight road with an external ego that keeps
// its lane at 13 m/s for 2 simulated minutes, stepped (a) through the C API (libsdv.so), (b) by a
// client over loopback TCP in the binary encoding (the server of `sdv run --cosim` in a thread
// of this process, the client in another: a round trip per step), against (c) the same scenario
// run without co-simulation (the ego a trajectory vehicle on the same path). Reports steps/s and
// the per-step time percentiles, and what each adds to (c) at the median.
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

#include <memory>
#include <thread>

#include "compiler/sema/compile.h"
#include "include/sdv/sdv.h"
#include "runtime/cosim/codec.h"
#include "runtime/cosim/framing.h"
#include "runtime/cosim/protocol.h"
#include "runtime/cosim/server.h"
#include "runtime/cosim/transport.h"
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

// Per-step round trips of a binary client over loopback TCP: send the ego's state, wait for the
// StepResult (which carries every actor's state and the events).
std::vector<double> run_tcp(const sdv::ir::Program& program) {
    namespace cosim = sdv::cosim;
    namespace v1 = sdv::cosim::v1;
    std::string error;
    auto shared = std::make_shared<const sdv::ir::Program>(program);
    auto session = cosim::Session::create(shared, 0, {}, error);
    const auto endpoint = cosim::parse_endpoint("tcp://127.0.0.1:0", error);
    auto server = session && endpoint ? cosim::Server::listen(*endpoint, {}, {}, error) : nullptr;
    if (!server) {
        std::fprintf(stderr, "cosim_bench: %s\n", error.c_str());
        std::exit(1);
    }
    const cosim::WelcomeInfo info = cosim::welcome_info(*shared, 0);
    std::thread serving([&] { server->serve(*session, info); });
    const auto to = cosim::parse_endpoint("tcp://127.0.0.1:" + std::to_string(server->port()), error);
    cosim::Socket sock = cosim::connect_to(*to, cosim::deadline_after(10), error);
    auto send = [&](const v1::Envelope& e) { cosim::write_frame(sock.fd(), cosim::encode(e, cosim::Encoding::binary), std::nullopt); };
    auto receive = [&](v1::Envelope& e) {
        std::string payload;
        cosim::read_frame(sock.fd(), payload, std::nullopt);
        cosim::decode(payload, cosim::Encoding::binary, e, error);
    };
    v1::Envelope hello;
    hello.set_seq(1);
    hello.mutable_hello()->set_protocol("sdv-cosim");
    hello.mutable_hello()->set_version_major(1);
    auto* claim = hello.mutable_hello()->add_claims();
    claim->set_actor_name("ego");
    claim->set_mode(v1::CONTROL_MODE_POSE);
    send(hello);
    v1::Envelope in;
    receive(in);
    v1::ActorState me = in.welcome().initial().actors(0);
    uint64_t tick = in.welcome().initial().tick();
    std::vector<double> step_us;
    for (uint64_t seq = 2;; ++seq) {
        const auto t0 = Clock::now();
        v1::Envelope req;
        req.set_seq(seq);
        req.mutable_step()->set_tick(tick);
        me.set_x(me.x() + 13.0 / 30);
        me.set_speed(13);
        auto* up = req.mutable_step()->add_updates();
        up->set_id(me.id());
        *up->mutable_state() = me;
        send(req);
        receive(in);
        step_us.push_back(us_since(t0));
        if (!in.has_step_result()) break;
        tick = in.step_result().observation().tick();
        if (in.step_result().run_state() != v1::StepResult::RUNNING) break;
    }
    v1::Envelope bye;
    bye.mutable_bye()->set_reason("done");
    send(bye);
    serving.join();
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
    sdv::diag::DiagnosticEngine diags;
    auto plain = sdv::compiler::compile_source("plain.sdv", scenario(n, false), sm, diags);
    if (!plain.program) {
        std::fprintf(stderr, "cosim_bench: the plain scenario does not compile\n");
        return 1;
    }
    std::printf("%d SDVs + 1 external ego, 120 s at 30 Hz, one thread, best of %d runs by median\n", n, repeat);
    std::printf("%-26s %10s %10s %10s %12s\n", "run", "steps/s", "p50 us", "p99 us", "steps");
    sdv::diag::SourceManager sm2;
    sdv::diag::DiagnosticEngine diags2;
    auto external = sdv::compiler::compile_source("external.sdv", scenario(n, true), sm2, diags2);
    if (!external.program) {
        std::fprintf(stderr, "cosim_bench: the external scenario does not compile\n");
        return 1;
    }
    std::vector<double> best_c, best_p, best_t;
    auto keep = [](std::vector<double>& best, std::vector<double> v) {
        if (best.empty() || pct(v, 0.5) < pct(best, 0.5)) best = std::move(v);
    };
    for (int r = 0; r < repeat; ++r) {
        keep(best_c, run_capi(path));
        keep(best_p, run_plain(*plain.program));
        keep(best_t, run_tcp(*external.program));
    }
    auto row = [](const char* name, const std::vector<double>& v) {
        double total = 0;
        for (double x : v) total += x;
        std::printf("%-26s %10.0f %10.1f %10.1f %12zu\n", name, static_cast<double>(v.size()) / (total * 1e-6), pct(v, 0.5), pct(v, 0.99), v.size());
    };
    row("without co-simulation", best_p);
    row("C API (in process)", best_c);
    row("TCP loopback, binary", best_t);
    std::printf("added per step (p50): C API %.1f us, TCP %.1f us\n", pct(best_c, 0.5) - pct(best_p, 0.5),
                pct(best_t, 0.5) - pct(best_p, 0.5));
    std::remove(path.c_str());
    return 0;
}
