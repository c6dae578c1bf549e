// The owned AST of a .sdv file. Every node carries the source range it came from so that
// every later message (checker, runtime, traces) can point back to the text. The AST is a
// faithful record of what was written: no defaults, no name resolution, units as spelled
// (canonicalised to ASCII) next to the SI value.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "compiler/diag/source_manager.h"

namespace sdv::compiler::ast {

using diag::SourceRange;

struct Ident {
    std::string text;
    SourceRange range;
};

struct QualName {
    std::vector<Ident> parts;
    SourceRange range;

    std::string str() const;  // "std.drive"
};

// A number with an optional unit, e.g. `-3 m/s`, `10%`, `4`.
struct Quantity {
    double value = 0.0;    // as written (not SI)
    std::string text;      // the number as written, e.g. "13.9"
    bool is_integer = false;
    std::string unit;      // canonical ASCII unit ("m/s^2"); empty when none
    SourceRange unit_range;
};

struct Arith;

struct Primary {
    // `expr`: arithmetic (`20 m + 25 m * i`); a lone number or name stays a quantity or name.
    enum class Kind { quantity, name, string, expr } kind = Kind::quantity;
    Quantity quantity;
    QualName name;
    std::string string;  // unescaped
    std::shared_ptr<const Arith> expr;  // immutable once built: copies share it
    SourceRange range;
};

// Arithmetic: a sum or product is a flat list of operands with the operators between them
// (ops[k] joins operands[k] and operands[k + 1]), so a long sum does not nest; a group is
// `-(...) unit` (its operand the parenthesised arithmetic). Leaves are numbers and names.
struct Arith {
    enum class Kind { quantity, name, sum, product, group } kind = Kind::quantity;
    Quantity quantity;
    QualName name;
    bool negate = false;  // `-name`, `-(...)`
    std::vector<Arith> operands;
    std::vector<char> ops;  // '+', '-', '*', '/'
    std::string unit;       // group: canonical unit after ')'; empty when none
    SourceRange unit_range;
    SourceRange range;
};

struct Samples {
    int64_t count = 1;
    SourceRange count_range;
    std::optional<Ident> method;       // linear (default), uniform, normal
    std::optional<Primary> method_arg; // normal(σ)
    SourceRange range;
};

// An optional value held on the heap: what std::optional offers the AST (test, *, ->, assign a
// value), a pointer's size when empty. For the parts most values never have: a Value holding
// three inline optionals was 1,000 bytes, 171 MB of the AST of a 10 MB file.
template <typename T>
class Boxed {
public:
    Boxed() = default;
    Boxed(const Boxed& o) : p_(o.p_ ? std::make_unique<T>(*o.p_) : nullptr) {}
    Boxed(Boxed&&) noexcept = default;
    Boxed& operator=(const Boxed& o) {
        p_ = o.p_ ? std::make_unique<T>(*o.p_) : nullptr;
        return *this;
    }
    Boxed& operator=(Boxed&&) noexcept = default;
    Boxed& operator=(T v) {
        p_ = std::make_unique<T>(std::move(v));
        return *this;
    }
    bool has_value() const { return p_ != nullptr; }
    explicit operator bool() const { return p_ != nullptr; }
    T& operator*() { return *p_; }
    const T& operator*() const { return *p_; }
    T* operator->() { return p_.get(); }
    const T* operator->() const { return p_.get(); }
    void reset() { p_.reset(); }

private:
    std::unique_ptr<T> p_;
};

// A value: a primary, optionally spread (`14 m/s ±10% samples 3`), an interval
// (`10 m .. 20 m samples 5`), or a list (`[a, b]`).
struct Value {
    enum class Kind { single, interval, list } kind = Kind::single;
    Primary lo;
    Boxed<Primary> spread;   // single: ± amount
    Boxed<Primary> hi;       // interval: upper bound
    Boxed<Samples> samples;
    std::vector<Value> items;  // list
    SourceRange range;
};

struct Arg {
    QualName name;  // `speed`, or `keep.speed` for a node override at a subtree reference
    Value value;
    SourceRange range;
};

enum class NodeKind {
    fallback,
    sequence,
    reactive_sequence,
    parallel,
    condition,
    maneuver,
    subtree,
    not_,
    once,
    latch,
};
const char* to_string(NodeKind kind);

struct Node {
    NodeKind kind = NodeKind::sequence;
    std::optional<Ident> label;  // `keep: maneuver keep_velocity(...)`
    QualName callee;             // condition / maneuver / subtree name
    std::vector<Arg> args;       // leaf parameters, subtree arguments, parallel policy
    std::vector<std::unique_ptr<Node>> children;
    SourceRange keyword_range;   // the node's keyword, where carets point
    SourceRange range;
};

struct Param {
    Ident name;
    Ident type;
    std::optional<Value> def;
    SourceRange range;
};

struct TreeDecl {
    Ident name;
    std::vector<Param> params;
    std::vector<std::unique_ptr<Node>> body;  // exactly one root when valid
    SourceRange range;
};

// `key value...` statements whose shape the checker validates (lane_width 3.5 m, timeout 30 s).
struct Setting {
    Ident key;
    std::vector<Value> values;
    SourceRange range;
};

struct Segment {
    bool arc = false;
    Value length;
    std::optional<Value> radius;
    std::optional<Ident> side;  // left / right
    SourceRange range;
};

struct LaneCount {
    int64_t count = 0;
    SourceRange count_range;
    Ident direction;  // forward / backward
    SourceRange range;
};

// `crosswalk NAME [on ARM] [at D] [width W] [signalised]` of a road or junction.
struct CrosswalkDecl {
    Ident name;
    std::optional<Ident> arm;
    std::optional<Value> at, width;
    std::optional<SourceRange> signalised;
    SourceRange range;
};

struct RoadDecl {
    Ident name;
    std::vector<LaneCount> lanes;
    SourceRange lanes_range;
    std::vector<Setting> settings;  // lane_width, speed_limit, origin (2 values), heading
    std::vector<Segment> segments;
    std::vector<CrosswalkDecl> crosswalks;
    SourceRange range;
};

struct JunctionDecl {
    Ident name;
    std::vector<Setting> settings;  // lanes, lane_width, speed_limit, arm_length, control
    std::vector<CrosswalkDecl> crosswalks;
    SourceRange range;
};

struct MapDecl {
    Ident name;
    std::vector<Setting> settings;  // file "x.osm", origin (lat, lon[, alt])
    SourceRange range;
};

struct LaneRef {
    enum class Kind { index, name, string } kind = Kind::index;
    int64_t index = 0;
    QualName name;
    std::string string;
    SourceRange range;

