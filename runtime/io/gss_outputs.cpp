#include "runtime/io/gss_outputs.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace sdv::io {
namespace {

constexpr double kPi = 3.14159265358979323846;

int vid_of(const ir::Vehicle& v, size_t index) {
    const std::string& n = v.name;
    if (n.size() > 1 && (n[0] == 'v' || n[0] == 'p') && n.find_first_not_of("0123456789", 1) == std::string::npos && n.size() < 9) {
        return std::stoi(n.substr(1));
    }
    return static_cast<int>(index) + 1;
}

// The reference's vehicle types (Vehicle.py): SDV 1, EV 2 (external), TV 3 (trajectory); static
// objects are not vehicles there and are written as 0.
int type_of(const ir::Vehicle& v) {
    switch (v.kind) {
        case ir::VehicleKind::sdv: return 1;
        case ir::VehicleKind::external: return 2;
        case ir::VehicleKind::trajectory: return 3;
        case ir::VehicleKind::path: return 5;  // PV (Vehicle.py)
        case ir::VehicleKind::static_object: return 0;
    }
    return 0;
}

// A float as Python's repr prints it: the shortest text that reads back the same ("12.34",
// "-5.0").
std::string py_float(double v) {
    char buf[40];
    for (int prec = 1; prec <= 17; ++prec) {
        std::snprintf(buf, sizeof buf, "%.*g", prec, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    std::string out = buf;
    if (out.find_first_of(".en") == std::string::npos) out += ".0";
    return out;
}

std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4f", std::fabs(v) < 5e-5 ? 0.0 : v);
    return buf;
}

}  // namespace

std::string violations_json(const ir::Program& p, int scenario, const sim::RunResult& r, const PoseAt& pose) {
    const ir::Scenario& sc = p.scenarios.at(static_cast<size_t>(scenario));
    std::map<int, nlohmann::ordered_json> by_vid;
    std::map<int, size_t> index_of;
    // The reference's violations are its SDVs' (simulated pedestrians are not vehicles there).
    const auto is_sdv = [](const ir::Vehicle& v) { return v.kind == ir::VehicleKind::sdv && !v.pedestrian; };
    for (size_t i = 0; i < sc.vehicles.size(); ++i) {
        if (!is_sdv(sc.vehicles[i])) continue;
        by_vid[vid_of(sc.vehicles[i], i)] = nlohmann::ordered_json::object();
        index_of[static_cast<int>(i)] = i;
    }
    // The tick key: the reference's planner tick in progress at t (its ticks k at k / rate from
    // 0): a 20 s timeout at 5 Hz is tick 99, the last one that ran.
    auto tick_of = [&](double t) {
        return std::to_string(std::max(0LL, static_cast<long long>(std::ceil(t * sc.planning_rate - 1e-9)) - 1));
    };
    auto add = [&](int vehicle, double t, const std::string& cls, nlohmann::ordered_json payload) {
        const auto& v = sc.vehicles.at(static_cast<size_t>(vehicle));
        if (!is_sdv(v)) return;
        auto& entry = by_vid[vid_of(v, static_cast<size_t>(vehicle))];
        entry[tick_of(t)][cls] = std::move(payload);
    };
    auto message = [](const std::string& m) { return nlohmann::ordered_json{{"message", m}}; };
    auto vid_at = [&](int i) { return vid_of(sc.vehicles.at(static_cast<size_t>(i)), static_cast<size_t>(i)); };
    for (const auto& e : r.events) {
        if (e.kind == "collision" && e.vehicles.size() == 2) {
            for (int k = 0; k < 2; ++k) {
                const int me = e.vehicles[static_cast<size_t>(k)], other = e.vehicles[static_cast<size_t>(1 - k)];
                const auto& o = sc.vehicles.at(static_cast<size_t>(other));
                // The reference checks its SDVs against vehicles and pedestrians only (no static
                // objects: HardRequirements.detect_collisions).
                if (o.object) continue;
                nlohmann::ordered_json payload;
                if (o.pedestrian) {
                    // Where the pedestrian is seen from the vehicle (HardRequirements.collision_check):
                    // its bearing off the heading in degrees (left positive), and the side: front
                    // or rear within the angle of the corners, else left or right.
                    const auto a = pose(me, e.time), b = pose(other, e.time);
                    const double bearing = std::atan2(b.y - a.y, b.x - a.x) - a.yaw;
                    double angle = std::remainder(bearing, 2 * kPi) * 180.0 / kPi;
                    angle = std::round(angle * 100) / 100;
                    const auto& mv = sc.vehicles.at(static_cast<size_t>(me));
                    const double corner = std::asin(std::min(1.0, mv.width / mv.length)) * 180.0 / kPi;
                    const std::string zone = std::fabs(angle) <= corner ? "front" : std::fabs(angle) >= 180 - corner ? "rear" : angle < 0 ? "right" : "left";
                    const std::string alias = "p_" + std::to_string(vid_at(other));
                    payload["angle"] = std::stod(py_float(angle));
                    payload["collections"] = {{"pedestrians", {{"alias", alias}, {"id", vid_at(other)}}}};
                    payload["message"] = "v_" + std::to_string(vid_at(me)) + " bounding box overlapped with the pedestrian agent " + alias +
                                         " on the vehicle " + zone + " side at " + py_float(angle) + " degrees";
                    payload["zone"] = zone;
                    add(me, e.time, "CollisionWithPedestrian", payload);
                } else {
                    const std::string alias = "v_" + std::to_string(vid_at(other));
                    payload["collections"] = {{"vehicles", {{"alias", alias}, {"id", vid_at(other)}}}};
                    payload["message"] = "v_" + std::to_string(vid_at(me)) + " bounding box overlapped with the vehicle agent " + alias;
                    add(me, e.time, "CollisionWithVehicle", payload);
                }
            }
        } else if (e.kind == "goal_overshot" && !e.vehicles.empty()) {
            const int me = e.vehicles[0];
            add(me, e.time, "GoalOvershot", message("v" + std::to_string(vid_at(me)) + " drove past its target location"));
        } else if (e.kind == "timeout") {
            for (size_t i = 0; i < sc.vehicles.size(); ++i) {
                // Those that did not reach their goal (the message says so).
                if (!is_sdv(sc.vehicles[i]) || (i < r.vehicles.size() && r.vehicles[i].reached_goal)) continue;
                // The timeout as Python prints a float: "20.0", "20.5".
                char t[40];
                std::snprintf(t, sizeof t, "%.15g", sc.timeout);
                if (std::string(t).find_first_of(".e") == std::string::npos) std::strcat(t, ".0");
                add(static_cast<int>(i), e.time, "ScenarioTimeout",
                    message("v" + std::to_string(vid_of(sc.vehicles[i], i)) + " did not reach its target location during the " + t +
                            " seconds allowed by this scenario."));
            }
        }
    }
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    for (auto& [vid, v] : by_vid) j[std::to_string(vid)] = v;
    return j.dump(4) + "\n";
}

std::string write_gss_outputs(const std::string& dir, const ir::Program& p, int scenario, const sim::RunResult& r,
                              std::istream& trajectories_csv) {
    namespace fs = std::filesystem;
    const ir::Scenario& sc = p.scenarios.at(static_cast<size_t>(scenario));
    // Rows of trajectories.csv per vehicle: time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver
    std::map<std::string, size_t> index;
    for (size_t i = 0; i < sc.vehicles.size(); ++i) index[sc.vehicles[i].name] = i;
    struct Row {
        double t, x, y, yaw, speed, accel, s, d;
        long tick;
    };
    std::vector<std::vector<Row>> rows(sc.vehicles.size());
    std::istream& in = trajectories_csv;
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ls(line);
        for (std::string c; std::getline(ls, c, ',');) f.push_back(c);
        if (f.size() < 11) continue;
        auto it = index.find(f[2]);
        if (it == index.end()) continue;
        rows[it->second].push_back({std::stod(f[0]), std::stod(f[4]), std::stod(f[5]), std::stod(f[6]), std::stod(f[7]),
                                    std::stod(f[8]), std::stod(f[9]), std::stod(f[10]), std::stol(f[1])});
    }
    const PoseAt pose = [&](int i, double t) {
        const auto& rs = rows.at(static_cast<size_t>(i));
        auto it = std::lower_bound(rs.begin(), rs.end(), t - 1e-9, [](const Row& w, double x) { return w.t < x; });
        if (it == rs.end()) {
            if (rs.empty()) return Pose{};
            --it;
        }
        return Pose{it->x, it->y, it->yaw};
    };
    {
        std::ofstream o(fs::path(dir) / "violations.json", std::ios::binary);
        o << violations_json(p, scenario, r, pose);
        if (!o) return "cannot write " + (fs::path(dir) / "violations.json").string();
    }
    const double dt = 1.0 / sc.traffic_rate;
    for (size_t i = 0; i < sc.vehicles.size(); ++i) {
        const int vid = vid_of(sc.vehicles[i], i);
        const fs::path path = fs::path(dir) / ("trajectory_v" + std::to_string(vid) + ".csv");
        std::ofstream o(path, std::ios::binary);
        o << "id,type,sim_state,tick_count,sim_time,delta_time,x,x_vel,x_acc,y,y_vel,y_acc,s,s_vel,s_acc,d,d_vel,d_acc,angle\n";
        const auto& rs = rows[i];
        for (size_t k = 0; k < rs.size(); ++k) {
            const Row& w = rs[k];
            const double c = std::cos(w.yaw), sn = std::sin(w.yaw);
            // Lateral rates by central differences of d (one-sided at the ends).
            auto d_at = [&](size_t m) { return rs[std::min(m, rs.size() - 1)].d; };
            const size_t a = k > 0 ? k - 1 : k, b = k + 1 < rs.size() ? k + 1 : k;
            const double span = static_cast<double>(b - a) * dt;
            const double d_vel = span > 0 ? (d_at(b) - d_at(a)) / span : 0;
            const double d_acc = (k > 0 && k + 1 < rs.size()) ? (d_at(k + 1) - 2 * w.d + d_at(k - 1)) / (dt * dt) : 0;
            o << vid << "," << type_of(sc.vehicles[i]) << ",1," << w.tick << "," << fmt(w.t) << "," << fmt(k == 0 ? 0 : dt) << ","
              << fmt(w.x) << "," << fmt(w.speed * c) << "," << fmt(w.accel * c) << "," << fmt(w.y) << "," << fmt(w.speed * sn) << ","
              << fmt(w.accel * sn) << "," << fmt(w.s) << "," << fmt(w.speed) << "," << fmt(w.accel) << "," << fmt(w.d) << ","
              << fmt(d_vel) << "," << fmt(d_acc) << "," << fmt(w.yaw * 180.0 / kPi) << "\n";
        }
        if (!o) return "cannot write " + path.string();
    }
    return "";
}

}  // namespace sdv::io
