// Roads shared between runs (see road_cache.h).
#include "runtime/sim/road_cache.h"

namespace sdv::sim {

std::shared_ptr<const road::RoadNetwork> RoadCache::network(const std::string& key,
                                                            const std::function<std::string(road::RoadNetwork&)>& build,
                                                            std::string& error) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (auto it = networks_.find(key); it != networks_.end()) return it->second;
    }
    // Built outside the lock (a map can take seconds); a second builder of the same key keeps
    // the first one's network (they are equal).
    auto net = std::make_shared<road::RoadNetwork>();
    error = build(*net);
    if (!error.empty()) return nullptr;
    std::lock_guard<std::mutex> lock(mutex_);
    return networks_.try_emplace(key, std::move(net)).first->second;
}

std::shared_ptr<PathCache> RoadCache::paths(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto& p = paths_[key];
    if (!p) p = std::make_shared<PathCache>();
    return p;
}

}  // namespace sdv::sim
