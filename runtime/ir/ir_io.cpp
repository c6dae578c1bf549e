// The canonical JSON form of the IR. Keys are written in a fixed order (ordered_json), enums
// as names, leaf parameters keyed by their catalog names, source locations as [file, line,
// col]. The reader walks the same layout with a path for every message, so an error says
// where the file is wrong ("program.instances[2].nodes[5].children[0]: index 99 out of range").
#include "runtime/ir/ir_io.h"

#include "runtime/ir/bindings.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>

namespace sdv::ir {
namespace {

using Json = nlohmann::ordered_json;

const char* kNodeKinds[] = {"fallback", "sequence", "reactive_sequence", "parallel",
                            "condition", "maneuver", "not", "once", "latch"};
const char* kRoadKinds[] = {"road", "junction", "lanelet2"};
const char* kVehicleKinds[] = {"sdv", "trajectory", "static", "external", "path"};
const char* kVaryKinds[] = {"set", "range", "normal", "uniform"};
const char* kVarySamples[] = {"grid", "random", "latin"};
const char* kMethods[] = {"linear", "uniform", "normal"};
const char* kRefKinds[] = {"none", "self", "vehicle", "zone"};
const char* kExpectKinds[] = {"not", "and", "or", "call"};

uint64_t fnv1a(std::string_view s) {
    uint64_t h = 1469598103934665603ull;
    for (char c : s) {
        h ^= static_cast<unsigned char>(c);
        h *= 1099511628211ull;
    }
    return h;
}

std::string hex(uint64_t h) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

// ------------------------------------------------------------------ writing

Json loc_json(const SourceLoc& l) { return Json::array({l.file, l.line, l.col}); }

Json sampled_json(const Sampled& s) {
    if (s.samples == 1 && s.lo == s.value && s.hi == s.value) return s.value;
    Json j;
    j["value"] = s.value;
    j["lo"] = s.lo;
    j["hi"] = s.hi;
    j["samples"] = s.samples;
    j["method"] = kMethods[static_cast<int>(s.method)];
    if (s.method == SampleMethod::normal) j["sigma"] = s.sigma;
    return j;
}

const std::vector<catalog::ParamDef>* leaf_defs(const Node& n) {
    if (n.kind == NodeKind::maneuver && n.leaf >= 0 &&
        static_cast<size_t>(n.leaf) < catalog::maneuvers().size()) {
        return &catalog::maneuvers()[static_cast<size_t>(n.leaf)].params;
    }
    if (n.kind == NodeKind::condition && n.leaf >= 0 &&
        static_cast<size_t>(n.leaf) < catalog::conditions().size()) {
        return &catalog::conditions()[static_cast<size_t>(n.leaf)].params;
    }
    return nullptr;
}

Json param_json(const ParamValue& v, const catalog::ParamDef& def) {
    switch (def.type) {
        case catalog::ParamType::choice: return def.choices.at(static_cast<size_t>(v.choice));
        case catalog::ParamType::boolean: return v.number.value != 0;
        case catalog::ParamType::vehicle: {
            Json j;
            j["kind"] = kRefKinds[static_cast<int>(v.vehicle.kind)];
            if (v.vehicle.kind == VehicleRef::Kind::vehicle) j["vehicle"] = v.vehicle.vehicle;
            if (v.vehicle.kind == VehicleRef::Kind::zone) j["zone"] = v.vehicle.zone;
            return j;
        }
        default: return sampled_json(v.number);
    }
}

Json node_json(const Node& n) {
    Json j;
    j["kind"] = kNodeKinds[static_cast<int>(n.kind)];
    j["name"] = n.name;
    j["path"] = n.path;
    j["tree"] = n.tree;
    j["loc"] = loc_json(n.loc);
    if (const auto* defs = leaf_defs(n)) {
        j[n.kind == NodeKind::maneuver ? "maneuver" : "condition"] =
            n.kind == NodeKind::maneuver ? catalog::maneuvers()[static_cast<size_t>(n.leaf)].name
                                         : catalog::conditions()[static_cast<size_t>(n.leaf)].name;
        Json params = Json::object();
        for (size_t i = 0; i < defs->size() && i < n.params.size(); ++i) {
            if (!n.params[i].given) continue;
            params[(*defs)[i].name] = param_json(n.params[i], (*defs)[i]);
        }
        j["params"] = params;
    }
    if (n.kind == NodeKind::parallel) j["success_threshold"] = n.success_threshold;
    j["children"] = n.children;
    return j;
}

Json position_json(const Position& p) {
    Json j;
    if (p.xy) {
        j["x"] = p.x;
        j["y"] = p.y;
        if (p.has_heading) j["heading"] = p.heading;
    } else {
        j["lane"] = p.lane;
        j["s"] = p.s;
        j["offset"] = p.offset;
    }
    j["loc"] = loc_json(p.loc);
    return j;
}

Json crosswalks_json(const std::vector<Crosswalk>& cs) {
    Json out = Json::array();
    for (const auto& c : cs) {
        out.push_back({{"name", c.name}, {"arm", c.arm}, {"at", c.at}, {"width", c.width},
                       {"signalised", c.signalised}, {"loc", loc_json(c.loc)}});
    }
    return out;
}

Json program_json(const Program& p) {
    Json j;
    j["files"] = p.files;
    j["trees"] = Json::array();
    for (const auto& t : p.trees) {
        j["trees"].push_back({{"name", t.name}, {"params", t.params}, {"node_count", t.node_count},
                              {"loc", loc_json(t.loc)}});
    }
    j["instances"] = Json::array();
    for (const auto& inst : p.instances) {
        Json nodes = Json::array();
        for (const auto& n : inst.nodes) nodes.push_back(node_json(n));
        j["instances"].push_back({{"nodes", nodes}});
    }
    j["roads"] = Json::array();
    for (const auto& r : p.roads) {
        Json rj;
        rj["kind"] = kRoadKinds[static_cast<int>(r.kind)];
        rj["name"] = r.name;
        rj["loc"] = loc_json(r.loc);
        switch (r.kind) {
            case RoadKind::road: {
                rj["lanes_forward"] = r.lanes_forward;
                rj["lanes_backward"] = r.lanes_backward;
                rj["lane_width"] = r.lane_width;
                rj["speed_limit"] = r.speed_limit;
                rj["origin"] = {r.origin_x, r.origin_y};
                rj["heading"] = r.heading;
                Json segs = Json::array();
                for (const auto& s : r.segments) {
                    Json sj;
                    sj["kind"] = s.arc ? "arc" : "straight";
                    sj["length"] = s.length;
                    if (s.arc) sj["radius"] = s.radius;
                    segs.push_back(sj);
                }
                rj["segments"] = segs;
                if (!r.crosswalks.empty()) rj["crosswalks"] = crosswalks_json(r.crosswalks);
                break;
            }
            case RoadKind::junction:
                rj["lanes"] = r.lanes_forward;
                rj["lane_width"] = r.lane_width;
                rj["speed_limit"] = r.speed_limit;
                rj["arm_length"] = r.arm_length;
                rj["control"] = r.control;
                if (!r.crosswalks.empty()) rj["crosswalks"] = crosswalks_json(r.crosswalks);
                break;
            case RoadKind::lanelet2:
                rj["map_file"] = r.map_file;
                if (r.has_origin) rj["origin"] = {r.origin_lat, r.origin_lon, r.origin_alt};
                break;
        }
        j["roads"].push_back(rj);
    }
    j["scenarios"] = Json::array();
    for (const auto& s : p.scenarios) {
        Json sj;
        sj["name"] = s.name;
        sj["loc"] = loc_json(s.loc);
        sj["road"] = s.road;
        sj["timeout"] = s.timeout;
        sj["seed"] = s.seed;
        sj["traffic_rate"] = s.traffic_rate;
        sj["planning_rate"] = s.planning_rate;
        sj["planning_latency"] = s.planning_latency;
        sj["sensor_range"] = s.sensor_range;
        sj["vehicles"] = Json::array();
        for (const auto& v : s.vehicles) {
            Json vj;
            vj["name"] = v.name;
            vj["kind"] = kVehicleKinds[static_cast<int>(v.kind)];
            if (v.pedestrian) vj["pedestrian"] = true;
            if (v.object) vj["object"] = true;
            if (!v.meet.empty()) vj["meet"] = v.meet;
            vj["ego"] = v.is_ego;
            vj["length"] = v.length;
            vj["width"] = v.width;
            vj["speed"] = v.speed;
            vj["start"] = position_json(v.start);
            if (v.goal) vj["goal"] = position_json(*v.goal);
            if (v.goal_ends_run) vj["goal_ends_run"] = true;
            vj["route"] = v.route;
            vj["tree"] = v.tree;
            Json traj = Json::array();
            for (const auto& w : v.trajectory) {
                traj.push_back({{"time", w.time}, {"position", position_json(w.position)}, {"speed", w.speed}});
            }
            vj["trajectory"] = traj;
            vj["loc"] = loc_json(v.loc);
            sj["vehicles"].push_back(vj);
        }
        sj["lights"] = Json::array();
        for (const auto& l : s.lights) {
            Json phases = Json::array();
            for (const auto& ph : l.phases) phases.push_back({{"state", ph.state}, {"duration", ph.duration}});
            sj["lights"].push_back({{"name", l.name}, {"phases", phases}, {"offset", l.offset}, {"loc", loc_json(l.loc)}});
        }
        sj["expects"] = Json::array();
        for (const auto& e : s.expects) {
            Json ej;
            ej["kind"] = kExpectKinds[static_cast<int>(e.kind)];
            ej["lhs"] = e.lhs;
            ej["rhs"] = e.rhs;
            ej["function"] = e.function >= 0 && static_cast<size_t>(e.function) < catalog::expectations().size()
                                 ? Json(catalog::expectations()[static_cast<size_t>(e.function)].name)
                                 : Json(nullptr);
            ej["vehicles"] = e.vehicles;
            ej["cmp"] = e.cmp;
            ej["bound"] = e.bound;
            ej["text"] = e.text;
            if (e.after || e.before) {
                ej["window"] = {{"after", e.after ? Json(*e.after) : Json(nullptr)},
                                {"before", e.before ? Json(*e.before) : Json(nullptr)},
                                {"text", e.window}};
            }
            ej["loc"] = loc_json(e.loc);
            sj["expects"].push_back(ej);
        }
        sj["expect_roots"] = s.expect_roots;
        if (!s.vary.empty()) {  // absent for a single run: IR hashes of plain scenarios stay as they were
            Json vj;
            vj["sample"] = kVarySamples[static_cast<int>(s.vary.sample)];
            vj["count"] = s.vary.count;
            vj["seed"] = s.vary.seed;
            vj["loc"] = loc_json(s.vary.loc);
            vj["params"] = Json::array();
            for (const auto& vp : s.vary.params) {
                Json pj;
                pj["name"] = vp.name;
                pj["unit"] = vp.unit;
                pj["domain"] = vp.domain;
                pj["kind"] = kVaryKinds[static_cast<int>(vp.kind)];
                pj["values"] = vp.values;
                pj["lo"] = vp.lo;
                pj["hi"] = vp.hi;
                pj["count"] = vp.count;
                pj["mean"] = vp.mean;
                pj["sd"] = vp.sd;
                pj["integer"] = vp.integer;
                pj["seed"] = vp.seed;
                pj["bindings"] = Json::array();
                for (const auto& b : vp.bindings) pj["bindings"].push_back({b.number, b.scale, b.offset});
                pj["loc"] = loc_json(vp.loc);
                vj["params"].push_back(pj);
            }
            sj["vary"] = vj;
        }
        j["scenarios"].push_back(sj);
    }
    return j;
}

std::string canonical(const Json& program) { return program.dump(1); }

// ------------------------------------------------------------------ reading

// A failed read: the first error wins and stops the reader.
struct ReadError {
    std::string message;
};

class Reader {
public:
    const Json& field(const Json& obj, const char* key, const std::string& path) {
        if (!obj.is_object()) fail(path + ": expected an object");
        auto it = obj.find(key);
        if (it == obj.end()) fail(path + ": missing field '" + key + "'");
        return *it;
    }
    bool has(const Json& obj, const char* key) { return obj.is_object() && obj.contains(key); }

