// Ground truth at every tick (SPEC §3.10): collisions (oriented boxes, once per contact
// episode), per-pair clearances, same-lane gaps, TTC and headway, per-vehicle extremes, the
// stop-line latch, goals. It observes the world after every agent has advanced and before anyone
// plans, and folds each tick into the whole run and into every expectation window that holds it.
// Pairs are measured while their centres are within the pair range (the sensor range, at least
// 100 m; found through the snapshot's grid) and always for the pairs an expectation names; a
// pair never measured has no entry (RunResult::pairs holds the measured ones, by (a, b)). A
// pair's clearance is computed only at the ticks that may hold its least: one it closes in at
// waits until a later tick rules it out or, at the latest, until finish().
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "runtime/sim/collision.h"
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
        double late = INFINITY, late_t = 0;  // the clearance of an earlier tick, computed at this one, and when
        int64_t pair = -1;  // its index in the pairs, when it was known at this tick
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
    // Per vehicle i: (j, pair index) of its pairs so far, by j (a row's lookups walk it in step
    // with its ascending neighbours).
    std::vector<std::vector<std::pair<int, uint32_t>>> index_;
    std::vector<int> touching_tick_;                // per pair: the last tick it was in contact
    // A tick at which a pair closed in, its clearance not computed yet: a later tick nearer by
    // its bounds proves it is not the pair's least and replaces it (measure_pairs).
    struct Deferred {
        Box a, b;
        double lower = 0, upper = 0;  // its clearance's bounds, with room for rounding
        double t = 0;
        bool pending = false;
    };
    std::vector<Deferred> deferred_;  // per pair
    // Folds the clearance of pair `pair` at an earlier time t into the run and the windows holding t.
    void fold_late(uint32_t pair, double clearance, double t);
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
