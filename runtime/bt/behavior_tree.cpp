// Tick semantics. Memory of a sequence survives only while the sequence is ticked on
// consecutive ticks: when a fallback above it switches to an earlier child, the sequence is not
// ticked, and the next time it is, it starts from its first child again (the effect of a halt
// in BehaviorTree.CPP, without a separate halt pass).
#include "runtime/bt/behavior_tree.h"

namespace sdv::bt {

const char* to_string(Status s) {
    switch (s) {
        case Status::success: return "SUCCESS";
        case Status::failure: return "FAILURE";
        case Status::running: return "RUNNING";
    }
    return "?";
}

BehaviorTree::BehaviorTree(const ir::TreeInstance* instance)
    : instance_(instance), memory_(instance->nodes.size()) {}

Status BehaviorTree::tick(TickContext& ctx, std::vector<Visit>* trace) {
    ++tick_;
    selected_now_ = false;
    if (instance_->nodes.empty()) return Status::failure;
    return tick_node(0, ctx, trace);
}

Status BehaviorTree::tick_node(int32_t i, TickContext& ctx, std::vector<Visit>* trace) {
    const ir::Node& n = instance_->nodes[static_cast<size_t>(i)];
    Memory& mem = memory_[static_cast<size_t>(i)];
    const bool continued = mem.last_tick + 1 == tick_;
    mem.last_tick = tick_;
    Status result = Status::failure;
    const auto count = static_cast<int32_t>(n.children.size());
    switch (n.kind) {
        case ir::NodeKind::fallback:
            for (int32_t c : n.children) {
                result = tick_node(c, ctx, trace);
                if (result != Status::failure) break;
            }
            break;
        case ir::NodeKind::sequence:
        case ir::NodeKind::reactive_sequence: {
            int32_t k = (n.kind == ir::NodeKind::sequence && continued) ? mem.running_child : 0;
            result = Status::success;
            for (; k < count; ++k) {
                result = tick_node(n.children[static_cast<size_t>(k)], ctx, trace);
                if (result != Status::success) break;
            }
            mem.running_child = result == Status::running ? k : 0;
            break;
        }
        case ir::NodeKind::parallel: {
            int32_t ok = 0, failed = 0;
            for (int32_t c : n.children) {
                const Status s = tick_node(c, ctx, trace);
                ok += s == Status::success;
                failed += s == Status::failure;
            }
            result = ok >= n.success_threshold           ? Status::success
                     : failed > count - n.success_threshold ? Status::failure
                                                            : Status::running;
            break;
        }
        case ir::NodeKind::condition:
            result = ctx.condition(n, i) ? Status::success : Status::failure;
            break;
        case ir::NodeKind::maneuver:
            result = ctx.maneuver(n, i);
            if (result != Status::failure) {
                selected_ = i;
                selected_now_ = true;
            }
            break;
        case ir::NodeKind::not_: {
            const Status s = count > 0 ? tick_node(n.children[0], ctx, trace) : Status::failure;
            result = s == Status::success   ? Status::failure
                     : s == Status::failure ? Status::success
                                            : Status::running;
            break;
        }
        case ir::NodeKind::once:
        case ir::NodeKind::latch: {
            // After its child's first SUCCESS the child is no longer ticked: once is FAILURE
            // from then on, latch SUCCESS.
            if (mem.once_fired) {
                result = n.kind == ir::NodeKind::latch ? Status::success : Status::failure;
                break;
            }
            result = count > 0 ? tick_node(n.children[0], ctx, trace) : Status::failure;
            if (result == Status::success) mem.once_fired = true;
            break;
        }
    }
    if (trace != nullptr) trace->push_back({i, result});
    return result;
}

}  // namespace sdv::bt
