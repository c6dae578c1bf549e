// A vehicle's behavior tree at run time: the IR's expanded tree instance as a flat node array
// plus per-node memory, ticked with the semantics of SPEC §3.4:
//   fallback           children in order from the first, every tick (no memory);
//   sequence           resumes at its RUNNING child (memory), while ticked on consecutive ticks;
//   reactive_sequence  children in order from the first, every tick;
//   parallel           ticks every child; SUCCESS when `success_threshold` succeeded, FAILURE
//                      when that can no longer happen, RUNNING otherwise;
//   not                swaps SUCCESS and FAILURE; once: the first SUCCESS of its child, then FAILURE;
//   latch              its child until that succeeds, then SUCCESS for the rest of the run.
// Leaves are answered by a TickContext (the simulator): conditions are SUCCESS or FAILURE, a
// maneuver leaf selects its configuration and reports SUCCESS, RUNNING (lane change / cut-in
// until done) or FAILURE (cannot apply). The last selected maneuver is sticky.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/ir/ir.h"

namespace sdv::bt {

enum class Status : uint8_t { success, failure, running };
const char* to_string(Status s);

// What the tree asks of the world while ticking.
class TickContext {
public:
    virtual ~TickContext() = default;
    virtual bool condition(const ir::Node& node, int32_t index) = 0;
    // Called when a maneuver leaf is ticked; returns its status. The tree records the leaf as
    // the selection when the status is not FAILURE.
    virtual Status maneuver(const ir::Node& node, int32_t index) = 0;
};

// One visited node of a tick, for decision traces.
struct Visit {
    int32_t node;
    Status status;
};

class BehaviorTree {
public:
    explicit BehaviorTree(const ir::TreeInstance* instance);

    // Ticks from the root. Returns the root's status; selected() then names the maneuver leaf
    // in force (sticky across ticks that select none), or -1 before the first selection.
    Status tick(TickContext& ctx, std::vector<Visit>* trace = nullptr);

    int32_t selected() const { return selected_; }
    // Whether the last tick selected a maneuver itself (rather than keeping the previous one).
    bool selected_this_tick() const { return selected_now_; }
    const ir::TreeInstance& instance() const { return *instance_; }
    uint64_t ticks() const { return tick_; }

private:
    struct Memory {
        uint64_t last_tick = 0;  // tick number when last ticked (0: never)
        int32_t running_child = 0;
        bool once_fired = false;
    };

    Status tick_node(int32_t i, TickContext& ctx, std::vector<Visit>* trace);

    const ir::TreeInstance* instance_;
    std::vector<Memory> memory_;
    uint64_t tick_ = 0;
    int32_t selected_ = -1;
    bool selected_now_ = false;
};

}  // namespace sdv::bt
