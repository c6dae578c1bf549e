#include "runtime/io/outputs.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "runtime/catalog/catalog.h"

namespace sdv::io {
namespace {

using Json = nlohmann::ordered_json;

// Numbers in outputs are rounded to fixed decimals so that the text is stable.
Json num(double v, int digits = 4) {
    if (!std::isfinite(v)) return nullptr;
    const double k = std::pow(10.0, digits);
    double r = std::round(v * k) / k;
    if (r == 0) r = 0;  // no -0
    return r;
}

// The catalog entry of a part's function.
const catalog::ExpectDef& def_of(const sim::ExpectPart& part) {
    return catalog::expectations()[static_cast<size_t>(part.function)];
}

// "12.053 m", "4.2 %": a measured value in its SI unit.
std::string quantity_text(double v, catalog::Dim dim) {
    char buf[64];
    if (dim == catalog::Dim::ratio) {
        std::snprintf(buf, sizeof buf, "%.1f %%", 100 * v);
    } else {
        std::snprintf(buf, sizeof buf, "%.3f %s", v, std::string(catalog::si_unit(dim)).c_str());
    }
    return buf;
}

// What a part measured, in words: "same-lane bumper gap 12.053 m", "never closing",
// "collision at 12.30 s", "no collision".
std::string measured_text(const sim::ExpectPart& part) {
    const auto& d = def_of(part);
    if (!d.boolean) return part.value ? d.label + " " + quantity_text(*part.value, d.result) : d.label + ": " + d.none;
    if (!part.time) return "no " + d.label;
    char buf[32];
    std::snprintf(buf, sizeof buf, " at %.2f s", *part.time);
    return d.label + buf;
}

}  // namespace

std::string summary_json(const ir::Program& p, int scenario, const sim::RunResult& r, const RunInfo& info) {
    const ir::Scenario& sc = p.scenarios.at(static_cast<size_t>(scenario));
    Json j;
    j["scenario"] = sc.name;
    j["ir_hash"] = info.ir_hash;
    j["seed"] = info.seed;
    j["traffic_rate"] = sc.traffic_rate;
    j["planning_rate"] = sc.planning_rate;
    j["planning_latency"] = sc.planning_latency >= 0 ? sc.planning_latency : 1.0 / sc.planning_rate;
    j["duration"] = num(r.duration);
    j["ticks"] = r.ticks;
    j["passed"] = r.passed();
    if (!r.error.empty()) j["error"] = r.error;
    if (!info.cosim_ending.empty()) {
        j["cosim"] = {{"ending", info.cosim_ending}, {"aborted", info.cosim_ending.rfind("aborted", 0) == 0}};
    }
    j["expectations"] = Json::array();
    for (size_t k = 0; k < r.expectations.size(); ++k) {
        const auto& e = r.expectations[k];
        Json ej;
        ej["expect"] = e.text;
        ej["passed"] = e.passed;
        if (e.value) ej["value"] = num(*e.value);
        if (k < sc.expect_roots.size()) {
            const ir::Expect& root = sc.expects[static_cast<size_t>(sc.expect_roots[k])];
            if (root.after || root.before) {
                ej["window"] = {{"after", root.after ? num(*root.after) : Json(nullptr)},
                                {"before", root.before ? num(*root.before) : Json(nullptr)}};
            }
        }
        // Every call of the expression: the metric it checks and what it measured.
        Json parts = Json::array();
        for (const auto& part : e.parts) {
            const auto& d = def_of(part);
            Json pj;
            pj["call"] = part.text;
            pj["metric"] = d.name;
            pj["holds"] = part.holds;
            if (d.boolean) {
                pj["time"] = part.time ? num(*part.time) : Json(nullptr);
            } else {
                pj["value"] = part.value ? num(*part.value) : Json(nullptr);
                pj["unit"] = d.result == catalog::Dim::ratio ? "ratio" : std::string(catalog::si_unit(d.result));
                if (!part.value) pj["none"] = d.none;
            }
            parts.push_back(pj);
        }
        ej["parts"] = parts;
        ej["line"] = e.loc.line;
        j["expectations"].push_back(ej);
    }
    j["events"] = Json::array();
    for (const auto& ev : r.events) {
        Json ej;
        ej["time"] = num(ev.time);
        ej["kind"] = ev.kind;
        Json vs = Json::array();
        for (int v : ev.vehicles) vs.push_back(sc.vehicles[static_cast<size_t>(v)].name);
        ej["vehicles"] = vs;
        if (ev.kind == "collision") {
            ej["relative_speed"] = num(ev.relative_speed);
            ej["zone"] = ev.zone;
        }
        j["events"].push_back(ej);
    }
    Json pairs = Json::array();
    for (const auto& m : r.pairs) {
        Json pj;
        pj["vehicles"] = {sc.vehicles[static_cast<size_t>(m.a)].name, sc.vehicles[static_cast<size_t>(m.b)].name};
        pj["min_clearance"] = num(m.min_clearance);
        pj["min_gap"] = num(m.min_gap);
        pj["min_lateral"] = num(m.min_lateral);
        pj["min_ttc"] = num(m.min_ttc);
        pj["min_headway"] = num(m.min_headway);
        pairs.push_back(pj);
    }
    Json vehicles = Json::array();
    for (size_t i = 0; i < r.vehicles.size(); ++i) {
        const auto& m = r.vehicles[i];
        Json vj;
        vj["vehicle"] = sc.vehicles[i].name;
        vj["length"] = sc.vehicles[i].length;
        vj["width"] = sc.vehicles[i].width;
        vj["min_speed"] = num(m.min_speed);
        vj["max_speed"] = num(m.max_speed);
        vj["min_acc"] = num(m.min_acc);
        vj["max_acc"] = num(m.max_acc);
        vj["max_jerk"] = num(m.max_jerk);
        vj["reached_goal"] = m.reached_goal;
        vj["fallback_used"] = m.fallback_used;
        vj["plans"] = m.plans;
        vj["fallback_plans"] = m.fallback_plans;
        vj["fallback_share"] = num(m.fallback_share());
        vj["longest_stall_s"] = num(m.longest_stall_s);
        vehicles.push_back(vj);
    }
    j["metrics"] = {{"pairs", pairs}, {"vehicles", vehicles}};
    return j.dump(2) + "\n";
}

std::string timing_json(const sim::RunResult& r, int threads) {
    Json j;
    j["wall_s"] = r.timing.wall_s;
    j["real_time_factor"] = r.timing.wall_s > 0 ? r.duration / r.timing.wall_s : 0.0;
    j["threads"] = threads;
    const double plans = static_cast<double>(r.timing.plan_us.count());
    j["plans_per_s"] = r.timing.wall_s > 0 ? plans / r.timing.wall_s : 0.0;
    j["candidates_per_s"] = r.timing.wall_s > 0 ? static_cast<double>(r.timing.candidates) / r.timing.wall_s : 0.0;
    j["tick_us"] = {{"p50", r.timing.tick_us.percentile(0.5)}, {"p90", r.timing.tick_us.percentile(0.9)}, {"p99", r.timing.tick_us.percentile(0.99)},
                    {"max", r.timing.tick_us.percentile(1.0)}};
    j["plan_us"] = {{"p50", r.timing.plan_us.percentile(0.5)}, {"p90", r.timing.plan_us.percentile(0.9)}, {"p99", r.timing.plan_us.percentile(0.99)},
                    {"max", r.timing.plan_us.percentile(1.0)}};
    return j.dump(2) + "\n";
}

std::string write_outputs(const std::string& dir, const ir::Program& p, int scenario, const sim::RunResult& r,
                          const Recording& rec, const RunInfo& info) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) return "cannot create '" + dir + "': " + ec.message();
    auto write = [&](const std::string& name, const std::string& text) -> std::string {
        std::ofstream o(fs::path(dir) / name, std::ios::binary);
        o << text;
        return o ? "" : "cannot write '" + (fs::path(dir) / name).string() + "'";
    };
    // A streamed recording (Recorder::open) has written its rows already.
    if (!rec.trajectories_csv.empty()) {
        if (auto e = write("trajectories.csv", rec.trajectories_csv); !e.empty()) return e;
    }
    if (auto e = write("summary.json", summary_json(p, scenario, r, info)); !e.empty()) return e;
    if (auto e = write("timing.json", timing_json(r, info.threads)); !e.empty()) return e;
    if (auto e = write("road.json", rec.road_json); !e.empty()) return e;
    if (info.trace && !rec.decisions_jsonl.empty()) {
        if (auto e = write("decisions.jsonl", rec.decisions_jsonl); !e.empty()) return e;
    }
    return "";
}

