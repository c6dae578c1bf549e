// The co-simulation server (`sdv run SCENARIO --cosim ENDPOINT`, docs/cosim.md): listens, takes
// one client, and runs the sdv-cosim v1 state machine (protocol.h) over its frames in lockstep
// until Bye, an Error or the end of the connection. sdv never advances without a request and
// never reads the wall clock except for the liveness time-outs, which only ever abort.
#pragma once

#include <memory>
#include <string>

#include "runtime/cosim/protocol.h"
#include "runtime/cosim/record.h"
#include "runtime/cosim/transport.h"

namespace sdv::cosim {

// Exit statuses of `sdv run --cosim` (0–3 as every sdv command; 4–6 only in co-simulation).
inline constexpr int kExitOk = 0;        // Bye, and every expectation held
inline constexpr int kExitFailed = 1;    // Bye, and an expectation failed (or outputs not written)
inline constexpr int kExitUsage = 2;     // bad flags; an external vehicle without --cosim
inline constexpr int kExitInternal = 3;  // an internal error
inline constexpr int kExitDisconnected = 4;   // the client went away without Bye (or sent Error)
inline constexpr int kExitProtocolError = 5;  // sdv sent an Error (any code but TIMEOUT)
inline constexpr int kExitTimeout = 6;        // no client, or no request, within the time-out

// The exit status of a finished session: the outcome, and for Bye the run's verdict.
int exit_status(const Protocol::Outcome& outcome, const Session& session);

struct ServerOptions {
    Encoding encoding = Encoding::binary;
    // Until the client has connected and sent Hello; 0: forever.
    double connect_timeout_s = 60;
    // For every later frame (and for sending a reply); 0: forever.
    double step_timeout_s = 0;
    // Written (atomically) once listening: the TCP port, or the Unix socket's path, and a newline.
    std::string port_file;
    // The session's record; "" for none.
    std::string record_path;
};

struct ServeResult {
    Protocol::Outcome outcome;
    int exit_status = kExitInternal;
    uint64_t steps = 0;
    std::string client_name;
    std::string finish_error;  // the outputs could not be written
};

class Server {
  public:
    // Listens on the endpoint (writing the port file and creating the record); nullptr with
    // `error` on failure. `header` fills the record's header.
    static std::unique_ptr<Server> listen(const Endpoint& endpoint, const ServerOptions& options,
                                          const RecordHeader& header, std::string& error);
    // The address to connect to, with the actual port ("tcp://127.0.0.1:40153").
    std::string address() const { return listener_->address(); }
    uint16_t port() const { return listener_->port(); }

    // Serves one client over `session` until the session is closed, then finishes the session
    // (outputs written, marked with how it ended). Call once.
    ServeResult serve(Session& session, const WelcomeInfo& info);

  private:
    Server() = default;
    std::unique_ptr<Listener> listener_;
    std::unique_ptr<RecordWriter> record_;
    ServerOptions options_;
    Deadline connect_deadline_;
};

}  // namespace sdv::cosim