    double number(const Json& j, const std::string& path) {
        if (!j.is_number()) fail(path + ": expected a number");
        const double v = j.get<double>();
        if (!std::isfinite(v)) fail(path + ": number is not finite");
        return v;
    }
    int64_t integer(const Json& j, const std::string& path, int64_t lo, int64_t hi) {
        if (!j.is_number_integer()) fail(path + ": expected an integer");
        const auto v = j.get<int64_t>();
        if (v < lo || v > hi) {
            fail(path + ": value " + std::to_string(v) + " out of range [" + std::to_string(lo) + ", " +
                 std::to_string(hi) + "]");
        }
        return v;
    }
    std::string string(const Json& j, const std::string& path) {
        if (!j.is_string()) fail(path + ": expected a string");
        return j.get<std::string>();
    }
    bool boolean(const Json& j, const std::string& path) {
        if (!j.is_boolean()) fail(path + ": expected true or false");
        return j.get<bool>();
    }
    const Json& array(const Json& j, const std::string& path) {
        if (!j.is_array()) fail(path + ": expected an array");
        return j;
    }
    template <size_t N>
    int enumeration(const Json& j, const char* const (&names)[N], const std::string& path) {
        const std::string s = string(j, path);
        for (size_t i = 0; i < N; ++i) {
            if (s == names[i]) return static_cast<int>(i);
        }
        fail(path + ": unknown value '" + s + "'");
    }
    SourceLoc loc(const Json& j, const std::string& path, size_t files) {
        array(j, path);
        if (j.size() != 3) fail(path + ": expected [file, line, col]");
        SourceLoc l;
        l.file = static_cast<uint32_t>(integer(j[0], path + "[0]", 0, files == 0 ? 0 : static_cast<int64_t>(files) - 1));
        l.line = static_cast<uint32_t>(integer(j[1], path + "[1]", 0, UINT32_MAX));
        l.col = static_cast<uint32_t>(integer(j[2], path + "[2]", 0, UINT32_MAX));
        return l;
    }
    [[noreturn]] void fail(const std::string& msg) { throw ReadError{msg}; }

