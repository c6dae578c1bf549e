#include "runtime/cosim/session.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "runtime/io/outputs.h"
#include "runtime/io/recorder.h"
#include "runtime/ir/ir_io.h"
#include "runtime/road/geometry.h"
#include "runtime/sim/world.h"

namespace sdv::cosim {
namespace {

// sdv has no vehicle heights; a passenger car's (for the wire and OSI only).
constexpr double kHeight = 1.5;

double wrap(double a) { return std::remainder(a, 2 * M_PI); }

bool finite(const ActorState& s) {
    for (double v : {s.x, s.y, s.z, s.yaw, s.speed, s.accel, s.yaw_rate, s.s, s.d}) {
        if (!std::isfinite(v)) return false;
    }
    return true;
}

}  // namespace

struct Session::Impl {
    Impl(std::shared_ptr<const ir::Program> p, int sc, const SessionOptions& o)
        : program(std::move(p)), scenario(sc), options(o),
          sim(*program, sc, run_options(o), o.output_dir.empty() ? nullptr : &recorder) {}

    static sim::RunOptions run_options(const SessionOptions& o) {
        sim::RunOptions r;
        r.seed = o.seed;
        r.threads = o.threads;
        r.trace = o.trace;
        r.roads = o.roads;
        return r;
    }

    std::shared_ptr<const ir::Program> program;
    int scenario;
    SessionOptions options;
    io::Recorder recorder;  // before sim: the simulation reports to it
    sim::Simulation sim;
    std::vector<ActorInfo> actors;
    std::vector<bool> claimed;
    std::vector<std::optional<ActorState>> pending;  // per vehicle: its state for k+1
    std::vector<double> yaw_rate;
    std::vector<std::string> maneuver;  // per vehicle: the maneuver last reported
    std::vector<Event> events;
    size_t events_seen = 0;             // of the simulation's events
    bool stepped = false;
    std::optional<sim::RunResult> result;
    bool written = false;
    RunState state = RunState::running;

