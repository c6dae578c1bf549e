// The co-simulation scenario and a client for the tests: the frames a client sends, and a
// scripted ego that drives straight on at its speed, computed from the last observation.
#pragma once

#include <doctest/doctest.h>

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "compiler/sema/compile.h"
#include "runtime/cosim/codec.h"
#include "runtime/cosim/protocol.h"
#include "runtime/cosim/session.h"

namespace sdv::test {

// A fresh private directory under the system's temp directory.
inline std::string temp_dir() {
    std::string t = (std::filesystem::temp_directory_path() / "sdv-cosim-XXXXXX").string();
    REQUIRE(mkdtemp(t.data()) != nullptr);
    return t;
}

// tests/cli/data/cosim_highway.sdv: the one scenario of the co-simulation tests (the CLI test
// runs it too). An external ego, a lead SDV ahead of it and v2 that overtakes it and cuts in;
// timeout 4 s (120 ticks), seed 7.
inline std::string cosim_scenario_path() {
    return std::string(SDV_SOURCE_DIR) + "/tests/cli/data/cosim_highway.sdv";
}

inline std::shared_ptr<const ir::Program> cosim_program() {
    static std::shared_ptr<const ir::Program> program = [] {
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        std::ifstream in(cosim_scenario_path(), std::ios::binary);
        std::stringstream text;
        text << in.rdbuf();
        auto c = compiler::compile_source(cosim_scenario_path(), text.str(), sm, diags);
        for (const auto& d : diags.sorted()) MESSAGE(d.message);
        REQUIRE(c.program);
        return std::make_shared<const ir::Program>(std::move(*c.program));
    }();
    return program;
}

inline std::unique_ptr<cosim::Session> cosim_session(const std::string& output_dir = "",
                                                     std::optional<uint64_t> seed = std::nullopt) {
    cosim::SessionOptions o;
    o.output_dir = output_dir;
    o.seed = seed;
    std::string error;
    auto s = cosim::Session::create(cosim_program(), 0, o, error);
    INFO(error);
    REQUIRE(s);
    return s;
}

inline cosim::v1::Envelope hello(uint64_t seq = 1, const std::string& actor = "ego",
                                 uint32_t major = 1,
                                 cosim::v1::ControlMode mode = cosim::v1::CONTROL_MODE_POSE) {
    cosim::v1::Envelope e;
    e.set_seq(seq);
    auto& h = *e.mutable_hello();
    h.set_protocol("sdv-cosim");
    h.set_version_major(major);
    h.set_client_name("doctest");
    if (!actor.empty()) {
        auto& c = *h.add_claims();
        c.set_actor_name(actor);
        c.set_mode(mode);
    }
    return e;
}

// The ego's state at k+1: straight on along its heading at its speed, from observation k.
inline cosim::v1::ActorState ego_next(const cosim::v1::Observation& obs, uint64_t ego_id = 1) {
    for (const auto& a : obs.actors()) {
        if (a.id() != ego_id) continue;
        cosim::v1::ActorState s = a;
        s.set_x(a.x() + a.speed() / 30.0 * std::cos(a.yaw()));
        s.set_y(a.y() + a.speed() / 30.0 * std::sin(a.yaw()));
        s.set_accel(0);
        s.set_yaw_rate(0);
        return s;
    }
    FAIL("no ego in the observation");
    return {};
}

inline cosim::v1::Envelope step(uint64_t seq, const cosim::v1::Observation& obs,
                                uint64_t ego_id = 1) {
    cosim::v1::Envelope e;
    e.set_seq(seq);
    auto& st = *e.mutable_step();
    st.set_tick(obs.tick());
    auto& u = *st.add_updates();
    u.set_id(ego_id);
    *u.mutable_state() = ego_next(obs, ego_id);
    return e;
}

inline cosim::v1::Envelope bye(uint64_t seq, const std::string& reason = "done") {
    cosim::v1::Envelope e;
    e.set_seq(seq);
    e.mutable_bye()->set_reason(reason);
    return e;
}

// Sends a message to the protocol and decodes its reply (an empty Envelope when there is none).
inline cosim::v1::Envelope exchange(cosim::Protocol& p, const cosim::v1::Envelope& in) {
    const auto reply = p.on_frame(cosim::encode(in, p.encoding()));
    cosim::v1::Envelope out;
    if (reply) {
        std::string error;
        REQUIRE(cosim::decode(*reply, p.encoding(), out, error));
    }
    return out;
}

}  // namespace sdv::test
