// The GeoScenario `.btree` front end, part 2: lowering to .sdv trees. Each .btree file becomes
// one parameterless `tree` whose nodes use the catalog's conditions and maneuvers: the
// reference's MConfig classes, their fields (MP samplers, LT lateral targets, tuples, constants)
// and its conditions are mapped onto ours (docs/geoscenario.md has the table). Subtrees are
// found as NAME.btree along a search path and lowered first; overrides at a subtree reference
// (`subtree drive(m_keep=MVelKeepConfig(vel=MP(16,10,6)))`) become node overrides that replace
// the whole configuration, as the reference does. Everything that cannot be mapped gets a
// located diagnostic in the .btree file (E09xx); parameters the reference itself ignores get a
// warning (W0901).
//
// A tree is a vehicle's (btrees/sdv: MVelKeepConfig, lane_occupied, ...) or a pedestrian's
// (btrees/sp: MKeepInLaneConfig, has_target_crosswalk, ...): the two share names (MStopConfig,
// reached_goal) with different meanings, so each file is lowered for one agent, the one its own
// leaves name (else the one that uses it: an SP's tree, a subtree of a pedestrian's tree).
//
// The result is .sdv source text, which the ordinary front end then parses and checks, so a
// .btree and its conversion compile to the same IR by construction.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/source_manager.h"
#include "compiler/gss/btree.h"

namespace sdv::compiler::gss {

// Whose tree a .btree file is: unknown lets its leaves decide (a vehicle's when they do not).
enum class BtAgent { unknown, vehicle, pedestrian };

// A condition of the reference's trees that the converter maps (docs/geoscenario.md), with the
// parameters of it sdv reads.
struct ReferenceCondition {
    std::string name;
    std::vector<std::string> reads;
};
// Those a tree of `agent` (vehicle or pedestrian) may use, in the order of the mapping.
std::vector<ReferenceCondition> reference_conditions(BtAgent agent);

// An MConfig class of the reference that the converter maps to a maneuver, with the fields it
// knows (those it converts and those it ignores with W0901; every MConfig's own and the common ones).
struct ReferenceManeuver {
    std::string name;
    std::vector<std::string> fields;
};
// Those a tree of `agent` (vehicle or pedestrian) may use, in the order of the mapping.
std::vector<ReferenceManeuver> reference_maneuvers(BtAgent agent);

class BtreeLibrary {
public:
    // `search_path`: directories searched, in order, for NAME.btree and then, as the
    // reference's search locations are, for <btype>/NAME.btree (sdv/ for a vehicle's tree, sp/
    // for a pedestrian's; both, vehicle first, when the agent is not known).
    BtreeLibrary(std::vector<std::string> search_path, diag::SourceManager& sm, diag::DiagnosticEngine& diags);

    // Lowers the .btree file at `path` and every subtree it uses. Returns the .sdv name of its
    // tree, or nullopt after errors. `where` locates the reference in messages (may be invalid).
    // `agent`: who uses it (an SDV, an SP), for files whose leaves do not tell.
    std::optional<std::string> add_file(const std::string& path, diag::SourceRange where = {},
                                        BtAgent agent = BtAgent::unknown);
    // The same for a tree referred to by name (`st_standard_driver.btree` or `drive`), looked
    // up along the search path.
    std::optional<std::string> add_named(const std::string& name, diag::SourceRange where,
                                         BtAgent agent = BtAgent::unknown);

    // The call of the tree `name` (as for add_named) with a GeoScenario agent's `btconfig`
    // overrides ("NODE=MConfigClass(...);NODE2=..."), as .sdv text: "tree(node.field = ...)",
    // the overrides replacing each node's whole configuration as subtree overrides do. The
    // overrides are read as a source file named `who` (its diagnostics point there).
    std::optional<std::string> call_with_config(const std::string& name, const std::string& config, const std::string& who,
                                                diag::SourceRange where, BtAgent agent);
    // Whose tree the lowered tree `name` (as add_* returned it) is.
    BtAgent agent(const std::string& name) const;

