// The two encodings of one schema.
#include "runtime/cosim/codec.h"

#include <doctest/doctest.h>
#include <google/protobuf/util/message_differencer.h>

#include <cmath>

// This file's tests and helpers, apart from the other files of its unity batch.
namespace codec_test {

using namespace sdv::cosim;

namespace {

v1::Envelope sample() {
    v1::Envelope e;
    e.set_seq(42);
    auto& r = *e.mutable_step_result();
    auto& o = *r.mutable_observation();
    o.set_tick(42);
    o.set_time_s(1.4);
    auto& a = *o.add_actors();
    a.set_id(1);
    a.set_x(34.166666666666664);
    a.set_y(-1.75);
    a.set_speed(24.9);
    a.set_lane_id("highway.1");
    a.set_active(true);
    auto& b = *o.add_actors();
    b.set_id(2);
    b.set_yaw(-0.061);
    auto& ev = *r.add_events();
    ev.set_tick(42);
    ev.mutable_maneuver()->set_id(2);
    ev.mutable_maneuver()->set_maneuver("lane_change");
    ev.mutable_maneuver()->set_bt_node("cut_in/cutin");
    r.set_run_state(v1::StepResult::RUNNING);
    return e;
}

bool same(const v1::Envelope& a, const v1::Envelope& b) {
    return google::protobuf::util::MessageDifferencer::Equals(a, b);
}

}  // namespace

TEST_CASE("codec: binary and JSON round trips keep every value, doubles bit for bit") {
    const v1::Envelope e = sample();
    for (Encoding enc : {Encoding::binary, Encoding::json}) {
        v1::Envelope back;
        std::string error;
        REQUIRE(decode(encode(e, enc), enc, back, error));
        CHECK(same(e, back));
        CHECK(back.step_result().observation().actors(0).x() == 34.166666666666664);
        CHECK(encode(back, enc) == encode(e, enc));  // deterministic
    }
}

TEST_CASE("codec: JSON uses the schema's field names and prints defaults") {
    const std::string json = encode(sample(), Encoding::json);
    CHECK(json.find("\"step_result\"") != std::string::npos);
    CHECK(json.find("\"run_state\":\"RUNNING\"") != std::string::npos);
    CHECK(json.find("\"time_s\":1.4") != std::string::npos);
    CHECK(json.find("\"seq\":\"42\"") != std::string::npos);  // uint64 as a string (proto3 JSON)
    CHECK(json.find("\"yaw_rate\":0") != std::string::npos);  // a default value is printed
    CHECK(json.find("\"bt_node\":\"cut_in/cutin\"") != std::string::npos);
}

TEST_CASE(
    "codec: a JSON client may send numbers or strings, omit defaults and add unknown fields") {
    v1::Envelope e;
    std::string error;
    REQUIRE(decode(
        R"({"seq": 7, "hello": {"protocol": "sdv-cosim", "version_major": 1, "future_field": [1, 2],
                       "claims": [{"actor_name": "ego", "mode": "CONTROL_MODE_POSE"}]}, "extension": {}})",
        Encoding::json, e, error));
    CHECK(e.seq() == 7);
    CHECK(e.hello().claims(0).mode() == v1::CONTROL_MODE_POSE);
    REQUIRE(decode(
        R"({"seq": "8", "step": {"tick": "3", "updates": [{"id": 1, "state": {"x": 1e3, "active": true}}]}})",
        Encoding::json, e, error));
    CHECK(e.step().tick() == 3);
    CHECK(e.step().updates(0).state().x() == 1000.0);
    // proto3 JSON spells non-finite doubles as strings; the protocol refuses them later
    // (INVALID_VALUE).
    REQUIRE(decode(R"({"step": {"updates": [{"id": 1, "state": {"x": "NaN"}}]}})", Encoding::json,
                   e, error));
    CHECK(std::isnan(e.step().updates(0).state().x()));
}

TEST_CASE("codec: bytes that are no Envelope are refused with a message") {
    v1::Envelope e;
    std::string error;
    CHECK_FALSE(decode("{\"seq\": ", Encoding::json, e, error));
    CHECK(error.find("not a JSON Envelope") != std::string::npos);
    CHECK_FALSE(decode("\x01\x02\x03", Encoding::json, e, error));
    CHECK_FALSE(decode(R"({"seq": "x"})", Encoding::json, e, error));
    CHECK_FALSE(decode(std::string("\x0a\xff\xff\xff\xff\xff\xff", 7), Encoding::binary, e, error));
    CHECK(error.find("not a binary Envelope") != std::string::npos);
    // An empty payload is an empty Envelope in binary (the protocol then says it carries nothing).
    CHECK(decode("", Encoding::binary, e, error));
    CHECK(e.body_case() == v1::Envelope::BODY_NOT_SET);
    CHECK_FALSE(decode("", Encoding::json, e, error));
    // Deeply nested garbage does not overflow the stack.
    std::string deep(100000, '[');
    CHECK_FALSE(decode(deep, Encoding::json, e, error));
    // 100,000 nested start-group tags of an unknown field (field 100, wire type 3).
    std::string groups;
    for (int i = 0; i < 100000; ++i) groups += "\xa3\x06";
    CHECK_FALSE(decode(groups, Encoding::binary, e, error));
}

TEST_CASE("codec: encoding names") {
    CHECK(parse_encoding("binary") == Encoding::binary);
    CHECK(parse_encoding("json") == Encoding::json);
    CHECK_FALSE(parse_encoding("xml"));
    CHECK(std::string(encoding_name(Encoding::json)) == "json");
}

}  // namespace codec_test
