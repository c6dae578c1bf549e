// Frames over a socketpair: partial transfers, the limits, the ends of a stream.
#include "runtime/cosim/framing.h"

#include <doctest/doctest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

#include "runtime/cosim/transport.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace framing_test {

using namespace sdv::cosim;

namespace {

struct Pair {
    Socket a, b;
    Pair() {
        int fds[2];
        REQUIRE(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) == 0);
        a = Socket(fds[0]);
        b = Socket(fds[1]);
    }
};

void raw(const Socket& s, std::string_view bytes) {
    REQUIRE(write_all(s.fd(), bytes, std::nullopt).empty());
}

}  // namespace

TEST_CASE("framing: the prefix is uint32 little-endian") {
    CHECK(frame_prefix(0) == std::string("\0\0\0\0", 4));
    CHECK(frame_prefix(0x01020304) == std::string("\x04\x03\x02\x01", 4));
    Pair p;
    REQUIRE(write_frame(p.a.fd(), "hello", std::nullopt).empty());
    char buf[9];
    REQUIRE(::read(p.b.fd(), buf, 9) == 9);
    CHECK(std::string(buf, 9) == std::string("\x05\0\0\0hello", 9));
}

TEST_CASE("framing: a frame arriving one byte at a time is read whole") {
    Pair p;
    std::string payload(3000, 'x');
    for (size_t i = 0; i < payload.size(); ++i) payload[i] = static_cast<char>(i * 7);
    const std::string frame = frame_prefix(static_cast<uint32_t>(payload.size())) + payload;
    std::thread writer([&] {
        for (size_t i = 0; i < frame.size(); i += (i < 8 ? 1 : 500)) {
            const size_t n = i < 8 ? 1 : std::min<size_t>(500, frame.size() - i);
            raw(p.a, std::string_view(frame).substr(i, n));
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    });
    std::string got;
    const FrameRead r = read_frame(p.b.fd(), got, deadline_after(30));
    writer.join();
    CHECK(r.status == FrameStatus::ok);
    CHECK(r.length == payload.size());
    CHECK(got == payload);
}

TEST_CASE("framing: a zero-length frame is a valid, empty payload") {
    Pair p;
    REQUIRE(write_frame(p.a.fd(), "", std::nullopt).empty());
    REQUIRE(write_frame(p.a.fd(), "next", std::nullopt).empty());
    std::string got = "stale";
    CHECK(read_frame(p.b.fd(), got, deadline_after(5)).status == FrameStatus::ok);
    CHECK(got.empty());
    CHECK(read_frame(p.b.fd(), got, deadline_after(5)).status == FrameStatus::ok);
    CHECK(got == "next");
}

TEST_CASE("framing: a 1 GiB length prefix is refused before anything is allocated for it") {
    Pair p;
    raw(p.a, frame_prefix(1u << 30) + "abc");
    std::string got;
    const FrameRead r = read_frame(p.b.fd(), got, deadline_after(5));
    CHECK(r.status == FrameStatus::too_large);
    CHECK(r.length == (1u << 30));
    CHECK(r.error.find("exceeds the maximum of 67108864 bytes") != std::string::npos);
    CHECK(got.capacity() < 4096);
    // Exactly the maximum is allowed (checked on the prefix alone: the limit is inclusive).
    Pair q;
    raw(q.a, frame_prefix(kMaxFramePayload));
    q.a.reset();
    CHECK(read_frame(q.b.fd(), got, deadline_after(5)).status == FrameStatus::truncated);
    // A smaller limit, as a reader may choose.
    Pair s;
    raw(s.a, frame_prefix(11) + "hello world");
    CHECK(read_frame(s.b.fd(), got, deadline_after(5), 10).status == FrameStatus::too_large);
}

TEST_CASE("framing: the end of the stream at a boundary, in the prefix and in the payload") {
    {
        Pair p;
        p.a.reset();
        std::string got;
        CHECK(read_frame(p.b.fd(), got, deadline_after(5)).status == FrameStatus::eof);
    }
    {
        Pair p;
        raw(p.a, std::string("\x05\0", 2));
        p.a.reset();
        std::string got;
        const FrameRead r = read_frame(p.b.fd(), got, deadline_after(5));
        CHECK(r.status == FrameStatus::truncated);
        CHECK(r.error.find("length prefix (2 of 4 bytes)") != std::string::npos);
    }
    {
        Pair p;
        raw(p.a, frame_prefix(10) + "abc");
        p.a.reset();
        std::string got;
        const FrameRead r = read_frame(p.b.fd(), got, deadline_after(5));
        CHECK(r.status == FrameStatus::truncated);
        CHECK(r.error.find("3 of 10 payload bytes") != std::string::npos);
    }
}

TEST_CASE("framing: a deadline bounds the wait for a frame, also for a trickling peer") {
    Pair p;
    std::string got;
    auto t0 = std::chrono::steady_clock::now();
    CHECK(read_frame(p.b.fd(), got, deadline_after(0.05)).status == FrameStatus::timeout);
    CHECK(std::chrono::steady_clock::now() - t0 >= std::chrono::milliseconds(45));
    raw(p.a, frame_prefix(10) + "ab");
    const FrameRead r = read_frame(p.b.fd(), got, deadline_after(0.05));
    CHECK(r.status == FrameStatus::timeout);
    CHECK(r.error.find("2 of 10") != std::string::npos);
    // Data already there is read even when the deadline has passed.
    Pair q;
    REQUIRE(write_frame(q.a.fd(), "late", std::nullopt).empty());
    CHECK(read_frame(q.b.fd(), got, std::chrono::steady_clock::now() - std::chrono::seconds(1))
              .status == FrameStatus::ok);
    CHECK(got == "late");
}

TEST_CASE(
    "framing: writing to a closed peer is an error, not SIGPIPE; a peer that never reads times "
    "out") {
    {
        Pair p;
        p.b.reset();
        const std::string e = write_frame(p.a.fd(), std::string(1 << 20, 'x'), deadline_after(5));
        CHECK(e.find("write") != std::string::npos);
    }
    {
        Pair p;
        const std::string e =
            write_frame(p.a.fd(), std::string(32 << 20, 'x'), deadline_after(0.1));
        CHECK(e.find("timed out writing") != std::string::npos);
    }
    Pair p;
    CHECK(write_frame(p.a.fd(), std::string(100, 'x'), std::nullopt, 10)
              .find("exceeds the maximum") != std::string::npos);
}

TEST_CASE("framing: frames over a pipe and a file (no socket)") {
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    Socket r(fds[0]), w(fds[1]);
    REQUIRE(write_frame(w.fd(), "through a pipe", deadline_after(5)).empty());
    std::string got;
    CHECK(read_frame(r.fd(), got, deadline_after(5)).status == FrameStatus::ok);
    CHECK(got == "through a pipe");
}

}  // namespace framing_test
