// The server over real sockets (TCP on an ephemeral port, Unix sockets) with an in-test client on
// a thread: whole sessions, the exit statuses of every way a session ends, several servers in one
// process, and record/replay.
#include "runtime/cosim/server.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "cosim_fixture.h"
#include "runtime/cosim/replay.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace server_test {

using namespace sdv;
using namespace sdv::cosim;

namespace {

using sdv::test::temp_dir;

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

struct Running {
    std::unique_ptr<Session> session;
    std::unique_ptr<Server> server;
    Endpoint endpoint;  // where the client connects
};

Running start(const std::string& where, ServerOptions options, const std::string& output_dir = "") {
    Running r;
    r.session = test::cosim_session(output_dir);
    std::string e;
    auto ep = parse_endpoint(where, e);
    REQUIRE(ep);
    RecordHeader h;
    h.scenario = "cosim_highway.sdv";
    h.scenario_name = "cosim_highway";
    r.server = Server::listen(*ep, options, h, e);
    INFO(e);
    REQUIRE(r.server);
    r.endpoint = *ep;
    r.endpoint.port = r.server->port();
    return r;
}

WelcomeInfo info() { return WelcomeInfo{"test", "cosim_highway.sdv", "ab", "", false, 0, 0, 0}; }

// A client over a socket: sends a message, reads the reply.
struct Wire {
    Socket s;
    Encoding enc;
    Wire(const Endpoint& ep, Encoding e) : enc(e) {
        std::string error;
        s = connect_to(ep, deadline_after(30), error);
        INFO(error);
        REQUIRE(s.valid());
    }
    void send(const v1::Envelope& m) {
        REQUIRE(write_frame(s.fd(), encode(m, enc), deadline_after(30)).empty());
    }
    v1::Envelope receive() {
        std::string payload;
        const FrameRead f = read_frame(s.fd(), payload, deadline_after(60));
        INFO(f.error);
        REQUIRE(f.status == FrameStatus::ok);
        v1::Envelope m;
        std::string error;
        REQUIRE(decode(payload, enc, m, error));
        return m;
    }
    // The server closes after an Error.
    bool closed_by_server() {
        std::string payload;
        return read_frame(s.fd(), payload, deadline_after(30)).status == FrameStatus::eof;
    }
};

// Drives the whole run and says Bye; returns the observations' bytes.
std::string full_session(const Endpoint& ep, Encoding enc, uint64_t steps = 1000) {
    Wire w(ep, enc);
    w.send(test::hello());
    v1::Envelope m = w.receive();
    REQUIRE(m.has_welcome());
    v1::Observation obs = m.welcome().initial();
    std::string trace = obs.SerializeAsString();
    for (uint64_t k = 0; k < steps; ++k) {
        w.send(test::step(k + 2, obs));
        m = w.receive();
        REQUIRE(m.has_step_result());
        obs = m.step_result().observation();
        trace += obs.SerializeAsString();
        if (m.step_result().run_state() != v1::StepResult::RUNNING) break;
    }
    w.send(test::bye(9999));
    CHECK(w.closed_by_server());
    return trace;
}

}  // namespace

TEST_CASE(
    "server: a whole session over TCP, outputs written, exit 0; the port file holds the port") {
    const std::string dir = temp_dir();
    ServerOptions o;
    o.port_file = dir + "/port";
    Running r = start("tcp://127.0.0.1:0", o, dir + "/out");
    CHECK(slurp(o.port_file) == std::to_string(r.server->port()) + "\n");
    std::thread client([&] { full_session(r.endpoint, Encoding::binary); });
    const ServeResult res = r.server->serve(*r.session, info());
    client.join();
    CHECK(res.outcome.kind == Protocol::Outcome::Kind::bye);
    CHECK(res.exit_status == kExitOk);
    CHECK(res.steps == 120);
    CHECK(res.client_name == "doctest");
    CHECK(res.finish_error.empty());
    const std::string summary = slurp(dir + "/out/summary.json");
    CHECK(summary.find("\"cosim\"") != std::string::npos);
    CHECK(summary.find("\"aborted\": false") != std::string::npos);
    CHECK(std::filesystem::exists(dir + "/out/trajectories.csv"));
    std::filesystem::remove_all(dir);
}

