// The "sdv-cosim v1" state machine over a Session (docs/cosim.md "Step semantics", "Errors"):
// one client payload in, at most one payload out, no I/O. The network server (server.h) runs it
// over a connection; replay (replay.h) runs it over a recorded session; tests run it directly.
// Phases: waiting for Hello → running (StepRequests) → ended (the run is over, only Bye is
// expected) → closed (Bye, an Error sent, or the client gone). Every refusal is an Error with a
// code and a message naming what was expected; after it the session is closed.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/cosim/codec.h"
#include "runtime/cosim/session.h"
#include "runtime/ir/ir.h"

namespace sdv::cosim {

// The protocol version sdv speaks.
inline constexpr uint32_t kVersionMajor = 1;
inline constexpr uint32_t kVersionMinor = 0;
inline constexpr const char* kProtocolName = "sdv-cosim";

// What Welcome says besides the session's own data.
struct WelcomeInfo {
    std::string sdv_version;
    std::string scenario;         // the scenario file as given to sdv
    std::string scenario_sha256;  // of that file's bytes
    std::string map_reference;    // the map file; "" on a built-in road
    bool has_origin = false;
    double origin_lat_deg = 0, origin_lon_deg = 0, origin_alt_m = 0;
};

// The map reference and geographic origin of a scenario's road.
WelcomeInfo welcome_info(const ir::Program& program, int scenario);

class Protocol {
  public:
    enum class Phase { hello, running, ended, closed };

    // How the session ended.
    struct Outcome {
        enum class Kind {
            open,          // not yet
            bye,           // the client said Bye
            disconnected,  // the connection ended without Bye
            client_error,  // the client sent an Error
            error,         // sdv sent an Error (code below)
            timeout,       // a liveness time-out (code TIMEOUT)
        } kind = Kind::open;
        v1::Error::Code code = v1::Error::CODE_UNSPECIFIED;
        std::string message;  // the Error's message, the Bye's reason, what happened
        std::string ending;   // for Session::finish: "bye: ...", "aborted: ..."
    };

    Protocol(Session& session, WelcomeInfo info, Encoding encoding);

    // Handles one frame's payload from the client: the payload to send back, if any (none after
    // Bye or a client's Error, or once closed).
    std::optional<std::string> on_frame(std::string_view payload);
    // A failure found below the protocol (FRAME_TOO_LARGE, TIMEOUT): closes the session and
    // returns the Error to send (the connection may or may not still take it).
    std::string fail(v1::Error::Code code, const std::string& message);
    // The connection ended without Bye (or broke while sending).
    void disconnected(const std::string& why);

    // Ends the run and writes its outputs with the outcome's ending (once the session is closed;
    // the server calls it after the last frame went out, so the client is not kept waiting by the
    // writing). An error message or "".
    std::string finish();

    Phase phase() const { return phase_; }
    bool closed() const { return phase_ == Phase::closed; }
    const Outcome& outcome() const { return outcome_; }
    const std::string& client_name() const { return client_name_; }
    Encoding encoding() const { return encoding_; }
    // StepRequests handled so far.
    uint64_t steps() const { return steps_; }

  private:
    std::string error(uint64_t seq, v1::Error::Code code, const std::string& message);
    std::string on_hello(uint64_t seq, const v1::Hello& hello);
    std::string on_step(uint64_t seq, const v1::StepRequest& step);
    void close(Outcome::Kind kind, v1::Error::Code code, const std::string& message,
               const std::string& ending);
    void observation(v1::Observation& out) const;
    std::string name_of(uint64_t id) const;

    Session& session_;
    WelcomeInfo info_;
    Encoding encoding_;
    Phase phase_ = Phase::hello;
    Outcome outcome_;
    std::vector<uint64_t> claimed_;  // ids, in claim order
    std::string client_name_;
    uint64_t steps_ = 0;
    uint64_t frames_ = 0;
    bool finished_ = false;
};

// The name of an Error code ("BAD_TICK").
std::string code_name(v1::Error::Code code);

// `text` made safe to quote in an Error, summary.json or a terminal: valid UTF-8 kept, any other
// byte written as \xNN, control characters as spaces, at most about `max_bytes`.
std::string printable(std::string_view text, size_t max_bytes = 1000);

}  // namespace sdv::cosim
