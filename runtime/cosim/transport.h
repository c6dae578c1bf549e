// Where the co-simulation server listens and how a client reaches it (docs/cosim.md
// "Transports"): `tcp://HOST:PORT` (loopback unless a host says otherwise; port 0 picks an
// ephemeral port) or `unix:PATH`. One client per session: the listener accepts one connection
// and then stops listening, so a second client is refused instead of waiting forever. Every
// descriptor is close-on-exec and owned by an RAII object.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "runtime/cosim/framing.h"

namespace sdv::cosim {

struct Endpoint {
    enum class Kind { tcp, unix_socket } kind = Kind::tcp;
    std::string host = "127.0.0.1";  // tcp: a name or an address (IPv6 in brackets in the text)
    uint16_t port = 0;               // tcp: 0 = ephemeral
    std::string path;                // unix: the socket's path
};

// Parses "tcp://HOST:PORT", "tcp://:PORT" (loopback), "tcp://[::1]:PORT" or "unix:PATH";
// nullopt with `error` saying what is wrong.
std::optional<Endpoint> parse_endpoint(const std::string& text, std::string& error);

// An owned file descriptor.
class Socket {
  public:
    Socket() = default;
    explicit Socket(int fd) : fd_(fd) {}
    ~Socket() { reset(); }
    Socket(Socket&& o) noexcept : fd_(o.release()) {}
    Socket& operator=(Socket&& o) noexcept;
    Socket(const Socket&) = delete;
    Socket& operator=(const Socket&) = delete;
    int fd() const { return fd_; }
    bool valid() const { return fd_ >= 0; }
    int release();
    void reset();

  private:
    int fd_ = -1;
};

enum class AcceptStatus { ok, timeout, error };

class Listener {
  public:
    // Binds and listens; nullptr with `error` on failure (address in use, path too long, ...).
    static std::unique_ptr<Listener> open(const Endpoint& endpoint, std::string& error);
    ~Listener();  // closes, and removes the Unix socket file (and its PATH.lock) it created
    Listener(const Listener&) = delete;
    Listener& operator=(const Listener&) = delete;

    // The address clients connect to, with the port actually bound: "tcp://127.0.0.1:40153",
    // "unix:/tmp/x.sock".
    std::string address() const;
    uint16_t port() const { return port_; }
    const Endpoint& endpoint() const { return endpoint_; }

    // Waits for the one client until the deadline, then stops listening. TCP connections get
    // TCP_NODELAY (every frame is a whole message; Nagle would add up to 40 ms per step).
    AcceptStatus accept(Socket& client, Deadline deadline, std::string& error);
    void close();

  private:
    Listener() = default;
    Socket socket_;
    Endpoint endpoint_;
    uint16_t port_ = 0;
    Socket lock_;  // Unix sockets: PATH.lock, locked while this listener owns PATH
    std::string lock_path_;
    bool created_file_ = false;
    uint64_t file_inode_ = 0;  // the socket file we bound (not a later one at the same path)
};

// Connects to a listening server (clients, tests and replay), retrying refused connections until
// the deadline. An invalid Socket with `error` on failure.
Socket connect_to(const Endpoint& endpoint, Deadline deadline, std::string& error);

// Writes `text` to `path` atomically (a temporary file in the same directory, then rename), so a
// reader polling for the file never sees half of it. An error message or "".
std::string write_file_atomically(const std::string& path, const std::string& text);

}  // namespace sdv::cosim
