// Ground truth at every tick (SPEC §3.10): collisions (oriented boxes, once per contact
// episode), per-pair clearances, same-lane gaps, TTC and headway, per-vehicle extremes, the
// stop-line latch, goals. It observes the world after every agent has advanced and before anyone
// plans, and folds each tick into the whole run and into every expectation window that holds it.
#pragma once

#include <vector>

#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"

namespace sdv::sim {

class GroundTruth {
public:
    // Writes events and metrics into `out` (pairs, vehicles and windows sized here and at the
    // first observation).
    GroundTruth(size_t agents, RunResult& out);
    void observe(World& w, double t, int tick);
    // A vehicle whose goal ends the run reached it.
    bool ended() const { return ended_; }

private:
    // Where an agent is along the lane its centre is in, at this tick.
    struct OnLane {
        LaneId lane = kNoLane;
        double s = 0;
        double speed = 0;  // along the lane's direction
    };
    void start(const World& w);
    void measure_pairs(World& w, double t);
    void measure_vehicles(World& w, double t, int tick);
    OnLane on_lane(const World& w, const Agent& a) const;

    RunResult& out_;
    std::vector<std::vector<bool>> touching_;
    std::vector<OnLane> lanes_;
    std::vector<WindowMetrics*> now_;  // the windows holding this tick
    bool started_ = false;
    bool ended_ = false;
};

}  // namespace sdv::sim
