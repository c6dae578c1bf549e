#include "runtime/io/recorder.h"

#include <cstdio>

#include "runtime/catalog/catalog.h"
#include "runtime/sim/agents.h"
#include "runtime/sim/pedestrian.h"
#include "runtime/sim/world.h"

namespace sdv::io {

using sim::fmt;

Recorder::Recorder() : csv_(&csv_memory_), decisions_(&decisions_memory_) {}

Recorder::~Recorder() { discard(); }

std::string Recorder::open(const std::string& dir, bool trace) {
    auto file = [&](const char* name, std::unique_ptr<File>& f) -> std::string {
        f = std::make_unique<File>();
        f->path = dir + "/" + name;
        f->out.open(f->path + ".part", std::ios::binary | std::ios::trunc);
        return f->out ? "" : "cannot write '" + f->path + ".part'";
    };
    if (auto e = file("trajectories.csv", csv_file_); !e.empty()) return e;
    csv_ = &csv_file_->out;
    if (trace) {
        if (auto e = file("decisions.jsonl", decisions_file_); !e.empty()) return e;
        decisions_ = &decisions_file_->out;
    } else {
        std::remove((dir + "/decisions.jsonl").c_str());  // not a stale one from an earlier run
    }
    return "";
}

std::string Recorder::commit() {
    for (auto* f : {&csv_file_, &decisions_file_}) {
        if (!*f) continue;
        (*f)->out.close();
        if (!(*f)->out) return "cannot write '" + (*f)->path + "'";
        if (std::rename(((*f)->path + ".part").c_str(), (*f)->path.c_str()) != 0) return "cannot write '" + (*f)->path + "'";
        f->reset();
    }
    csv_ = &csv_memory_;
    decisions_ = &decisions_memory_;
    return "";
}

void Recorder::discard() {
    for (auto* f : {&csv_file_, &decisions_file_}) {
        if (!*f) continue;
        (*f)->out.close();
        std::remove(((*f)->path + ".part").c_str());
        f->reset();
    }
    csv_ = &csv_memory_;
    decisions_ = &decisions_memory_;
}

void Recorder::start(const sim::World& w) {
    *csv_ << "time,tick,vehicle,kind,x,y,yaw,speed,accel,s,d,lane,maneuver\n";
    road_ = road_json(w);
}

void Recorder::tick(const sim::World& w, int tick, double t) {
    for (const sim::Agent& a : w.agents) {
        if (!a.active) continue;
        *csv_ << fmt(t) << "," << tick << "," << a.v->name << "," << a.model->kind() << "," << fmt(a.x) << "," << fmt(a.y) << ","
             << fmt(a.yaw) << "," << fmt(a.speed) << "," << fmt(a.accel) << "," << fmt(a.lane_s) << "," << fmt(a.lane_d) << ","
             << (a.centre_lane != sim::kNoLane ? w.net.lane(a.centre_lane).name : "") << ","
             << (a.driver ? a.driver->maneuver_name : a.walker ? a.walker->maneuver_name : "") << "\n";
    }
}

void Recorder::plan(const sim::World& w, const sim::Agent& a) {
    if (a.driver && a.driver->trace) *decisions_ << decision_line(w, a, *a.driver->trace);
    if (a.walker && w.options.trace) *decisions_ << walker_line(w, a);
}

// A pedestrian's tree tick: the nodes visited, the maneuver in force and the intent it set
// (its phase with its target crosswalk, the desired speed, where it walks).
std::string walker_line(const sim::World& w, const sim::Agent& a) {
    static const char* kPhases[] = {"none", "approaching", "crossing", "back", "done"};
    const sim::Walker& k = *a.walker;
    const auto& nodes = k.tree->instance().nodes;
    std::ostringstream o;
    o << "{\"time\":" << fmt(k.cycle_time) << ",\"vehicle\":\"" << a.v->name << "\",\"plan\":" << k.cycles << ",\"nodes\":[";
    for (size_t i = 0; i < k.visits.size(); ++i) {
        const auto& node = nodes[static_cast<size_t>(k.visits[i].node)];
        o << (i ? "," : "") << "{\"node\":\"" << node.path << "\",\"status\":\"" << bt::to_string(k.visits[i].status) << "\"}";
    }
    const char* kind = k.maneuver >= 0 ? catalog::maneuvers()[static_cast<size_t>(nodes[static_cast<size_t>(k.maneuver)].leaf)].name.c_str() : "none";
    const sim::Intent in = sim::intent(w, a);
    o << "],\"maneuver\":\"" << k.maneuver_name << "\",\"kind\":\"" << kind << "\",\"walker\":{\"phase\":\""
      << kPhases[static_cast<int>(k.phase)] << "\",\"crosswalk\":";
    if (k.crosswalk >= 0) o << "\"" << w.net.crosswalks[static_cast<size_t>(k.crosswalk)].name << "\"";
    else o << "null";
    o << ",\"speed\":" << fmt(in.speed) << ",\"target\":[" << fmt(in.target.x, 2) << "," << fmt(in.target.y, 2) << "]}}\n";
    return o.str();
}

Recording Recorder::take() { return {csv_memory_.str(), decisions_memory_.str(), road_}; }

std::string decision_line(const sim::World& w, const sim::Agent& a, const sim::PlanTrace& tr) {
    (void)w;
    const auto& nodes = a.driver->tree->instance().nodes;
    std::ostringstream o;
    o << "{\"time\":" << fmt(tr.time) << ",\"vehicle\":\"" << a.v->name << "\",\"plan\":" << tr.plan_number << ",\"nodes\":[";
    for (size_t i = 0; i < tr.visits.size(); ++i) {
        const auto& node = nodes[static_cast<size_t>(tr.visits[i].node)];
        o << (i ? "," : "") << "{\"node\":\"" << node.path << "\",\"status\":\"" << bt::to_string(tr.visits[i].status) << "\"}";
    }
    const auto& rec = tr.record;
    o << "],\"maneuver\":\"" << tr.maneuver << "\",\"kind\":\"" << catalog::maneuver(tr.kind).name << "\",\"candidates\":" << rec.candidates
      << ",\"feasible\":" << rec.feasible << ",\"rejected\":{";
    for (size_t c = 0; c < planner::kCauseCount; ++c) {
        o << (c ? "," : "") << "\"" << planner::to_string(static_cast<planner::RejectCause>(c)) << "\":" << rec.rejections[c];
    }
    const auto& wc = rec.winner_cost;
    o << "},\"winner\":" << rec.winner << ",\"fallback\":" << (rec.fallback ? "true" : "false");
    if (tr.fallback) o << ",\"fallback_kind\":\"" << tr.fallback << "\"";
    o << ",\"cost\":{\"time\":" << fmt(wc.time)
      << ",\"efficiency\":" << fmt(wc.efficiency) << ",\"lane_offset\":" << fmt(wc.lane_offset) << ",\"long_jerk\":" << fmt(wc.long_jerk)
      << ",\"lat_jerk\":" << fmt(wc.lat_jerk) << ",\"long_acc\":" << fmt(wc.long_acc) << ",\"lat_acc\":" << fmt(wc.lat_acc)
      << ",\"proximity\":" << fmt(wc.proximity) << ",\"total\":" << fmt(wc.total) << "}";
    const auto& st = tr.start;
    o << ",\"start\":{\"s\":" << fmt(st.s) << ",\"s_d\":" << fmt(st.s_d) << ",\"s_dd\":" << fmt(st.s_dd) << ",\"d\":" << fmt(st.d)
      << ",\"d_d\":" << fmt(st.d_d) << ",\"d_dd\":" << fmt(st.d_dd) << "}";
    o << ",\"paths\":[";
    for (size_t c = 0; c < tr.paths.size(); ++c) {
        o << (c ? "," : "") << "{\"status\":\"" << tr.paths[c].status << "\",\"xy\":[";
        for (size_t k = 0; k < tr.paths[c].xy.size(); ++k) o << (k ? "," : "") << fmt(tr.paths[c].xy[k], 2);
        o << "]}";
    }
    o << "]}\n";
    return o.str();
}

namespace {

// A JSON string literal (names come from maps: ids, but any text is written validly).
std::string json_string(const std::string& s) {
    std::string out = "\"";
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += ch;
        } else if (c < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        } else {
            out += ch;
        }
    }
    return out + "\"";
}

}  // namespace