TEST_CASE("server: JSON over a Unix socket gives the same observations as binary over TCP") {
    const std::string dir = temp_dir();
    std::string tcp_trace, unix_trace;
    {
        Running r = start("tcp://127.0.0.1:0", ServerOptions{});
        std::thread client([&] { tcp_trace = full_session(r.endpoint, Encoding::binary); });
        CHECK(r.server->serve(*r.session, info()).exit_status == kExitOk);
        client.join();
    }
    {
        ServerOptions o;
        o.encoding = Encoding::json;
        o.port_file = dir + "/port";
        Running r = start("unix:" + dir + "/s.sock", o);
        CHECK(slurp(o.port_file) == dir + "/s.sock\n");
        std::thread client([&] { unix_trace = full_session(r.endpoint, Encoding::json); });
        CHECK(r.server->serve(*r.session, info()).exit_status == kExitOk);
        client.join();
    }
    CHECK(!tcp_trace.empty());
    CHECK(tcp_trace == unix_trace);
    std::filesystem::remove_all(dir);
}

TEST_CASE("server: several servers and sessions at once in one process") {
    std::vector<Running> runs;
    for (int i = 0; i < 3; ++i) runs.push_back(start("tcp://127.0.0.1:0", ServerOptions{}));
    std::vector<std::string> traces(runs.size());
    std::vector<std::thread> threads;
    std::vector<int> status(runs.size(), -1);
    for (size_t i = 0; i < runs.size(); ++i) {
        threads.emplace_back(
            [&, i] { traces[i] = full_session(runs[i].endpoint, Encoding::binary, 40); });
        threads.emplace_back(
            [&, i] { status[i] = runs[i].server->serve(*runs[i].session, info()).exit_status; });
    }
    for (auto& t : threads) t.join();
    for (size_t i = 0; i < runs.size(); ++i) {
        CHECK(traces[i] == traces[0]);
        CHECK(status[i] == kExitOk);  // an early Bye: the verdict of the ticks run
    }
}

TEST_CASE("server: a client that disconnects mid-session: exit 4, outputs marked aborted") {
    const std::string dir = temp_dir();
    Running r = start("tcp://127.0.0.1:0", ServerOptions{}, dir + "/out");
    std::thread client([&] {
        Wire w(r.endpoint, Encoding::binary);
        w.send(test::hello());
        v1::Observation obs = w.receive().welcome().initial();
        w.send(test::step(2, obs));
        obs = w.receive().step_result().observation();
        // Half a frame, then gone.
        REQUIRE(write_all(w.s.fd(), frame_prefix(100) + "abc", deadline_after(5)).empty());
    });
    const ServeResult res = r.server->serve(*r.session, info());
    client.join();
    CHECK(res.outcome.kind == Protocol::Outcome::Kind::disconnected);
    CHECK(res.exit_status == kExitDisconnected);
    const std::string summary = slurp(dir + "/out/summary.json");
    CHECK(summary.find("aborted: client disconnected") != std::string::npos);
    CHECK(summary.find("\"aborted\": true") != std::string::npos);
    std::filesystem::remove_all(dir);
}

TEST_CASE("server: a stalled client gets Error TIMEOUT after --cosim-step-timeout: exit 6") {
    ServerOptions o;
    o.step_timeout_s = 0.3;
    Running r = start("tcp://127.0.0.1:0", o);
    std::thread client([&] {
        Wire w(r.endpoint, Encoding::binary);
        w.send(test::hello());
        REQUIRE(w.receive().has_welcome());
        const v1::Envelope e = w.receive();  // sends nothing: the server gives up
        REQUIRE(e.has_error());
        CHECK(e.error().code() == v1::Error::TIMEOUT);
        CHECK(e.error().message() == "no request within 0.3 s (--cosim-step-timeout)");
        CHECK(w.closed_by_server());
    });
    const ServeResult res = r.server->serve(*r.session, info());
    client.join();
    CHECK(res.exit_status == kExitTimeout);
}

TEST_CASE("server: no client within --cosim-connect-timeout: exit 6") {
    ServerOptions o;
    o.connect_timeout_s = 0.1;
    Running r = start("tcp://127.0.0.1:0", o);
    const ServeResult res = r.server->serve(*r.session, info());
    CHECK(res.outcome.kind == Protocol::Outcome::Kind::timeout);
    CHECK(res.outcome.message.find("no client connected within 0.1 s") != std::string::npos);
    CHECK(res.exit_status == kExitTimeout);
}

