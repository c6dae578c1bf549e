#include "compiler/sema/overlaps.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace sdv::compiler::sema {

namespace {

bool usable(const Footprint& f) {
    return f.group >= 0 && std::isfinite(f.s_lo) && std::isfinite(f.s_hi) && std::isfinite(f.lat_lo) &&
           std::isfinite(f.lat_hi) && f.s_lo < f.s_hi && f.lat_lo < f.lat_hi;
}

constexpr double kNone = -std::numeric_limits<double>::infinity();

// A max segment tree over leaves 0..m-1, bottom-up: each node holds the largest value below it
// and the leftmost leaf holding it (so that ties are decided by position, never by chance).
class MaxTree {
public:
    MaxTree(size_t leaves, OverlapWork* work) : work_(work) {
        while (base_ < leaves) base_ *= 2;
        nodes_.assign(2 * base_, Node{kNone, 0});
        for (size_t i = 0; i < base_; ++i) nodes_[base_ + i].leaf = i;
        for (size_t i = base_ - 1; i >= 1; --i) nodes_[i] = nodes_[2 * i];
    }

    void set(size_t leaf, double value) {
        size_t i = base_ + leaf;
        nodes_[i].value = value;
        for (i /= 2; i >= 1; i /= 2) {
            nodes_[i] = best(nodes_[2 * i], nodes_[2 * i + 1]);
            step();
        }
    }

    // The largest value among leaves [0, k) and its leaf (kNone when k is 0 or none is set).
    std::pair<double, size_t> prefix_max(size_t k) {
        Node left{kNone, 0}, right{kNone, 0};
        for (size_t l = base_, r = base_ + k; l < r; l /= 2, r /= 2) {
            if (l & 1) left = best(left, nodes_[l++]);
            if (r & 1) right = best(nodes_[--r], right);
            step();
        }
        const Node n = best(left, right);
        return {n.value, n.leaf};
    }

private:
    struct Node {
        double value;
        size_t leaf;
    };
    // The larger; of equal ones the one to the left (`a`).
    static Node best(const Node& a, const Node& b) { return b.value > a.value ? b : a; }
    void step() {
        if (work_ != nullptr) ++work_->tree_steps;
    }

    size_t base_ = 1;
    std::vector<Node> nodes_;
    OverlapWork* work_;
};

}  // namespace

bool footprints_overlap(const Footprint& a, const Footprint& b) {
    return usable(a) && usable(b) && a.group == b.group && a.s_lo < b.s_hi && b.s_lo < a.s_hi && a.lat_lo < b.lat_hi &&
           b.lat_lo < a.lat_hi;
}

// Per group, the footprints in the order of their backs along the lane (then of the list) each
// ask a segment tree whose leaves are the group's footprints sorted by lat_lo: among those
// already passed whose front (s_hi) is still ahead of this back (the others are taken out as the
// sweep passes their fronts) and whose lat_lo is below this lat_hi (a prefix of the leaves), the
// largest lat_hi. That footprint overlaps this one iff its lat_hi is above this lat_lo, and if
// any passed footprint overlaps this one, it does.
std::vector<Overlap> find_overlaps(const std::vector<Footprint>& footprints, OverlapWork* work) {
    const auto& f = footprints;
    std::vector<size_t> order;
    for (size_t i = 0; i < f.size(); ++i) {
        if (usable(f[i])) order.push_back(i);
    }
    auto behind = [&](size_t a, size_t b) {
        if (f[a].group != f[b].group) return f[a].group < f[b].group;
        if (f[a].s_lo != f[b].s_lo) return f[a].s_lo < f[b].s_lo;
        return a < b;
    };
    std::sort(order.begin(), order.end(), behind);

    std::vector<Overlap> found;
    std::vector<size_t> leaf_of(f.size());
    for (size_t g0 = 0; g0 < order.size();) {
        size_t g1 = g0;
        while (g1 < order.size() && f[order[g1]].group == f[order[g0]].group) ++g1;
        const std::vector<size_t> members(order.begin() + static_cast<std::ptrdiff_t>(g0),
                                          order.begin() + static_cast<std::ptrdiff_t>(g1));
        g0 = g1;

        std::vector<size_t> leaves = members;
        std::sort(leaves.begin(), leaves.end(), [&](size_t a, size_t b) {
            return f[a].lat_lo != f[b].lat_lo ? f[a].lat_lo < f[b].lat_lo : a < b;
        });
        std::vector<double> leaf_lo(leaves.size());
        for (size_t k = 0; k < leaves.size(); ++k) {
            leaf_of[leaves[k]] = k;
            leaf_lo[k] = f[leaves[k]].lat_lo;
        }
        std::vector<size_t> fronts = members;
        std::sort(fronts.begin(), fronts.end(), [&](size_t a, size_t b) {
            return f[a].s_hi != f[b].s_hi ? f[a].s_hi < f[b].s_hi : a < b;
        });

        MaxTree tree(members.size(), work);
        size_t passed = 0;  // fronts taken out of the tree
        for (const size_t b : members) {
            // A front at or behind this back: that footprint (passed already, its back being
            // behind its front) cannot overlap this one or any after it.
            for (; passed < fronts.size() && f[fronts[passed]].s_hi <= f[b].s_lo; ++passed) {
                tree.set(leaf_of[fronts[passed]], kNone);
            }
            const size_t below = static_cast<size_t>(
                std::lower_bound(leaf_lo.begin(), leaf_lo.end(), f[b].lat_hi) - leaf_lo.begin());
            const auto [lat_hi, leaf] = tree.prefix_max(below);
            if (lat_hi > f[b].lat_lo) found.push_back({b, leaves[leaf]});
            tree.set(leaf_of[b], f[b].lat_hi);
        }
    }
    std::sort(found.begin(), found.end(), [](const Overlap& a, const Overlap& b) { return a.ahead < b.ahead; });
    return found;
}

}  // namespace sdv::compiler::sema
