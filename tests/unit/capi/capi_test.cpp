// The C API (include/sdv/sdv.h) as a C caller sees it: status codes and messages of every misuse,
// the two-call buffers, Jacobi steps (an NPC's move to k+1 never depends on the external state
// given for k+1), no global state (handles interleaved in one thread give the same runs as alone),
// thread counts, and the outputs of finished and abandoned runs.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "include/sdv/sdv.h"

// This file's tests and helpers, apart from the other files of its unity batch.
namespace capi_test {

namespace {

namespace fs = std::filesystem;

// A straight two-lane road: the external ego in lane 1, an SDV behind it in lane 2 that
// overtakes, and a parked object far ahead in lane 2.
const char* kScenario = R"(import "std/drive.sdv"
road r {
    lanes 2 forward
    speed_limit 60 km/h
    straight 600 m
}
scenario s {
    road r
    timeout 8 s
    seed 3
    ego ego: external { start lane 1 at 50 m  speed 10 m/s }
    vehicle v2: sdv { start lane 2 at 20 m  speed 12 m/s  tree std.drive(speed = 15 m/s) }
    object cone { start lane 2 at 500 m }
    expect not collision(ego, v2)
}
)";

std::string temp_dir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / ("sdv_capi_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d.string();
}

std::string write_scenario(const std::string& dir, const char* text = kScenario) {
    const std::string path = dir + "/s.sdv";
    std::ofstream(path) << text;
    return path;
}

std::string read(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// `path` must outlive the configuration (it keeps its c_str()).
sdv_config config(const std::string& path, const char* out = nullptr, int threads = 1) {
    sdv_config c{};
    c.struct_size = sizeof c;
    c.scenario_path = path.c_str();
    c.output_dir = out;
    c.threads = threads;
    return c;
}

std::vector<sdv_actor_state> states(sdv_sim* h) {
    size_t n = 0;
    REQUIRE(sdv_get_actor_states(h, nullptr, 0, &n) == SDV_ERR_BUFFER);
    std::vector<sdv_actor_state> v(n);
    REQUIRE(sdv_get_actor_states(h, v.data(), v.size(), &n) == SDV_OK);
    return v;
}

// The ego's scripted state at tick k: straight along its lane at 10 m/s.
sdv_actor_state ego_at(const sdv_actor_state& start, uint64_t id, uint64_t k) {
    sdv_actor_state s = start;
    s.struct_size = sizeof s;
    s.id = id;
    s.x = start.x + 10.0 * static_cast<double>(k) / 30.0;
    s.speed = 10;
    s.accel = 0;
    return s;
}

// Runs a whole scenario with the scripted ego; every tick's states, flattened.
std::vector<double> run(const std::string& path, int threads, const char* out = nullptr) {
    sdv_sim* h = nullptr;
    const sdv_config c = config(path, out, threads);
    REQUIRE(sdv_create(&c, &h) == SDV_OK);
    uint64_t ego = 0;
    REQUIRE(sdv_claim(h, "ego", SDV_CONTROL_POSE, &ego) == SDV_OK);
    const sdv_actor_state start = states(h)[ego - 1];
    std::vector<double> all;
    sdv_run_state rs = SDV_RUNNING;
    for (uint64_t k = 0; rs == SDV_RUNNING; ++k) {
        const sdv_actor_state next = ego_at(start, ego, k + 1);
        REQUIRE(sdv_set_external_state(h, &next) == SDV_OK);
        REQUIRE(sdv_step(h, &rs) == SDV_OK);
        for (const auto& s : states(h)) all.insert(all.end(), {s.x, s.y, s.yaw, s.speed, s.accel, s.s, s.d});
    }
    REQUIRE(sdv_finish(h) == SDV_OK);
    sdv_destroy(h);
    return all;
}

}  // namespace

TEST_CASE("version and the failed loads say why") {
    CHECK(sdv_api_version() == SDV_API_VERSION);
    CHECK(std::string(sdv_version_string()).rfind("sdv ", 0) == 0);
    sdv_sim* h = nullptr;
    CHECK(sdv_create(nullptr, &h) == SDV_ERR_ARG);
    CHECK(std::string(sdv_last_error(h)) == "no configuration");
    sdv_destroy(h);
    const std::string nowhere = "/nonexistent/x.sdv";
    const sdv_config missing = config(nowhere);
    CHECK(sdv_create(&missing, &h) == SDV_ERR_SCENARIO);
    CHECK(std::string(sdv_last_error(h)).find("/nonexistent/x.sdv") != std::string::npos);
    uint64_t id = 0;
    CHECK(sdv_claim(h, "ego", SDV_CONTROL_POSE, &id) == SDV_ERR_STATE);  // a failed handle refuses work
    sdv_destroy(h);
    const std::string dir = temp_dir("bad");
    const std::string bad = write_scenario(dir, "scenario s {\n    road nowhere\n}\n");
    const sdv_config c = config(bad);
    CHECK(sdv_create(&c, &h) == SDV_ERR_SCENARIO);
    CHECK(std::string(sdv_last_error(h)).find("error[E") != std::string::npos);  // the compiler's diagnostics
    sdv_destroy(h);
    const std::string good = write_scenario(dir);
    sdv_config wrong_step = config(good);
    wrong_step.step_num = 1;
    wrong_step.step_den = 100;
    CHECK(sdv_create(&wrong_step, &h) == SDV_ERR_UNSUPPORTED);
    sdv_destroy(h);
    sdv_destroy(nullptr);
}

TEST_CASE("claims, states and steps refuse misuse with a message") {
    const std::string path = write_scenario(temp_dir("misuse"));
    sdv_sim* h = nullptr;
    const sdv_config c = config(path);
    REQUIRE(sdv_create(&c, &h) == SDV_OK);
    size_t n = 0;
    CHECK(sdv_get_actor_info(h, nullptr, 0, &n) == SDV_ERR_BUFFER);
    REQUIRE(n == 3);
    std::vector<sdv_actor_info> info(n);
    CHECK(sdv_get_actor_info(h, info.data(), 1, &n) == SDV_ERR_BUFFER);  // too small: the count needed
    CHECK(n == 3);
    REQUIRE(sdv_get_actor_info(h, info.data(), info.size(), &n) == SDV_OK);
    CHECK(std::string(info[0].name) == "ego");
    CHECK(info[0].external == 1);
    CHECK(info[1].external == 0);
    CHECK(info[2].kind == SDV_KIND_OBJECT);
    CHECK(info[0].id == 1);
    CHECK(info[2].id == 3);

    sdv_run_state rs{};
    CHECK(sdv_step(h, &rs) == SDV_ERR_STATE);  // the external ego is not claimed
    CHECK(std::string(sdv_last_error(h)).find("'ego' is not claimed") != std::string::npos);
    uint64_t id = 0;
    CHECK(sdv_claim(h, "v2", SDV_CONTROL_POSE, &id) == SDV_ERR_NOT_FOUND);
    CHECK(std::string(sdv_last_error(h)).find("not external") != std::string::npos);
    CHECK(sdv_claim(h, "nobody", SDV_CONTROL_POSE, &id) == SDV_ERR_NOT_FOUND);
    CHECK(sdv_claim(h, "ego", SDV_CONTROL_COMMAND, &id) == SDV_ERR_UNSUPPORTED);
    CHECK(sdv_set_external_command(h, 1, 0, 0) == SDV_ERR_UNSUPPORTED);
    REQUIRE(sdv_claim(h, "ego", SDV_CONTROL_POSE, &id) == SDV_OK);
    CHECK(id == 1);
    CHECK(sdv_claim(h, "ego", SDV_CONTROL_POSE, &id) == SDV_ERR_STATE);  // twice

    CHECK(sdv_step(h, &rs) == SDV_ERR_STATE);  // no state for tick 1
    CHECK(std::string(sdv_last_error(h)).find("no state of 'ego' for tick 1") != std::string::npos);
    sdv_actor_state st = states(h)[0];
    st.x = NAN;
    CHECK(sdv_set_external_state(h, &st) == SDV_ERR_ARG);
    st = states(h)[0];
    st.id = 2;  // not claimed
    CHECK(sdv_set_external_state(h, &st) == SDV_ERR_NOT_FOUND);
    st.id = 1;
    st.struct_size = 4;
    CHECK(sdv_set_external_state(h, &st) == SDV_ERR_ARG);
    st.struct_size = sizeof st;
    REQUIRE(sdv_set_external_state(h, &st) == SDV_OK);
    CHECK(std::string(sdv_last_error(h)).empty());  // a call that succeeds clears it
    REQUIRE(sdv_step(h, &rs) == SDV_OK);
    CHECK(rs == SDV_RUNNING);
    CHECK(sdv_claim(h, "ego", SDV_CONTROL_POSE, &id) == SDV_ERR_STATE);  // after the first step
    uint64_t tick = 0;
    double t = 0;
    REQUIRE(sdv_get_tick(h, &tick, &t) == SDV_OK);
    CHECK(tick == 1);
    CHECK(t == 1.0 / 30);
    CHECK(sdv_get_osi_ground_truth(h, nullptr, 0, &n) == SDV_ERR_UNSUPPORTED);
    sdv_destroy(h);
}

TEST_CASE("output arrays: whatever the caller's memory held (uninitialised in C), they are filled") {
    // examples/cosim/c_client.c declared its array without initialising it; the library read
    // each element's struct_size from it and, with stack garbage below sizeof, refused the call
    // (under ASan, whose fresh stack differs from a release build's).
    const std::string path = write_scenario(temp_dir("garbage"));
    sdv_sim* h = nullptr;
    const sdv_config c = config(path);
    REQUIRE(sdv_create(&c, &h) == SDV_OK);
    for (const int fill : {0x00, 0x01, 0xAB, 0xFF, -1}) {
        CAPTURE(fill);
        std::vector<sdv_actor_state> states(8);
        std::memset(states.data(), fill < 0 ? 0 : fill, states.size() * sizeof(sdv_actor_state));
        if (fill < 0)
            for (auto& st : states) st.struct_size = 4;  // small and not 0, as garbage may be
        size_t n = 0;
        REQUIRE(sdv_get_actor_states(h, states.data(), states.size(), &n) == SDV_OK);
        REQUIRE(n == 3);
        for (size_t i = 0; i < n; ++i) CHECK(states[i].struct_size == sizeof(sdv_actor_state));
        std::vector<sdv_actor_info> info(8);
        std::memset(info.data(), fill < 0 ? 0 : fill, info.size() * sizeof(sdv_actor_info));
        if (fill < 0)
            for (auto& in : info) in.struct_size = 4;
        CHECK(sdv_get_actor_info(h, info.data(), info.size(), &n) == SDV_OK);
    }
    sdv_destroy(h);
}

TEST_CASE("a step is Jacobi: where the ego goes at k+1 does not move an NPC at k+1") {
    const std::string path = write_scenario(temp_dir("jacobi"));
    sdv_sim *a = nullptr, *b = nullptr;
    const sdv_config c = config(path);
    REQUIRE(sdv_create(&c, &a) == SDV_OK);
    REQUIRE(sdv_create(&c, &b) == SDV_OK);
    uint64_t ego = 0;
    REQUIRE(sdv_claim(a, "ego", SDV_CONTROL_POSE, &ego) == SDV_OK);
    REQUIRE(sdv_claim(b, "ego", SDV_CONTROL_POSE, &ego) == SDV_OK);
    const sdv_actor_state start = states(a)[0];
    sdv_run_state rs{};
    for (uint64_t k = 0; k < 90; ++k) {
        const sdv_actor_state s = ego_at(start, ego, k + 1);
        REQUIRE(sdv_set_external_state(a, &s) == SDV_OK);
        REQUIRE(sdv_set_external_state(b, &s) == SDV_OK);
        REQUIRE(sdv_step(a, &rs) == SDV_OK);
        REQUIRE(sdv_step(b, &rs) == SDV_OK);
    }
    // Step 90 → 91: b's ego jumps into lane 2, right next to v2.
    sdv_actor_state sa = ego_at(start, ego, 91), sb = sa;
    sb.y += 3.5;
    REQUIRE(sdv_set_external_state(a, &sa) == SDV_OK);
    REQUIRE(sdv_set_external_state(b, &sb) == SDV_OK);
    REQUIRE(sdv_step(a, &rs) == SDV_OK);
    REQUIRE(sdv_step(b, &rs) == SDV_OK);
    const auto xa = states(a), xb = states(b);
    CHECK(xa[0].y != xb[0].y);
    CHECK(xa[1].x == xb[1].x);  // v2 at 91 comes from its plan made from the snapshot at 90
    CHECK(xa[1].y == xb[1].y);
    CHECK(xa[1].speed == xb[1].speed);
    sdv_destroy(a);
    sdv_destroy(b);
}

TEST_CASE("no global state: interleaved handles and thread counts give the same runs") {
    const std::string path = write_scenario(temp_dir("interleave"));
    const std::vector<double> alone = run(path, 1);
    REQUIRE(alone.size() > 100);
    CHECK(run(path, 2) == alone);
    // Two handles stepped in turn in one thread.
    sdv_sim *a = nullptr, *b = nullptr;
    const sdv_config c = config(path);
    REQUIRE(sdv_create(&c, &a) == SDV_OK);
    REQUIRE(sdv_create(&c, &b) == SDV_OK);
    uint64_t ego = 0;
    REQUIRE(sdv_claim(a, "ego", SDV_CONTROL_POSE, &ego) == SDV_OK);
    REQUIRE(sdv_claim(b, "ego", SDV_CONTROL_POSE, &ego) == SDV_OK);
    const sdv_actor_state start = states(a)[0];
    std::vector<double> ra, rb;
    sdv_run_state sa = SDV_RUNNING, sb = SDV_RUNNING;
    for (uint64_t k = 0; sa == SDV_RUNNING; ++k) {
        const sdv_actor_state s = ego_at(start, ego, k + 1);
        REQUIRE(sdv_set_external_state(a, &s) == SDV_OK);
        REQUIRE(sdv_step(a, &sa) == SDV_OK);
        REQUIRE(sdv_set_external_state(b, &s) == SDV_OK);
        REQUIRE(sdv_step(b, &sb) == SDV_OK);
        for (const auto& x : states(a)) ra.insert(ra.end(), {x.x, x.y, x.yaw, x.speed, x.accel, x.s, x.d});
        for (const auto& x : states(b)) rb.insert(rb.end(), {x.x, x.y, x.yaw, x.speed, x.accel, x.s, x.d});
    }
    CHECK(sb == sa);
    CHECK(ra == alone);
    CHECK(rb == alone);
    CHECK(sa == SDV_ENDED_SUCCESS);  // timeout with every expectation holding
    sdv_run_state after{};
    CHECK(sdv_step(a, &after) == SDV_ERR_STATE);  // nothing after the end
    sdv_destroy(a);
    sdv_destroy(b);
}

TEST_CASE("outputs: a finished run as `sdv run` writes it, an abandoned one marked aborted") {
    const std::string dir = temp_dir("outputs");
    const std::string path = write_scenario(dir);
    const std::string done = dir + "/done";
    run(path, 1, done.c_str());
    CHECK(fs::exists(done + "/trajectories.csv"));
    CHECK(!fs::exists(done + "/trajectories.csv.part"));
    const std::string summary = read(done + "/summary.json");
    CHECK(summary.find("\"ending\": \"finished\"") != std::string::npos);
    CHECK(summary.find("\"passed\": true") != std::string::npos);
    CHECK(read(done + "/trajectories.csv").find(",ego,external,") != std::string::npos);

    const std::string left = dir + "/left";
    sdv_sim* h = nullptr;
    const sdv_config c = config(path, left.c_str());
    REQUIRE(sdv_create(&c, &h) == SDV_OK);
    uint64_t ego = 0;
    REQUIRE(sdv_claim(h, "ego", SDV_CONTROL_POSE, &ego) == SDV_OK);
    sdv_actor_state s = states(h)[0];
    sdv_run_state rs{};
    REQUIRE(sdv_set_external_state(h, &s) == SDV_OK);
    REQUIRE(sdv_step(h, &rs) == SDV_OK);
    size_t n = 0;
    CHECK(sdv_poll_events(h, nullptr, 0, &n) == SDV_OK);
    sdv_destroy(h);  // without sdv_finish
    CHECK(read(left + "/summary.json").find("\"aborted\": true") != std::string::npos);
}

TEST_CASE("events: an NPC's maneuver changes and the end of the run, drained in order") {
    const std::string path = write_scenario(temp_dir("events"));
    sdv_sim* h = nullptr;
    const sdv_config c = config(path);
    REQUIRE(sdv_create(&c, &h) == SDV_OK);
    uint64_t ego = 0;
    REQUIRE(sdv_claim(h, "ego", SDV_CONTROL_POSE, &ego) == SDV_OK);
    const sdv_actor_state start = states(h)[0];
    std::vector<sdv_event> seen;
    sdv_run_state rs = SDV_RUNNING;
    for (uint64_t k = 0; rs == SDV_RUNNING; ++k) {
        const sdv_actor_state s = ego_at(start, ego, k + 1);
        REQUIRE(sdv_set_external_state(h, &s) == SDV_OK);
        REQUIRE(sdv_step(h, &rs) == SDV_OK);
        sdv_event ev[1];
        size_t n = 0;
        // One at a time: the rest wait for the next call.
        while (sdv_poll_events(h, ev, 1, &n) == SDV_OK && n == 1) seen.push_back(ev[0]);
    }
    REQUIRE(!seen.empty());
    CHECK(seen.back().type == SDV_EVENT_SCENARIO_END);
    CHECK(std::string(seen.back().text) == "timeout");
    CHECK(seen.back().tick == 240);
    bool maneuver = false;
    for (size_t i = 0; i + 1 < seen.size(); ++i) {
        CHECK(seen[i].tick <= seen[i + 1].tick);
        if (seen[i].type == SDV_EVENT_MANEUVER && seen[i].a == 2) maneuver = true;
    }
    CHECK(maneuver);
    sdv_destroy(h);
}

}  // namespace capi_test
