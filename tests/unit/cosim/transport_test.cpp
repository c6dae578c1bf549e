// Endpoints, listening, one client per session, the port file.
#include "runtime/cosim/transport.h"

#include <doctest/doctest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "cosim_fixture.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace transport_test {

using namespace sdv::cosim;
using sdv::test::temp_dir;

TEST_CASE("transport: endpoints") {
    std::string e;
    auto a = parse_endpoint("tcp://127.0.0.1:0", e);
    REQUIRE(a);
    CHECK(a->kind == Endpoint::Kind::tcp);
    CHECK(a->host == "127.0.0.1");
    CHECK(a->port == 0);
    a = parse_endpoint("tcp://:5555", e);
    REQUIRE(a);
    CHECK(a->host == "127.0.0.1");  // loopback by default
    CHECK(a->port == 5555);
    a = parse_endpoint("tcp://[::1]:80", e);
    REQUIRE(a);
    CHECK(a->host == "::1");
    a = parse_endpoint("unix:/tmp/x.sock", e);
    REQUIRE(a);
    CHECK(a->kind == Endpoint::Kind::unix_socket);
    CHECK(a->path == "/tmp/x.sock");
    CHECK(parse_endpoint("unix:///tmp/y.sock", e)->path == "/tmp/y.sock");

    CHECK_FALSE(parse_endpoint("tcp://127.0.0.1", e));
    CHECK(e.find("has no port") != std::string::npos);
    CHECK_FALSE(parse_endpoint("tcp://127.0.0.1:65536", e));
    CHECK_FALSE(parse_endpoint("tcp://127.0.0.1:-1", e));
    CHECK_FALSE(parse_endpoint("tcp://::1:80", e));
    CHECK(e.find("brackets") != std::string::npos);
    CHECK_FALSE(parse_endpoint("udp://127.0.0.1:0", e));
    CHECK(e.find("expected tcp://HOST:PORT") != std::string::npos);
    CHECK_FALSE(parse_endpoint("unix:", e));
    CHECK_FALSE(parse_endpoint("unix:/" + std::string(200, 'x'), e));
    CHECK(e.find("1 to 107 bytes") != std::string::npos);
}

TEST_CASE("transport: TCP on an ephemeral port takes one client, then refuses") {
    std::string e;
    auto l = Listener::open(*parse_endpoint("tcp://127.0.0.1:0", e), e);
    REQUIRE(l);
    CHECK(l->port() != 0);
    CHECK(l->address() == "tcp://127.0.0.1:" + std::to_string(l->port()));
    Endpoint to = l->endpoint();
    to.port = l->port();
    Socket c = connect_to(to, deadline_after(10), e);
    REQUIRE(c.valid());
    Socket s;
    REQUIRE(l->accept(s, deadline_after(10), e) == AcceptStatus::ok);
    REQUIRE(write_frame(c.fd(), "ping", deadline_after(5)).empty());
    std::string got;
    CHECK(read_frame(s.fd(), got, deadline_after(5)).status == FrameStatus::ok);
    CHECK(got == "ping");
    // The listener is closed after the one client: a second one is refused at once.
    Socket c2 = connect_to(to, std::nullopt, e);
    CHECK_FALSE(c2.valid());
    CHECK(e.find("Connection refused") != std::string::npos);
}

TEST_CASE("transport: accept times out without a client") {
    std::string e;
    auto l = Listener::open(*parse_endpoint("tcp://127.0.0.1:0", e), e);
    REQUIRE(l);
    Socket s;
    CHECK(l->accept(s, deadline_after(0.05), e) == AcceptStatus::timeout);
    CHECK(e.find("no client connected") != std::string::npos);
}

TEST_CASE("transport: Unix sockets, a stale socket file, a path in use, cleanup") {
    const std::string dir = temp_dir();
    const std::string path = dir + "/s.sock";
    std::string e;
    const Endpoint ep = *parse_endpoint("unix:" + path, e);
    {
        auto l = Listener::open(ep, e);
        REQUIRE(l);
        CHECK(l->address() == "unix:" + path);
        // A second server on the same path is refused while the first listens.
        CHECK_FALSE(Listener::open(ep, e));
        CHECK(e.find("another sdv is listening there") != std::string::npos);
        std::thread client([&] {
            std::string ce;
            Socket c = connect_to(ep, deadline_after(10), ce);
            CHECK(c.valid());
            CHECK(write_frame(c.fd(), "over unix", deadline_after(5)).empty());
        });
        Socket s;
        REQUIRE(l->accept(s, deadline_after(10), e) == AcceptStatus::ok);
        std::string got;
        CHECK(read_frame(s.fd(), got, deadline_after(5)).status == FrameStatus::ok);
        CHECK(got == "over unix");
        client.join();
    }
    CHECK_FALSE(std::filesystem::exists(path));  // removed by the listener
    CHECK_FALSE(std::filesystem::exists(path + ".lock"));
    {
        // A stale socket file (its server gone without cleaning up) is replaced.
        Socket stale(::socket(AF_UNIX, SOCK_STREAM, 0));
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::memcpy(addr.sun_path, path.c_str(), path.size());
        REQUIRE(::bind(stale.fd(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0);
        stale.reset();
        REQUIRE(std::filesystem::exists(path));
        auto l = Listener::open(ep, e);
        INFO(e);
        CHECK(l);
    }
    std::ofstream(dir + "/plain") << "x";
    CHECK_FALSE(Listener::open(*parse_endpoint("unix:" + dir + "/plain", e), e));
    CHECK(e.find("not a socket") != std::string::npos);
    std::filesystem::remove_all(dir);
}

TEST_CASE("transport: a client retries until the server listens, within its deadline") {
    std::string e;
    const std::string dir = temp_dir();
    const Endpoint ep = *parse_endpoint("unix:" + dir + "/late.sock", e);
    std::unique_ptr<Listener> l;
    std::thread server([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        std::string se;
        l = Listener::open(ep, se);
    });
    Socket c = connect_to(ep, deadline_after(30), e);
    server.join();
    CHECK(c.valid());
    Socket none =
        connect_to(*parse_endpoint("unix:" + dir + "/never.sock", e), deadline_after(0.1), e);
    CHECK_FALSE(none.valid());
    l.reset();
    std::filesystem::remove_all(dir);
}

TEST_CASE("transport: the port file is written whole, by rename") {
    const std::string dir = temp_dir();
    const std::string f = dir + "/port";
    CHECK(write_file_atomically(f, "40153\n").empty());
    std::ifstream in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    CHECK(ss.str() == "40153\n");
    CHECK(std::distance(std::filesystem::directory_iterator(dir),
                        std::filesystem::directory_iterator()) == 1);
    CHECK_FALSE(write_file_atomically(dir + "/missing/port", "1\n").empty());
    std::filesystem::remove_all(dir);
}

}  // namespace transport_test
