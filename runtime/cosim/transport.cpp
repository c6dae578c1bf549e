// Listening, accepting and connecting with plain POSIX sockets. A Unix socket path left behind
// by a killed server is reused when no sdv holds its lock file; the files a listener created are
// removed when it closes, unless another server has bound the same path since.
#include "runtime/cosim/transport.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <thread>

namespace sdv::cosim {
namespace {

std::string sys_error(const std::string& what) { return what + ": " + std::strerror(errno); }

struct AddrInfo {
    addrinfo* list = nullptr;
    ~AddrInfo() {
        if (list) freeaddrinfo(list);
    }
};

// Resolves a TCP endpoint; an error message or "".
std::string resolve(const Endpoint& e, bool passive, AddrInfo& out) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_NUMERICSERV | (passive ? AI_PASSIVE : 0);
    const std::string port = std::to_string(e.port);
    const int r = getaddrinfo(e.host.c_str(), port.c_str(), &hints, &out.list);
    if (r != 0) return "cannot resolve '" + e.host + "': " + gai_strerror(r);
    return "";
}

bool unix_address(const std::string& path, sockaddr_un& addr, std::string& error) {
    addr = {};
    addr.sun_family = AF_UNIX;
    if (path.empty() || path.size() >= sizeof addr.sun_path) {
        error = "Unix socket path '" + path + "' must have 1 to " +
                std::to_string(sizeof addr.sun_path - 1) + " bytes";
        return false;
    }
    std::memcpy(addr.sun_path, path.data(), path.size());
    return true;
}

// Connects `fd` to `addr`, waiting at most until the deadline (a non-blocking connect). 0, or
// the errno of the failure (ETIMEDOUT once the deadline passed).
int connect_until(int fd, const sockaddr* addr, socklen_t len, Deadline deadline) {
    const int flags = fcntl(fd, F_GETFL);
    fcntl(fd, F_SETFL, flags | O_NONBLOCK);
    int err = 0;
    if (::connect(fd, addr, len) != 0) {
        err = errno;
        if (err == EINPROGRESS || err == EINTR) {
            std::string perr;
            const int w = wait_fd(fd, POLLOUT, deadline, perr);
            if (w == 0) {
                err = ETIMEDOUT;
            } else if (w < 0) {
                err = EIO;
            } else {
                socklen_t l = sizeof err;
                if (getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &l) != 0) err = errno;
            }
        }
    }
    fcntl(fd, F_SETFL, flags);
    return err;
}

bool expired(const Deadline& d) { return d && std::chrono::steady_clock::now() >= *d; }

}  // namespace

std::optional<Endpoint> parse_endpoint(const std::string& text, std::string& error) {
    Endpoint e;
    if (text.rfind("unix:", 0) == 0) {
        e.kind = Endpoint::Kind::unix_socket;
        e.path = text.substr(5);
        if (e.path.rfind("//", 0) == 0) e.path = e.path.substr(2);  // unix:///tmp/x.sock
        sockaddr_un addr;
        if (!unix_address(e.path, addr, error)) return std::nullopt;
        return e;
    }
    if (text.rfind("tcp://", 0) != 0) {
        error = "unknown endpoint '" + text +
                "': expected tcp://HOST:PORT (e.g. tcp://127.0.0.1:0) or unix:PATH";
        return std::nullopt;
    }
    const std::string rest = text.substr(6);
    std::string host, port;
    if (!rest.empty() && rest[0] == '[') {
        const size_t close = rest.find(']');
        if (close == std::string::npos || close + 1 >= rest.size() || rest[close + 1] != ':') {
            error = "endpoint '" + text + "': expected tcp://[IPV6]:PORT";
            return std::nullopt;
        }
        host = rest.substr(1, close - 1);
        port = rest.substr(close + 2);
    } else {
        const size_t colon = rest.rfind(':');
        if (colon == std::string::npos) {
            error = "endpoint '" + text +
                    "' has no port: write tcp://HOST:PORT (port 0 picks a free one)";
            return std::nullopt;
        }
        host = rest.substr(0, colon);
        port = rest.substr(colon + 1);
        if (host.find(':') != std::string::npos) {
            error = "endpoint '" + text + "': write an IPv6 address in brackets, tcp://[::1]:PORT";
            return std::nullopt;
        }
    }
    if (port.empty() || port.size() > 5 ||
        port.find_first_not_of("0123456789") != std::string::npos || std::stoul(port) > 65535) {
        error = "endpoint '" + text + "': the port must be a number from 0 to 65535";
        return std::nullopt;
    }
    // Loopback unless a host is given: a simulator port open to the network is a choice.
    e.host = host.empty() ? "127.0.0.1" : host;
    e.port = static_cast<uint16_t>(std::stoul(port));
    return e;
}

