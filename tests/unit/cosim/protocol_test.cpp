// The sdv-cosim v1 state machine over a real session: the handshake, lockstep steps, the end,
// and every Error code a client can provoke.
#include "runtime/cosim/protocol.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "cosim_fixture.h"
#include "runtime/sim/road_cache.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace protocol_test {

using namespace sdv;
using namespace sdv::cosim;
using sdv::test::bye;
using sdv::test::exchange;
using sdv::test::hello;
using sdv::test::step;

namespace {

struct Client {
    std::unique_ptr<Session> session = test::cosim_session();
    Protocol protocol;
    explicit Client(Encoding enc = Encoding::binary)
        : protocol(*session, WelcomeInfo{"test", "s.sdv", "00", "", false, 0, 0, 0}, enc) {}
};

// The reply must be an Error with this code; the session is then closed.
void expect_error(Protocol& p, const v1::Envelope& reply, v1::Error::Code code,
                  const std::string& part) {
    REQUIRE(reply.has_error());
    CHECK(code_name(reply.error().code()) == code_name(code));
    INFO(reply.error().message());
    CHECK(reply.error().message().find(part) != std::string::npos);
    CHECK(p.closed());
    CHECK(p.outcome().kind == (code == v1::Error::TIMEOUT ? Protocol::Outcome::Kind::timeout
                                                          : Protocol::Outcome::Kind::error));
    CHECK(p.outcome().ending.rfind("aborted: " + code_name(code), 0) == 0);
    // Nothing is answered after an Error.
    CHECK_FALSE(p.on_frame(encode(hello(), p.encoding())));
}

}  // namespace

TEST_CASE("protocol: Hello, Welcome, lockstep steps to the end, Bye") {
    Client c;
    const v1::Envelope w = exchange(c.protocol, hello(5));
    REQUIRE(w.has_welcome());
    CHECK(w.seq() == 5);
    const v1::Welcome& welcome = w.welcome();
    CHECK(welcome.version_major() == 1);
    CHECK(welcome.step_num() == 1);
    CHECK(welcome.step_den() == 30);
    CHECK(welcome.seed() == 7);
    CHECK(welcome.sdv_version() == "test");
    CHECK(welcome.scenario() == "s.sdv");
    CHECK(welcome.has_origin());
    REQUIRE(welcome.actors_size() == 3);
    CHECK(welcome.actors(0).name() == "ego");
    CHECK(welcome.actors(0).external());
    CHECK(welcome.actors(0).kind() == v1::ActorInfo::KIND_CAR);
    CHECK_FALSE(welcome.actors(1).external());
    CHECK(welcome.initial().tick() == 0);
    REQUIRE(welcome.initial().actors_size() == 3);
    CHECK(welcome.initial().actors(0).id() == 1);
    CHECK(welcome.initial().actors(0).speed() == doctest::Approx(10));
    CHECK(c.protocol.phase() == Protocol::Phase::running);

    v1::Observation obs = welcome.initial();
    uint64_t seq = 10;
    v1::StepResult::RunState rs = v1::StepResult::RUNNING;
    bool ended_event = false;
    while (rs == v1::StepResult::RUNNING) {
        const v1::ActorState want = test::ego_next(obs);
        const v1::Envelope r = exchange(c.protocol, step(seq, obs));
        REQUIRE(r.has_step_result());
        CHECK(r.seq() == seq);
        const uint64_t k = obs.tick();
        obs = r.step_result().observation();
        CHECK(obs.tick() == k + 1);
        CHECK(obs.time_s() == static_cast<double>(obs.tick()) / 30.0);
        // The ego is where the client put it.
        CHECK(obs.actors(0).x() == want.x());
        CHECK(obs.actors(0).y() == want.y());
        for (const auto& e : r.step_result().events()) {
            CHECK(e.tick() == obs.tick());
            if (e.has_scenario_end()) ended_event = true;
        }
        rs = r.step_result().run_state();
        ++seq;
        REQUIRE(seq < 1000);
    }
    CHECK(obs.tick() == 120);  // timeout 4 s
    CHECK(ended_event);
    CHECK(c.protocol.phase() == Protocol::Phase::ended);
    CHECK(c.protocol.steps() == 120);
    CHECK_FALSE(exchange(c.protocol, bye(seq)).body_case());
    CHECK(c.protocol.closed());
    CHECK(c.protocol.outcome().kind == Protocol::Outcome::Kind::bye);
    CHECK(c.protocol.outcome().ending == "bye: done");
    CHECK(c.protocol.finish().empty());
    REQUIRE(c.session->result());
}

