// Every check of a StepRequest happens before anything reaches the session, so a refused request
// leaves the run exactly at tick k (the outputs then end there). Messages name what was expected
// and what came, with the tick and the actor's name, because the person reading them is
// debugging a client.
#include "runtime/cosim/protocol.h"

#include <algorithm>
#include <cmath>

#include "runtime/ir/utf8.h"

namespace sdv::cosim {
namespace {

v1::StepResult::RunState wire_state(RunState s) {
    switch (s) {
        case RunState::running:
            return v1::StepResult::RUNNING;
        case RunState::ended_success:
            return v1::StepResult::ENDED_SUCCESS;
        case RunState::ended_failure:
            return v1::StepResult::ENDED_FAILURE;
        case RunState::ended_timeout:
            return v1::StepResult::ENDED_TIMEOUT;
    }
    return v1::StepResult::RUN_STATE_UNSPECIFIED;
}

v1::ActorInfo::Kind wire_kind(ActorKind k) {
    switch (k) {
        case ActorKind::car:
            return v1::ActorInfo::KIND_CAR;
        case ActorKind::truck:
            return v1::ActorInfo::KIND_TRUCK;
        case ActorKind::pedestrian:
            return v1::ActorInfo::KIND_PEDESTRIAN;
        case ActorKind::cyclist:
            return v1::ActorInfo::KIND_CYCLIST;
        case ActorKind::object:
            return v1::ActorInfo::KIND_OBJECT;
    }
    return v1::ActorInfo::KIND_UNSPECIFIED;
}

void to_wire(const ActorState& s, v1::ActorState& out) {
    out.set_id(s.id);
    out.set_x(s.x);
    out.set_y(s.y);
    out.set_z(s.z);
    out.set_yaw(s.yaw);
    out.set_speed(s.speed);
    out.set_accel(s.accel);
    out.set_yaw_rate(s.yaw_rate);
    out.set_lane_id(s.lane_id);
    out.set_s(s.s);
    out.set_d(s.d);
    out.set_active(s.active);
}

// The first non-finite field of a state, or nullptr.
const char* non_finite_field(const v1::ActorState& s) {
    const std::pair<const char*, double> fields[] = {{"x", s.x()},
                                                     {"y", s.y()},
                                                     {"z", s.z()},
                                                     {"yaw", s.yaw()},
                                                     {"speed", s.speed()},
                                                     {"accel", s.accel()},
                                                     {"yaw_rate", s.yaw_rate()},
                                                     {"s", s.s()},
                                                     {"d", s.d()}};
    for (const auto& [name, v] : fields) {
        if (!std::isfinite(v)) return name;
    }
    return nullptr;
}

std::string number(double v) {
    if (std::isnan(v)) return "NaN";
    return v > 0 ? "Infinity" : "-Infinity";
}

double field(const v1::ActorState& s, const std::string& name) {
    if (name == "x") return s.x();
    if (name == "y") return s.y();
    if (name == "z") return s.z();
    if (name == "yaw") return s.yaw();
    if (name == "speed") return s.speed();
    if (name == "accel") return s.accel();
    if (name == "yaw_rate") return s.yaw_rate();
    if (name == "s") return s.s();
    return s.d();
}

const char* run_state_name(RunState s) {
    switch (s) {
        case RunState::running:
            return "RUNNING";
        case RunState::ended_success:
            return "ENDED_SUCCESS";
        case RunState::ended_failure:
            return "ENDED_FAILURE";
        case RunState::ended_timeout:
            return "ENDED_TIMEOUT";
    }
    return "?";
}

}  // namespace

std::string code_name(v1::Error::Code code) { return v1::Error::Code_Name(code); }

std::string printable(std::string_view text, size_t max_bytes) {
    std::string out;
    size_t i = 0;
    while (i < text.size() && out.size() < max_bytes) {
        const auto c = static_cast<unsigned char>(text[i]);
        const size_t n = ir::utf8_sequence_length(text, i);
        if (n == 0) {
            static constexpr char kHex[] = "0123456789abcdef";
            out += "\\x";
            out += kHex[c >> 4];
            out += kHex[c & 15];
            ++i;
        } else if (n == 1 && (c < 0x20 || c == 0x7f)) {
            out += ' ';
            ++i;
        } else {
            out.append(text.substr(i, n));
            i += n;
        }
    }
    if (i < text.size()) out += "...";
    return out;
}

WelcomeInfo welcome_info(const ir::Program& program, int scenario) {
    WelcomeInfo info;
    if (scenario < 0 || static_cast<size_t>(scenario) >= program.scenarios.size()) return info;
    const ir::Scenario& sc = program.scenarios[static_cast<size_t>(scenario)];
    if (sc.road < 0 || static_cast<size_t>(sc.road) >= program.roads.size()) return info;
    const ir::Road& road = program.roads[static_cast<size_t>(sc.road)];
    info.map_reference = road.map_file;
    info.has_origin = road.has_origin;
    info.origin_lat_deg = road.origin_lat;
    info.origin_lon_deg = road.origin_lon;
    info.origin_alt_m = road.origin_alt;
    return info;
}

Protocol::Protocol(Session& session, WelcomeInfo info, Encoding encoding)
    : session_(session), info_(std::move(info)), encoding_(encoding) {}

std::string Protocol::name_of(uint64_t id) const {
    for (const auto& a : session_.actors()) {
        if (a.id == id) return "actor " + std::to_string(id) + " '" + a.name + "'";
    }
    return "actor " + std::to_string(id);
}

void Protocol::close(Outcome::Kind kind, v1::Error::Code code, const std::string& message,
                     const std::string& ending) {
    // Both may quote what the client sent; they go into an Error, summary.json and the terminal.
    phase_ = Phase::closed;
    outcome_.kind = kind;
    outcome_.code = code;
    outcome_.message = printable(message);
    outcome_.ending = printable(ending);
}

std::string Protocol::error(uint64_t seq, v1::Error::Code code, const std::string& message) {
    close(code == v1::Error::TIMEOUT ? Outcome::Kind::timeout : Outcome::Kind::error, code, message,
          "aborted: " + code_name(code) + ": " + message);
    v1::Envelope e;
    e.set_seq(seq);
    e.mutable_error()->set_code(code);
    e.mutable_error()->set_message(outcome_.message);
    return encode(e, encoding_);
}

std::string Protocol::fail(v1::Error::Code code, const std::string& message) {
    if (closed()) {
        v1::Envelope e;
        e.mutable_error()->set_code(code);
        e.mutable_error()->set_message(printable(message));
        return encode(e, encoding_);
    }
    return error(0, code, message);
}

void Protocol::disconnected(const std::string& why) {
    if (closed()) return;
    close(Outcome::Kind::disconnected, v1::Error::CODE_UNSPECIFIED, why,
          "aborted: client disconnected");
}

std::string Protocol::finish() {
    if (finished_) return "";
    finished_ = true;
    return session_.finish(outcome_.ending.empty() ? "aborted: the session was not closed"
                                                   : outcome_.ending);
}

void Protocol::observation(v1::Observation& out) const {
    out.set_tick(session_.tick());
    out.set_time_s(session_.time());
    for (const ActorState& s : session_.states()) to_wire(s, *out.add_actors());
}

std::optional<std::string> Protocol::on_frame(std::string_view payload) {
    if (closed()) return std::nullopt;
    ++frames_;
    v1::Envelope in;
    std::string why;
    if (!decode(payload, encoding_, in, why)) {
        return error(0, v1::Error::PROTOCOL_VIOLATION,
                     "frame " + std::to_string(frames_) + " (" + std::to_string(payload.size()) +
                         " bytes): " + why +
                         (encoding_ == Encoding::binary ? "; this session speaks binary protobuf"
                                                        : "; this session speaks proto3-JSON"));
    }
    const uint64_t seq = in.seq();
    switch (in.body_case()) {
        case v1::Envelope::kHello:
            if (phase_ != Phase::hello) {
                return error(seq, v1::Error::PROTOCOL_VIOLATION,
                             std::string("Hello was already received; expected ") +
                                 (phase_ == Phase::running ? "StepRequest or Bye" : "Bye"));
            }
            return on_hello(seq, in.hello());
        case v1::Envelope::kStep:
            if (phase_ == Phase::hello) {
                return error(seq, v1::Error::PROTOCOL_VIOLATION,
                             "StepRequest before Hello; the first message must be Hello");
            }
            if (phase_ == Phase::ended) {
                return error(seq, v1::Error::PROTOCOL_VIOLATION,
                             "StepRequest after the end of the run (" +
                                 std::string(run_state_name(session_.run_state())) + " at tick " +
                                 std::to_string(session_.tick()) + "); expected Bye");
            }
            return on_step(seq, in.step());
        case v1::Envelope::kBye: {
            const std::string reason = in.bye().reason();
            close(Outcome::Kind::bye, v1::Error::CODE_UNSPECIFIED, reason, "bye: " + reason);
            return std::nullopt;
        }
        case v1::Envelope::kError: {
            const std::string m = code_name(in.error().code()) + ": " + in.error().message();
            close(Outcome::Kind::client_error, in.error().code(), m, "aborted: client error " + m);
            return std::nullopt;
        }
        case v1::Envelope::kWelcome:
        case v1::Envelope::kStepResult:
            return error(seq, v1::Error::PROTOCOL_VIOLATION,
                         std::string(in.has_welcome() ? "Welcome" : "StepResult") +
                             " is sent by sdv, not by the client");
        case v1::Envelope::BODY_NOT_SET:
            break;
    }
    return error(
        seq, v1::Error::PROTOCOL_VIOLATION,
        std::string(
            "the Envelope carries no message (or one this version does not know); expected ") +
            (phase_ == Phase::hello     ? "Hello"
             : phase_ == Phase::running ? "StepRequest or Bye"
                                        : "Bye"));
}

std::string Protocol::on_hello(uint64_t seq, const v1::Hello& hello) {
    if (hello.protocol() != kProtocolName) {
        return error(
            seq, v1::Error::PROTOCOL_VIOLATION,
            "Hello.protocol is '" + hello.protocol() + "'; expected '" + kProtocolName + "'");
    }
    if (hello.version_major() != kVersionMajor) {
        return error(seq, v1::Error::VERSION_MISMATCH,
                     "the client speaks sdv-cosim " + std::to_string(hello.version_major()) + "." +
                         std::to_string(hello.version_minor()) + "; this sdv speaks " +
                         std::to_string(kVersionMajor) + "." + std::to_string(kVersionMinor) +
                         " (major versions must match)");
    }
    client_name_ = printable(hello.client_name(), 200);
    for (const auto& c : hello.claims()) {
        if (c.mode() == v1::CONTROL_MODE_COMMAND) {
            // COMMAND is a v1.1 feature: the client asks for more than this version offers.
            return error(seq, v1::Error::VERSION_MISMATCH,
                         "claim of '" + c.actor_name() +
                             "': CONTROL_MODE_COMMAND is sdv-cosim 1.1; this sdv (" +
                             std::to_string(kVersionMajor) + "." + std::to_string(kVersionMinor) +
                             ") supports CONTROL_MODE_POSE only");
        }
        if (c.mode() != v1::CONTROL_MODE_POSE) {
            return error(
                seq, v1::Error::INVALID_VALUE,
                "claim of '" + c.actor_name() + "' has mode " +
                    std::to_string(static_cast<int>(c.mode())) +
                    (c.mode() == v1::CONTROL_MODE_UNSPECIFIED ? " (CONTROL_MODE_UNSPECIFIED)"
                                                              : "") +
                    "; expected CONTROL_MODE_POSE");
        }
        uint64_t id = 0;
        switch (session_.claim(c.actor_name(), ControlMode::pose, id)) {
            case Status::ok:
                claimed_.push_back(id);
                break;
            case Status::not_found:
                return error(seq, v1::Error::UNKNOWN_ACTOR,
                             "claim of '" + c.actor_name() + "': " + session_.last_error());
            case Status::state:
                return error(seq, v1::Error::PROTOCOL_VIOLATION,
                             "claim of '" + c.actor_name() + "': " + session_.last_error());
            case Status::unsupported:
                return error(seq, v1::Error::VERSION_MISMATCH,
                             "claim of '" + c.actor_name() + "': " + session_.last_error());
            default:
                return error(seq, v1::Error::INTERNAL,
                             "claim of '" + c.actor_name() + "': " + session_.last_error());
        }
    }
    // v1 has no other driver for an external vehicle (engage_tick is v1.1): the one client
    // drives them all, so an unclaimed one is refused now rather than at the first step.
    for (const auto& a : session_.actors()) {
        if (a.external && std::find(claimed_.begin(), claimed_.end(), a.id) == claimed_.end()) {
            return error(seq, v1::Error::PROTOCOL_VIOLATION,
                         "external vehicle '" + a.name +
                             "' is not claimed; Hello must claim every external vehicle");
        }
    }
    v1::Envelope out;
    out.set_seq(seq);
    v1::Welcome& w = *out.mutable_welcome();
    w.set_version_major(kVersionMajor);
    w.set_version_minor(kVersionMinor);
    w.set_sdv_version(info_.sdv_version);
    w.set_step_num(session_.step_num());
    w.set_step_den(session_.step_den());
    w.set_seed(session_.seed());
    w.set_scenario(info_.scenario);
    w.set_scenario_sha256(info_.scenario_sha256);
    w.set_map_reference(info_.map_reference);
    // Always present (zeros when unknown), so a client reads it without checking.
    v1::GeoOrigin& o = *w.mutable_origin();
    if (info_.has_origin) {
        o.set_lat_deg(info_.origin_lat_deg);
        o.set_lon_deg(info_.origin_lon_deg);
        o.set_alt_m(info_.origin_alt_m);
    }
    for (const ActorInfo& a : session_.actors()) {
        v1::ActorInfo& ai = *w.add_actors();
        ai.set_id(a.id);
        ai.set_name(a.name);
        ai.set_kind(wire_kind(a.kind));
        ai.set_external(a.external);
        ai.set_length(a.length);
        ai.set_width(a.width);
        ai.set_height(a.height);
        ai.set_bbcenter_to_rear_x(a.bbcenter_to_rear_x);
    }
    observation(*w.mutable_initial());
    phase_ = session_.run_state() == RunState::running ? Phase::running : Phase::ended;
    return encode(out, encoding_);
}

std::string Protocol::on_step(uint64_t seq, const v1::StepRequest& step) {
    const uint64_t k = session_.tick();
    if (step.tick() != k) {
        return error(seq, v1::Error::BAD_TICK,
                     "expected tick " + std::to_string(k) + ", got " + std::to_string(step.tick()));
    }
    std::vector<const v1::ActorState*> states(claimed_.size(), nullptr);
    for (const auto& u : step.updates()) {
        const auto it = std::find(claimed_.begin(), claimed_.end(), u.id());
        if (it == claimed_.end()) {
            std::string list;
            for (uint64_t id : claimed_) list += (list.empty() ? "" : ", ") + name_of(id);
            return error(seq, v1::Error::UNKNOWN_ACTOR,
                         "tick " + std::to_string(k) + ": update for " + name_of(u.id()) +
                             ", which this client did not claim (claimed: " +
                             (list.empty() ? "none" : list) + ")");
        }
        const size_t i = static_cast<size_t>(it - claimed_.begin());
        if (states[i]) {
            return error(seq, v1::Error::PROTOCOL_VIOLATION,
                         "tick " + std::to_string(k) + ": two updates for " + name_of(u.id()) +
                             "; send exactly one per claimed actor");
        }
        if (u.input_case() != v1::ExternalUpdate::kState) {
            return error(seq, v1::Error::PROTOCOL_VIOLATION,
                         "tick " + std::to_string(k) + ": the update for " + name_of(u.id()) +
                             (u.has_command() ? " carries a command" : " carries no state") +
                             "; it is claimed with CONTROL_MODE_POSE, so it needs `state` (its "
                             "state at tick " +
                             std::to_string(k + 1) + ")");
        }
        if (u.state().id() != 0 && u.state().id() != u.id()) {
            return error(seq, v1::Error::INVALID_VALUE,
                         "tick " + std::to_string(k) + ": the update for " + name_of(u.id()) +
                             " carries the state of actor " + std::to_string(u.state().id()));
        }
        states[i] = &u.state();
    }
    for (size_t i = 0; i < claimed_.size(); ++i) {
        if (!states[i]) {
            return error(seq, v1::Error::MISSING_UPDATE,
                         "tick " + std::to_string(k) + ": no update for " + name_of(claimed_[i]) +
                             "; send exactly one per claimed actor");
        }
    }
    for (size_t i = 0; i < claimed_.size(); ++i) {
        if (const char* f = non_finite_field(*states[i])) {
            return error(seq, v1::Error::INVALID_VALUE,
                         "tick " + std::to_string(k) + ": " + name_of(claimed_[i]) + " has " + f +
                             " = " + number(field(*states[i], f)) + "; every value must be finite");
        }
    }
    for (size_t i = 0; i < claimed_.size(); ++i) {
        const v1::ActorState& w = *states[i];
        ActorState s;
        s.id = claimed_[i];
        s.x = w.x();
        s.y = w.y();
        s.z = w.z();
        s.yaw = w.yaw();
        s.speed = w.speed();
        s.accel = w.accel();
        s.yaw_rate = w.yaw_rate();
        s.lane_id = w.lane_id();
        s.s = w.s();
        s.d = w.d();
        s.active = w.active();
        switch (session_.set_external_state(s)) {
            case Status::ok:
                break;
            case Status::not_found:
                return error(seq, v1::Error::UNKNOWN_ACTOR, session_.last_error());
            case Status::arg:
                return error(seq, v1::Error::INVALID_VALUE, session_.last_error());
            default:
                return error(seq, v1::Error::INTERNAL, session_.last_error());
        }
    }
    RunState rs = RunState::running;
    switch (session_.step(rs)) {
        case Status::ok:
            break;
        case Status::state:
            return error(seq, v1::Error::PROTOCOL_VIOLATION,
                         "tick " + std::to_string(k) + ": " + session_.last_error());
        case Status::scenario:
            return error(seq, v1::Error::SCENARIO_ERROR,
                         "tick " + std::to_string(k) + ": " + session_.last_error());
        default:
            return error(seq, v1::Error::INTERNAL,
                         "tick " + std::to_string(k) + ": " + session_.last_error());
    }
    ++steps_;
    v1::Envelope out;
    out.set_seq(seq);
    v1::StepResult& r = *out.mutable_step_result();
    observation(*r.mutable_observation());
    for (const Event& e : session_.poll_events()) {
        v1::Event& we = *r.add_events();
        we.set_tick(e.tick);
        switch (e.type) {
            case Event::Type::collision:
                we.mutable_collision()->set_a(e.a);
                we.mutable_collision()->set_b(e.b);
                break;
            case Event::Type::scenario_end:
                we.mutable_scenario_end()->set_reason(e.text);
                break;
            case Event::Type::maneuver:
                we.mutable_maneuver()->set_id(e.a);
                we.mutable_maneuver()->set_maneuver(e.text);
                we.mutable_maneuver()->set_bt_node(e.node);
                break;
        }
    }
    r.set_run_state(wire_state(rs));
    if (rs != RunState::running) phase_ = Phase::ended;
    return encode(out, encoding_);
}

}  // namespace sdv::cosim
