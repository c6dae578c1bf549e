#include "runtime/sim/path.h"

#include <algorithm>

namespace sdv::sim {
namespace {

constexpr double kPathAhead = 300.0;  // m of lanes in a reference line ahead of the vehicle
constexpr double kPathBehind = 60.0;

}  // namespace

std::shared_ptr<const road::ReferenceLine> build_path(const road::RoadNetwork& net, const std::vector<road::RouteStep>& route,
                                                      Driver& d, LaneId from, double from_s, PathCache& cache) {
    d.path.clear();
    d.path_start.clear();
    std::vector<road::Vec2> pts;
    double len = 0;
    // One predecessor behind, so that vehicles behind project well.
    const auto& first = net.lane(from);
    if (!first.predecessors.empty()) {
        const auto& pre = net.lane(first.predecessors.front());
        const double skip = std::max(0.0, pre.length - kPathBehind);
        double acc = 0;
        for (size_t i = 0; i < pre.centre.size(); ++i) {
            if (i > 0) acc += road::distance(pre.centre[i - 1], pre.centre[i]);
            if (acc >= skip) pts.push_back(pre.centre[i]);
        }
    }
    const double behind = road::polyline_length(pts);
    LaneId cur = from;
    double s0 = behind;
    const double ahead = kPathAhead + behind + std::max(0.0, from_s);
    for (int guard = 0; guard < 64 && cur != kNoLane && len < ahead; ++guard) {
        const auto& l = net.lane(cur);
        d.path.push_back(cur);
        d.path_start.push_back(s0);
        s0 += l.length;
        len = s0;
        // Next lane: along the route when it continues by a successor, else the first successor.
        // (A route that passes a lane twice continues from its first pass.)
        LaneId next = kNoLane;
        for (size_t r = 0; r + 1 < route.size(); ++r) {
            if (route[r].lane == cur && !route[r + 1].by_lane_change) {
                next = route[r + 1].lane;
                break;
            }
        }
        if (next == kNoLane && !l.successors.empty()) {
            // Prefer going straight (lowest turn change) deterministically: the first successor.
            next = l.successors.front();
            for (LaneId sc : l.successors) {
                if (net.lane(sc).turn == road::Turn::straight) next = sc;
            }
        }
        if (std::find(d.path.begin(), d.path.end(), next) != d.path.end()) break;  // loops
        cur = next;
    }
    // The line is a function of its lanes (the predecessor, then the path): shared by key.
    std::vector<LaneId> key;
    key.reserve(d.path.size() + 1);
    key.push_back(first.predecessors.empty() ? kNoLane : first.predecessors.front());
    key.insert(key.end(), d.path.begin(), d.path.end());
    {
        std::lock_guard<std::mutex> lock(cache.mutex);
        if (auto it = cache.lines.find(key); it != cache.lines.end()) {
            d.path_start = it->second.starts;
            return it->second.line;
        }
    }
    // Not built yet: its points (lanes can be kilometres of points; a cached line needs none).
    for (const LaneId id : d.path) {
        for (const auto& q : net.lane(id).centre) {
            if (pts.empty() || road::distance(pts.back(), q) > 1e-3) pts.push_back(q);
        }
    }
    auto ref = road::ReferenceLine::build(pts);
    if (!ref) return nullptr;
    // Lane starts measured on the fitted line.
    for (size_t i = 0; i < d.path.size(); ++i) {
        d.path_start[i] = ref->project(net.lane(d.path[i]).centre.front(), d.path_start[i]).s;
    }
    auto line = std::make_shared<const road::ReferenceLine>(std::move(*ref));
    std::lock_guard<std::mutex> lock(cache.mutex);
    // Another thread may have built the same line meanwhile: keep the first (they are equal).
    const auto [it, fresh] = cache.lines.try_emplace(key, PathCache::Entry{line, d.path_start});
    d.path_start = it->second.starts;
    return it->second.line;
}

}  // namespace sdv::sim