TEST_CASE("protocol: the ego moves as the client says, and the NPCs react to it") {
    Client c;
    v1::Observation obs = exchange(c.protocol, hello()).welcome().initial();
    const double x0 = obs.actors(0).x();
    for (int k = 0; k < 30; ++k) {
        const v1::Envelope r = exchange(c.protocol, step(static_cast<uint64_t>(k), obs));
        REQUIRE(r.has_step_result());
        obs = r.step_result().observation();
    }
    CHECK(obs.actors(0).x() == doctest::Approx(x0 + 10.0).epsilon(1e-9));
    CHECK(obs.actors(0).lane_id() != "");
    CHECK(obs.actors(1).x() > 90.0);  // the lead drives on
}

TEST_CASE("protocol: binary and JSON sessions give the same observations, bit for bit") {
    Client b(Encoding::binary), j(Encoding::json);
    v1::Observation ob = exchange(b.protocol, hello()).welcome().initial();
    v1::Observation oj = exchange(j.protocol, hello()).welcome().initial();
    for (int k = 0; k < 60; ++k) {
        ob = exchange(b.protocol, step(static_cast<uint64_t>(k + 1), ob))
                 .step_result()
                 .observation();
        oj = exchange(j.protocol, step(static_cast<uint64_t>(k + 1), oj))
                 .step_result()
                 .observation();
        REQUIRE(ob.SerializeAsString() == oj.SerializeAsString());
    }
}

TEST_CASE("protocol: sessions sharing a road cache give the same observations, bit for bit") {
    // The first session builds its own road, the second fills the cache, the third copies the
    // road from it. All three must be the same run.
    const auto roads = std::make_shared<sim::RoadCache>();
    std::vector<std::unique_ptr<Session>> sessions;
    for (const bool shared : {false, true, true}) {
        SessionOptions o;
        if (shared) o.roads = roads;
        std::string error;
        sessions.push_back(Session::create(test::cosim_program(), 0, o, error));
        INFO(error);
        REQUIRE(sessions.back());
    }
    std::vector<std::unique_ptr<Protocol>> protocols;
    std::vector<v1::Observation> obs;
    for (auto& s : sessions) {
        protocols.push_back(std::make_unique<Protocol>(*s, WelcomeInfo{"test", "s.sdv", "00", "", false, 0, 0, 0},
                                                       Encoding::binary));
        obs.push_back(exchange(*protocols.back(), hello()).welcome().initial());
    }
    for (int k = 0; k < 60; ++k) {
        for (size_t i = 0; i < protocols.size(); ++i) {
            obs[i] = exchange(*protocols[i], step(static_cast<uint64_t>(k + 1), obs[i]))
                         .step_result()
                         .observation();
        }
        REQUIRE(obs[1].SerializeAsString() == obs[0].SerializeAsString());
        REQUIRE(obs[2].SerializeAsString() == obs[0].SerializeAsString());
    }
    CHECK(obs[0].tick() == 60);
}

TEST_CASE("protocol: StepRequest before Hello is a PROTOCOL_VIOLATION") {
    Client c;
    v1::Observation obs;
    obs.add_actors()->set_id(1);
    const v1::Envelope r = exchange(c.protocol, step(3, obs));
    CHECK(r.seq() == 3);
    expect_error(c.protocol, r, v1::Error::PROTOCOL_VIOLATION, "StepRequest before Hello");
}

TEST_CASE("protocol: Hello twice is a PROTOCOL_VIOLATION") {
    Client c;
    REQUIRE(exchange(c.protocol, hello()).has_welcome());
    expect_error(c.protocol, exchange(c.protocol, hello(2)), v1::Error::PROTOCOL_VIOLATION,
                 "Hello was already received");
}

TEST_CASE("protocol: another major version is a VERSION_MISMATCH; a newer minor is fine") {
    Client c;
    expect_error(c.protocol, exchange(c.protocol, hello(1, "ego", 2)), v1::Error::VERSION_MISMATCH,
                 "the client speaks sdv-cosim 2.0; this sdv speaks 1.0");
    Client d;
    v1::Envelope h = hello();
    h.mutable_hello()->set_version_minor(7);
    CHECK(exchange(d.protocol, h).has_welcome());
}

