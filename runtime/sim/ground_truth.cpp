#include "runtime/sim/ground_truth.h"

#include <algorithm>
#include <cmath>

#include "runtime/sim/collision.h"

namespace sdv::sim {

GroundTruth::GroundTruth(size_t n, RunResult& out) : out_(out), touching_(n, std::vector<bool>(n, false)) {
    out.vehicles.resize(n);
    for (size_t i = 0; i < n; ++i) {
        for (size_t j = i + 1; j < n; ++j) {
            PairMetrics m;
            m.a = static_cast<int>(i);
            m.b = static_cast<int>(j);
            out.pairs.push_back(m);
        }
    }
}

void GroundTruth::observe(World& w, double t, int tick) {
    auto& agents = w.agents;
    const size_t n = agents.size();
    std::vector<Box> boxes(n);
    for (size_t i = 0; i < n; ++i) boxes[i] = {{agents[i].x, agents[i].y}, agents[i].yaw, agents[i].v->length, agents[i].v->width};
    size_t pi = 0;
    for (size_t i = 0; i < n; ++i) {
        for (size_t j = i + 1; j < n; ++j, ++pi) {
            if (!agents[i].active || !agents[j].active) continue;
            PairMetrics& m = out_.pairs[pi];
            // The exact box distance only when it could matter: a lower bound from the
            // centres and the half diagonals first.
            const double centre = road::distance(boxes[i].centre, boxes[j].centre);
            const double reach = 0.5 * (std::hypot(boxes[i].length, boxes[i].width) + std::hypot(boxes[j].length, boxes[j].width));
            const bool near = centre - reach < m.min_gap || touching_[i][j] || centre <= reach;
            const double g = near ? gap(boxes[i], boxes[j]) : centre - reach;
            m.min_gap = std::min(m.min_gap, g);
            const bool hit = near && g <= 0;
            if (hit && !touching_[i][j]) {
                const double rel = std::hypot(agents[i].vx - agents[j].vx, agents[i].vy - agents[j].vy);
                out_.events.push_back({t, "collision", {static_cast<int>(i), static_cast<int>(j)}, rel, impact_zone(boxes[i], boxes[j])});
            }
            touching_[i][j] = hit;
            // Longitudinal relations when one is ahead of the other in the same lane.
            for (int dir = 0; dir < 2; ++dir) {
                const Agent& f = agents[dir ? j : i];
                const Agent& l = agents[dir ? i : j];
                const road::Vec2 h{std::cos(f.yaw), std::sin(f.yaw)};
                const road::Vec2 rel{l.x - f.x, l.y - f.y};
                const double lon = road::dot(rel, h), lat = std::fabs(road::cross(h, rel));
                if (lon <= 0 || lat > 0.5 * (f.v->width + l.v->width)) continue;
                const double bumper = lon - 0.5 * (f.v->length + l.v->length);
                if (f.speed > 0.1) m.min_headway = std::min(m.min_headway, std::max(0.0, bumper) / f.speed);
                const double closing = f.speed - (l.vx * h.x + l.vy * h.y);
                if (closing > 0.01) m.min_ttc = std::min(m.min_ttc, std::max(0.0, bumper) / closing);
            }
        }
    }
    for (size_t i = 0; i < n; ++i) {
        Agent& a = agents[i];
        if (!a.active) continue;
        VehicleMetrics& vm = out_.vehicles[i];
        // The centre off every lane: one event per episode.
        const bool off = a.centre_lane == kNoLane;
        if (off && !a.off_lanes) out_.events.push_back({t, "off_road", {static_cast<int>(i)}, 0, ""});
        a.off_lanes = off;
        vm.max_speed = std::max(vm.max_speed, std::fabs(a.speed));
        vm.max_acc = std::max(vm.max_acc, std::fabs(a.accel));
        if (tick > 0) vm.max_jerk = std::max(vm.max_jerk, std::fabs(a.accel - a.prev_accel) / w.dt);
        a.prev_accel = a.accel;
        // Stopping at a stop line (the front bumper within 5 m before it) is remembered.
        if (a.lane != kNoLane && std::fabs(a.speed) < 0.1) {
            const auto& l = w.net.lane(a.lane);
            const double g = l.stop_line_s ? *l.stop_line_s - (a.lane_s + 0.5 * a.v->length) : -1;
            if (g >= -0.5 && g <= 5.0 && (a.stopped_line != a.lane || g < a.stopped_gap)) {
                a.stopped_line = a.lane;
                a.stopped_gap = std::max(0.0, g);
            }
        }
        if (a.goal_lane != kNoLane && !a.goal_reached) {
            // Within 4 m along and 2 m across the goal the vehicle may keep closing in; the
            // goal is reached when the along-track distance stops decreasing (overshot when
            // it is then faster than 1 m/s), as in the reference implementation.
            const std::optional<double> dist = w.goal_distance(a);
            if (dist && (a.goal_dist >= 0 || (*dist <= 4.0 && std::fabs(a.lane_d) <= 2.0))) {
                if (a.goal_dist >= 0 && *dist >= a.goal_dist - 1e-9) {
                    a.goal_reached = true;
                    vm.reached_goal = true;
                    out_.events.push_back({t, std::fabs(a.speed) > 1.0 ? "goal_overshot" : "goal_reached", {static_cast<int>(i)}, 0, ""});
                    if (a.v->goal_ends_run) ended_ = true;
                } else {
                    a.goal_dist = *dist;
                }
            }
        }
    }
}

}  // namespace sdv::sim