    // Every tree lowered so far, callees before callers, as .sdv text.
    const std::string& text() const { return text_; }
    // The .btree files read, in order.
    const std::vector<std::string>& files() const { return files_; }

    // The .sdv tree name a .btree file stem gets.
    static std::string tree_name(const std::string& stem);

private:
    struct NodeInfo {
        std::string sdv_label;
        std::string mconfig;                 // class of a maneuver node
        std::set<std::string> fields;        // catalog parameters its configuration sets
        std::optional<BtValue> condition;    // a condition node's call, when overrides can reach it
    };
    struct Lowered;
    // A leaf or a subtree reference of a lowered tree, in the order of the .btree text (the
    // order of the reference's leaves once its subtrees are linked in).
    struct Item {
        std::string name;                  // a leaf: its .btree name
        size_t info = 0;                   //   its index in Lowered::nodes[name]
        std::string sub_label;             // a subtree reference: its .sdv label
        const Lowered* sub = nullptr;      //   the tree it refers to
        std::map<std::string, std::set<std::string>> sub_fields;  // label in `sub` → fields it overrides
    };
    struct Lowered {
        std::string name;
        BtAgent agent = BtAgent::vehicle;
        // Original node name → the .sdv nodes carrying it (names may repeat in a .btree).
        std::map<std::string, std::vector<NodeInfo>> nodes;
        std::vector<Item> order;
        bool selects = false;  // some leaf of it, or of a tree it uses, is a .sdv maneuver
        bool never_fails = false;  // its root never fails (NodeText)
    };
    // A lowered node: its .sdv text; how many .sdv nodes it is (0: a condition the maneuver that
    // follows implies, which is left out); whether it never fails as the checker sees the text
    // (a maneuver that never fails, a sequence of such nodes, a fallback with one): a fallback
    // never gets past it, in the reference either, and the checker refuses what follows (E0403).
    struct NodeText {
        std::string text;
        int nodes = 0;
        bool never_fails = false;
    };
    struct TreeState;
    // A node found by its .btree name: its .sdv override path (`sub.label.`) and the fields
    // the trees above it set, which a reconfiguration resets.
    struct Found {
        std::string path;
        const NodeInfo* info = nullptr;
        std::set<std::string> fields;
    };

    std::optional<std::string> find(const std::string& name, BtAgent agent) const;
    const Lowered* lower_file(const std::string& path, diag::SourceRange where, BtAgent agent);
    NodeText lower_node(const BtNode& n, int depth, TreeState& t);
    std::string lower_leaf(const BtNode& n, const std::string& ind, TreeState& t, bool& never_fails);
    // A subtree reference: `subtree NAME(overrides)`, labelled when it is a node of `t`.
    // `deep`: overrides reach the nodes of the tree's own subtrees too (a vehicle's btconfig).
    // `never_fails`, when given: whether the tree's root never fails (NodeText).
    std::string lower_subtree(const BtNode& n, BtAgent agent, TreeState* t, bool deep, bool* never_fails = nullptr);
    // A btconfig's `ID=condition,args=(k=v,...)` entries of one node, in order: overrides of
    // that condition node's arguments, each entry's merged into the node's as the one before
    // left them (BCondition.reconfigure).
    void condition_overrides(const std::vector<const BtNode*>& entries, const Lowered& root, std::vector<std::string>& out);
    static std::optional<Found> find_node(const Lowered& l, const std::string& name, bool deep);
    static void node_names(const Lowered& l, bool deep, std::vector<std::string>& out);

    std::vector<std::string> search_path_;
    diag::SourceManager& sm_;
    diag::DiagnosticEngine& diags_;
    std::map<std::string, Lowered> done_;   // by canonical path
    std::set<std::string> in_progress_;
    std::vector<std::string> files_;
    std::set<std::string> names_;
    std::string text_;
};

}  // namespace sdv::compiler::gss