    Sampled sampled(const Json& j, const std::string& path) {
        Sampled s;
        if (j.is_number()) {
            s.value = s.lo = s.hi = number(j, path);
            return s;
        }
        s.value = number(field(j, "value", path), path + ".value");
        s.lo = number(field(j, "lo", path), path + ".lo");
        s.hi = number(field(j, "hi", path), path + ".hi");
        s.samples = static_cast<int>(integer(field(j, "samples", path), path + ".samples", 1, 100));
        s.method = static_cast<SampleMethod>(enumeration(field(j, "method", path), kMethods, path + ".method"));
        if (s.method == SampleMethod::normal) s.sigma = number(field(j, "sigma", path), path + ".sigma");
        if (s.lo > s.hi) fail(path + ": lo is above hi");
        return s;
    }

    Position position(const Json& j, const std::string& path, size_t files) {
        Position p;
        p.xy = has(j, "x");
        if (p.xy) {
            p.x = number(field(j, "x", path), path + ".x");
            p.y = number(field(j, "y", path), path + ".y");
            p.has_heading = has(j, "heading");
            if (p.has_heading) p.heading = number(j["heading"], path + ".heading");
        } else {
            p.lane = string(field(j, "lane", path), path + ".lane");
            p.s = number(field(j, "s", path), path + ".s");
            p.offset = number(field(j, "offset", path), path + ".offset");
        }
        p.loc = loc(field(j, "loc", path), path + ".loc", files);
        return p;
    }