std::string event_line(const ir::Scenario& sc, const sim::Event& ev) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "  %7.2f s  %s", ev.time, ev.kind.c_str());
    std::string o = buf;
    for (int v : ev.vehicles) o += " " + sc.vehicles.at(static_cast<size_t>(v)).name;
    if (ev.kind == "collision") {
        std::snprintf(buf, sizeof buf, " (%.1f m/s, %s)", ev.relative_speed, ev.zone.c_str());
        o += buf;
    }
    return o;
}

std::string report(const ir::Program& p, int scenario, const sim::RunResult& r) {
    const ir::Scenario& sc = p.scenarios.at(static_cast<size_t>(scenario));
    std::ostringstream o;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s: %.1f s simulated in %.3f s (%.0fx real time), %lld plans\n", sc.name.c_str(), r.duration,
                  r.timing.wall_s, r.timing.wall_s > 0 ? r.duration / r.timing.wall_s : 0.0, r.timing.plan_us.count());
    o << buf;
    // Fallback plans are summarised per vehicle below, not listed as events.
    std::vector<double> first_fallback(sc.vehicles.size(), -1);
    for (const auto& ev : r.events) {
        if (ev.kind == "fallback") {
            for (int v : ev.vehicles) {
                if (first_fallback[static_cast<size_t>(v)] < 0) first_fallback[static_cast<size_t>(v)] = ev.time;
            }
        }
    }
    for (const auto& ev : r.events) {
        if (ev.kind == "timeout" || ev.kind == "fallback") continue;
        o << event_line(sc, ev) << "\n";
    }
    // Fallback: how much of each driver's planning found no feasible trajectory (the emergency
    // fallback of docs/language.md), most first; many vehicles are summed up after the first five.
    std::vector<size_t> fb;
    long long fb_plans = 0, all_plans = 0;
    for (size_t i = 0; i < r.vehicles.size() && i < sc.vehicles.size(); ++i) {
        all_plans += r.vehicles[i].plans;
        if (r.vehicles[i].fallback_plans == 0) continue;
        fb.push_back(i);
        fb_plans += r.vehicles[i].fallback_plans;
    }
    std::stable_sort(fb.begin(), fb.end(), [&](size_t a, size_t b) {
        return r.vehicles[a].fallback_share() > r.vehicles[b].fallback_share();
    });
    constexpr size_t kListed = 5;
    for (size_t k = 0; k < fb.size() && k < kListed; ++k) {
        const auto& m = r.vehicles[fb[k]];
        std::snprintf(buf, sizeof buf, "  fallback %s: %d of %d plans (%.0f %%), first at %.2f s\n",
                      sc.vehicles[fb[k]].name.c_str(), m.fallback_plans, m.plans, 100 * m.fallback_share(),
                      std::max(0.0, first_fallback[fb[k]]));
        o << buf;
    }
    if (fb.size() > kListed) {
        std::snprintf(buf, sizeof buf, "  fallback: %zu more vehicles; %lld of %lld plans of all vehicles (%.1f %%)\n",
                      fb.size() - kListed, fb_plans, all_plans, all_plans > 0 ? 100.0 * static_cast<double>(fb_plans) / static_cast<double>(all_plans) : 0.0);
        o << buf;
    }
    // A single call shows what it measured on its line; a compound one, every part below it.
    for (const auto& e : r.expectations) {
        o << "  " << (e.passed ? "PASS" : "FAIL") << "  expect " << e.text;
        const bool single = e.parts.size() == 1 && e.parts[0].holds == e.passed;
        if (single) {
            o << "  (" << measured_text(e.parts[0]) << ")\n";
            continue;
        }
        o << "\n";
        for (const auto& part : e.parts) {
            o << "          " << part.text << " is " << (part.holds ? "true" : "false") << "  (" << measured_text(part) << ")\n";
        }
    }
    size_t passed = 0;
    for (const auto& e : r.expectations) passed += e.passed;
    o << passed << " of " << r.expectations.size() << " expectations hold\n";
    return o.str();
}

}  // namespace sdv::io
