// Ground truth at every tick (SPEC §3.10): collisions (oriented boxes, once per contact
// episode), per-pair clearances, same-lane gaps, TTC and headway, per-vehicle extremes, the
// stop-line latch, goals. It observes the world after every agent has advanced and before anyone
// plans, and folds each tick into the whole run and into every expectation window that holds it.
// Pairs are measured while their centres are within the pair range (the sensor range, at least
// 100 m; found through the snapshot's grid) and always for the pairs an expectation names; a
// pair never measured has no entry (RunResult::pairs holds the measured ones, by (a, b)).
#pragma once

#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "runtime/sim/grid.h"
#include "runtime/sim/pool.h"
#include "runtime/sim/simulation.h"
#include "runtime/sim/world.h"

namespace sdv::sim {

class GroundTruth {
public:
    // What one tick measured of a pair (INFINITY: not measured at this tick), and of which.
    struct Sample {
        double clearance = INFINITY, gap = INFINITY, lateral = INFINITY, ttc = INFINITY, headway = INFINITY;
    };
    struct Measured {
        int j = 0;
        Sample s;
        bool hit = false;
    };

    // Writes events and metrics into `out` (pairs, vehicles and windows sized here and at the
    // first observation).
    GroundTruth(size_t agents, RunResult& out);
    // `pool` measures the pairs of each vehicle in parallel (folded in vehicle order after).
    void observe(World& w, double t, int tick, Pool* pool = nullptr);
    // Puts the pairs in (a, b) order (in the run and in every window); call once, at the end.
    void finish();
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
    void measure_pairs(World& w, double t, int tick, Pool* pool);
    // The pair's index in out_.pairs (and every window's pairs), created on first use (i < j).
    uint32_t pair_index(int i, int j);
    void measure_vehicles(World& w, double t, int tick);
    OnLane on_lane(const World& w, const Agent& a) const;

    RunResult& out_;
    size_t n_ = 0;
    std::unordered_map<uint64_t, uint32_t> index_;  // i·n + j → pair index
    std::vector<int> touching_tick_;                // per pair: the last tick it was in contact
    std::vector<std::vector<int>> named_;           // per vehicle i: the j > i an expectation names
    std::vector<std::vector<Measured>> rows_;       // per vehicle i: this tick's pairs (i, j > i)
    std::vector<double> half_diagonal_;            // per vehicle: half its footprint's diagonal
    std::vector<OnLane> lanes_;
    // This tick's active agents other than pedestrians by position (for pedestrians' rows), and
    // what it is built from.
    Grid vehicles_;
    std::vector<double> vehicle_x_, vehicle_y_;
    std::vector<char> is_vehicle_;
    std::vector<WindowMetrics*> now_;  // the windows holding this tick
    bool started_ = false;
    bool ended_ = false;
};

}  // namespace sdv::sim