    Node node(const Json& j, const std::string& path, size_t files, size_t trees, size_t count) {
        Node n;
        n.kind = static_cast<NodeKind>(enumeration(field(j, "kind", path), kNodeKinds, path + ".kind"));
        n.name = string(field(j, "name", path), path + ".name");
        n.path = string(field(j, "path", path), path + ".path");
        n.tree = static_cast<int32_t>(integer(field(j, "tree", path), path + ".tree", -1, static_cast<int64_t>(trees) - 1));
        n.loc = loc(field(j, "loc", path), path + ".loc", files);
        const Json& children = array(field(j, "children", path), path + ".children");
        for (size_t i = 0; i < children.size(); ++i) {
            n.children.push_back(static_cast<int32_t>(
                integer(children[i], path + ".children[" + std::to_string(i) + "]", 1, static_cast<int64_t>(count) - 1)));
        }
        if (n.kind == NodeKind::parallel) {
            n.success_threshold = static_cast<int32_t>(integer(field(j, "success_threshold", path),
                                                               path + ".success_threshold", 1,
                                                               std::max<int64_t>(1, static_cast<int64_t>(n.children.size()))));
        }
        if (n.kind == NodeKind::maneuver || n.kind == NodeKind::condition) {
            const bool man = n.kind == NodeKind::maneuver;
            const std::string name = string(field(j, man ? "maneuver" : "condition", path), path);
            const std::vector<catalog::ParamDef>* defs = nullptr;
            if (man) {
                if (const auto* m = catalog::find_maneuver(name)) {
                    n.leaf = static_cast<int32_t>(m->kind);
                    defs = &m->params;
                }
            } else if (const auto* c = catalog::find_condition(name)) {
                n.leaf = static_cast<int32_t>(c->kind);
                defs = &c->params;
            }
            if (defs == nullptr) fail(path + ": unknown " + (man ? "maneuver" : "condition") + " '" + name + "'");
            const Json& params = field(j, "params", path);
            if (!params.is_object()) fail(path + ".params: expected an object");
            for (auto it = params.begin(); it != params.end(); ++it) {
                bool known = false;
                for (const auto& d : *defs) known = known || d.name == it.key();
                if (!known) fail(path + ".params: unknown parameter '" + it.key() + "' of '" + name + "'");
            }
            for (const auto& d : *defs) {
                ParamValue v;
                const std::string ppath = path + ".params." + d.name;
                if (!params.contains(d.name)) {
                    if (d.required()) fail(ppath + ": missing required parameter");
                    if (d.def) fail(ppath + ": missing (defaults are resolved in the IR)");
                    v.given = false;
                    n.params.push_back(v);
                    continue;
                }
                const Json& pj = params[d.name];
                switch (d.type) {
                    case catalog::ParamType::choice: {
                        const std::string s = string(pj, ppath);
                        auto c = std::find(d.choices.begin(), d.choices.end(), s);
                        if (c == d.choices.end()) fail(ppath + ": '" + s + "' is not a valid choice");
                        v.choice = static_cast<int32_t>(c - d.choices.begin());
                        break;
                    }
                    case catalog::ParamType::boolean:
                        v.number.value = v.number.lo = v.number.hi = boolean(pj, ppath) ? 1.0 : 0.0;
                        break;
                    case catalog::ParamType::vehicle: {
                        v.vehicle.kind = static_cast<VehicleRef::Kind>(enumeration(field(pj, "kind", ppath), kRefKinds, ppath + ".kind"));
                        if (v.vehicle.kind == VehicleRef::Kind::vehicle) {
                            v.vehicle.vehicle = static_cast<int32_t>(integer(field(pj, "vehicle", ppath), ppath + ".vehicle", 0, 1 << 20));
                            vehicle_refs_.push_back({v.vehicle.vehicle, ppath});
                        }
                        if (v.vehicle.kind == VehicleRef::Kind::zone) {
                            v.vehicle.zone = static_cast<int32_t>(integer(field(pj, "zone", ppath), ppath + ".zone", 0,
                                                                          static_cast<int64_t>(catalog::vehicle_zones().size()) - 1));
                        }
                        break;
                    }
                    default: v.number = sampled(pj, ppath);
                }
                n.params.push_back(v);
            }
        }
        return n;
    }

    // Every node reached exactly once from the root: a tree, no cycles, no orphans.
    void check_tree(const TreeInstance& inst, const std::string& path) {
        std::vector<int> seen(inst.nodes.size(), 0);
        std::vector<int32_t> stack = {0};
        while (!stack.empty()) {
            const int32_t i = stack.back();
            stack.pop_back();
            if (seen[static_cast<size_t>(i)]++) fail(path + ".nodes[" + std::to_string(i) + "]: reached twice (not a tree)");
            for (int32_t c : inst.nodes[static_cast<size_t>(i)].children) stack.push_back(c);
        }
        for (size_t i = 0; i < seen.size(); ++i) {
            if (!seen[i]) fail(path + ".nodes[" + std::to_string(i) + "]: not reachable from the root");
        }
    }