TEST_CASE("server: a client that connects and never says Hello times out on the connect time-out") {
    ServerOptions o;
    o.connect_timeout_s = 0.3;
    Running r = start("tcp://127.0.0.1:0", o);
    std::thread client([&] {
        Wire w(r.endpoint, Encoding::binary);
        const v1::Envelope e = w.receive();
        CHECK(e.error().code() == v1::Error::TIMEOUT);
        CHECK(e.error().message().find("no Hello within") != std::string::npos);
    });
    CHECK(r.server->serve(*r.session, info()).exit_status == kExitTimeout);
    client.join();
}

TEST_CASE(
    "server: a 1 GiB length prefix gets FRAME_TOO_LARGE and garbage a PROTOCOL_VIOLATION: exit 5") {
    {
        Running r = start("tcp://127.0.0.1:0", ServerOptions{});
        std::thread client([&] {
            Wire w(r.endpoint, Encoding::binary);
            REQUIRE(write_all(w.s.fd(), frame_prefix(1u << 30) + std::string(1000, 'x'),
                              deadline_after(5))
                        .empty());
            const v1::Envelope e = w.receive();
            CHECK(e.error().code() == v1::Error::FRAME_TOO_LARGE);
            CHECK(e.error().message() ==
                  "frame of 1073741824 bytes exceeds the maximum of 67108864 bytes");
        });
        CHECK(r.server->serve(*r.session, info()).exit_status == kExitProtocolError);
        client.join();
    }
    {
        ServerOptions o;
        o.encoding = Encoding::json;
        Running r = start("tcp://127.0.0.1:0", o);
        std::thread client([&] {
            Wire w(r.endpoint, Encoding::json);
            REQUIRE(write_frame(w.s.fd(), "\x01\x02 not json at all", deadline_after(5)).empty());
            const v1::Envelope e = w.receive();
            CHECK(e.error().code() == v1::Error::PROTOCOL_VIOLATION);
            CHECK(w.closed_by_server());
        });
        const ServeResult res = r.server->serve(*r.session, info());
        CHECK(res.exit_status == kExitProtocolError);
        CHECK(res.outcome.code == v1::Error::PROTOCOL_VIOLATION);
        client.join();
    }
}

