// One co-simulation session over a loaded scenario (COSIM.md "sdv-cosim v1"): the one
// implementation of the step semantics under both the C API (include/sdv/sdv.h) and the network
// server (server.h). A client claims external vehicles, sets each one's state at k+1, and steps:
// every SDV is planned from the snapshot at k (Jacobi steps), so results never depend on the
// client's speed or on thread counts. Nothing here reads the wall clock. Not thread-safe: one
// thread per session; sessions share nothing but an optional road cache (SessionOptions::roads,
// thread-safe), so a process may run several.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "runtime/ir/ir.h"
#include "runtime/sim/simulation.h"

namespace sdv::cosim {

// The C API's status codes (sdv.h), also the server's view of what went wrong.
enum class Status { ok = 0, arg = -1, state = -2, not_found = -3, scenario = -4, buffer = -5, unsupported = -6, internal = -99 };

enum class RunState { running = 1, ended_success = 2, ended_failure = 3, ended_timeout = 4 };
enum class ControlMode { pose = 1, command = 2 };
enum class ActorKind { car = 1, truck = 2, pedestrian = 3, cyclist = 4, object = 5 };

// Static data of an actor. Ids are the vehicle's position in the scenario plus one, stable for
// the session (and the same in every session of the scenario).
struct ActorInfo {
    uint64_t id = 0;
    std::string name;
    ActorKind kind = ActorKind::car;
    bool external = false;  // declared `external` in the scenario (claimable)
    double length = 0, width = 0, height = 0;
    // From the bounding-box centre to the rear axle, along the heading (OSI's bbcenter_to_rear).
    // sdv moves vehicles by their box centre and models no axle: 0.
    double bbcenter_to_rear_x = 0;
};

// The state of an actor: bounding-box centre in map metres (x east, y north), yaw radians
// counter-clockwise from +x, signed speed and longitudinal acceleration, yaw rate, and its lane
// coordinates (lane name, s along it, d to the left of its centre; empty lane: off every lane).
struct ActorState {
    uint64_t id = 0;
    double x = 0, y = 0, z = 0, yaw = 0;
    double speed = 0, accel = 0, yaw_rate = 0;
    std::string lane_id;
    double s = 0, d = 0;
    bool active = true;
};

struct Event {
    enum class Type { collision = 1, scenario_end = 2, maneuver = 3 };
    uint64_t tick = 0;
    Type type = Type::collision;
    uint64_t a = 0, b = 0;  // collision: the two actors; maneuver: the actor in a
    std::string text;       // scenario_end: the reason; maneuver: the maneuver's name
    std::string node;       // maneuver: the behavior-tree node that selected it
};

struct SessionOptions {
    std::optional<uint64_t> seed;  // overrides the scenario's
    int threads = 1;
    bool trace = false;
    bool maneuver_events = true;   // report NPC maneuver changes as events
    std::string output_dir;        // empty: write no outputs
    // The road network and path lines shared with other sessions and runs of this process
    // (runtime/sim/road_cache.h): a session then starts without building its road. Null:
    // built by the session. The states are the same bytes either way.
    std::shared_ptr<sim::RoadCache> roads;
};

class Session {
public:
    // Loads the scenario (index into program.scenarios) and takes tick 0. On failure returns
    // nullptr and sets `error` (a located message).
    static std::unique_ptr<Session> create(std::shared_ptr<const ir::Program> program, int scenario,
                                           const SessionOptions& options, std::string& error);
    ~Session();  // writes the outputs (as aborted) if finish() was not called
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    // Takes control of an external vehicle by name, before the first step. `not_found` for a
    // name that is no external vehicle of the scenario; `state` after the first step or when
    // claimed twice; `unsupported` for ControlMode::command (v1.1).
    Status claim(const std::string& name, ControlMode mode, uint64_t& id);
    const std::vector<ActorInfo>& actors() const;

    // The state of a claimed actor at tick k+1 (replacing any earlier one for this step).
    // `not_found`: not a claimed actor; `arg`: a non-finite value.
    Status set_external_state(const ActorState& state);
    // k → k+1: every claimed actor must have a state for k+1 (`state` otherwise: the message
    // names the missing one). SDVs plan from the snapshot at k; then every agent moves to k+1,
    // the claimed ones to their given states; collisions and events at k+1. `state` once ended.
    Status step(RunState& run_state);

    uint64_t tick() const;
    double time() const;  // tick · step_num / step_den, computed, never accumulated
    uint32_t step_num() const { return 1; }
    uint32_t step_den() const;
    uint64_t seed() const;
    RunState run_state() const;
    const std::string& scenario_name() const;

    // Every actor at the current tick, sorted by id.
    std::vector<ActorState> states() const;
    // Events since the last call, in order (at most `max`; the rest stay for the next call).
    std::vector<Event> poll_events(size_t max = SIZE_MAX);
    size_t pending_events() const;

    // Ends the run: evaluates the expectations and writes the outputs (when an output directory
    // was given) marked with `ending` ("finished", "bye: <reason>", "aborted: <why>").
    // Idempotent; an error message or "".
    std::string finish(const std::string& ending = "finished");
    // The result of the run once finished (expectations, metrics, events).
    const sim::RunResult* result() const;

    // Why the last call that failed failed (each call clears it).
    const std::string& last_error() const { return last_error_; }

private:
    struct Impl;
    explicit Session(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
    std::string last_error_;
};

}  // namespace sdv::cosim