    void collect_events();
    void end_run();
};

Session::Session(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Session::~Session() {
    if (impl_ && !impl_->written) finish("aborted: the session was destroyed before it finished");
}

std::unique_ptr<Session> Session::create(std::shared_ptr<const ir::Program> program, int scenario,
                                         const SessionOptions& options, std::string& error) {
    if (!program || scenario < 0 || static_cast<size_t>(scenario) >= program->scenarios.size()) {
        error = "no such scenario";
        return nullptr;
    }
    auto impl = std::make_unique<Impl>(program, scenario, options);
    if (!options.output_dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(options.output_dir, ec);
        if (ec) {
            error = "cannot create '" + options.output_dir + "': " + ec.message();
            return nullptr;
        }
        if (auto e = impl->recorder.open(options.output_dir, options.trace); !e.empty()) {
            error = e;
            return nullptr;
        }
    }
    if (auto e = impl->sim.start(); !e.empty()) {
        impl->recorder.discard();
        impl->written = true;  // nothing to write
        error = e;
        return nullptr;
    }
    const sim::World& w = impl->sim.world();
    const size_t n = w.agents.size();
    impl->claimed.assign(n, false);
    impl->pending.assign(n, std::nullopt);
    impl->yaw_rate.assign(n, 0.0);
    impl->maneuver.assign(n, "");
    for (size_t i = 0; i < n; ++i) {
        const sim::Agent& a = w.agents[i];
        ActorInfo info;
        info.id = i + 1;
        info.name = a.v->name;
        info.kind = a.v->kind == ir::VehicleKind::static_object ? ActorKind::object
                    : a.v->length > 7.5                        ? ActorKind::truck
                                                               : ActorKind::car;
        info.external = a.v->kind == ir::VehicleKind::external;
        info.length = a.v->length;
        info.width = a.v->width;
        info.height = kHeight;
        impl->actors.push_back(info);
        if (a.driver) impl->maneuver[i] = a.driver->maneuver_name;
    }
    impl->collect_events();
    impl->events.clear();  // tick 0 has no maneuver changes to report: it is where they start
    return std::unique_ptr<Session>(new Session(std::move(impl)));
}

Status Session::claim(const std::string& name, ControlMode mode, uint64_t& id) {
    last_error_.clear();
    Impl& s = *impl_;
    for (size_t i = 0; i < s.actors.size(); ++i) {
        if (s.actors[i].name != name) continue;
        if (!s.actors[i].external) {
            last_error_ = "vehicle '" + name + "' is not external (declare it 'vehicle " + name + ": external')";
            return Status::not_found;
        }
        if (mode == ControlMode::command) {
            last_error_ = "control by command (acceleration, steering) is not supported yet; send poses";
            return Status::unsupported;
        }
        if (s.stepped) {
            last_error_ = "vehicles are claimed before the first step";
            return Status::state;
        }
        if (s.claimed[i]) {
            last_error_ = "vehicle '" + name + "' is claimed already";
            return Status::state;
        }
        s.claimed[i] = true;
        id = s.actors[i].id;
        return Status::ok;
    }
    last_error_ = "no vehicle '" + name + "' in scenario '" + scenario_name() + "'";
    return Status::not_found;
}

const std::vector<ActorInfo>& Session::actors() const { return impl_->actors; }

Status Session::set_external_state(const ActorState& state) {
    last_error_.clear();
    Impl& s = *impl_;
    if (state.id == 0 || state.id > s.actors.size() || !s.claimed[state.id - 1]) {
        last_error_ = "actor " + std::to_string(state.id) + " is not claimed by this client";
        return Status::not_found;
    }
    if (!finite(state)) {
        last_error_ = "the state of '" + s.actors[state.id - 1].name + "' has a non-finite value";
        return Status::arg;
    }
    // As far as a map may reach (1,000 km from its origin): the world indexes positions in cells.
    constexpr double kMaxPosition = 1e6;
    if (std::fabs(state.x) > kMaxPosition || std::fabs(state.y) > kMaxPosition || std::fabs(state.z) > kMaxPosition) {
        last_error_ = "the state of '" + s.actors[state.id - 1].name + "' is more than 1,000 km from the origin";
        return Status::arg;
    }
    s.pending[state.id - 1] = state;
    return Status::ok;
}

Status Session::step(RunState& run_state) {
    last_error_.clear();
    Impl& s = *impl_;
    run_state = s.state;
    if (s.result || s.sim.ended()) {
        last_error_ = "the run has ended (tick " + std::to_string(tick()) + ")";
        return Status::state;
    }
    for (size_t i = 0; i < s.actors.size(); ++i) {
        if (!s.actors[i].external) continue;
        if (!s.claimed[i]) {
            last_error_ = "external vehicle '" + s.actors[i].name + "' is not claimed: nothing would drive it";
            return Status::state;
        }
        if (!s.pending[i] && s.sim.world().agents[i].active) {
            last_error_ = "no state of '" + s.actors[i].name + "' for tick " + std::to_string(tick() + 1);
            return Status::state;
        }
    }
    sim::World& w = s.sim.world();
    std::vector<double> yaw0(w.agents.size());
    for (size_t i = 0; i < w.agents.size(); ++i) {
        yaw0[i] = w.agents[i].yaw;
        if (s.pending[i]) {
            const ActorState& p = *s.pending[i];
            w.agents[i].external = sim::Agent::ExternalState{p.x, p.y, p.yaw, p.speed, p.accel, p.active};
            s.pending[i].reset();
        }
    }
    s.stepped = true;
    s.sim.step();
    for (size_t i = 0; i < w.agents.size(); ++i) s.yaw_rate[i] = wrap(w.agents[i].yaw - yaw0[i]) / w.dt;
    s.collect_events();
    if (s.sim.ended()) s.end_run();
    run_state = s.state;
    return Status::ok;
}

void Session::Impl::collect_events() {
    const sim::World& w = sim.world();
    const uint64_t k = static_cast<uint64_t>(sim.tick());
    const auto& all = sim.result().events;
    for (; events_seen < all.size(); ++events_seen) {
        const sim::Event& e = all[events_seen];
        if (e.kind != "collision" || e.vehicles.size() < 2) continue;
        Event out;
        out.tick = k;
        out.type = Event::Type::collision;
        out.a = static_cast<uint64_t>(e.vehicles[0]) + 1;
        out.b = static_cast<uint64_t>(e.vehicles[1]) + 1;
        out.text = e.zone;
        events.push_back(out);
    }
    if (!options.maneuver_events) return;
    for (size_t i = 0; i < w.agents.size(); ++i) {
        const sim::Agent& a = w.agents[i];
        if (!a.driver || a.driver->maneuver_name == maneuver[i]) continue;
        maneuver[i] = a.driver->maneuver_name;
        Event out;
        out.tick = k;
        out.type = Event::Type::maneuver;
        out.a = i + 1;
        out.text = a.driver->maneuver_name;
        const int32_t node = a.driver->maneuver;
        if (node >= 0) out.node = a.driver->tree->instance().nodes[static_cast<size_t>(node)].path;
        events.push_back(out);
    }
}

// The run ended at this tick: its verdict, and the event that says why.
void Session::Impl::end_run() {
    result = sim.finish();
    const ir::Scenario& sc = program->scenarios[static_cast<size_t>(scenario)];
    std::string reason = "timeout";
    bool goal_missed = false;
    for (size_t i = 0; i < sc.vehicles.size(); ++i) {
        if (!sc.vehicles[i].goal_ends_run) continue;
        if (result->vehicles[i].reached_goal) reason = "goal of '" + sc.vehicles[i].name + "' reached";
        else goal_missed = true;
    }
    if (!result->timed_out && reason == "timeout") reason = "the scenario's end condition";
    state = !result->passed()                   ? RunState::ended_failure
            : result->timed_out && goal_missed ? RunState::ended_timeout
                                               : RunState::ended_success;
    Event e;
    e.tick = static_cast<uint64_t>(sim.tick());
    e.type = Event::Type::scenario_end;
    e.text = reason;
    events.push_back(e);
}

uint64_t Session::tick() const { return static_cast<uint64_t>(impl_->sim.tick()); }

double Session::time() const {
    // tick · 1 / rate: exact for every tick, never a running sum.
    return static_cast<double>(tick()) / static_cast<double>(step_den());
}

uint32_t Session::step_den() const {
    return static_cast<uint32_t>(std::llround(impl_->program->scenarios[static_cast<size_t>(impl_->scenario)].traffic_rate));
}

uint64_t Session::seed() const { return impl_->sim.world().seed; }

RunState Session::run_state() const { return impl_->state; }

const std::string& Session::scenario_name() const {
    return impl_->program->scenarios[static_cast<size_t>(impl_->scenario)].name;
}

std::vector<ActorState> Session::states() const {
    const sim::World& w = impl_->sim.world();
    std::vector<ActorState> out;
    out.reserve(w.agents.size());
    for (size_t i = 0; i < w.agents.size(); ++i) {
        const sim::Agent& a = w.agents[i];
        ActorState st;
        st.id = i + 1;
        st.x = a.x;
        st.y = a.y;
        st.yaw = a.yaw;
        st.speed = a.speed;
        st.accel = a.accel;
        st.yaw_rate = impl_->yaw_rate[i];
        if (a.lane != sim::kNoLane) {
            st.lane_id = w.net.lane(a.lane).name;
            st.s = a.lane_s;
            st.d = a.lane_d;
        }
        st.active = a.active;
        out.push_back(st);
    }
    return out;
}

std::vector<Event> Session::poll_events(size_t max) {
    auto& all = impl_->events;
    const size_t n = std::min(max, all.size());
    std::vector<Event> out(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(n));
    all.erase(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(n));
    return out;
}

size_t Session::pending_events() const { return impl_->events.size(); }

std::string Session::finish(const std::string& ending) {
    last_error_.clear();
    Impl& s = *impl_;
    if (s.written) return "";
    s.written = true;
    const bool ended = s.result.has_value();
    if (!ended) s.result = s.sim.finish();
    if (s.options.output_dir.empty()) return "";
    io::RunInfo info;
    info.ir_hash = ir::program_hash(*s.program);
    info.seed = s.sim.world().seed;
    info.trace = s.options.trace;
    info.threads = s.options.threads;
    // A client's Bye after the end is a normal end; before it, a stop at that tick. The Bye's
    // reason is the client's and stays out, so that every transport writes the same bytes.
    if (ending.rfind("aborted", 0) == 0) info.cosim_ending = ending;
    else if (ended) info.cosim_ending = "finished";
    else info.cosim_ending = "stopped by client at tick " + std::to_string(tick());
    if (auto e = s.recorder.commit(); !e.empty()) return e;
    return io::write_outputs(s.options.output_dir, *s.program, s.scenario, *s.result, s.recorder.take(), info);
}

const sim::RunResult* Session::result() const { return impl_->result ? &*impl_->result : nullptr; }

}  // namespace sdv::cosim