TEST_CASE("protocol: a wrong protocol name is a PROTOCOL_VIOLATION") {
    Client c;
    v1::Envelope h = hello();
    h.mutable_hello()->set_protocol("traci");
    expect_error(c.protocol, exchange(c.protocol, h), v1::Error::PROTOCOL_VIOLATION,
                 "expected 'sdv-cosim'");
}

TEST_CASE("protocol: claims of unknown and of non-external vehicles are UNKNOWN_ACTOR") {
    {
        Client c;
        expect_error(c.protocol, exchange(c.protocol, hello(1, "nobody")), v1::Error::UNKNOWN_ACTOR,
                     "no vehicle 'nobody'");
    }
    {
        Client c;
        expect_error(c.protocol, exchange(c.protocol, hello(1, "lead")), v1::Error::UNKNOWN_ACTOR,
                     "'lead' is not external");
    }
}

TEST_CASE("protocol: COMMAND mode is VERSION_MISMATCH (v1.1); no mode is INVALID_VALUE") {
    {
        Client c;
        expect_error(c.protocol, exchange(c.protocol, hello(1, "ego", 1, v1::CONTROL_MODE_COMMAND)),
                     v1::Error::VERSION_MISMATCH, "CONTROL_MODE_COMMAND is sdv-cosim 1.1");
    }
    {
        Client c;
        expect_error(c.protocol,
                     exchange(c.protocol, hello(1, "ego", 1, v1::CONTROL_MODE_UNSPECIFIED)),
                     v1::Error::INVALID_VALUE, "expected CONTROL_MODE_POSE");
    }
}

TEST_CASE("protocol: every external vehicle must be claimed, once") {
    {
        Client c;
        expect_error(c.protocol, exchange(c.protocol, hello(1, "")), v1::Error::PROTOCOL_VIOLATION,
                     "'ego' is not claimed");
    }
    {
        Client c;
        v1::Envelope h = hello();
        *h.mutable_hello()->add_claims() = h.hello().claims(0);
        expect_error(c.protocol, exchange(c.protocol, h), v1::Error::PROTOCOL_VIOLATION,
                     "claimed already");
    }
}

TEST_CASE("protocol: a wrong tick is BAD_TICK") {
    Client c;
    v1::Observation obs = exchange(c.protocol, hello()).welcome().initial();
    obs = exchange(c.protocol, step(2, obs)).step_result().observation();
    v1::Envelope s = step(3, obs);
    s.mutable_step()->set_tick(0);  // a replay of the last request
    expect_error(c.protocol, exchange(c.protocol, s), v1::Error::BAD_TICK,
                 "expected tick 1, got 0");
    CHECK(c.session->tick() == 1);  // nothing happened
}

TEST_CASE("protocol: no update for a claimed actor is MISSING_UPDATE") {
    Client c;
    const v1::Observation obs = exchange(c.protocol, hello()).welcome().initial();
    v1::Envelope s = step(2, obs);
    s.mutable_step()->clear_updates();
    expect_error(c.protocol, exchange(c.protocol, s), v1::Error::MISSING_UPDATE,
                 "tick 0: no update for actor 1 'ego'");
}

TEST_CASE("protocol: NaN and infinities are INVALID_VALUE") {
    for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
        Client c;
        const v1::Observation obs = exchange(c.protocol, hello()).welcome().initial();
        v1::Envelope s = step(2, obs);
        s.mutable_step()->mutable_updates(0)->mutable_state()->set_speed(bad);
        expect_error(c.protocol, exchange(c.protocol, s), v1::Error::INVALID_VALUE, "has speed = ");
        CHECK(c.session->tick() == 0);
    }
}

