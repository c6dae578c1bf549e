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

namespace sdv::io {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

bool read(const fs::path& p, std::string& out) {
    std::ifstream in(p, std::ios::binary);
    if (!in) return false;
    std::stringstream ss;
    ss << in.rdbuf();
    out = ss.str();
    return true;
}

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

int index_of(std::vector<std::string>& names, std::map<std::string, int>& idx, const std::string& n) {
    auto [it, fresh] = idx.try_emplace(n, static_cast<int>(names.size()));
    if (fresh) names.push_back(n);
    return it->second;
}

}  // namespace

std::string view_report(const std::string& run_dir, std::string& error) {
    const fs::path dir(run_dir);
    std::string summary_text, road_text, csv, decisions_text;
    if (!read(dir / "summary.json", summary_text) || !read(dir / "trajectories.csv", csv)) {
        error = "'" + run_dir + "' is not a run directory (it needs summary.json and trajectories.csv from `sdv run -o`)";
        return "";
    }
    Json summary = Json::parse(summary_text, nullptr, false);
    if (summary.is_discarded() || !summary.is_object()) {
        error = (dir / "summary.json").string() + ": not valid JSON";
        return "";
    }
    Json road = Json::object();
    if (read(dir / "road.json", road_text)) {
        road = Json::parse(road_text, nullptr, false);
        if (road.is_discarded()) {
            error = (dir / "road.json").string() + ": not valid JSON";
            return "";
        }
    }
    // trajectories.csv: time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver
    std::vector<std::string> times;
    std::vector<Series> vehicles;
    std::map<std::string, size_t> by_name;
    std::vector<std::string> lanes, maneuvers;
    std::map<std::string, int> lane_idx, man_idx;
    std::istringstream in(csv);
    std::string line;
    std::getline(in, line);
    if (line.rfind("time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver", 0) != 0) {
        error = (dir / "trajectories.csv").string() + ": unexpected header";
        return "";
    }
    size_t row = 1;
    while (std::getline(in, line)) {
        ++row;
        std::vector<std::string> f;
        f.reserve(13);
        size_t start = 0;
        for (size_t i = 0; i <= line.size(); ++i) {
            if (i == line.size() || line[i] == ',') {
                f.emplace_back(line, start, i - start);
                start = i + 1;
            }
        }
        if (f.size() != 13) {
            error = (dir / "trajectories.csv").string() + ":" + std::to_string(row) + ": expected 13 columns";
            return "";
        }
        const long tick = std::strtol(f[1].c_str(), nullptr, 10);
        if (tick < 0 || tick > 100000000) {
            error = (dir / "trajectories.csv").string() + ":" + std::to_string(row) + ": bad tick";
            return "";
        }
        if (static_cast<size_t>(tick) >= times.size()) times.resize(static_cast<size_t>(tick) + 1);
        times[static_cast<size_t>(tick)] = f[0];
        auto [it, fresh] = by_name.try_emplace(f[2], vehicles.size());
        if (fresh) {
            vehicles.emplace_back();
            vehicles.back().name = f[2];
            vehicles.back().kind = f[3];
            vehicles.back().first = tick;
        }
        Series& v = vehicles[it->second];
        v.x.push_back(f[4]);
        v.y.push_back(f[5]);
        v.yaw.push_back(f[6]);
        v.speed.push_back(f[7]);
        v.accel.push_back(f[8]);
        v.s.push_back(f[9]);
        v.d.push_back(f[10]);
        v.lane.push_back(index_of(lanes, lane_idx, f[11]));
        v.maneuver.push_back(index_of(maneuvers, man_idx, f[12].empty() ? "none" : f[12]));
    }
    // A replay (sdv replay) keeps the replaced vehicle's recording in recorded.csv
    // (vehicle,t,x,y,heading,speed): shown as one more agent of kind "recorded", sampled at the
    // run's ticks within the recorded span, next to the simulated one.
    std::string recorded_text;
    if (read(dir / "recorded.csv", recorded_text) && !times.empty()) {
        struct Rec {
            double t, x, y, h, v;
        };
        std::vector<Rec> pts;
        std::string rec_name;
        std::istringstream rl(recorded_text);
        std::getline(rl, line);
        while (std::getline(rl, line)) {
            std::vector<std::string> f;
            std::stringstream ls(line);
            for (std::string c; std::getline(ls, c, ',');) f.push_back(c);
            if (f.size() != 6) continue;
            char* e = nullptr;
            Rec r{std::strtod(f[1].c_str(), &e), std::strtod(f[2].c_str(), nullptr), std::strtod(f[3].c_str(), nullptr),
                  std::strtod(f[4].c_str(), nullptr), std::strtod(f[5].c_str(), nullptr)};
            if (!pts.empty() && !(r.t > pts.back().t)) continue;
            rec_name = f[0];
            pts.push_back(r);
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
                if (t < pts.front().t - 1e-9 || t > pts.back().t + 1e-9) {
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
    if (summary.contains("metrics") && summary["metrics"].contains("vehicles")) {
        for (const auto& vj : summary["metrics"]["vehicles"]) {
            if (vj.contains("vehicle") && vj.contains("length") && vj.contains("width")) {
                sizes[vj["vehicle"].get<std::string>()] = {vj["length"].get<double>(), vj["width"].get<double>()};
            }
        }
    }
    std::string data = "{\"format\":\"sdv-view/1\",\"scenario\":" + Json(summary.value("scenario", "")).dump();
    data += ",\"summary\":" + summary.dump() + ",\"road\":" + road.dump() + ",\"times\":";
    array(data, times);
    data += ",\"lanes\":" + Json(lanes).dump() + ",\"maneuvers\":" + Json(maneuvers).dump() + ",\"vehicles\":[";
    for (size_t i = 0; i < vehicles.size(); ++i) {
        const Series& v = vehicles[i];
        // Pedestrians default to 0.5 m x 0.5 m (a disc of 0.25 m radius in the viewer).
        const std::pair<double, double> fallback = v.kind == "pedestrian" ? std::pair{0.5, 0.5} : std::pair{4.5, 1.8};
        const auto sz = sizes.count(v.name) ? sizes[v.name] : fallback;
        data += (i ? ",{" : "{");
        data += "\"name\":" + Json(v.name).dump() + ",\"kind\":" + Json(v.kind).dump() + ",\"length\":" + Json(sz.first).dump() +
                ",\"width\":" + Json(sz.second).dump() + ",\"first\":" + std::to_string(v.first);
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
    if (read(dir / "decisions.jsonl", decisions_text)) {
        data += "[";
        std::istringstream dl(decisions_text);
        bool first = true;
        size_t n = 0;
        while (std::getline(dl, line)) {
            ++n;
            if (line.empty()) continue;
            Json d = Json::parse(line, nullptr, false);
            if (d.is_discarded() || !d.is_object()) {
                error = (dir / "decisions.jsonl").string() + ":" + std::to_string(n) + ": not valid JSON";
                return "";
            }
            if (d.contains("nodes") && d["nodes"].is_array()) {
                Json packed = Json::array();
                for (const auto& nd : d["nodes"]) {
                    if (!nd.is_object()) continue;
                    packed.push_back({index_of(node_paths, node_idx, nd.value("node", "")),
                                      index_of(node_statuses, status_idx, nd.value("status", ""))});
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
                    flat.push_back(index_of(path_statuses, path_status_idx, p.value("status", "")));
                    for (const auto& c : p["xy"]) flat.push_back(c.is_number() ? std::round(c.get<double>() * 10) / 10 : 0.0);
                }
                d["paths"] = std::move(flat);
            }
            data += (first ? "" : ",") + d.dump();
            first = false;
        }
        data += "]";
    } else {
        data += "null";
    }
    data += ",\"node_paths\":" + Json(node_paths).dump() + ",\"node_statuses\":" + Json(node_statuses).dump() +
            ",\"path_statuses\":" + Json(path_statuses).dump();
    for (const char* field : {"rejected", "cost", "start"}) data += ",\"" + std::string(field) + "_keys\":" + Json(keyed[field]).dump();
    data += "}";
    // Inside <script>, "</script>" or "<!--" in a string would end or confuse the element: '<'
    // is written as its JSON escape, which JSON.parse reads back unchanged (outside strings
    // JSON never contains '<').
    std::string safe;
    safe.reserve(data.size());
    for (char c : data) {
        if (c == '<') safe += "\\u003c";
        else safe += c;
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