    Program program(const Json& j) {
        Program p;
        const std::string root = "program";
        const Json& files = array(field(j, "files", root), root + ".files");
        for (size_t i = 0; i < files.size(); ++i) p.files.push_back(string(files[i], root + ".files[" + std::to_string(i) + "]"));
        const size_t nf = p.files.size();
        const Json& trees = array(field(j, "trees", root), root + ".trees");
        for (size_t i = 0; i < trees.size(); ++i) {
            const std::string tp = root + ".trees[" + std::to_string(i) + "]";
            TreeDecl t;
            t.name = string(field(trees[i], "name", tp), tp + ".name");
            const Json& params = array(field(trees[i], "params", tp), tp + ".params");
            for (size_t k = 0; k < params.size(); ++k) t.params.push_back(string(params[k], tp + ".params"));
            t.node_count = static_cast<int32_t>(integer(field(trees[i], "node_count", tp), tp + ".node_count", 0, 1 << 30));
            t.loc = loc(field(trees[i], "loc", tp), tp + ".loc", nf);
            p.trees.push_back(std::move(t));
        }
        const Json& instances = array(field(j, "instances", root), root + ".instances");
        for (size_t i = 0; i < instances.size(); ++i) {
            const std::string ip = root + ".instances[" + std::to_string(i) + "]";
            const Json& nodes = array(field(instances[i], "nodes", ip), ip + ".nodes");
            if (nodes.empty()) fail(ip + ".nodes: an instance needs a root node");
            TreeInstance inst;
            for (size_t k = 0; k < nodes.size(); ++k) {
                inst.nodes.push_back(node(nodes[k], ip + ".nodes[" + std::to_string(k) + "]", nf, p.trees.size(), nodes.size()));
            }
            check_tree(inst, ip);
            p.instances.push_back(std::move(inst));
        }
        const Json& roads = array(field(j, "roads", root), root + ".roads");
        for (size_t i = 0; i < roads.size(); ++i) {
            const std::string rp = root + ".roads[" + std::to_string(i) + "]";
            const Json& rj = roads[i];
            Road r;
            r.kind = static_cast<RoadKind>(enumeration(field(rj, "kind", rp), kRoadKinds, rp + ".kind"));
            r.name = string(field(rj, "name", rp), rp + ".name");
            r.loc = loc(field(rj, "loc", rp), rp + ".loc", nf);
            if (r.kind == RoadKind::road) {
                r.lanes_forward = static_cast<int32_t>(integer(field(rj, "lanes_forward", rp), rp + ".lanes_forward", 0, 8));
                r.lanes_backward = static_cast<int32_t>(integer(field(rj, "lanes_backward", rp), rp + ".lanes_backward", 0, 8));
                r.lane_width = number(field(rj, "lane_width", rp), rp + ".lane_width");
                r.speed_limit = number(field(rj, "speed_limit", rp), rp + ".speed_limit");
                const Json& o = array(field(rj, "origin", rp), rp + ".origin");
                if (o.size() != 2) fail(rp + ".origin: expected [x, y]");
                r.origin_x = number(o[0], rp + ".origin[0]");
                r.origin_y = number(o[1], rp + ".origin[1]");
                r.heading = number(field(rj, "heading", rp), rp + ".heading");
                const Json& segs = array(field(rj, "segments", rp), rp + ".segments");
                double total = 0;
                for (size_t k = 0; k < segs.size(); ++k) {
                    const std::string sp = rp + ".segments[" + std::to_string(k) + "]";
                    Segment s;
                    s.arc = string(field(segs[k], "kind", sp), sp + ".kind") == "arc";
                    s.length = number(field(segs[k], "length", sp), sp + ".length");
                    if (!(s.length > 0)) fail(sp + ".length: must be positive");
                    if (s.arc) s.radius = number(field(segs[k], "radius", sp), sp + ".radius");
                    r.segments.push_back(s);
                    total += s.length;
                }
                if (total > kMaxRoadLength) fail(rp + ".segments: the road is longer than 100 km");
                if (!(r.lane_width > 0 && r.lane_width <= 10)) fail(rp + ".lane_width: out of range");
                if (has(rj, "crosswalks")) r.crosswalks = crosswalks(rj["crosswalks"], rp + ".crosswalks", p.files.size());
            } else if (r.kind == RoadKind::junction) {
                r.lanes_forward = static_cast<int32_t>(integer(field(rj, "lanes", rp), rp + ".lanes", 1, 4));
                r.lane_width = number(field(rj, "lane_width", rp), rp + ".lane_width");
                r.speed_limit = number(field(rj, "speed_limit", rp), rp + ".speed_limit");
                r.arm_length = number(field(rj, "arm_length", rp), rp + ".arm_length");
                if (!(r.arm_length > 0 && r.arm_length <= kMaxRoadLength)) fail(rp + ".arm_length: out of range");
                if (!(r.lane_width > 0 && r.lane_width <= 10)) fail(rp + ".lane_width: out of range");
                r.control = string(field(rj, "control", rp), rp + ".control");
                if (has(rj, "crosswalks")) r.crosswalks = crosswalks(rj["crosswalks"], rp + ".crosswalks", p.files.size());
            } else {
                r.map_file = string(field(rj, "map_file", rp), rp + ".map_file");
                if (has(rj, "origin")) {
                    const Json& o = array(rj["origin"], rp + ".origin");
                    if (o.size() != 3) fail(rp + ".origin: expected [lat, lon, alt]");
                    r.origin_lat = number(o[0], rp + ".origin[0]");
                    r.origin_lon = number(o[1], rp + ".origin[1]");
                    r.origin_alt = number(o[2], rp + ".origin[2]");
                    r.has_origin = true;
                }
            }
            p.roads.push_back(std::move(r));
        }
        const Json& scenarios = array(field(j, "scenarios", root), root + ".scenarios");
        for (size_t i = 0; i < scenarios.size(); ++i) {
            const std::string sp = root + ".scenarios[" + std::to_string(i) + "]";
            p.scenarios.push_back(scenario(scenarios[i], sp, p));
            if (has(scenarios[i], "vary")) {
                p.scenarios.back().vary = vary(scenarios[i]["vary"], sp + ".vary", p.files.size(),
                                               scenario_number_values(p, static_cast<int>(i)).size());
            }
        }
        return p;
    }

