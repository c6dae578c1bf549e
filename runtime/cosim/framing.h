// The frames of "sdv-cosim v1" (docs/cosim.md "Framing"): a uint32 little-endian payload length,
// then the payload, over any file descriptor (socket, pipe, file). Reads and writes survive
// partial transfers and EINTR, and wait at most until a deadline (poll), which is how the
// server's liveness time-outs are implemented; an over-size length is refused before anything is
// allocated for it, and the end of the stream at a frame boundary is told apart from the end in
// the middle of a frame and from errors.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace sdv::cosim {

// The largest payload either side may send (64 MiB).
inline constexpr uint32_t kMaxFramePayload = 64u * 1024u * 1024u;

// A point in time after which an I/O call gives up; nullopt: wait forever. Measured on the
// steady clock: only liveness depends on it, never a simulation result.
using Deadline = std::optional<std::chrono::steady_clock::time_point>;

// `seconds` from now; 0 (or less): never.
Deadline deadline_after(double seconds);

enum class FrameStatus {
    ok,
    eof,        // the stream ended cleanly before the first byte of a frame
    truncated,  // the stream ended inside a frame
    too_large,  // the length prefix exceeds the maximum (nothing read past the prefix)
    timeout,    // the deadline passed
    error,      // an I/O error (message set)
};

struct FrameRead {
    FrameStatus status = FrameStatus::ok;
    uint32_t length = 0;  // the declared payload length, once the prefix was read
    std::string error;    // for `error`, `truncated`, `too_large` and `timeout`: what happened
};

// Reads one frame into `payload`. The deadline covers the whole frame (a peer that trickles a
// byte at a time still times out). The payload buffer grows with the bytes that arrive, so a
// length prefix that promises more than is sent does not cost its size in memory.
FrameRead read_frame(int fd, std::string& payload, Deadline deadline,
                     uint32_t max_payload = kMaxFramePayload);

// Writes one frame (prefix and payload). An empty string on success, else the error ("timed
// out ..." once the deadline passed, or the system's message). Never raises SIGPIPE: a closed
// peer is an error like any other.
std::string write_frame(int fd, std::string_view payload, Deadline deadline,
                        uint32_t max_payload = kMaxFramePayload);

// The 4-byte prefix of a payload of `length` bytes.
std::string frame_prefix(uint32_t length);

// Low-level helpers shared with the transports and the record: read or write exactly `n` bytes
// (partial transfers, EINTR), waiting at most until the deadline. read_exact returns the number
// of bytes read: n, or fewer at the end of the stream or when the deadline passed (`timed_out`
// and `error` set); -1 on an I/O error (`error` set).
long long read_exact(int fd, char* data, size_t n, Deadline deadline, std::string& error,
                     bool& timed_out);
std::string write_all(int fd, std::string_view bytes, Deadline deadline);
// Waits until `fd` is ready for the poll(2) `events`: 1 ready (or in an error or hang-up state
// that the next call reports), 0 the deadline passed, -1 a poll error (`error` set).
int wait_fd(int fd, short events, Deadline deadline, std::string& error);

}  // namespace sdv::cosim
