// The checked IR (.sdvir): what the runtime runs. Self-contained (imports inlined, subtrees
// expanded per vehicle, defaults resolved), SI units only, names resolved to indices, every
// node with its source location. Plain data in flat vectors; it exists only when the checker
// found no errors, and the reader validates everything it loads.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "runtime/catalog/catalog.h"

namespace sdv::ir {

inline constexpr int kFormatVersion = 1;
inline constexpr const char* kFormatName = "sdvir";

// A source position kept for messages and traces: index into Program::files, 1-based line/col.
struct SourceLoc {
    uint32_t file = 0;
    uint32_t line = 0;
    uint32_t col = 0;
    friend bool operator==(const SourceLoc&, const SourceLoc&) = default;
};

enum class SampleMethod { linear, uniform, normal };

// A possibly sampled number in SI units. A single value has samples == 1 and lo == hi == value.
struct Sampled {
    double value = 0.0;
    double lo = 0.0;
    double hi = 0.0;
    int samples = 1;
    SampleMethod method = SampleMethod::linear;
    double sigma = 0.0;  // normal: standard deviation (SI)
    friend bool operator==(const Sampled&, const Sampled&) = default;
};

// How a vehicle parameter names its vehicle.
struct VehicleRef {
    enum class Kind { none, self, vehicle, zone } kind = Kind::none;
    int32_t vehicle = -1;  // Kind::vehicle: index into Scenario::vehicles
    int32_t zone = -1;     // Kind::zone: index into catalog::vehicle_zones() (front = 2, ...)
    friend bool operator==(const VehicleRef&, const VehicleRef&) = default;
};

// One parameter of a leaf, resolved. `given` is false only for optional parameters that have
// no default and were not written (e.g. sim_time's `before`).
struct ParamValue {
    bool given = true;
    Sampled number;      // quantity, integer, boolean (0/1)
    int32_t choice = -1; // choice: index into the catalog's choices
    VehicleRef vehicle;  // vehicle
    friend bool operator==(const ParamValue&, const ParamValue&) = default;
};

enum class NodeKind {
    fallback,
    sequence,
    reactive_sequence,
    parallel,
    condition,
    maneuver,
    not_,
    once,
    latch,
};

// One node of an expanded tree. Subtree references are gone: their roots are inlined, and
// `path` records where a node came from ("cut_in/fallback[0]/std.drive/keep").
struct Node {
    NodeKind kind = NodeKind::sequence;
    std::vector<int32_t> children;  // indices into TreeInstance::nodes
    int32_t leaf = -1;              // maneuver: catalog::ManeuverKind; condition: ConditionKind
    std::vector<ParamValue> params; // leaves: one per catalog parameter, in catalog order
    int32_t success_threshold = 0;  // parallel: children that must succeed
    std::string name;               // label, or the leaf's catalog name
    std::string path;
    int32_t tree = -1;              // index into Program::trees of the declaring tree
    SourceLoc loc;
};

struct TreeInstance {
    std::vector<Node> nodes;  // nodes[0] is the root
};

// A tree as declared (for tooling: reuse, diff); the runtime uses the instances.
struct TreeDecl {
    std::string name;  // qualified: "std.drive", "cut_in"
    std::vector<std::string> params;
    int32_t node_count = 0;  // nodes in the declaration itself (subtree calls count as one)
    SourceLoc loc;
};

enum class RoadKind { road, junction, lanelet2 };

// The longest built-in road (its segments together): building one is linear in its length.
inline constexpr double kMaxRoadLength = 100e3;

struct Segment {
    bool arc = false;
    double length = 0.0;
    double radius = 0.0;  // signed: > 0 turns left
};

// A crosswalk of a built-in road (`at`: along the reference line) or junction (`arm`, `at`: its
// near edge's distance from the junction box).
struct Crosswalk {
    std::string name;
    std::string arm;  // junction: north | east | south | west
    double at = 0.0;
    double width = 3.0;
    bool signalised = false;
    SourceLoc loc;
};

struct Road {
    RoadKind kind = RoadKind::road;
    std::string name;
    // road
    int32_t lanes_forward = 1;
    int32_t lanes_backward = 0;
    double lane_width = 3.5;
    double speed_limit = 13.89;
    double origin_x = 0.0, origin_y = 0.0, heading = 0.0;
    std::vector<Segment> segments;
    // junction (lanes_forward = lanes per direction)
    double arm_length = 100.0;
    std::string control;  // stop_signs | traffic_lights | none
    std::vector<Crosswalk> crosswalks;  // road and junction
    // lanelet2
    std::string map_file;  // path as resolved at compile time
    double origin_lat = 0.0, origin_lon = 0.0, origin_alt = 0.0;
    bool has_origin = false;
    SourceLoc loc;
};

// How an agent moves: its tree (sdv; a pedestrian's tree: "sdp"), time-stamped waypoints
// (trajectory), waypoints with speeds (path: timed by the runtime once it has placed them),
// not at all (static), or by a co-simulation client (external).
enum class VehicleKind { sdv, trajectory, static_object, external, path };

struct Position {
    bool xy = false;
    std::string lane;  // lane name in the road model ("highway.1", lanelet id)
    double s = 0.0;
    double offset = 0.0;
    double x = 0.0, y = 0.0, heading = 0.0;
    bool has_heading = false;
    SourceLoc loc;
};

struct Waypoint {
    double time = 0.0;
    Position position;
    double speed = -1.0;  // < 0: derived from the neighbouring waypoints
};

// An agent of a scenario: a vehicle, a static object or (`pedestrian`) a pedestrian.
struct Vehicle {
    std::string name;
    VehicleKind kind = VehicleKind::sdv;
    bool pedestrian = false;
    // Declared `object` (an obstacle: a cone, debris), not `vehicle NAME: static` (a parked
    // car, which drivers' conditions count as traffic); both are static_object.
    bool object = false;
    bool is_ego = false;
    double length = 4.5;
    double width = 1.8;
    double speed = 0.0;
    Position start;
    std::optional<Position> goal;
    bool goal_ends_run = false;  // reaching the goal ends the run (GeoScenario's goal_ends_simulation)
    std::vector<std::string> route;  // lane names
    int32_t tree = -1;               // index into Program::instances; sdv only
    // path: the agent it times its motion to meet (GeoScenario's collision_vehicle_vid): while
    // that one heads for a point of the path, the speed that reaches the point when it does.
    std::string meet;
    std::vector<Waypoint> trajectory;  // path: the points, with time < 0 and their speeds
    SourceLoc loc;
};

struct LightPhase {
    std::string state;  // red | yellow | green
    double duration = 0.0;
};

struct LightProgram {
    std::string name;  // the light's name in the road model
    std::vector<LightPhase> phases;
    double offset = 0.0;
    SourceLoc loc;
};

// Expectations, as a flat expression tree (index 0..n; `lhs`/`rhs` index this vector).
struct Expect {
    enum class Kind { not_, and_, or_, call } kind = Kind::call;
    int32_t lhs = -1, rhs = -1;
    int32_t function = -1;          // catalog::ExpectKind
    std::vector<int32_t> vehicles;  // indices into Scenario::vehicles
    std::string cmp;                // "<", "<=", ">", ">=" or empty
    double bound = 0.0;             // SI
    std::string text;               // as written, for messages
    // The time window of an `expect` statement (on its root only): the metrics and events
    // of ticks with after <= t <= before count. Unset: from the start / to the end.
    std::optional<double> after, before;
    std::string window;  // as written ("during 5 s .. 20 s"); `text` ends with it
    SourceLoc loc;
};

// A campaign (`vary` block): the parameters a sweep varies, their domains, and how each one
// reaches the IR. A variant's IR is the scenario's IR plus bindings: for every binding,
// number(index) += scale * value + offset - base, where number(i) enumerates the scenario's
// numbers in the order of ir::scenario_numbers (runtime/ir/bindings.h) and base is the number
// in the IR as compiled. The checker finds the bindings by compiling the scenario at several
// values of the parameter and proves them linear there.
struct VaryBinding {
    int32_t number = -1;  // index into scenario_numbers()
    double scale = 0.0;
    double offset = 0.0;
    friend bool operator==(const VaryBinding&, const VaryBinding&) = default;
};

struct VaryParam {
    std::string name;     // the path as written: "v2.tree.accept_gap"
    std::string unit;     // SI unit of the values ("m", "m/s"; empty: plain number)
    std::string domain;   // as written: "2 m .. 10 m count 5"
    enum class Kind { set, range, normal, uniform } kind = Kind::set;
    std::vector<double> values;  // set: its elements (SI)
    double lo = 0.0, hi = 0.0;   // range and uniform: bounds; normal: truncated at mean ± 3 sd
    int32_t count = 0;           // range: number of levels (0: continuous)
    double mean = 0.0, sd = 0.0; // normal
    bool integer = false;        // values are whole numbers (seeds)
    bool seed = false;           // binds the scenario's seed (no number bindings)
    std::vector<VaryBinding> bindings;
    SourceLoc loc;
    friend bool operator==(const VaryParam&, const VaryParam&) = default;
};

struct Vary {
    enum class Sample { grid, random, latin } sample = Sample::grid;
    int64_t count = 0;  // random / latin: number of variants
    uint64_t seed = 0;  // of the sampler
    std::vector<VaryParam> params;
    SourceLoc loc;
    bool empty() const { return params.empty(); }
};

struct Scenario {
    std::string name;
    int32_t road = -1;  // index into Program::roads
    double timeout = 60.0;
    uint64_t seed = 0;
    double traffic_rate = 30.0;
    double planning_rate = 3.0;
    double planning_latency = -1.0;  // < 0: 1 / planning_rate
    double sensor_range = 100.0;
    std::vector<Vehicle> vehicles;
    std::vector<LightProgram> lights;
    std::vector<Expect> expects;
    std::vector<int32_t> expect_roots;  // one per `expect` statement
    Vary vary;                          // empty: a single run
    SourceLoc loc;
};

struct Program {
    std::string compiler_version;
    std::vector<std::string> files;  // source files, as given / "std/drive.sdv"
    std::vector<TreeDecl> trees;
    std::vector<TreeInstance> instances;
    std::vector<Road> roads;
    std::vector<Scenario> scenarios;
};

}  // namespace sdv::ir
