// Ground truth at every tick (SPEC §3.10): collisions (oriented boxes, once per contact
// episode), per-pair gaps, TTC and headway, per-agent extremes, the stop-line latch, goals.
// It observes the world after every agent has advanced and before anyone plans.
#pragma once

#include <vector>

#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"

namespace sdv::sim {

class GroundTruth {
public:
    // Writes events and metrics into `out` (pairs and vehicles sized here).
    GroundTruth(size_t agents, RunResult& out);
    void observe(World& w, double t, int tick);
    // A vehicle whose goal ends the run reached it.
    bool ended() const { return ended_; }

private:
    RunResult& out_;
    std::vector<std::vector<bool>> touching_;
    bool ended_ = false;
};

}  // namespace sdv::sim