TEST_CASE(
    "protocol: updates for unclaimed ids are UNKNOWN_ACTOR; two for one are a PROTOCOL_VIOLATION") {
    {
        Client c;
        const v1::Observation obs = exchange(c.protocol, hello()).welcome().initial();
        v1::Envelope s = step(2, obs);
        auto& u = *s.mutable_step()->add_updates();
        u = s.step().updates(0);
        u.set_id(2);
        u.mutable_state()->set_id(2);
        expect_error(c.protocol, exchange(c.protocol, s), v1::Error::UNKNOWN_ACTOR,
                     "actor 2 'lead', which this client did not claim");
    }
    {
        Client c;
        const v1::Observation obs = exchange(c.protocol, hello()).welcome().initial();
        v1::Envelope s = step(2, obs);
        *s.mutable_step()->add_updates() = s.step().updates(0);
        expect_error(c.protocol, exchange(c.protocol, s), v1::Error::PROTOCOL_VIOLATION,
                     "two updates for actor 1");
    }
    {
        Client c;
        const v1::Observation obs = exchange(c.protocol, hello()).welcome().initial();
        v1::Envelope s = step(2, obs);
        s.mutable_step()->mutable_updates(0)->mutable_command()->set_accel(1);
        expect_error(c.protocol, exchange(c.protocol, s), v1::Error::PROTOCOL_VIOLATION,
                     "carries a command");
    }
    {
        Client c;
        const v1::Observation obs = exchange(c.protocol, hello()).welcome().initial();
        v1::Envelope s = step(2, obs);
        s.mutable_step()->mutable_updates(0)->mutable_state()->set_id(3);
        expect_error(c.protocol, exchange(c.protocol, s), v1::Error::INVALID_VALUE,
                     "carries the state of actor 3");
    }
}

TEST_CASE("protocol: a StepRequest after the end is a PROTOCOL_VIOLATION") {
    Client c;
    v1::Observation obs = exchange(c.protocol, hello()).welcome().initial();
    for (int k = 0; k < 120; ++k)
        obs = exchange(c.protocol, step(1, obs)).step_result().observation();
    REQUIRE(c.protocol.phase() == Protocol::Phase::ended);
    expect_error(c.protocol, exchange(c.protocol, step(9, obs)), v1::Error::PROTOCOL_VIOLATION,
                 "StepRequest after the end of the run (ENDED_SUCCESS at tick 120); expected Bye");
}

TEST_CASE(
    "protocol: garbage bytes, an empty Envelope and server messages are PROTOCOL_VIOLATIONs") {
    {
        Client c;
        const auto r = c.protocol.on_frame(std::string("\xff\xfe\x00garbage", 10));
        REQUIRE(r);
        v1::Envelope e;
        std::string why;
        REQUIRE(decode(*r, Encoding::binary, e, why));
        expect_error(c.protocol, e, v1::Error::PROTOCOL_VIOLATION,
                     "frame 1 (10 bytes): not a binary Envelope");
    }
    {
        Client c(Encoding::json);
        const auto r = c.protocol.on_frame("GET / HTTP/1.1\r\n\r\n");
        REQUIRE(r);
        v1::Envelope e;
        std::string why;
        REQUIRE(decode(*r, Encoding::json, e, why));
        expect_error(c.protocol, e, v1::Error::PROTOCOL_VIOLATION, "not a JSON Envelope");
    }
    {
        // Invalid UTF-8 quoted back by the parser's message is escaped: the Error, summary.json
        // and the terminal only ever get valid UTF-8.
        Client c(Encoding::json);
        const auto r = c.protocol.on_frame(std::string("\x00\xffnot an envelope{", 18));
        REQUIRE(r);
        v1::Envelope e;
        std::string why;
        REQUIRE(decode(*r, Encoding::json, e, why));
        CHECK(printable(e.error().message()) == e.error().message());
        CHECK(e.error().message().find("\\xff") != std::string::npos);
        CHECK(c.protocol.outcome().ending == printable(c.protocol.outcome().ending));
    }
    {
        Client c;
        expect_error(c.protocol, exchange(c.protocol, v1::Envelope()),
                     v1::Error::PROTOCOL_VIOLATION, "carries no message");
    }
    {
        Client c;
        v1::Envelope w;
        w.mutable_welcome();
        expect_error(c.protocol, exchange(c.protocol, w), v1::Error::PROTOCOL_VIOLATION,
                     "Welcome is sent by sdv");
    }
}

