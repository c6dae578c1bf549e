// Frame I/O over a file descriptor. Sockets are written with send(MSG_NOSIGNAL | MSG_DONTWAIT)
// so that a closed peer is an EPIPE error instead of a process-wide SIGPIPE (no signal handler:
// the library keeps no global state), and so that a peer that stops reading cannot block a
// write past its deadline; other descriptors (files, pipes) fall back to write().
#include "runtime/cosim/framing.h"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

namespace sdv::cosim {
namespace {

using Clock = std::chrono::steady_clock;

std::string timed_out_message(const char* what, size_t done, size_t n) {
    return std::string("timed out ") + what + " (" + std::to_string(done) + " of " +
           std::to_string(n) + " bytes)";
}

}  // namespace

int wait_fd(int fd, short events, Deadline deadline, std::string& error) {
    for (;;) {
        int timeout_ms = -1;
        if (deadline) {
            const auto left =
                std::chrono::duration_cast<std::chrono::milliseconds>(*deadline - Clock::now())
                    .count();
            if (left <= 0) {
                // One last non-blocking look: data that is already there is not late.
                timeout_ms = 0;
            } else {
                timeout_ms = static_cast<int>(std::min<long long>(left + 1, 24LL * 3600 * 1000));
            }
        }
        pollfd p{fd, events, 0};
        const int r = ::poll(&p, 1, timeout_ms);
        if (r > 0) return 1;
        if (r == 0) {
            if (timeout_ms == 0) return 0;
            continue;  // woke up early (rounding): recompute what is left
        }
        if (errno == EINTR) continue;
        error = std::string("poll: ") + std::strerror(errno);
        return -1;
    }
}

Deadline deadline_after(double seconds) {
    if (!(seconds > 0) || !std::isfinite(seconds)) return std::nullopt;
    return Clock::now() +
           std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

std::string frame_prefix(uint32_t length) {
    std::string p(4, '\0');
    for (int i = 0; i < 4; ++i)
        p[static_cast<size_t>(i)] = static_cast<char>((length >> (8 * i)) & 0xff);
    return p;
}

long long read_exact(int fd, char* data, size_t n, Deadline deadline, std::string& error,
                     bool& timed_out) {
    timed_out = false;
    size_t done = 0;
    while (done < n) {
        const int w = wait_fd(fd, POLLIN, deadline, error);
        if (w == 0) {
            timed_out = true;
            error = timed_out_message("reading", done, n);
            return static_cast<long long>(done);
        }
        if (w < 0) return -1;
        const ssize_t r = ::read(fd, data + done, n - done);
        if (r == 0) break;  // end of stream
        if (r < 0) {
            if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) continue;
            error = std::string("read: ") + std::strerror(errno);
            return -1;
        }
        done += static_cast<size_t>(r);
    }
    return static_cast<long long>(done);
}

std::string write_all(int fd, std::string_view bytes, Deadline deadline) {
    size_t done = 0;
    bool socket = true;
    while (done < bytes.size()) {
        std::string error;
        const int w = wait_fd(fd, POLLOUT, deadline, error);
        if (w == 0) return timed_out_message("writing", done, bytes.size());
        if (w < 0) return error;
        ssize_t r;
        if (socket) {
            r = ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL | MSG_DONTWAIT);
            if (r < 0 && errno == ENOTSOCK) {
                socket = false;
                continue;
            }
        } else {
            r = ::write(fd, bytes.data() + done, bytes.size() - done);
        }
        if (r < 0) {
            if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) continue;
            return std::string("write: ") + std::strerror(errno);
        }
        done += static_cast<size_t>(r);
    }
    return "";
}

FrameRead read_frame(int fd, std::string& payload, Deadline deadline, uint32_t max_payload) {
    FrameRead out;
    payload.clear();
    char prefix[4];
    bool timed_out = false;
    const long long got = read_exact(fd, prefix, sizeof prefix, deadline, out.error, timed_out);
    if (got < 0 || timed_out) {
        out.status = got < 0 ? FrameStatus::error : FrameStatus::timeout;
        return out;
    }
    if (got == 0) {
        out.status = FrameStatus::eof;
        return out;
    }
    if (got < 4) {
        out.status = FrameStatus::truncated;
        out.error = "the stream ended inside a frame's length prefix (" + std::to_string(got) +
                    " of 4 bytes)";
        return out;
    }
    for (int i = 0; i < 4; ++i)
        out.length |= static_cast<uint32_t>(static_cast<unsigned char>(prefix[i])) << (8 * i);
    if (out.length > max_payload) {
        out.status = FrameStatus::too_large;
        out.error = "frame of " + std::to_string(out.length) + " bytes exceeds the maximum of " +
                    std::to_string(max_payload) + " bytes";
        return out;
    }
    // Grow with what arrives (1 MiB at a time) rather than trusting the prefix with an allocation.
    constexpr size_t kChunk = size_t{1} << 20;
    while (payload.size() < out.length) {
        const size_t old = payload.size();
        const size_t want = std::min<size_t>(kChunk, out.length - old);
        payload.resize(old + want);
        const long long r =
            read_exact(fd, payload.data() + old, want, deadline, out.error, timed_out);
        if (r < 0 || timed_out) {
            payload.resize(old + static_cast<size_t>(std::max(r, 0LL)));
            out.status = r < 0 ? FrameStatus::error : FrameStatus::timeout;
            if (timed_out)
                out.error = timed_out_message("reading a frame", payload.size(), out.length);
            return out;
        }
        if (static_cast<size_t>(r) < want) {
            payload.resize(old + static_cast<size_t>(r));
            out.status = FrameStatus::truncated;
            out.error = "the stream ended inside a frame (" + std::to_string(payload.size()) +
                        " of " + std::to_string(out.length) + " payload bytes)";
            return out;
        }
    }
    return out;
}

std::string write_frame(int fd, std::string_view payload, Deadline deadline, uint32_t max_payload) {
    if (payload.size() > max_payload) {
        return "frame of " + std::to_string(payload.size()) + " bytes exceeds the maximum of " +
               std::to_string(max_payload) + " bytes";
    }
    // One buffer, one send in the common case: with TCP_NODELAY two writes would be two segments.
    std::string frame = frame_prefix(static_cast<uint32_t>(payload.size()));
    frame.append(payload);
    return write_all(fd, frame, deadline);
}

}  // namespace sdv::cosim
