#include "runtime/io/view.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

#include "runtime/io/run_dir.h"
#include "runtime/io/text.h"
#include "runtime/ir/ir_io.h"
#include "runtime/road/reader_text.h"

namespace sdv::io {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// One vehicle's columns, kept as the CSV's own number text (already rounded).
struct Series {
    std::string name, kind;
    long first = -1;
    std::vector<std::string> x, y, yaw, speed, accel, s, d;
    std::vector<int> lane, maneuver;
};

// "12.5000" → "12.5", "-0.0000" → "0": the same number in fewer bytes.
std::string_view trim(std::string_view t) {
    if (t.find('.') == std::string_view::npos) return t;
    while (t.back() == '0') t.remove_suffix(1);
    if (t.back() == '.') t.remove_suffix(1);
    if (t == "-0") return "0";
    return t;
}

void array(std::string& out, const std::vector<std::string>& v) {
    out += '[';
    for (size_t i = 0; i < v.size(); ++i) {
        if (i) out += ',';
        if (v[i].empty()) out += "null";
        else out += trim(v[i]);
    }
    out += ']';
}

void array(std::string& out, const std::vector<int>& v) {
    out += '[';
    for (size_t i = 0; i < v.size(); ++i) {
        if (i) out += ',';
        out += std::to_string(v[i]);
    }
    out += ']';
}

// The string `key` of object `j`, or "" when it has none (nlohmann's value() throws on a key of
// another type).
std::string text_of(const Json& j, const char* key) {
    const auto it = j.find(key);
    return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

int index_of(std::vector<std::string>& names, std::map<std::string, int>& idx, const std::string& n) {
    auto [it, fresh] = idx.try_emplace(n, static_cast<int>(names.size()));
    if (fresh) names.push_back(n);
    return it->second;
}

}  // namespace

std::string view_report(const std::string& run_dir, std::string& error) {
    const fs::path dir(run_dir);
    std::string summary_text, road_text, csv, decisions_text;
    if (!road::read_file((dir / "summary.json").string(), summary_text) || !road::read_file((dir / "trajectories.csv").string(), csv)) {
        error = "'" + run_dir + "' is not a run directory (it needs summary.json and trajectories.csv from `sdv run -o`)";
        return "";
    }
    auto too_deep = [&](const char* name, const std::string& text) {
        if (ir::json_depth(text) <= kMaxRunJsonDepth) return false;
        error = (dir / name).string() + ": JSON nested more than " + std::to_string(kMaxRunJsonDepth) + " levels deep";
        return true;
    };
    if (too_deep("summary.json", summary_text)) return "";
    Json summary = Json::parse(summary_text, nullptr, false);
    if (summary.is_discarded() || !summary.is_object()) {
        error = (dir / "summary.json").string() + ": not valid JSON";
        return "";
    }
    Json road = Json::object();
    if (road::read_file((dir / "road.json").string(), road_text)) {
        if (too_deep("road.json", road_text)) return "";
        road = Json::parse(road_text, nullptr, false);
        if (road.is_discarded()) {
            error = (dir / "road.json").string() + ": not valid JSON";
            return "";
        }
    }
    // trajectories.csv (run_dir.h): a row per agent and tick, each agent at every tick from its
    // first to its last (the viewer places an agent's values by tick from its first).
    std::vector<std::string> times;
    std::vector<Series> vehicles;
    std::vector<std::string> lanes, maneuvers;
    std::map<std::string, int> lane_idx, man_idx;
    std::string line;
    TrajectoryReader in(csv, (dir / "trajectories.csv").string());
    TrajectoryRow r;
    size_t filled = 0;  // ticks with a row
    while (in.next(r)) {
        const auto tick = static_cast<size_t>(r.tick);
        if (tick >= times.size()) {
            if (tick - filled > static_cast<size_t>(kMaxEmptyTicks)) {
                error = in.where() + "tick " + std::to_string(tick) + " leaves " + std::to_string(tick - filled) +
                        " ticks without a row before it (a report holds a time per tick: at most " + std::to_string(kMaxEmptyTicks) + ")";
                return "";
            }
            times.resize(tick + 1);
        }
        filled += times[tick].empty();
        times[tick] = r.time;
        if (in.agent() == vehicles.size()) {
            vehicles.emplace_back();
            vehicles.back().name = r.vehicle;
            vehicles.back().kind = r.kind;
            vehicles.back().first = r.tick;
        }
        Series& v = vehicles[in.agent()];
        v.x.emplace_back(r.x);
        v.y.emplace_back(r.y);
        v.yaw.emplace_back(r.yaw);
        v.speed.emplace_back(r.speed);
        v.accel.emplace_back(r.accel);
        v.s.emplace_back(r.s);
        v.d.emplace_back(r.d);
        v.lane.push_back(index_of(lanes, lane_idx, std::string(r.lane)));
        v.maneuver.push_back(index_of(maneuvers, man_idx, r.maneuver.empty() ? "none" : std::string(r.maneuver)));
    }
    if (!in.error().empty()) {
        error = in.error();
        return "";
    }
    // A replay (sdv replay) keeps the replaced vehicle's recording in recorded.csv
    // (vehicle,t,x,y,heading,speed): shown as one more agent of kind "recorded", sampled at the
    // run's ticks within the recorded span, next to the simulated one.
    std::string recorded_text;
    if (road::read_file((dir / "recorded.csv").string(), recorded_text) && !times.empty()) {
        struct Rec {
            double t, x, y, h, v;
        };
        std::vector<Rec> pts;
        std::string rec_name;
        std::istringstream rl(recorded_text);
        std::getline(rl, line);
        size_t rec_row = 1;
        while (std::getline(rl, line)) {
            ++rec_row;
            std::vector<std::string> f;
            std::stringstream ls(line);
            for (std::string c; std::getline(ls, c, ',');) f.push_back(c);
            // vehicle,t,x,y,heading,speed: finite numbers (a NaN would be written into the
            // page as "nan", which is no JSON), times increasing.
            bool ok = f.size() == 6;
            double n[5] = {};
            for (size_t k = 0; ok && k < 5; ++k) {
                char* end = nullptr;
                n[k] = std::strtod(f[k + 1].c_str(), &end);
                ok = !f[k + 1].empty() && *end == '\0' && std::isfinite(n[k]) && std::fabs(n[k]) < 1e9;
            }
            if (!ok) {
                error = (dir / "recorded.csv").string() + ":" + std::to_string(rec_row) +
                        ": expected vehicle,t,x,y,heading,speed with numbers under 1e9";
                return "";
            }
            const Rec rec{n[0], n[1], n[2], n[3], n[4]};
            if (!pts.empty() && !(rec.t > pts.back().t)) continue;
            rec_name = f[0];
            pts.push_back(rec);
        }
        if (pts.size() >= 2) {
            Series v;
            v.name = rec_name + " recorded";
            v.kind = "recorded";
            v.first = -1;
            size_t k = 0;
            char buf[32];
            auto put = [&](std::vector<std::string>& col, double x, int digits) {
                std::snprintf(buf, sizeof buf, "%.*f", digits, x);
                col.emplace_back(buf);
            };
            for (size_t tick = 0; tick < times.size(); ++tick) {
                const double t = std::strtod(times[tick].c_str(), nullptr);
                if (times[tick].empty() || t < pts.front().t - 1e-9 || t > pts.back().t + 1e-9) {
                    if (v.first >= 0) break;
                    continue;
                }
                if (v.first < 0) v.first = static_cast<long>(tick);
                while (k + 2 < pts.size() && pts[k + 1].t <= t) ++k;
                const double f = std::clamp((t - pts[k].t) / (pts[k + 1].t - pts[k].t), 0.0, 1.0);
                put(v.x, pts[k].x + f * (pts[k + 1].x - pts[k].x), 4);
                put(v.y, pts[k].y + f * (pts[k + 1].y - pts[k].y), 4);
                put(v.yaw, f < 0.5 ? pts[k].h : pts[k + 1].h, 4);
                put(v.speed, pts[k].v + f * (pts[k + 1].v - pts[k].v), 4);
                v.accel.emplace_back("0");
                v.s.emplace_back("");
                v.d.emplace_back("");
                v.lane.push_back(index_of(lanes, lane_idx, ""));
                v.maneuver.push_back(index_of(maneuvers, man_idx, "recorded"));
            }
            if (v.first >= 0) vehicles.push_back(std::move(v));
        }
    }
    // Sizes from the summary (written by sdv run); defaults otherwise.
    std::map<std::string, std::pair<double, double>> sizes;
    const Json& metrics = summary.contains("metrics") ? summary["metrics"] : Json();
    if (metrics.is_object() && metrics.contains("vehicles") && metrics["vehicles"].is_array()) {
        for (const auto& vj : metrics["vehicles"]) {
            if (vj.is_object() && vj.contains("vehicle") && vj["vehicle"].is_string() && vj.contains("length") &&
                vj["length"].is_number() && vj.contains("width") && vj["width"].is_number()) {
                sizes[vj["vehicle"].get<std::string>()] = {vj["length"].get<double>(), vj["width"].get<double>()};
            }
        }
    }
    const Json scenario = summary.contains("scenario") && summary["scenario"].is_string() ? summary["scenario"] : Json("");
    std::string data = "{\"format\":\"sdv-view/1\",\"scenario\":" + json_text(scenario);
    data += ",\"summary\":" + json_text(summary) + ",\"road\":" + json_text(road) + ",\"times\":";
    array(data, times);
    data += ",\"lanes\":" + json_text(Json(lanes)) + ",\"maneuvers\":" + json_text(Json(maneuvers)) + ",\"vehicles\":[";
    for (size_t i = 0; i < vehicles.size(); ++i) {
        const Series& v = vehicles[i];
        // Pedestrians default to 0.5 m x 0.5 m (a disc of 0.25 m radius in the viewer).
        const std::pair<double, double> fallback = v.kind == "pedestrian" ? std::pair{0.5, 0.5} : std::pair{4.5, 1.8};
        const auto sz = sizes.count(v.name) ? sizes[v.name] : fallback;
        data += (i ? ",{" : "{");
        data += "\"name\":" + json_text(Json(v.name)) + ",\"kind\":" + json_text(Json(v.kind)) + ",\"length\":" +
                json_text(Json(sz.first)) + ",\"width\":" + json_text(Json(sz.second)) + ",\"first\":" + std::to_string(v.first);
        const std::pair<const char*, const std::vector<std::string>*> cols[] = {
            {"x", &v.x}, {"y", &v.y}, {"yaw", &v.yaw}, {"speed", &v.speed}, {"accel", &v.accel}, {"s", &v.s}, {"d", &v.d}};
        for (const auto& [key, col] : cols) {
            data += ",\"" + std::string(key) + "\":";
            array(data, *col);
        }
        data += ",\"lane\":";
        array(data, v.lane);
        data += ",\"maneuver\":";
        array(data, v.maneuver);
        data += "}";
    }
    data += "],\"decisions\":";
    // Decisions, compacted for large runs (the viewer expands them on demand): tree nodes as
    // [path index, status index] into `node_paths` / `node_statuses`, candidate paths as one
    // flat array [status index, x0, y0, ..., x5, y5, status index, ...] into `path_statuses`
    // with decimetre coordinates, `rejected` / `cost` / `start` as arrays in key-table order.
    std::vector<std::string> node_paths, node_statuses, path_statuses;
    std::map<std::string, int> node_idx, status_idx, path_status_idx;
    std::map<std::string, std::vector<std::string>> keyed;
    if (road::read_file((dir / "decisions.jsonl").string(), decisions_text)) {
        data += "[";
        std::istringstream dl(decisions_text);
        bool first = true;
        size_t n = 0;
        while (std::getline(dl, line)) {
            ++n;
            if (line.empty()) continue;
            if (ir::json_depth(line) > kMaxRunJsonDepth) {
                error = (dir / "decisions.jsonl").string() + ":" + std::to_string(n) + ": JSON nested more than " +
                        std::to_string(kMaxRunJsonDepth) + " levels deep";
                return "";
            }
            Json d = Json::parse(line, nullptr, false);
            if (d.is_discarded() || !d.is_object()) {
                error = (dir / "decisions.jsonl").string() + ":" + std::to_string(n) + ": not valid JSON";
                return "";
            }
            if (d.contains("nodes") && d["nodes"].is_array()) {
                Json packed = Json::array();
                for (const auto& nd : d["nodes"]) {
                    if (!nd.is_object()) continue;
                    packed.push_back({index_of(node_paths, node_idx, text_of(nd, "node")),
                                      index_of(node_statuses, status_idx, text_of(nd, "status"))});
                }
                d["nodes"] = std::move(packed);
            }
            // The small fixed-key objects become arrays in the order of `<field>_keys`.
            for (const char* field : {"rejected", "cost", "start"}) {
                if (!d.contains(field) || !d[field].is_object()) continue;
                auto& keys = keyed[field];
                if (keys.empty()) {
                    for (const auto& [k, v] : d[field].items()) keys.push_back(k);
                }
                bool same = d[field].size() == keys.size();
                Json values = Json::array();
                for (const auto& k : keys) {
                    same = same && d[field].contains(k);
                    if (same) values.push_back(d[field][k]);
                }
                if (same) d[field] = std::move(values);
            }
            if (d.contains("paths") && d["paths"].is_array()) {
                Json flat = Json::array();
                for (const auto& p : d["paths"]) {
                    if (!p.is_object() || !p.contains("xy") || !p["xy"].is_array() || p["xy"].size() != 12) continue;
                    flat.push_back(index_of(path_statuses, path_status_idx, text_of(p, "status")));
                    for (const auto& c : p["xy"]) flat.push_back(c.is_number() ? std::round(c.get<double>() * 10) / 10 : 0.0);
                }
                d["paths"] = std::move(flat);
            }
            data += (first ? "" : ",") + json_text(d);
            first = false;
        }
        data += "]";
    } else {
        data += "null";
    }
    data += ",\"node_paths\":" + json_text(Json(node_paths)) + ",\"node_statuses\":" + json_text(Json(node_statuses)) +
            ",\"path_statuses\":" + json_text(Json(path_statuses));
    for (const char* field : {"rejected", "cost", "start"}) data += ",\"" + std::string(field) + "_keys\":" + json_text(Json(keyed[field]));
    data += "}";
    // Inside <script>, "</script>" or "<!--" in a string would end or confuse the element: '<'
    // is written as its JSON escape, which JSON.parse reads back unchanged (outside strings
    // JSON never contains '<').
    std::string safe;
    safe.reserve(data.size());
    for (size_t at = 0;;) {
        const size_t lt = data.find('<', at);
        safe.append(data, at, lt == std::string::npos ? std::string::npos : lt - at);
        if (lt == std::string::npos) break;
        safe += "\\u003c";
        at = lt + 1;
    }
    std::string html(viewer_template());
    const std::string marker = "__SDV_DATA__";
    const size_t at = html.find(marker);
    if (at == std::string::npos) {
        error = "the embedded viewer has no data placeholder (a build problem)";
        return "";
    }
    html.replace(at, marker.size(), safe);
    return html;
}

}  // namespace sdv::io
