// The leaves of one driver's tree, answered against its view of the snapshot: conditions (one
// function per catalog condition, conditions.cpp) and maneuver leaves (their status, SPEC §3.4).
// Conditions see the state at the plan's start (the own state predicted one latency ahead along
// the plan in force, others at constant velocity).
#pragma once

#include <cstdint>
#include <span>

#include "runtime/bt/behavior_tree.h"
#include "runtime/catalog/catalog.h"
#include "runtime/sim/perception.h"
#include "runtime/sim/world.h"

namespace sdv::sim {

// A parameter of a leaf as given in the scenario (null when left to its default).
const ir::ParamValue* leaf_param(const ir::Node& n, const char* name);
// A number parameter of a leaf of `tree` (NaN when not given). A condition threshold given as a
// range is one draw per agent, node and run: an acceptance gap varies between drivers (and
// pedestrians), not from tick to tick.
double leaf_number(const ir::Node& n, const char* name, const ir::TreeInstance& tree, uint64_t seed, int agent);

class Leaves : public bt::TickContext {
public:
    Leaves(const World& world, Agent& agent, double plan_time, double start_time)
        : w(world), a(agent), t0(plan_time), t_start(start_time) {}
    bool condition(const ir::Node& n, int32_t index) override;
    bt::Status maneuver(const ir::Node& n, int32_t index) override;
    void perceive() { view.build(w, a, t0, t_start); }

    // leaf_param and leaf_number of this driver's tree.
    const ir::ParamValue* param(const ir::Node& n, const char* name) const;
    double num(const ir::Node& n, const char* name) const;
    // A vehicle parameter resolved against the view (the nearest leader ahead when not given
    // and `default_leader`); null when it names nobody in sensor range.
    const Seen* vehicle(const ir::Node& n, const char* name, bool default_leader) const;
    // A lane change's (and a cut-in's) move to the neighbour lane: RUNNING until the footprint
    // is in it (sets `switched`), SUCCESS when already there, FAILURE when there is none.
    bt::Status lane_move(const ir::Node& n, catalog::ManeuverKind kind);

    const World& w;
    Agent& a;
    const double t0, t_start;
    View view;
    bool switched = false;  // a lane change completed during this cycle
};

// One function per catalog condition, indexed by catalog::ConditionKind.
using ConditionFn = bool (*)(Leaves& leaves, const ir::Node& node, int32_t index);
struct ConditionEntry {
    catalog::ConditionKind kind;
    ConditionFn fn;
};
std::span<const ConditionEntry> condition_table();
// stop_for_light (lights.cpp): keeps the driver's decision in Driver::light_stop.
bool stop_for_light(Leaves& leaves, const ir::Node& node, int32_t index);

}  // namespace sdv::sim