    std::vector<Crosswalk> crosswalks(const Json& j, const std::string& path, size_t nf) {
        const Json& a = array(j, path);
        std::vector<Crosswalk> out;
        for (size_t k = 0; k < a.size(); ++k) {
            const std::string cp = path + "[" + std::to_string(k) + "]";
            Crosswalk c;
            c.name = string(field(a[k], "name", cp), cp + ".name");
            c.arm = string(field(a[k], "arm", cp), cp + ".arm");
            c.at = number(field(a[k], "at", cp), cp + ".at");
            c.width = number(field(a[k], "width", cp), cp + ".width");
            c.signalised = boolean(field(a[k], "signalised", cp), cp + ".signalised");
            c.loc = loc(field(a[k], "loc", cp), cp + ".loc", nf);
            if (!(c.width >= 1 && c.width <= 20) || !(c.at >= 0 && c.at <= kMaxRoadLength)) fail(cp + ": out of range");
            out.push_back(std::move(c));
        }
        return out;
    }

    Scenario scenario(const Json& j, const std::string& sp, const Program& p) {
        const size_t nf = p.files.size();
        Scenario s;
        s.name = string(field(j, "name", sp), sp + ".name");
        s.loc = loc(field(j, "loc", sp), sp + ".loc", nf);
        s.road = static_cast<int32_t>(integer(field(j, "road", sp), sp + ".road", 0, static_cast<int64_t>(p.roads.size()) - 1));
        s.timeout = number(field(j, "timeout", sp), sp + ".timeout");
        const Json& seed = field(j, "seed", sp);
        if (!seed.is_number_unsigned() && !(seed.is_number_integer() && seed.get<int64_t>() >= 0)) fail(sp + ".seed: expected an unsigned integer");
        s.seed = seed.get<uint64_t>();
        s.traffic_rate = number(field(j, "traffic_rate", sp), sp + ".traffic_rate");
        s.planning_rate = number(field(j, "planning_rate", sp), sp + ".planning_rate");
        s.planning_latency = number(field(j, "planning_latency", sp), sp + ".planning_latency");
        s.sensor_range = number(field(j, "sensor_range", sp), sp + ".sensor_range");
        if (!(s.timeout > 0) || !(s.traffic_rate > 0) || !(s.planning_rate > 0)) fail(sp + ": timeout and rates must be positive");
        const Json& vehicles = array(field(j, "vehicles", sp), sp + ".vehicles");
        for (size_t i = 0; i < vehicles.size(); ++i) {
            const std::string vp = sp + ".vehicles[" + std::to_string(i) + "]";
            const Json& vj = vehicles[i];
            Vehicle v;
            v.name = string(field(vj, "name", vp), vp + ".name");
            v.kind = static_cast<VehicleKind>(enumeration(field(vj, "kind", vp), kVehicleKinds, vp + ".kind"));
            if (has(vj, "pedestrian")) v.pedestrian = boolean(vj["pedestrian"], vp + ".pedestrian");
            if (has(vj, "object")) v.object = boolean(vj["object"], vp + ".object");
            if (has(vj, "meet")) v.meet = string(vj["meet"], vp + ".meet");
            if (v.object && v.kind != VehicleKind::static_object) fail(vp + ".object: an object is static");
            if (v.pedestrian && (v.kind == VehicleKind::static_object || v.kind == VehicleKind::external)) {
                fail(vp + ".kind: a pedestrian is an sdp, path or trajectory agent");
            }
            v.is_ego = boolean(field(vj, "ego", vp), vp + ".ego");
            v.length = number(field(vj, "length", vp), vp + ".length");
            v.width = number(field(vj, "width", vp), vp + ".width");
            if (!(v.length > 0) || !(v.width > 0)) fail(vp + ": length and width must be positive");
            v.speed = number(field(vj, "speed", vp), vp + ".speed");
            v.start = position(field(vj, "start", vp), vp + ".start", nf);
            if (has(vj, "goal")) v.goal = position(vj["goal"], vp + ".goal", nf);
            if (has(vj, "goal_ends_run")) v.goal_ends_run = boolean(vj["goal_ends_run"], vp + ".goal_ends_run");
            const Json& route = array(field(vj, "route", vp), vp + ".route");
            for (size_t k = 0; k < route.size(); ++k) v.route.push_back(string(route[k], vp + ".route"));
            v.tree = static_cast<int32_t>(integer(field(vj, "tree", vp), vp + ".tree", -1, static_cast<int64_t>(p.instances.size()) - 1));
            if (v.kind == VehicleKind::sdv && v.tree < 0) fail(vp + ".tree: an sdv needs a tree instance");
            const Json& traj = array(field(vj, "trajectory", vp), vp + ".trajectory");
            for (size_t k = 0; k < traj.size(); ++k) {
                const std::string wp = vp + ".trajectory[" + std::to_string(k) + "]";
                Waypoint w;
                w.time = number(field(traj[k], "time", wp), wp + ".time");
                w.position = position(field(traj[k], "position", wp), wp + ".position", nf);
                w.speed = number(field(traj[k], "speed", wp), wp + ".speed");
                v.trajectory.push_back(w);
            }
            v.loc = loc(field(vj, "loc", vp), vp + ".loc", nf);
            s.vehicles.push_back(std::move(v));
        }
        const Json& lights = array(field(j, "lights", sp), sp + ".lights");
        for (size_t i = 0; i < lights.size(); ++i) {
            const std::string lp = sp + ".lights[" + std::to_string(i) + "]";
            LightProgram l;
            l.name = string(field(lights[i], "name", lp), lp + ".name");
            const Json& phases = array(field(lights[i], "phases", lp), lp + ".phases");
            for (size_t k = 0; k < phases.size(); ++k) {
                const std::string pp = lp + ".phases[" + std::to_string(k) + "]";
                l.phases.push_back({string(field(phases[k], "state", pp), pp + ".state"),
                                    number(field(phases[k], "duration", pp), pp + ".duration")});
            }
            l.offset = number(field(lights[i], "offset", lp), lp + ".offset");
            l.loc = loc(field(lights[i], "loc", lp), lp + ".loc", nf);
            s.lights.push_back(std::move(l));
        }
        const Json& expects = array(field(j, "expects", sp), sp + ".expects");
        const auto ne = static_cast<int64_t>(expects.size());
        for (size_t i = 0; i < expects.size(); ++i) {
            const std::string ep = sp + ".expects[" + std::to_string(i) + "]";
            const Json& ej = expects[i];
            Expect e;
            e.kind = static_cast<Expect::Kind>(enumeration(field(ej, "kind", ep), kExpectKinds, ep + ".kind"));
            // Operands come before their parent (post-order), which rules out cycles.
            e.lhs = static_cast<int32_t>(integer(field(ej, "lhs", ep), ep + ".lhs", -1, static_cast<int64_t>(i) - 1));
            e.rhs = static_cast<int32_t>(integer(field(ej, "rhs", ep), ep + ".rhs", -1, static_cast<int64_t>(i) - 1));
            const bool binary = e.kind == Expect::Kind::and_ || e.kind == Expect::Kind::or_;
            if ((e.kind != Expect::Kind::call && e.lhs < 0) || (binary && e.rhs < 0)) fail(ep + ": missing operand");
            const Json& f = field(ej, "function", ep);
            if (e.kind == Expect::Kind::call) {
                const auto* def = catalog::find_expectation(string(f, ep + ".function"));
                if (def == nullptr) fail(ep + ".function: unknown expectation '" + f.get<std::string>() + "'");
                e.function = static_cast<int32_t>(def->kind);
            }
            const Json& vs = array(field(ej, "vehicles", ep), ep + ".vehicles");
            for (size_t k = 0; k < vs.size(); ++k) {
                e.vehicles.push_back(static_cast<int32_t>(integer(vs[k], ep + ".vehicles", 0, static_cast<int64_t>(s.vehicles.size()) - 1)));
            }
            e.cmp = string(field(ej, "cmp", ep), ep + ".cmp");
            if (!e.cmp.empty() && e.cmp != "<" && e.cmp != "<=" && e.cmp != ">" && e.cmp != ">=") fail(ep + ".cmp: unknown comparison");
            e.bound = number(field(ej, "bound", ep), ep + ".bound");
            e.text = string(field(ej, "text", ep), ep + ".text");
            if (has(ej, "window")) {
                const std::string wp = ep + ".window";
                const Json& w = ej["window"];
                if (!w.is_object()) fail(wp + ": expected an object");
                for (const char* key : {"after", "before"}) {
                    const Json& b = field(w, key, wp);
                    if (b.is_null()) continue;
                    const double t = number(b, wp + "." + key);
                    if (!(t >= 0)) fail(wp + "." + key + ": a time must not be negative");
                    (std::string(key) == "after" ? e.after : e.before) = t;
                }
                if (!e.after && !e.before) fail(wp + ": neither 'after' nor 'before'");
                if (e.after && e.before && *e.after >= *e.before) fail(wp + ": empty window");
                e.window = string(field(w, "text", wp), wp + ".text");
                if (e.window.empty() || !e.text.ends_with(e.window)) fail(wp + ".text: not the end of the expectation's text");
            }
            e.loc = loc(field(ej, "loc", ep), ep + ".loc", nf);
            s.expects.push_back(std::move(e));
        }
        const Json& roots = array(field(j, "expect_roots", sp), sp + ".expect_roots");
        for (size_t k = 0; k < roots.size(); ++k) s.expect_roots.push_back(static_cast<int32_t>(integer(roots[k], sp + ".expect_roots", 0, ne - 1)));
        for (const auto& [v, path] : vehicle_refs_) {
            if (static_cast<size_t>(v) >= s.vehicles.size()) fail(path + ": vehicle index " + std::to_string(v) + " out of range");
        }
        vehicle_refs_.clear();
        return s;
    }