std::string road_json(const sim::World& w) {
    const auto& net = w.net;
    std::ostringstream o;
    auto pts = [&](const std::vector<road::Vec2>& v) {
        o << "[";
        double since = 1e9;
        bool first = true;
        for (size_t i = 0; i < v.size(); ++i) {
            if (i > 0) since += road::distance(v[i - 1], v[i]);
            if (since < 1.0 && i + 1 != v.size()) continue;
            since = 0;
            o << (first ? "" : ",") << "[" << fmt(v[i].x, 2) << "," << fmt(v[i].y, 2) << "]";
            first = false;
        }
        o << "]";
    };
    o << "{\"lanes\":[";
    for (size_t i = 0; i < net.lanes().size(); ++i) {
        const auto& l = net.lanes()[i];
        o << (i ? "," : "") << "{\"name\":\"" << l.name << "\",\"centre\":";
        pts(l.centre);
        o << ",\"left\":";
        pts(l.left_bound);
        o << ",\"right\":";
        pts(l.right_bound);
        // Its stop lines: [x, y, the light that controls it or -1].
        if (!l.stop_lines.empty()) {
            o << ",\"stop_lines\":[";
            for (size_t k = 0; k < l.stop_lines.size(); ++k) {
                const auto& line = l.stop_lines[k];
                const auto p = net.reference(l.id).point(line.s);
                o << (k ? "," : "") << "[" << fmt(p.x, 2) << "," << fmt(p.y, 2) << ","
                  << (line.traffic_lights.empty() ? -1 : line.traffic_lights.front()) << "]";
            }
            o << "]";
        }
        o << "}";
    }
    o << "],\"lights\":[";
    for (size_t i = 0; i < net.lights.size(); ++i) {
        const auto& tl = net.lights[i];
        o << (i ? "," : "") << "{\"name\":\"" << tl.name << "\",\"position\":[" << fmt(tl.position.x, 2) << "," << fmt(tl.position.y, 2)
          << "],\"lanes\":[";
        for (size_t k = 0; k < tl.lanes.size(); ++k) o << (k ? "," : "") << "\"" << net.lane(tl.lanes[k]).name << "\"";
        o << "],\"program\":[";
        const auto it = w.programs.find(tl.name);
        if (it != w.programs.end()) {
            for (size_t k = 0; k < it->second->phases.size(); ++k) {
                const auto& ph = it->second->phases[k];
                o << (k ? "," : "") << "{\"state\":\"" << ph.state << "\",\"duration\":" << fmt(ph.duration, 3) << "}";
            }
        }
        o << "],\"offset\":" << fmt(it != w.programs.end() ? it->second->offset : 0.0, 3) << "}";
    }
    o << "]";
    // Pedestrian areas, only when the road has them (runs without keep their road.json).
    if (!net.crosswalks.empty()) {
        o << ",\"crosswalks\":[";
        for (size_t i = 0; i < net.crosswalks.size(); ++i) {
            const auto& c = net.crosswalks[i];
            o << (i ? "," : "") << "{\"name\":" << json_string(c.name) << ",\"centre\":";
            pts(c.centre);
            o << ",\"left\":";
            pts(c.left_bound);
            o << ",\"right\":";
            pts(c.right_bound);
            o << ",\"width\":" << fmt(c.width, 2);
            if (c.light >= 0 && static_cast<size_t>(c.light) < net.lights.size()) {
                o << ",\"light\":" << json_string(net.lights[static_cast<size_t>(c.light)].name)
                  << ",\"light_inverse\":" << (c.light_inverse ? "true" : "false");
            }
            o << "}";
        }
        o << "]";
    }
    if (!net.walkways.empty()) {
        o << ",\"walkways\":[";
        for (size_t i = 0; i < net.walkways.size(); ++i) {
            const auto& wk = net.walkways[i];
            o << (i ? "," : "") << "{\"name\":" << json_string(wk.name) << ",\"left\":";
            pts(wk.left_bound);
            o << ",\"right\":";
            pts(wk.right_bound);
            o << "}";
        }
        o << "]";
    }
    o << "}\n";
    return o.str();
}

}  // namespace sdv::io