Socket& Socket::operator=(Socket&& o) noexcept {
    if (this != &o) {
        reset();
        fd_ = o.release();
    }
    return *this;
}

int Socket::release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
}

void Socket::reset() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
}

std::unique_ptr<Listener> Listener::open(const Endpoint& endpoint, std::string& error) {
    std::unique_ptr<Listener> l(new Listener());
    l->endpoint_ = endpoint;
    if (endpoint.kind == Endpoint::Kind::unix_socket) {
        sockaddr_un addr;
        if (!unix_address(endpoint.path, addr, error)) return nullptr;
        // PATH.lock, held while listening, tells a live sdv server from a socket file left
        // behind by one that was killed (the convention of Wayland's sockets). Probing by
        // connecting would not do: the probe would be the live server's one client.
        const std::string lock_path = endpoint.path + ".lock";
        l->lock_ = Socket(::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644));
        if (!l->lock_.valid()) {
            error = sys_error("cannot listen on 'unix:" + endpoint.path + "': cannot create '" +
                              lock_path + "'");
            return nullptr;
        }
        if (::flock(l->lock_.fd(), LOCK_EX | LOCK_NB) != 0) {
            error = "cannot listen on 'unix:" + endpoint.path +
                    "': another sdv is listening there (it holds '" + lock_path + "')";
            l->lock_.reset();
            return nullptr;
        }
        l->lock_path_ = lock_path;
        struct stat st {};
        if (lstat(endpoint.path.c_str(), &st) == 0) {
            if (!S_ISSOCK(st.st_mode)) {
                error = "cannot listen on 'unix:" + endpoint.path +
                        "': the path exists and is not a socket";
                return nullptr;
            }
            ::unlink(endpoint.path.c_str());  // stale: its server is gone
        }
        l->socket_ = Socket(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
        if (!l->socket_.valid()) {
            error = sys_error("socket");
            return nullptr;
        }
        if (::bind(l->socket_.fd(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
            error = sys_error("cannot listen on 'unix:" + endpoint.path + "'");
            return nullptr;
        }
        l->created_file_ = true;
        if (lstat(endpoint.path.c_str(), &st) == 0) l->file_inode_ = st.st_ino;
        if (::listen(l->socket_.fd(), 1) != 0) {
            error = sys_error("listen");
            return nullptr;
        }
        return l;
    }
    AddrInfo ai;
    if (auto e = resolve(endpoint, true, ai); !e.empty()) {
        error = "cannot listen on '" + endpoint.host + "': " + e;
        return nullptr;
    }
    std::string last = "no address";
    for (addrinfo* a = ai.list; a; a = a->ai_next) {
        Socket s(::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol));
        if (!s.valid()) {
            last = sys_error("socket");
            continue;
        }
        const int one = 1;
        setsockopt(s.fd(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
        if (::bind(s.fd(), a->ai_addr, a->ai_addrlen) != 0 || ::listen(s.fd(), 1) != 0) {
            last = std::strerror(errno);
            continue;
        }
        sockaddr_storage bound{};
        socklen_t len = sizeof bound;
        if (getsockname(s.fd(), reinterpret_cast<sockaddr*>(&bound), &len) != 0) {
            last = sys_error("getsockname");
            continue;
        }
        l->port_ = bound.ss_family == AF_INET6
                       ? ntohs(reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port)
                       : ntohs(reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
        l->socket_ = std::move(s);
        return l;
    }
    error = "cannot listen on 'tcp://" + endpoint.host + ":" + std::to_string(endpoint.port) +
            "': " + last;
    return nullptr;
}

Listener::~Listener() { close(); }

void Listener::close() {
    socket_.reset();
    if (created_file_) {
        struct stat st {};
        if (lstat(endpoint_.path.c_str(), &st) == 0 && st.st_ino == file_inode_)
            ::unlink(endpoint_.path.c_str());
        created_file_ = false;
    }
    if (lock_.valid()) {
        ::unlink(lock_path_.c_str());
        lock_.reset();  // releases the lock
    }
}

std::string Listener::address() const {
    if (endpoint_.kind == Endpoint::Kind::unix_socket) return "unix:" + endpoint_.path;
    const bool v6 = endpoint_.host.find(':') != std::string::npos;
    return "tcp://" + (v6 ? "[" + endpoint_.host + "]" : endpoint_.host) + ":" +
           std::to_string(port_);
}

AcceptStatus Listener::accept(Socket& client, Deadline deadline, std::string& error) {
    if (!socket_.valid()) {
        error = "the listener is closed";
        return AcceptStatus::error;
    }
    for (;;) {
        const int w = wait_fd(socket_.fd(), POLLIN, deadline, error);
        if (w == 0) {
            error = "no client connected to " + address();
            return AcceptStatus::timeout;
        }
        if (w < 0) return AcceptStatus::error;
        Socket s(::accept4(socket_.fd(), nullptr, nullptr, SOCK_CLOEXEC));
        if (!s.valid()) {
            // The client may have gone between poll and accept: wait for the next one.
            if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK ||
                errno == ECONNABORTED || errno == EPROTO)
                continue;
            error = sys_error("accept");
            return AcceptStatus::error;
        }
        if (endpoint_.kind == Endpoint::Kind::tcp) {
            const int one = 1;
            setsockopt(s.fd(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        }
        client = std::move(s);
        close();  // one client per session (v1)
        return AcceptStatus::ok;
    }
}

Socket connect_to(const Endpoint& endpoint, Deadline deadline, std::string& error) {
    for (;;) {
        int err = 0;
        if (endpoint.kind == Endpoint::Kind::unix_socket) {
            sockaddr_un addr;
            if (!unix_address(endpoint.path, addr, error)) return Socket();
            Socket s(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
            if (!s.valid()) {
                error = sys_error("socket");
                return Socket();
            }
            err = connect_until(s.fd(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr,
                                deadline);
            if (err == 0) return s;
        } else {
            AddrInfo ai;
            if (auto e = resolve(endpoint, false, ai); !e.empty()) {
                error = e;
                return Socket();
            }
            for (addrinfo* a = ai.list; a; a = a->ai_next) {
                Socket s(::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol));
                if (!s.valid()) {
                    err = errno;
                    continue;
                }
                err = connect_until(s.fd(), a->ai_addr, a->ai_addrlen, deadline);
                if (err == 0) {
                    const int one = 1;
                    setsockopt(s.fd(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
                    return s;
                }
            }
        }
        const std::string where =
            endpoint.kind == Endpoint::Kind::unix_socket
                ? "unix:" + endpoint.path
                : "tcp://" + endpoint.host + ":" + std::to_string(endpoint.port);
        // The server may not be listening yet: retry refused connections until the deadline.
        const bool retry = (err == ECONNREFUSED || err == ENOENT) && deadline && !expired(deadline);
        if (!retry) {
            error = "cannot connect to " + where + ": " + std::strerror(err);
            return Socket();
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

std::string write_file_atomically(const std::string& path, const std::string& text) {
    std::string tmpl = path + ".XXXXXX";
    const int fd = mkstemp(tmpl.data());
    if (fd < 0) return sys_error("cannot write '" + path + "'");
    Socket file(fd);  // owns and closes the descriptor
    if (auto e = write_all(file.fd(), text, std::nullopt); !e.empty()) {
        ::unlink(tmpl.c_str());
        return "cannot write '" + path + "': " + e;
    }
    fchmod(file.fd(), 0644);
    file.reset();
    if (::rename(tmpl.c_str(), path.c_str()) != 0) {
        const std::string e = sys_error("cannot rename '" + tmpl + "' to '" + path + "'");
        ::unlink(tmpl.c_str());
        return e;
    }
    return "";
}

}  // namespace sdv::cosim