    Vary vary(const Json& j, const std::string& vp, size_t nf, size_t numbers) {
        Vary v;
        if (!j.is_object()) fail(vp + ": expected an object");
        v.sample = static_cast<Vary::Sample>(enumeration(field(j, "sample", vp), kVarySamples, vp + ".sample"));
        v.count = integer(field(j, "count", vp), vp + ".count", 0, int64_t{1} << 40);
        if (v.sample != Vary::Sample::grid && v.count < 1) fail(vp + ".count: random and latin sampling need a count");
        const Json& seed = field(j, "seed", vp);
        if (!seed.is_number_unsigned() && !(seed.is_number_integer() && seed.get<int64_t>() >= 0)) fail(vp + ".seed: expected an unsigned integer");
        v.seed = seed.get<uint64_t>();
        v.loc = loc(field(j, "loc", vp), vp + ".loc", nf);
        const Json& params = array(field(j, "params", vp), vp + ".params");
        if (params.empty()) fail(vp + ".params: a campaign varies at least one parameter");
        for (size_t i = 0; i < params.size(); ++i) {
            const std::string pp = vp + ".params[" + std::to_string(i) + "]";
            const Json& pj = params[i];
            VaryParam p;
            p.name = string(field(pj, "name", pp), pp + ".name");
            p.unit = string(field(pj, "unit", pp), pp + ".unit");
            p.domain = string(field(pj, "domain", pp), pp + ".domain");
            p.kind = static_cast<VaryParam::Kind>(enumeration(field(pj, "kind", pp), kVaryKinds, pp + ".kind"));
            const Json& values = array(field(pj, "values", pp), pp + ".values");
            for (size_t k = 0; k < values.size(); ++k) p.values.push_back(number(values[k], pp + ".values"));
            p.lo = number(field(pj, "lo", pp), pp + ".lo");
            p.hi = number(field(pj, "hi", pp), pp + ".hi");
            p.count = static_cast<int32_t>(integer(field(pj, "count", pp), pp + ".count", 0, 1000000));
            p.mean = number(field(pj, "mean", pp), pp + ".mean");
            p.sd = number(field(pj, "sd", pp), pp + ".sd");
            p.integer = boolean(field(pj, "integer", pp), pp + ".integer");
            p.seed = boolean(field(pj, "seed", pp), pp + ".seed");
            if (p.kind == VaryParam::Kind::set && p.values.empty()) fail(pp + ".values: an empty set");
            if (p.kind != VaryParam::Kind::set && !(p.lo <= p.hi)) fail(pp + ": empty range");
            if (p.kind == VaryParam::Kind::normal && !(p.sd > 0)) fail(pp + ".sd: must be positive");
            if (v.sample == Vary::Sample::grid && p.kind != VaryParam::Kind::set &&
                !(p.kind == VaryParam::Kind::range && p.count > 0)) {
                fail(pp + ": a grid needs a set or a range with a count");
            }
            const Json& bindings = array(field(pj, "bindings", pp), pp + ".bindings");
            for (size_t k = 0; k < bindings.size(); ++k) {
                const std::string bp = pp + ".bindings[" + std::to_string(k) + "]";
                const Json& b = array(bindings[k], bp);
                if (b.size() != 3) fail(bp + ": expected [number, scale, offset]");
                p.bindings.push_back({static_cast<int32_t>(integer(b[0], bp + "[0]", 0, static_cast<int64_t>(numbers) - 1)),
                                      number(b[1], bp + "[1]"), number(b[2], bp + "[2]")});
            }
            if (!p.seed && p.bindings.empty()) fail(pp + ": binds nothing");
            p.loc = loc(field(pj, "loc", pp), pp + ".loc", nf);
            v.params.push_back(std::move(p));
        }
        return v;
    }

private:
    std::vector<std::pair<int32_t, std::string>> vehicle_refs_;
};

}  // namespace

namespace {

constexpr int kMaxIrDepth = 64;

}  // namespace

std::string write_ir(const Program& program) {
    const std::string body = canonical(program_json(program));
    std::string out = "{\n \"format\": \"sdvir\",\n \"version\": " + std::to_string(kFormatVersion) +
                      ",\n \"compiler\": " + Json(program.compiler_version).dump() + ",\n \"hash\": \"" +
                      hex(fnv1a(body)) + "\",\n \"program\": ";
    out += body;
    out += "\n}\n";
    return out;
}

std::string program_hash(const Program& program) { return hex(fnv1a(canonical(program_json(program)))); }

int json_depth(std::string_view text) {
    int depth = 0, deepest = 0;
    bool in_string = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\') ++i;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return deepest;
}

ReadResult read_ir(std::string_view text) {
    ReadResult r;
    if (text.empty()) {
        r.error = "not an sdv IR file: the file is empty";
        return r;
    }
    // The IR nests a few levels; deeper input would cost the parser, the canonical form and the
    // destructors work and stack per level. Refused before any of them runs.
    if (json_depth(text) > kMaxIrDepth) {
        r.error = "not an sdv IR file: JSON nested more than " + std::to_string(kMaxIrDepth) + " levels deep";
        return r;
    }
    Json j = Json::parse(text.begin(), text.end(), nullptr, false);
    if (j.is_discarded()) {
        r.error = "not an sdv IR file: invalid JSON (truncated or corrupted?)";
        return r;
    }
    try {
        Reader reader;
        if (!j.is_object() || !j.contains("format") || j["format"] != kFormatName) {
            r.error = "not an sdv IR file: missing \"format\": \"sdvir\"";
            return r;
        }
        if (!j.contains("version") || !j["version"].is_number_integer()) {
            r.error = "IR file has no format version";
            return r;
        }
        const auto version = j["version"].get<int64_t>();
        if (version != kFormatVersion) {
            r.error = "IR format version " + std::to_string(version) + " is not supported (this sdv reads version " +
                      std::to_string(kFormatVersion) + "); recompile the scenario";
            return r;
        }
        const std::string header_hash = reader.string(reader.field(j, "hash", "header"), "header.hash");
        const Json& body = reader.field(j, "program", "header");
        const std::string actual = hex(fnv1a(canonical(body)));
        if (actual != header_hash) {
            r.error = "IR file is corrupted: content hash mismatch (header " + header_hash + ", content " + actual + ")";
            return r;
        }
        Program p = reader.program(body);
        p.compiler_version = reader.string(reader.field(j, "compiler", "header"), "header.compiler");
        r.program = std::move(p);
    } catch (const ReadError& e) {
        r.error = "invalid IR: " + e.message;
    } catch (const std::exception& e) {
        r.error = std::string("invalid IR: ") + e.what();
    }
    return r;
}

}  // namespace sdv::ir
