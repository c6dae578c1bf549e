// Progress: how long each driven vehicle stood or crawled (below 0.5 m/s) while nothing asked it
// to wait. Waiting is the tree's choice of a stop maneuver, a queue (another vehicle standing
// or crawling just ahead in its lane), or a crash. A driver that stalls otherwise is a defect of
// the model, and runs report the longest such stall per vehicle (summary.json).
#pragma once

#include <vector>

#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"

namespace sdv::sim {

class ProgressMonitor {
public:
    explicit ProgressMonitor(size_t agents) : since_(agents, -1.0) {}
    // After each tick's ground truth; updates out.vehicles[i].longest_stall_s.
    void observe(const World& w, double t, RunResult& out);

private:
    std::vector<double> since_;  // start of the current stall (< 0: none)
};

}  // namespace sdv::sim
