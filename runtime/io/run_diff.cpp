#include "runtime/io/run_diff.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

#include "runtime/catalog/catalog.h"
#include "runtime/io/run_dir.h"
#include "runtime/io/text.h"
#include "runtime/ir/ir_io.h"
#include "runtime/road/reader_text.h"

namespace sdv::io {
namespace {

using Json = nlohmann::json;
constexpr auto num = catalog::format_number;

// One row of trajectories.csv: what a run diff compares. 48 bytes, so that runs of millions of
// rows (1,000 vehicles for 2 minutes is 3.6 million) fit: the agent is an index into the names
// of both runs, the numbers are finite (parse_trajectory_row bounds their digits).
struct Row {
    long tick = 0;
    uint32_t agent = 0;
    double time = 0, x = 0, y = 0, speed = 0;
};

// The agents' names of both runs, each once.
struct Names {
    std::map<std::string, uint32_t, std::less<>> index;
    std::vector<std::string> names;
    uint32_t of(std::string_view name) {
        const auto it = index.find(name);
        if (it != index.end()) return it->second;
        names.emplace_back(name);
        return index.emplace(std::string(name), static_cast<uint32_t>(names.size() - 1)).first->second;
    }
};

double number(std::string_view t) {
    double v = 0;
    std::from_chars(t.data(), t.data() + t.size(), v);
    return v;
}

// trajectories.csv of a run directory, checked as sdv view reads it (TrajectoryReader), at
// any tick a run can have. Returns "" or the error.
std::string read_rows(const std::string& dir, Names& names, std::vector<Row>& rows) {
    const std::string path = dir + "/trajectories.csv";
    std::string text;
    if (!road::read_file(path, text)) return "cannot read " + path;
    TrajectoryReader in(text, path, kMaxRunTicks);
    TrajectoryRow r;
    while (in.next(r)) rows.push_back({r.tick, names.of(r.vehicle), number(r.time), number(r.x), number(r.y), number(r.speed)});
    return in.error();
}

// Sorts rows by (tick, name): the order in which differences are reported. An agent has one row
// per tick (TrajectoryReader), so no two rows of a run share a place.
void sort_rows(std::vector<Row>& rows, const std::vector<uint32_t>& rank) {
    std::sort(rows.begin(), rows.end(), [&](const Row& p, const Row& q) {
        return p.tick != q.tick ? p.tick < q.tick : rank[p.agent] < rank[q.agent];
    });
}

// decisions.jsonl of a run directory by (time, agent), or nothing when the run has none. A line
// is a JSON object nested at most kMaxRunJsonDepth levels (deeper text is refused before it
// is parsed, as comparing it recurses per level); lines without a number `time` and a string
// `vehicle` name no decision and are left aside, as sdv view leaves fields of another type.
using Decisions = std::map<std::pair<double, std::string>, Json>;
std::string read_decisions(const std::string& dir, std::optional<Decisions>& out) {
    const std::string path = dir + "/decisions.jsonl";
    std::string text;
    if (!road::read_file(path, text)) return "";
    out.emplace();
    std::istringstream in(text);
    std::string line;
    for (size_t n = 1; std::getline(in, line); ++n) {
        if (line.empty()) continue;
        const std::string where = path + ":" + std::to_string(n) + ": ";
        if (ir::json_depth(line) > kMaxRunJsonDepth) {
            return where + "JSON nested more than " + std::to_string(kMaxRunJsonDepth) + " levels deep";
        }
        Json d = Json::parse(line, nullptr, false);
        if (d.is_discarded() || !d.is_object()) return where + "not valid JSON";
        const auto time = d.find("time");
        const auto vehicle = d.find("vehicle");
        if (time == d.end() || !time->is_number() || vehicle == d.end() || !vehicle->is_string()) continue;
        // What is compared, not the rest (tree nodes and candidate paths are most of a line).
        Json kept = Json::object();
        for (const char* key : {"maneuver", "winner", "cost"}) {
            if (const auto it = d.find(key); it != d.end()) kept[key] = std::move(*it);
        }
        out->emplace(std::pair<double, std::string>{time->get<double>(), vehicle->get<std::string>()}, std::move(kept));
    }
    return "";
}

// Field `key` of a decision, null when it has none.
const Json& field(const Json& d, const char* key) {
    static const Json kNull;
    const auto it = d.find(key);
    return it == d.end() ? kNull : *it;
}

// A JSON value as a short text: the whole of it up to 60 bytes.
std::string shown(const Json& v) {
    const std::string t = v.is_string() ? v.get<std::string>() : json_text(v);
    return t.size() > 60 ? t.substr(0, 57) + "..." : t;
}

nlohmann::ordered_json to_json(const RunDiff& d) {
    nlohmann::ordered_json j;
    j["equal"] = d.equal;
    if (!d.error.empty()) j["error"] = d.error;
    if (d.first_tick >= 0) {
        j["first_tick"] = d.first_tick;
        j["first_time"] = d.first_time;
        j["vehicles"] = d.vehicles;
        j["detail"] = d.detail;
    }
    if (!d.decision_detail.empty()) {
        j["decision"] = {{"time", d.decision_time}, {"vehicle", d.decision_vehicle}, {"detail", d.decision_detail}};
    }
    return j;
}

}  // namespace

RunDiff diff_runs(const std::string& dir_a, const std::string& dir_b, double tol) {
    RunDiff d;
    Names names;
    std::vector<Row> a, b;
    if (d.error = read_rows(dir_a, names, a); !d.error.empty()) return d;
    if (d.error = read_rows(dir_b, names, b); !d.error.empty()) return d;
    std::optional<Decisions> da, db;
    if (d.error = read_decisions(dir_a, da); !d.error.empty()) return d;
    if (d.error = read_decisions(dir_b, db); !d.error.empty()) return d;
    std::vector<uint32_t> rank(names.names.size());  // of each name in sorted order
    {
        uint32_t k = 0;
        for (const auto& [name, index] : names.index) rank[index] = k++;
    }
    sort_rows(a, rank);
    sort_rows(b, rank);
    // Both runs' rows in (tick, name) order: the first tick where an agent is in one run only,
    // or at another place or speed, and every agent that differs at that tick.
    auto place = [&](const Row& r) { return std::pair{r.tick, rank[r.agent]}; };
    auto ia = a.begin(), ib = b.begin();
    while (ia != a.end() || ib != b.end()) {
        const bool only_a = ib == b.end() || (ia != a.end() && place(*ia) < place(*ib));
        const bool only_b = !only_a && (ia == a.end() || place(*ib) < place(*ia));
        const Row& first = only_b ? *ib : *ia;
        if (d.first_tick >= 0 && first.tick != d.first_tick) break;
        const std::string& name = names.names[first.agent];
        std::string detail;
        if (only_a) {
            detail = name + " is missing from the second run";
        } else if (only_b) {
            detail = name + " is missing from the first run";
        } else {
            const double dp = std::hypot(ib->x - ia->x, ib->y - ia->y);
            const double dv = std::fabs(ib->speed - ia->speed);
            // What differs, beyond the tolerance: the position, the speed or both.
            const bool moved = !(dp <= tol), sped = !(dv <= tol);
            if (moved || sped) {
                detail = name + ":";
                if (moved) detail += " position differs by " + num(dp) + " m";
                if (moved && sped) detail += ",";
                if (sped) detail += " speed " + num(ia->speed) + " → " + num(ib->speed) + " m/s";
            }
        }
        if (!detail.empty()) {
            if (d.first_tick < 0) {
                d.equal = false;
                d.first_tick = first.tick;
                d.first_time = first.time;
                d.detail = detail;
            }
            d.vehicles.push_back(name);
        }
        if (!only_b) ++ia;
        if (!only_a) ++ib;
    }
    // Decision traces: the first planning cycle (by time, then agent) whose maneuver, winning
    // candidate or cost differs, or that one run has and the other not.
    if (da && db) {
        d.has_decisions = true;
        auto ja = da->begin(), jb = db->begin();
        while (ja != da->end() || jb != db->end()) {
            const bool only_a = jb == db->end() || (ja != da->end() && ja->first < jb->first);
            const bool only_b = !only_a && (ja == da->end() || jb->first < ja->first);
            const auto& key = only_a ? ja->first : jb->first;
            std::string what;
            if (only_a) {
                what = "no decision in the second run";
            } else if (only_b) {
                what = "no decision in the first run";
            } else {
                const Json &x = ja->second, &y = jb->second;
                if (field(x, "maneuver") != field(y, "maneuver")) {
                    what = "maneuver " + shown(field(x, "maneuver")) + " → " + shown(field(y, "maneuver"));
                } else if (field(x, "winner") != field(y, "winner") || field(x, "cost") != field(y, "cost")) {
                    const Json& ca = field(x, "cost");
                    const Json& cb = field(y, "cost");
                    what = "maneuver " + shown(field(x, "maneuver")) + ": winning candidate " + shown(field(x, "winner")) + " → " +
                           shown(field(y, "winner")) + " (cost " + shown(ca.is_object() ? field(ca, "total") : ca) + " → " +
                           shown(cb.is_object() ? field(cb, "total") : cb) + ")";
                }
            }
            if (!what.empty()) {
                d.equal = false;
                d.decision_time = key.first;
                d.decision_vehicle = key.second;
                d.decision_detail = what;
                break;
            }
            if (!only_b) ++ja;
            if (!only_a) ++jb;
        }
    }
    return d;
}

std::string render_text(const RunDiff& d) {
    if (!d.error.empty()) return d.error + "\n";
    if (d.equal) return "runs are equal\n";
    std::ostringstream o;
    if (d.first_tick >= 0) {
        o << "first divergence at tick " << d.first_tick << " (t = " << num(d.first_time) << " s): ";
        for (size_t i = 0; i < d.vehicles.size(); ++i) o << (i ? ", " : "") << d.vehicles[i];
        o << "\n  " << d.detail << "\n";
    } else if (!d.detail.empty()) {
        o << d.detail << "\n";
    }
    if (!d.decision_detail.empty()) {
        o << "first differing decision at t = " << num(d.decision_time) << " s, vehicle " << d.decision_vehicle << ": "
          << d.decision_detail << "\n";
    } else if (!d.has_decisions) {
        o << "(no decision traces to compare: run both with --trace)\n";
    }
    return o.str();
}

std::string render_json(const RunDiff& d) {
    return to_json(d).dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace sdv::io
