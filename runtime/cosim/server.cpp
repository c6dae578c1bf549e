// The connection loop: read a frame (bounded by the time-out of the phase), hand it to the
// protocol, record and send the reply. Anything the transport reports (end of stream, over-size
// frame, time-out, I/O error) becomes the protocol's outcome; nothing a client sends can make the
// loop throw, crash or wait without a bound other than the ones the user chose.
#include "runtime/cosim/server.h"

#include <sys/socket.h>

#include <cmath>
#include <sstream>

namespace sdv::cosim {
namespace {

std::string seconds(double s) {
    std::ostringstream o;
    o << s;
    return o.str() + " s";
}

// After an Error: stop sending, then read and drop what the client still sends for a moment, so
// that closing with unread input (which makes TCP send a reset) does not destroy the Error before
// the client has read it. Bounded in time and bytes.
void linger_close(Socket& s) {
    ::shutdown(s.fd(), SHUT_WR);
    const Deadline until = deadline_after(1.0);
    char buf[65536];
    size_t dropped = 0;
    while (dropped < (size_t{16} << 20)) {
        std::string e;
        bool timed_out = false;
        const long long n = read_exact(s.fd(), buf, sizeof buf, until, e, timed_out);
        if (n <= 0 || timed_out || static_cast<size_t>(n) < sizeof buf) break;
        dropped += static_cast<size_t>(n);
    }
    s.reset();
}

}  // namespace

int exit_status(const Protocol::Outcome& outcome, const Session& session) {
    switch (outcome.kind) {
        case Protocol::Outcome::Kind::bye:
            return session.result() && session.result()->passed() ? kExitOk : kExitFailed;
        case Protocol::Outcome::Kind::disconnected:
        case Protocol::Outcome::Kind::client_error:
            return kExitDisconnected;
        case Protocol::Outcome::Kind::error:
            return kExitProtocolError;
        case Protocol::Outcome::Kind::timeout:
            return kExitTimeout;
        case Protocol::Outcome::Kind::open:
            break;
    }
    return kExitInternal;
}

std::unique_ptr<Server> Server::listen(const Endpoint& endpoint, const ServerOptions& options,
                                       const RecordHeader& header, std::string& error) {
    std::unique_ptr<Server> s(new Server());
    s->options_ = options;
    if (!options.record_path.empty()) {
        RecordHeader h = header;
        h.encoding = options.encoding;
        s->record_ = RecordWriter::create(options.record_path, h, error);
        if (!s->record_) return nullptr;
    }
    s->listener_ = Listener::open(endpoint, error);
    if (!s->listener_) return nullptr;
    // The connect time-out runs from here: the client must connect and say Hello within it.
    s->connect_deadline_ = deadline_after(options.connect_timeout_s);
    if (!options.port_file.empty()) {
        const std::string text = endpoint.kind == Endpoint::Kind::tcp
                                     ? std::to_string(s->listener_->port())
                                     : endpoint.path;
        if (auto e = write_file_atomically(options.port_file, text + "\n"); !e.empty()) {
            error = e;
            return nullptr;
        }
    }
    return s;
}

ServeResult Server::serve(Session& session, const WelcomeInfo& info) {
    Protocol protocol(session, info, options_.encoding);
    // A record that cannot be written ends the session (INTERNAL): the user asked for it.
    auto record = [&](Direction d, std::string_view payload) -> std::string {
        if (!record_) return "";
        std::string e = record_->append(d, payload);
        if (!e.empty()) record_.reset();
        return e;
    };

    Socket client;
    std::string error;
    const AcceptStatus a = listener_->accept(client, connect_deadline_, error);
    if (a != AcceptStatus::ok) {
        // Nobody to tell: the outcome only goes into the outputs and the exit status.
        if (a == AcceptStatus::timeout) {
            (void)protocol.fail(v1::Error::TIMEOUT, "no client connected within " +
                                                        seconds(options_.connect_timeout_s) +
                                                        " (--cosim-connect-timeout)");
        } else {
            (void)protocol.fail(v1::Error::INTERNAL, error);
        }
    }
    bool sent_error = false;
    auto send = [&](std::string payload, bool is_error) {
        if (auto e = record(Direction::server, payload); !e.empty() && !protocol.closed()) {
            payload = protocol.fail(v1::Error::INTERNAL, e);
            is_error = true;
        }
        if (auto e = write_frame(client.fd(), payload, deadline_after(options_.step_timeout_s));
            !e.empty()) {
            protocol.disconnected("cannot send to the client: " + e);
            return;
        }
        sent_error = sent_error || is_error;
    };

    std::string payload;
    while (!protocol.closed()) {
        const bool greeting = protocol.phase() == Protocol::Phase::hello;
        const Deadline deadline =
            greeting ? connect_deadline_ : deadline_after(options_.step_timeout_s);
        const FrameRead f = read_frame(client.fd(), payload, deadline);
        switch (f.status) {
            case FrameStatus::ok: {
                if (auto e = record(Direction::client, payload); !e.empty()) {
                    send(protocol.fail(v1::Error::INTERNAL, e), true);
                    break;
                }
                const auto reply = protocol.on_frame(payload);
                if (reply) send(*reply, protocol.closed());
                break;
            }
            case FrameStatus::eof:
                protocol.disconnected("the client closed the connection without Bye");
                break;
            case FrameStatus::truncated:
            case FrameStatus::error:
                protocol.disconnected("the connection broke: " + f.error);
                break;
            case FrameStatus::too_large:
                send(protocol.fail(v1::Error::FRAME_TOO_LARGE, f.error), true);
                break;
            case FrameStatus::timeout:
                send(protocol.fail(v1::Error::TIMEOUT,
                                   greeting
                                       ? "no Hello within " + seconds(options_.connect_timeout_s) +
                                             " (--cosim-connect-timeout)"
                                       : "no request within " + seconds(options_.step_timeout_s) +
                                             " (--cosim-step-timeout)"),
                     true);
                break;
        }
    }
    if (client.valid()) {
        if (sent_error) {
            linger_close(client);
        } else {
            client.reset();
        }
    }
    ServeResult out;
    out.finish_error = protocol.finish();
    out.outcome = protocol.outcome();
    out.exit_status = exit_status(out.outcome, session);
    if (!out.finish_error.empty() && out.exit_status == kExitOk) out.exit_status = kExitFailed;
    out.steps = protocol.steps();
    out.client_name = protocol.client_name();
    return out;
}

}  // namespace sdv::cosim
