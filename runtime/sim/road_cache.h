// What the runs of one process that simulate the same road can share (the variants of a sweep,
// the runs of a search): the road network, built and prepared once, and the reference lines of
// the paths drivers take along it. Without a cache every run builds its own; the results are
// the same bytes either way, since a network is a pure function of its IR road and a path's
// line of its lanes. Thread-safe.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "runtime/road/reference_line.h"
#include "runtime/road/road_network.h"

namespace sdv::sim {

// Reference lines by the lanes they run along (with the lane starts on them): drivers on the
// same lanes share one line (memory per vehicle does not grow with lane length). Filled by
// the planning threads under its mutex; a line depends only on its lanes, so who builds it
// first changes nothing.
struct PathCache {
    struct Entry {
        std::shared_ptr<const road::ReferenceLine> line;
        std::vector<double> starts;
    };
    std::mutex mutex;
    std::map<std::vector<road::LaneId>, Entry> lines;
};

class RoadCache {
public:
    // The prepared network for `key` (a text naming the IR road completely), made by `build`
    // the first time; `build` returns an error message or "" (errors are not cached).
    std::shared_ptr<const road::RoadNetwork> network(const std::string& key,
                                                     const std::function<std::string(road::RoadNetwork&)>& build,
                                                     std::string& error);
    // The path lines along the network of `key`.
    std::shared_ptr<PathCache> paths(const std::string& key);

private:
    std::mutex mutex_;
    std::map<std::string, std::shared_ptr<const road::RoadNetwork>> networks_;
    std::map<std::string, std::shared_ptr<PathCache>> paths_;
};

}  // namespace sdv::sim
