// What one driver perceives at a planning cycle: its own state at the plan's start (along the
// plan in force) and every other agent within sensor range of the snapshot, projected into its
// reference line and predicted at constant Frenet velocity up to the plan's start (SPEC §3.3).
// Zones split the surroundings by lane band (own, left, right: |d| within half a lane width of
// the band's centre) and by position along s (ahead, beside: overlapping along s, behind).
#pragma once

#include <cmath>
#include <vector>

#include "runtime/sim/world.h"

namespace sdv::sim {

// Another agent as one driver sees it.
struct Seen {
    int index = -1;
    road::FrenetState f;
    double length = 4.5, width = 1.8;
    double speed = 0;
    double dist = 0;
    // Where a driver's lateral motion stops in this frame: another SDV driving along it moves
    // to where its plan in force ends (±∞: not known).
    double d_min = -INFINITY, d_max = INFINITY;
};

class View {
public:
    // (Re)builds the view of agent `a` (after a reference-line switch too).
    void build(const World& w, const Agent& a, double t0, double t_start);

    // band −1 right, 0 own, 1 left (9: none of them) of a lateral offset.
    int band_of(double d) const;
    // The nearest agent in a band (−1, 0, 1) and position (1 ahead, 0 beside, −1 behind);
    // static objects unless `objects` is false.
    const Seen* nearest(int band, int where, bool objects = true) const;
    // A perceived agent by index, or null when out of sensor range.
    const Seen* find(int index) const;

    road::FrenetState self;
    std::vector<Seen> seen;
    double lane_width = 3.5;

private:
    const World* w_ = nullptr;
    double own_length_ = 4.5;
};

}  // namespace sdv::sim
