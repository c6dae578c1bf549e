#include "runtime/realism/route.h"

#include <algorithm>
#include <cmath>

#include "runtime/road/routing.h"

namespace sdv::realism {

RecordedRoute recorded_route(const road::RoadNetwork& net, const Track& track, double beyond) {
    RecordedRoute out;
    std::vector<road::RoadNetwork::Location> at;
    for (const State& s : track.states) at.push_back(net.locate({s.x, s.y}, s.heading));
    if (at.empty() || at.front().lane == road::kNoLane) {
        out.error = "its first recorded position is on no lane";
        return out;
    }
    // Runs of states in one lane.
    std::vector<std::pair<road::LaneId, size_t>> runs;
    for (const auto& l : at) {
        if (l.lane == road::kNoLane) continue;
        if (runs.empty() || runs.back().first != l.lane) runs.push_back({l.lane, 0});
        ++runs.back().second;
    }
    // Each lane once, in the order first entered: a path that wanders back into a lane (a
    // located position flickering between overlapping lanes) continues from there. Lanes held
    // for fewer than three states in the middle are skipped unless the next lane cannot be
    // reached without them; a lane the route cannot reach at all (a turn across lanes of the
    // other direction) is left out.
    for (size_t i = 0; i < runs.size(); ++i) {
        const road::LaneId l = runs[i].first;
        if (auto it = std::find(out.lanes.begin(), out.lanes.end(), l); it != out.lanes.end()) {
            out.lanes.erase(it + 1, out.lanes.end());
            continue;
        }
        const bool edge = i == 0 || i + 1 == runs.size();
        if (!out.lanes.empty() && road::shortest_route(net, out.lanes.back(), l).steps.empty()) continue;
        if (!edge && runs[i].second < 3 && i + 1 < runs.size() && !out.lanes.empty() &&
            !road::shortest_route(net, out.lanes.back(), runs[i + 1].first).steps.empty())
            continue;
        out.lanes.push_back(l);
    }
    // The goal: `beyond` past the last state, straight on where lanes diverge.
    road::LaneId lane = out.lanes.back();
    double s = at.back().lane == lane ? at.back().s : net.reference(lane).project({track.states.back().x, track.states.back().y}).s;
    s = std::clamp(s, 0.0, net.lane(lane).length);
    double left = beyond;
    for (int hops = 0; hops < 100; ++hops) {
        const road::Lane& l = net.lane(lane);
        if (s + left <= l.length) {
            s += left;
            left = 0;
            break;
        }
        left -= std::max(0.0, l.length - s);
        s = l.length;
        if (l.successors.empty()) break;
        road::LaneId next = l.successors.front();
        for (road::LaneId c : l.successors)
            if (net.lane(c).turn == road::Turn::straight) next = c;
        lane = next;
        s = 0;
        if (std::find(out.lanes.begin(), out.lanes.end(), lane) == out.lanes.end()) out.lanes.push_back(lane);
    }
    out.has_goal = left <= 0;
    out.goal_lane = lane;
    // A little short of a lane's end, so that the goal lies on it.
    out.goal_s = std::clamp(s, 0.0, std::max(0.0, net.lane(lane).length - 0.5));
    return out;
}

}  // namespace sdv::realism