    std::string str() const;
};

struct Position {
    bool xy = false;
    LaneRef lane;
    std::optional<Value> s;       // lane position: `at 40 m`
    std::optional<Value> offset;  // lateral offset from the lane centre
    std::optional<Value> x, y;    // xy position: `at (10 m, 2 m)`
    std::optional<Value> heading;
    SourceRange range;
};

struct Waypoint {
    Value time;
    Position position;
    std::optional<Value> speed;
    SourceRange range;
};

// A point of a `path`: where, and the speed from there on (default: the previous point's).
struct PathPoint {
    Position position;
    std::optional<Value> speed;
    SourceRange range;
};

struct TreeRef {
    QualName name;
    std::vector<Arg> args;
    SourceRange range;
};

struct VehicleDecl {
    bool is_ego = false;
    bool is_object = false;  // `object name { ... }`: a static obstacle
    bool is_pedestrian = false;  // `pedestrian name: kind { ... }`
    Ident name;
    Ident kind;              // sdv / trajectory / path / static / external (objects: "static"); pedestrians: sdp / path / trajectory
    std::vector<Position> starts;  // more than one is an error
    std::vector<Position> goals;
    bool goal_ends_run = false;     // `goal ... ends run`
    std::vector<Setting> settings;  // speed, length, width
    std::vector<std::vector<LaneRef>> routes;
    std::vector<TreeRef> trees;
    std::vector<std::vector<Waypoint>> trajectories;
    std::vector<std::vector<PathPoint>> paths;
    std::vector<Ident> meets;  // `meet V`: a path agent times its way to meet V (more than one is an error)
    // `vehicle v[i = 1..50]: ...`: a template of agents v1 .. v50 (the checker expands it).
    struct Repeat {
        std::optional<Ident> var;  // the index variable when named; `i` otherwise
        Primary lo, hi;
        SourceRange range;  // from the name to ']'
    };
    Boxed<Repeat> repeat;
    // An agent expanded from a template (set by the checker, never by the parser): how
    // messages name it ("v7 (i = 7)") and the template it comes from ("v[1..50]").
    // `tree_of` is the template when its tree reference does not use the index, so that its
    // instances' trees expand alike (the checker expands it once per scenario); else null.
    struct Instance {
        std::string label;
        std::string of;
        const VehicleDecl* tree_of = nullptr;
    };
    std::shared_ptr<const Instance> instance;
    SourceRange range;
};

struct LightDecl {
    QualName name;
    std::vector<Setting> phases;  // green 20 s, yellow 3 s, red 23 s (in order)
    std::optional<Value> offset;
    SourceRange range;
};

struct Expr {
    enum class Kind { not_, and_, or_, call } kind = Kind::call;
    std::unique_ptr<Expr> lhs, rhs;
    Ident function;
    std::vector<Ident> args;
    std::string cmp;  // "<", "<=", ">", ">=" or empty
    std::optional<Value> bound;
    SourceRange range;
    // The time window of an `expect` statement, on its root expression only.
    struct Window {
        enum class Kind { during, after, before } kind = Kind::during;
        Ident keyword;
        Value value;
        SourceRange range;  // keyword and value
    };
    std::optional<Window> window;
};

// One varied parameter of a `vary` block: a path naming a value of the scenario or of a
// vehicle's tree call, and its domain.
struct VaryParam {
    QualName path;                  // `v2.speed`, `v2.tree.accept_gap`, `seed`
    enum class Kind { set, range, distribution } kind = Kind::set;
    std::vector<Primary> values;    // set: `[a, b, c]`; range: lo, hi; distribution: its two arguments
    std::optional<int64_t> count;   // range: `count N` (-1 when too large to read)
    SourceRange count_range;
    Ident distribution;             // distribution: normal | uniform
    SourceRange domain_range;       // what follows `in`
    SourceRange range;
};

struct VaryDecl {
    std::vector<VaryParam> params;
    std::vector<Setting> settings;  // sample METHOD [N], seed N (in order)
    SourceRange keyword_range;
    SourceRange range;
};

struct ScenarioDecl {
    Ident name;
    std::vector<Setting> settings;  // road NAME, timeout, seed, rate NAME VALUE
    std::vector<VehicleDecl> vehicles;
    std::vector<LightDecl> lights;
    std::vector<std::unique_ptr<Expr>> expects;
    std::vector<VaryDecl> varies;  // more than one is an error
    SourceRange range;
};

struct ImportDecl {
    std::string path;
    std::optional<Ident> alias;
    SourceRange range;
    SourceRange path_range;
};

struct File {
    diag::FileId file = 0;
    std::vector<ImportDecl> imports;
    std::vector<RoadDecl> roads;
    std::vector<JunctionDecl> junctions;
    std::vector<MapDecl> maps;
    std::vector<TreeDecl> trees;
    std::vector<ScenarioDecl> scenarios;
};

// A readable dump for `sdv compile --emit ast`.
std::string dump(const File& file, const diag::SourceManager& sm);

}  // namespace sdv::compiler::ast