TEST_CASE(
    "record/replay: a recorded session replays byte-identical; another seed differs at a tick") {
    const std::string dir = temp_dir();
    ServerOptions o;
    o.record_path = dir + "/session.cosim";
    o.encoding = Encoding::json;
    {
        Running r = start("tcp://127.0.0.1:0", o, dir + "/a");
        std::thread client([&] { full_session(r.endpoint, Encoding::json, 50); });
        CHECK(r.server->serve(*r.session, info()).exit_status == kExitOk);
        client.join();
    }
    std::string error;
    const auto summary = summarize_record(o.record_path, error);
    INFO(error);
    REQUIRE(summary);
    CHECK(summary->header.encoding == Encoding::json);
    CHECK(summary->header.scenario_name == "cosim_highway");
    REQUIRE(summary->welcome);
    CHECK(summary->welcome->seed() == 7);
    {
        auto session = test::cosim_session(dir + "/b", summary->welcome->seed());
        const ReplayResult res = replay(o.record_path, *session, info());
        INFO(res.error, res.first_difference);
        CHECK(res.identical);
        CHECK(res.compared == 51);  // Welcome and 50 StepResults
        CHECK(res.steps == 50);
        CHECK(res.outcome.kind == Protocol::Outcome::Kind::bye);
        CHECK(slurp(dir + "/a/trajectories.csv") == slurp(dir + "/b/trajectories.csv"));
        CHECK(slurp(dir + "/a/summary.json") == slurp(dir + "/b/summary.json"));
    }
    {
        // The same requests against a scenario run with another seed: the NPCs' sampling differs.
        // (Whatever the seed changes shows at some tick; the report names the first.)
        auto session = test::cosim_session("", 8);
        const ReplayResult res = replay(o.record_path, *session, info());
        CHECK_FALSE(res.identical);
        CHECK(res.differing >= 1);
        CHECK(res.first_difference.find("first difference at Welcome") != std::string::npos);
        CHECK(res.first_difference.find("seed") != std::string::npos);
    }
    {
        // A record whose reply at tick 10 was changed: the replay names that tick and the field.
        RecordHeader h;
        h.encoding = Encoding::json;
        auto w = RecordWriter::create(dir + "/changed.cosim", h, error);
        REQUIRE(w);
        auto rd = RecordReader::open(o.record_path, error);
        REQUIRE(rd);
        Direction d;
        std::string payload;
        while (rd->next(d, payload, error) == RecordReader::Next::frame) {
            v1::Envelope m;
            std::string why;
            if (d == Direction::server && decode(payload, Encoding::json, m, why) &&
                m.has_step_result() && m.step_result().observation().tick() == 10) {
                auto* lead = m.mutable_step_result()->mutable_observation()->mutable_actors(1);
                lead->set_x(lead->x() + 0.001);
                payload = encode(m, Encoding::json);
            }
            REQUIRE(w->append(d, payload).empty());
        }
        w.reset();
        auto session = test::cosim_session();
        const ReplayResult res = replay(dir + "/changed.cosim", *session, info());
        CHECK_FALSE(res.identical);
        CHECK(res.differing == 1);
        INFO(res.first_difference);
        CHECK(res.first_difference.find("first difference at tick 10 (seq 11)") !=
              std::string::npos);
        CHECK(res.first_difference.find("actors[1].x") != std::string::npos);
    }
    {
        // A record cut in the middle of an entry (a killed session) replays up to the cut.
        const std::string full = slurp(o.record_path);
        std::ofstream(dir + "/cut.cosim", std::ios::binary) << full.substr(0, full.size() / 2);
        auto session = test::cosim_session();
        const ReplayResult res = replay(dir + "/cut.cosim", *session, info());
        CHECK(res.error.find("entry") != std::string::npos);
        CHECK(res.outcome.kind == Protocol::Outcome::Kind::disconnected);
    }
    {
        std::ofstream(dir + "/not.cosim") << "hello";
        CHECK_FALSE(summarize_record(dir + "/not.cosim", error));
        CHECK(error.find("no sdv-cosim record") != std::string::npos);
    }
    std::filesystem::remove_all(dir);
}

TEST_CASE("record/replay: sessions that end in an Error replay identically too") {
    const std::string dir = temp_dir();
    ServerOptions o;
    o.record_path = dir + "/bad.cosim";
    {
        Running r = start("tcp://127.0.0.1:0", o);
        std::thread client([&] {
            Wire w(r.endpoint, Encoding::binary);
            w.send(test::hello());
            v1::Observation obs = w.receive().welcome().initial();
            for (int k = 0; k < 5; ++k) {
                w.send(test::step(1, obs));
                obs = w.receive().step_result().observation();
            }
            v1::Envelope s = test::step(1, obs);
            s.mutable_step()->set_tick(3);
            w.send(s);
            CHECK(w.receive().error().code() == v1::Error::BAD_TICK);
        });
        CHECK(r.server->serve(*r.session, info()).exit_status == kExitProtocolError);
        client.join();
    }
    {
        Running r = start("tcp://127.0.0.1:0", ServerOptions{.encoding = Encoding::binary,
                                                             .connect_timeout_s = 60,
                                                             .step_timeout_s = 0,
                                                             .port_file = "",
                                                             .record_path = dir + "/big.cosim"});
        std::thread client([&] {
            Wire w(r.endpoint, Encoding::binary);
            REQUIRE(write_all(w.s.fd(), frame_prefix(1u << 30), deadline_after(5)).empty());
            CHECK(w.receive().error().code() == v1::Error::FRAME_TOO_LARGE);
        });
        CHECK(r.server->serve(*r.session, info()).exit_status == kExitProtocolError);
        client.join();
    }
    for (const char* name : {"/bad.cosim", "/big.cosim"}) {
        auto session = test::cosim_session();
        const ReplayResult res = replay(dir + name, *session, info());
        INFO(name, res.error, res.first_difference);
        CHECK(res.identical);
        CHECK(res.outcome.kind == Protocol::Outcome::Kind::error);
    }
    std::filesystem::remove_all(dir);
}

}  // namespace server_test