TEST_CASE("protocol: errors found below the protocol, a client's Error and a lost client") {
    {
        Client c;
        v1::Envelope e;
        std::string why;
        REQUIRE(decode(c.protocol.fail(v1::Error::FRAME_TOO_LARGE, "frame of 1073741824 bytes"),
                       Encoding::binary, e, why));
        expect_error(c.protocol, e, v1::Error::FRAME_TOO_LARGE, "1073741824");
    }
    {
        Client c;
        v1::Envelope e;
        std::string why;
        REQUIRE(decode(c.protocol.fail(v1::Error::TIMEOUT, "no request within 2 s"),
                       Encoding::binary, e, why));
        expect_error(c.protocol, e, v1::Error::TIMEOUT, "2 s");
    }
    {
        Client c;
        REQUIRE(exchange(c.protocol, hello()).has_welcome());
        v1::Envelope err;
        err.mutable_error()->set_code(v1::Error::INTERNAL);
        err.mutable_error()->set_message("planner crashed");
        CHECK_FALSE(c.protocol.on_frame(encode(err, Encoding::binary)));
        CHECK(c.protocol.outcome().kind == Protocol::Outcome::Kind::client_error);
        CHECK(c.protocol.outcome().ending == "aborted: client error INTERNAL: planner crashed");
    }
    {
        Client c;
        REQUIRE(exchange(c.protocol, hello()).has_welcome());
        c.protocol.disconnected("gone");
        CHECK(c.protocol.outcome().kind == Protocol::Outcome::Kind::disconnected);
        CHECK(c.protocol.outcome().ending == "aborted: client disconnected");
    }
}

TEST_CASE("protocol: Bye before the end stops the run early") {
    Client c;
    v1::Observation obs = exchange(c.protocol, hello()).welcome().initial();
    for (int k = 0; k < 10; ++k)
        obs = exchange(c.protocol, step(1, obs)).step_result().observation();
    CHECK_FALSE(c.protocol.on_frame(encode(bye(2, "operator stop"), Encoding::binary)));
    CHECK(c.protocol.outcome().ending == "bye: operator stop");
    CHECK(c.protocol.finish().empty());
    REQUIRE(c.session->result());
    CHECK(c.session->tick() == 10);
}

TEST_CASE("protocol: printable keeps UTF-8 and escapes everything else") {
    CHECK(printable("plain text") == "plain text");
    CHECK(printable("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x9a\x97") ==
          "caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x9a\x97");
    CHECK(printable("a\xff"
                    "b") ==
          "a\\xff"
          "b");
    CHECK(printable("\xc3") == "\\xc3");                    // cut sequence
    CHECK(printable("\xc0\xaf") == "\\xc0\\xaf");           // overlong
    CHECK(printable("\xed\xa0\x80") == "\\xed\\xa0\\x80");  // surrogate
    CHECK(printable("line\nnext\t") == "line next ");
    CHECK(printable(std::string(5000, 'a')).size() == 1003);
}

TEST_CASE("protocol: random and mutated frames never crash; every reply is a valid Envelope") {
    // A deterministic stream of inputs: random bytes, and valid Hello / StepRequest frames with
    // bytes flipped, cut or appended, in both encodings.
    uint64_t state = 0x9e3779b97f4a7c15ULL;
    auto next = [&state] {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        return state;
    };
    int replies = 0;
    for (int i = 0; i < 300; ++i) {
        const Encoding enc = i % 2 ? Encoding::json : Encoding::binary;
        Client c(enc);
        v1::Observation obs;
        if (next() % 3 != 0) {
            const auto w = exchange(c.protocol, hello());
            if (w.has_welcome()) obs = w.welcome().initial();
        }
        std::string frame;
        switch (next() % 3) {
            case 0:
                frame.resize(next() % 300);
                for (char& ch : frame) ch = static_cast<char>(next());
                break;
            case 1:
                frame = encode(obs.actors_size() ? step(4, obs) : hello(), enc);
                break;
            default:
                frame = encode(bye(3), enc);
                break;
        }
        for (uint64_t m = next() % 4; m > 0 && !frame.empty(); --m) {
            const size_t at = next() % frame.size();
            switch (next() % 3) {
                case 0:
                    frame[at] = static_cast<char>(next());
                    break;
                case 1:
                    frame.resize(at);
                    break;
                default:
                    frame.insert(at, 1, static_cast<char>(next()));
                    break;
            }
        }
        const auto reply = c.protocol.on_frame(frame);
        if (reply) {
            ++replies;
            v1::Envelope e;
            std::string why;
            INFO(why);
            CHECK(decode(*reply, enc, e, why));
            CHECK((e.has_welcome() || e.has_step_result() || e.has_error()));
            if (e.has_error()) CHECK(printable(e.error().message()) == e.error().message());
        }
        CHECK(c.protocol.finish().empty());
    }
    CHECK(replies > 100);
}

}  // namespace protocol_test
