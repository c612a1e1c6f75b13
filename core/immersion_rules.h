// Rules 1–7 of paper §5.2 (Theorem 4) over the state of the immersion search.
//
// The search (graph_search_impl.h) works on a *partial* immersion graph: for every node n (a copy
// of a cell, NodeLayout) and every B-patch q of its cell there is one *slot* whose value is
//   Undecided            n has not yet chosen between owning and declining q;
//   Owned                n owns q (q is on the boundary of the immersed manifold at n);
//   Declined             n declines q but has no edge across q yet ("incomplete", paper §6);
//   Connected(m)         n declines q and is glued to node m across q (edge n–m).
// Every rule appears twice in this header:
//  - as a *propagator* that, given a partial state, derives the decisions the rule forces (or
//    reports a conflict), used to reach a fixpoint after each search decision;
//  - as a *predicate* `check_rule_k` over a complete state, run on every candidate immersion before
//    it is accepted, so that an incomplete propagator can never let a wrong graph through. The
//    predicates are written from the rules' statements in §5.2 and share no code with the
//    propagators (the arc rules read the complex's geometric-neighbour pairs, not ArcView).
//
// Local model of an arc (core/cell_complex.h): junction patches P0..P3 in cyclic order, wedge k
// between junctions k and k+1, C_k the cell of wedge k (none when its winding number is 0).
// A node x of C_k sees the arc through wedge k: its "left" junction is k and its "right" junction
// is k+1. Junctions k and k+2 lie on the same sheet. Every statement below is per wedge and per
// junction, never per patch, so arcs where one patch occurs at two junctions, or one cell at two
// wedges (self-touching cells, §4.2.1), need no special case: a node of a self-touching cell is
// simply looked at once through each of its wedges.
//
// The code here is dimension-free: a RuleContext is built from a CellComplex<D> for any D and
// the rules read only the context. It is included by graph_search_impl.h only.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/cell_complex.h"
#include "core/graph_search.h"
#include "core/immersion_graph.h"
#include "core/union_find.h"

namespace imm::detail {

// ---- slot values --------------------------------------------------------------------------

/// A slot value >= 0 is the partner node id (Connected); these are the other values.
inline constexpr std::int32_t kUndecided = -1;
inline constexpr std::int32_t kOwned = -2;
inline constexpr std::int32_t kDeclined = -3;  ///< declined, no edge yet ("incomplete")

/// @return true when the slot value means "n declines q" (with or without an edge).
inline bool is_declined(std::int32_t v) { return v == kDeclined || v >= 0; }

/// Why a slot got its value: the rule that forced it (0 = a search decision) and, for arc rules,
/// the arc. Kept per slot only to explain conflicts in words.
struct Reason {
  std::int8_t rule = 0;
  std::int32_t arc = -1;
};

// ---- static tables ---------------------------------------------------------------------------

/// The view of one arc the rules need: junction patches and the cell of each wedge.
struct ArcView {
  std::array<PatchId, 4> patch;
  std::array<CellId, 4> cell;  ///< invalid when the wedge has winding number 0
};

/// Everything the rules read from the cell complex, flattened once per search. Dimension-free.
class RuleContext {
 public:
  /// @pre complex is finalized, every winding number >= 0, and every arc has the winding pattern
  ///      of two crossing sheets (w, w+1, w+2, w+1 up to rotation).
  template <int D>
  explicit RuleContext(const CellComplex<D>& complex);

  NodeLayout layout;
  IdMap<CellId, int> winding;
  IdMap<CellId, std::vector<PatchId>> b_patches;  ///< sorted by patch id (complex.b_patches)
  IdMap<PatchId, CellId> inner;                   ///< negative side (always a cell)
  IdMap<PatchId, CellId> outer;                   ///< positive side, invalid for winding 0
  IdMap<PatchId, int> inner_local;                ///< index of the patch in b_patches[inner]
  IdMap<PatchId, int> outer_local;                ///< index in b_patches[outer], or -1
  IdMap<PatchId, std::vector<ArcId>> patch_arcs;
  IdMap<ArcId, ArcView> arcs;
  /// Per arc, the geometric-neighbour pairs the complex states for it
  /// (CellComplex::geometric_neighbors: one per wedge that lies in a cell, with the wedge index).
  /// Read only by the predicates of Rules 4–6, which are written in the paper's terms; the
  /// propagators read `arcs`.
  IdMap<ArcId, std::vector<GeometricNeighbors>> arc_geometric_neighbors;
  IdMap<NodeId, int> slot_base;                   ///< first slot of each node
  std::vector<NodeId> slot_node;                  ///< node of each slot
  std::vector<PatchId> slot_patch;                ///< patch of each slot

  // Independent subproblems ("groups"): cells linked by a patch or by a common arc. No rule
  // relates two groups, so the search solves them one by one and combines the solutions.
  IdMap<CellId, int> cell_group;
  IdMap<PatchId, int> patch_group;
  IdMap<ArcId, int> arc_group;
  std::vector<std::vector<CellId>> group_cells;    ///< per group, sorted
  std::vector<std::vector<PatchId>> group_patches; ///< per group, sorted
  std::vector<std::vector<ArcId>> group_arcs;      ///< per group, sorted
  [[nodiscard]] std::size_t group_count() const { return group_cells.size(); }

  [[nodiscard]] std::size_t cell_count() const { return winding.size(); }
  [[nodiscard]] std::size_t patch_count() const { return inner.size(); }
  [[nodiscard]] std::size_t arc_count() const { return arcs.size(); }
  [[nodiscard]] std::size_t node_count() const { return layout.node_count(); }
  [[nodiscard]] std::size_t slot_count() const { return slot_node.size(); }

  /// @pre the cell of n is one of the two sides of p.  @return the slot of (n, p).
  [[nodiscard]] int slot(NodeId n, PatchId p) const {
    const CellId c = layout.cell(n);
    const int local = c == inner[p] ? inner_local[p] : outer_local[p];
    return slot_base[n] + local;
  }
  /// The slots of the copies of cell c at one of its B-patches p: the slots of a node are
  /// consecutive and the nodes of a cell too, so copy n's slot is start + (n - first) * stride.
  /// Loops over the copies of a cell read one slot per copy this way, instead of looking up
  /// per copy its cell, the side of the patch it is on and its first slot (slot()): these loops
  /// are most of the search's time on piles of overlapping parts (issue 19).
  struct CopySlots {
    int start = 0, stride = 0, first = 0;
    [[nodiscard]] int at(NodeId n) const { return start + (n.value() - first) * stride; }
  };
  /// @pre c is one of the two sides of p.
  [[nodiscard]] CopySlots copy_slots(CellId c, PatchId p) const {
    const PatchSlots& ps = patch_slots[p];
    const CellCopies& cc = cell_copies[c];
    return CopySlots{c == ps.inner ? ps.inner_start : ps.outer_start, cc.width, cc.first};
  }
  /// Per patch, its sides and the slot of the first copy of each at the patch (copy_slots).
  struct PatchSlots {
    CellId inner, outer;
    int inner_start = 0, outer_start = 0;
  };
  IdMap<PatchId, PatchSlots> patch_slots;
  /// Per cell, its first node and the number of its B-patches (its nodes' slots each).
  struct CellCopies {
    int first = 0, width = 0;
  };
  IdMap<CellId, CellCopies> cell_copies;
  /// The nodes of a cell are first(c) .. first(c) + w(c) - 1.
  [[nodiscard]] NodeId first_node(CellId c) const { return layout.first(c); }
  [[nodiscard]] int node_end(CellId c) const { return layout.first(c).value() + winding[c]; }

  /// "node 4 (cell 2, copy 1)".
  [[nodiscard]] std::string describe(NodeId n) const {
    std::ostringstream os;
    os << "node " << n << " (cell " << layout.cell(n) << ", copy " << layout.copy(n) << ")";
    return os.str();
  }
};

template <int D>
RuleContext::RuleContext(const CellComplex<D>& complex) : layout(complex) {
  const std::size_t cells = complex.cell_count();
  winding = IdMap<CellId, int>(cells);
  b_patches = IdMap<CellId, std::vector<PatchId>>(cells);
  for (CellId c : ids<CellId>(cells)) {
    winding[c] = complex.winding_number(c);
    IMM_ASSERT(winding[c] > 0, "cells must have positive winding numbers (inversions are rejected "
                               "before the search)");
    for (const BPatch& b : complex.b_patches(c)) b_patches[c].push_back(b.patch);
    IMM_ASSERT(std::is_sorted(b_patches[c].begin(), b_patches[c].end()), "B-patches not sorted");
  }
  const std::size_t patches = complex.patch_count();
  inner = IdMap<PatchId, CellId>(patches);
  outer = IdMap<PatchId, CellId>(patches);
  inner_local = IdMap<PatchId, int>(patches, -1);
  outer_local = IdMap<PatchId, int>(patches, -1);
  patch_arcs = IdMap<PatchId, std::vector<ArcId>>(patches);
  for (PatchId p : ids<PatchId>(patches)) {
    inner[p] = complex.inner_cell(p);
    outer[p] = complex.outer_cell(p);
    const auto local_index = [&](CellId c) {
      const auto& list = b_patches[c];
      const auto it = std::lower_bound(list.begin(), list.end(), p);
      IMM_ASSERT(it != list.end() && *it == p, "patch missing from the B-patches of its cell");
      return static_cast<int>(it - list.begin());
    };
    inner_local[p] = local_index(inner[p]);
    if (outer[p].is_valid()) outer_local[p] = local_index(outer[p]);
    for (ArcId a : complex.arcs_of(p)) patch_arcs[p].push_back(a);
  }
  arcs = IdMap<ArcId, ArcView>(complex.arc_count());
  for (ArcId a : ids<ArcId>(complex.arc_count())) {
    const ArcJunctions& j = complex.arc(a);
    std::array<int, 4> w{};
    for (int k = 0; k < 4; ++k) {
      arcs[a].patch[k] = j.patch[k];
      arcs[a].cell[k] = complex.cell_of(j.wedge[k]);
      w[k] = complex.winding_number(j.wedge[k]);
    }
    // Two oriented sheets crossing: the step across junction k+2 undoes the step across k.
    for (int k = 0; k < 2; ++k) {
      const int step_k = w[k] - w[(k + 3) % 4];
      const int step_k2 = w[(k + 2) % 4] - w[(k + 1) % 4];
      std::ostringstream msg;
      msg << "arc " << a << ": wedge winding numbers " << w[0] << ',' << w[1] << ',' << w[2] << ','
          << w[3] << " are not those of two crossing sheets";
      IMM_ASSERT(step_k == -step_k2, msg.str());
    }
  }
  arc_geometric_neighbors = IdMap<ArcId, std::vector<GeometricNeighbors>>(complex.arc_count());
  for (const GeometricNeighbors& g : complex.geometric_neighbors()) {
    arc_geometric_neighbors[g.arc].push_back(g);
  }
  // Groups: cells linked by a patch or by a common arc fall into one set.
  UnionFind linked(cells);
  const auto unite = [&](CellId a, CellId b) {
    if (a.is_valid() && b.is_valid()) linked.unite(a.value(), b.value());
  };
  for (PatchId p : ids<PatchId>(patches)) unite(inner[p], outer[p]);
  for (ArcId a : ids<ArcId>(arcs.size())) {
    CellId first;
    for (int k = 0; k < 4; ++k) {
      if (!arcs[a].cell[k].is_valid()) continue;
      if (first.is_valid()) unite(first, arcs[a].cell[k]);
      else first = arcs[a].cell[k];
    }
  }
  cell_group = IdMap<CellId, int>(cells, -1);
  std::vector<int> root_group(cells, -1);
  for (CellId c : ids<CellId>(cells)) {
    const std::uint32_t root = linked.find(c.value());
    if (root_group[root] < 0) {
      root_group[root] = static_cast<int>(group_cells.size());
      group_cells.emplace_back();
      group_patches.emplace_back();
      group_arcs.emplace_back();
    }
    cell_group[c] = root_group[root];
    group_cells[cell_group[c]].push_back(c);
  }
  patch_group = IdMap<PatchId, int>(patches, -1);
  for (PatchId p : ids<PatchId>(patches)) {
    patch_group[p] = cell_group[inner[p]];
    group_patches[patch_group[p]].push_back(p);
  }
  arc_group = IdMap<ArcId, int>(arcs.size(), -1);
  for (ArcId a : ids<ArcId>(arcs.size())) {
    // Every arc has a wedge of positive winding number (the one of winding w + 2).
    for (int k = 0; k < 4 && arc_group[a] < 0; ++k) {
      if (arcs[a].cell[k].is_valid()) arc_group[a] = cell_group[arcs[a].cell[k]];
    }
    group_arcs[arc_group[a]].push_back(a);
  }

  slot_base = IdMap<NodeId, int>(layout.node_count());
  for (NodeId n : ids<NodeId>(layout.node_count())) {
    const CellId c = layout.cell(n);
    slot_base[n] = static_cast<int>(slot_node.size());
    for (PatchId p : b_patches[c]) {
      slot_node.push_back(n);
      slot_patch.push_back(p);
    }
  }
  cell_copies = IdMap<CellId, CellCopies>(cells);
  for (CellId c : ids<CellId>(cells)) {
    cell_copies[c] = CellCopies{layout.first(c).value(), static_cast<int>(b_patches[c].size())};
  }
  patch_slots = IdMap<PatchId, PatchSlots>(patches);
  for (PatchId p : ids<PatchId>(patches)) {
    PatchSlots& ps = patch_slots[p];
    ps.inner = inner[p];
    ps.outer = outer[p];
    ps.inner_start = slot_base[layout.first(inner[p])] + inner_local[p];
    if (outer[p].is_valid()) ps.outer_start = slot_base[layout.first(outer[p])] + outer_local[p];
  }
}

// ---- search state -----------------------------------------------------------------------------

/// One partial immersion graph. Copied only at branch points of the search.
struct SearchState {
  std::vector<std::int32_t> slot;  ///< per slot: kUndecided, kOwned, kDeclined or partner node
  std::vector<Reason> reason;      ///< per slot: why it was decided
  IdMap<PatchId, NodeId> owner;    ///< the owner of each patch, invalid while unknown
};

/// Patches and arcs whose rules must be re-run because a slot of theirs changed.
class Worklist {
 public:
  explicit Worklist(const RuleContext& ctx)
      : ctx_(&ctx), patch_queued_(ctx.patch_count(), 0), touch_pending_(ctx.patch_count(), 0),
        arc_queued_(ctx.arc_count(), 0),
        cell_dirty_(ctx.cell_count(), 0) {}

  void push_patch(PatchId p) {
    if (!patch_queued_[p.index()]) {
      patch_queued_[p.index()] = 1;
      patches_.push_back(p);
    }
  }
  void push_arc(ArcId a) {
    if (!arc_queued_[a.index()]) {
      arc_queued_[a.index()] = 1;
      arcs_.push_back(a);
    }
  }
  /// A slot of p changed: p and every arc with a junction on p must be revisited, and the two
  /// sides of p are recorded as dirty cells (dirty_cells()).
  void touch(PatchId p) {
    // While p waits in the queue after a touch, nothing that touch queued has been taken out:
    // arcs are taken only when no patch waits, sheet steps only when no arc waits either, and
    // the dirty cells are cleared only between propagations. So another touch would change
    // nothing (patches are touched once per slot change: millions of times on large piles).
    if (touch_pending_[p.index()]) return;
    touch_pending_[p.index()] = 1;
    push_patch(p);
    for (ArcId a : ctx_->patch_arcs[p]) push_arc(a);
    if (continue_sheets_) push_sheet(p);
    mark_dirty(ctx_->inner[p]);
    if (ctx_->outer[p].is_valid()) mark_dirty(ctx_->outer[p]);
  }
  /// The cells with a slot changed since the last clear_dirty(), in any state edited through this
  /// worklist (the search's current state and its trial copies alike: an over-approximation of the
  /// cells whose slots differ). clear() keeps them: the search reads them to refresh its choice of
  /// the next variable only where something changed.
  [[nodiscard]] const std::vector<CellId>& dirty_cells() const { return dirty_; }
  void clear_dirty() {
    for (CellId c : dirty_) cell_dirty_[c.index()] = 0;
    dirty_.clear();
  }
  /// Also queue touched patches for propagate_sheet_continuation (a search option, not a rule).
  void set_continue_sheets(bool on) { continue_sheets_ = on; }
  [[nodiscard]] bool has_sheet() const { return !sheet_.empty(); }
  PatchId pop_sheet() {
    const PatchId p = sheet_.back();
    sheet_.pop_back();
    sheet_queued_[p.index()] = 0;
    return p;
  }
  void push_everything() {
    for (PatchId p : ids<PatchId>(ctx_->patch_count())) push_patch(p);
    for (ArcId a : ids<ArcId>(ctx_->arc_count())) push_arc(a);
  }
  [[nodiscard]] bool has_patch() const { return patch_head_ < patches_.size(); }
  [[nodiscard]] bool has_arc() const { return arc_head_ < arcs_.size(); }
  PatchId pop_patch() {
    const PatchId p = patches_[patch_head_++];
    patch_queued_[p.index()] = 0;
    touch_pending_[p.index()] = 0;
    if (patch_head_ == patches_.size()) patches_.clear(), patch_head_ = 0;
    return p;
  }
  ArcId pop_arc() {
    const ArcId a = arcs_[arc_head_++];
    arc_queued_[a.index()] = 0;
    if (arc_head_ == arcs_.size()) arcs_.clear(), arc_head_ = 0;
    return a;
  }
  void clear() {
    for (PatchId p : sheet_) sheet_queued_[p.index()] = 0;
    sheet_.clear();
    for (std::size_t i = patch_head_; i < patches_.size(); ++i) {
      patch_queued_[patches_[i].index()] = 0;
      touch_pending_[patches_[i].index()] = 0;
    }
    for (std::size_t i = arc_head_; i < arcs_.size(); ++i) arc_queued_[arcs_[i].index()] = 0;
    patches_.clear();
    arcs_.clear();
    patch_head_ = arc_head_ = 0;
  }

 private:
  void mark_dirty(CellId c) {
    if (!cell_dirty_[c.index()]) {
      cell_dirty_[c.index()] = 1;
      dirty_.push_back(c);
    }
  }
  void push_sheet(PatchId p) {
    if (sheet_queued_.empty()) sheet_queued_.assign(ctx_->patch_count(), 0);
    if (!sheet_queued_[p.index()]) {
      sheet_queued_[p.index()] = 1;
      sheet_.push_back(p);
    }
  }

  const RuleContext* ctx_;
  std::vector<PatchId> patches_;
  std::vector<ArcId> arcs_;
  std::size_t patch_head_ = 0, arc_head_ = 0;
  std::vector<char> patch_queued_, touch_pending_, arc_queued_;
  bool continue_sheets_ = false;
  std::vector<PatchId> sheet_;  ///< a stack: the newest sheet is continued first
  std::vector<char> sheet_queued_;
  std::vector<CellId> dirty_;
  std::vector<char> cell_dirty_;
};

/// The only way the search changes a state: own / decline / connect, each checked against the
/// current values (a contradiction becomes a Conflict, never an overwrite) and reported to the
/// worklist.
class StateEditor {
 public:
  StateEditor(const RuleContext& ctx, SearchState& state, Worklist& worklist)
      : ctx_(ctx), state_(state), worklist_(worklist) {}

  [[nodiscard]] const RuleContext& ctx() const { return ctx_; }
  [[nodiscard]] const SearchState& state() const { return state_; }
  [[nodiscard]] std::int32_t value(NodeId n, PatchId p) const { return state_.slot[ctx_.slot(n, p)]; }
  [[nodiscard]] const Reason& reason(NodeId n, PatchId p) const {
    return state_.reason[ctx_.slot(n, p)];
  }
  [[nodiscard]] NodeId partner(NodeId n, PatchId p) const {
    const std::int32_t v = value(n, p);
    return v >= 0 ? NodeId(v) : NodeId();
  }

  /// n owns p. Conflicts: n is not a copy of p's inner cell (Rule 3), n already declined p
  /// (Rule 2), p already has another owner (Rule 7). `why.rule` names the rule that forced it.
  bool own(NodeId n, PatchId p, Reason why) {
    if (ctx_.layout.cell(n) != ctx_.inner[p]) {
      return fail(why.rule ? why.rule : 3, why.arc,
                  ctx_.describe(n) + " would have to own patch " + std::to_string(p.value()) +
                      ", whose orientation disagrees with cell " +
                      std::to_string(ctx_.layout.cell(n).value()) + " (Rule 3)" + because(why),
                  {n}, {p});
    }
    const int s = ctx_.slot(n, p);
    std::int32_t& v = state_.slot[s];
    if (v == kOwned) return true;
    if (v != kUndecided) {
      return fail(why.rule ? why.rule : 2, why.arc,
                  ctx_.describe(n) + " would have to own patch " + std::to_string(p.value()) +
                      " but already declined it" + explain(s) + because(why),
                  {n}, {p});
    }
    const NodeId other = state_.owner[p];
    if (other.is_valid() && other != n) {
      return fail(7, why.arc,
                  ctx_.describe(n) + " would have to own patch " + std::to_string(p.value()) +
                      ", already owned by " + ctx_.describe(other) + " (Rule 7)" + because(why),
                  {n, other}, {p});
    }
    v = kOwned;
    state_.reason[s] = why;
    state_.owner[p] = n;
    worklist_.touch(p);
    return true;
  }

  /// n declines p. Conflict: n owns p.
  bool decline(NodeId n, PatchId p, Reason why) {
    const int s = ctx_.slot(n, p);
    std::int32_t& v = state_.slot[s];
    if (is_declined(v)) return true;
    if (v == kOwned) {
      return fail(why.rule, why.arc,
                  ctx_.describe(n) + " would have to decline patch " + std::to_string(p.value()) +
                      " but owns it" + explain(s) + because(why),
                  {n}, {p});
    }
    v = kDeclined;
    state_.reason[s] = why;
    worklist_.touch(p);
    return true;
  }

  /// Edge a–b across p. Conflicts: either node owns p (Rule 2) or has another edge across p
  /// (Rule 1).
  bool connect(NodeId a, NodeId b, PatchId p, Reason why) {
    const CellId ca = ctx_.layout.cell(a), cb = ctx_.layout.cell(b);
    IMM_ASSERT((ca == ctx_.inner[p] && cb == ctx_.outer[p]) || (cb == ctx_.inner[p] && ca == ctx_.outer[p]),
               "connect: nodes are not on the two sides of the patch");
    const int sa = ctx_.slot(a, p), sb = ctx_.slot(b, p);
    if (state_.slot[sa] == b.value() && state_.slot[sb] == a.value()) return true;
    for (const auto& [x, y, sx] : {std::tuple{a, b, sa}, std::tuple{b, a, sb}}) {
      const std::int32_t v = state_.slot[sx];
      if (v == kOwned) {
        return fail(why.rule ? why.rule : 2, why.arc,
                    "edge " + ctx_.describe(x) + " - " + ctx_.describe(y) + " across patch " +
                        std::to_string(p.value()) + " is required, but " + ctx_.describe(x) +
                        " owns the patch" + explain(sx) + because(why),
                    {x, y}, {p});
      }
      if (v >= 0) {
        return fail(why.rule ? why.rule : 1, why.arc,
                    "edge " + ctx_.describe(x) + " - " + ctx_.describe(y) + " across patch " +
                        std::to_string(p.value()) + " is required, but " + ctx_.describe(x) +
                        " is already glued to " + ctx_.describe(NodeId(v)) +
                        " across it (Rule 1)" + because(why),
                    {x, y, NodeId(v)}, {p});
      }
    }
    state_.slot[sa] = b.value();
    state_.slot[sb] = a.value();
    state_.reason[sa] = why;
    state_.reason[sb] = why;
    worklist_.touch(p);
    return true;
  }

  /// Records a conflict and returns false.
  bool fail(int rule, std::int32_t arc, std::string message, std::vector<NodeId> nodes,
            std::vector<PatchId> patches) {
    Conflict c;
    c.rule = rule;
    c.nodes = std::move(nodes);
    c.patches = std::move(patches);
    if (arc >= 0) c.arc = ArcId(arc);
    for (NodeId n : c.nodes) {
      const CellId cell = ctx_.layout.cell(n);
      if (std::find(c.cells.begin(), c.cells.end(), cell) == c.cells.end()) c.cells.push_back(cell);
    }
    std::ostringstream os;
    os << "Rule " << rule;
    if (arc >= 0) os << " at arc " << arc;
    os << ": " << message;
    c.message = os.str();
    conflict_ = std::move(c);
    return false;
  }
  [[nodiscard]] const std::optional<Conflict>& conflict() const { return conflict_; }
  std::optional<Conflict> take_conflict() { return std::exchange(conflict_, std::nullopt); }

  /// " (declined by Rule 5 at arc 3)" for the decision already stored in slot s.
  [[nodiscard]] std::string explain(int s) const {
    const std::int32_t v = state_.slot[s];
    const Reason& r = state_.reason[s];
    std::string what = v == kOwned ? "owned" : v == kUndecided ? "undecided" : v == kDeclined ? "declined" : "glued";
    if (r.rule == 0) return " (" + what + " by a search decision)";
    std::string out = " (" + what + " by Rule " + std::to_string(r.rule);
    if (r.arc >= 0) out += " at arc " + std::to_string(r.arc);
    return out + ")";
  }
  [[nodiscard]] static std::string because(Reason why) {
    if (why.rule == 0) return "";
    std::string out = "; forced by Rule " + std::to_string(why.rule);
    if (why.arc >= 0) out += " at arc " + std::to_string(why.arc);
    return out;
  }

 private:
  const RuleContext& ctx_;
  SearchState& state_;
  Worklist& worklist_;
  std::optional<Conflict> conflict_;
};

// ---- Rule 3 (initial state) -------------------------------------------------------------------

/// The state before any decision: every slot Undecided, except that every node declines the
/// B-patches that disagree with its cell (it is the patch's outer cell).
/// Paper: §5.2 Rule 3 ("a node from cell C must decline a B-patch whose orientation does not
/// agree with C").
inline SearchState initial_state(const RuleContext& ctx) {
  SearchState state;
  state.slot.assign(ctx.slot_count(), kUndecided);
  state.reason.assign(ctx.slot_count(), Reason{});
  state.owner = IdMap<PatchId, NodeId>(ctx.patch_count());
  for (std::size_t s = 0; s < ctx.slot_count(); ++s) {
    const PatchId p = ctx.slot_patch[s];
    if (ctx.layout.cell(ctx.slot_node[s]) != ctx.inner[p]) {
      state.slot[s] = kDeclined;
      state.reason[s] = Reason{3, -1};
    }
  }
  return state;
}

// ---- patch propagators -------------------------------------------------------------------------

/// Exactly one node owns each patch, and only a copy of its inner cell can (Rule 3): once p has an
/// owner every other copy of the inner cell declines p; when a single copy is still undecided and
/// nobody owns p, that copy must own it; when none is left, p cannot be owned (conflict).
/// Paper: §5.2 Rule 7 (with Rule 3).
inline bool propagate_rule7(StateEditor& ed, PatchId p) {
  const RuleContext& ctx = ed.ctx();
  const CellId inner = ctx.inner[p];
  const NodeId owner = ed.state().owner[p];
  const Reason why{7, -1};
  const RuleContext::CopySlots at = ctx.copy_slots(inner, p);
  const std::vector<std::int32_t>& slot = ed.state().slot;
  if (owner.is_valid()) {
    for (int n = ctx.first_node(inner).value(); n < ctx.node_end(inner); ++n) {
      // decline() of a declined slot does nothing: only undecided copies are handed to it.
      if (slot[at.at(NodeId(n))] == kUndecided && NodeId(n) != owner && !ed.decline(NodeId(n), p, why)) {
        return false;
      }
    }
    return true;
  }
  NodeId candidate;
  int candidates = 0;
  for (int n = ctx.first_node(inner).value(); n < ctx.node_end(inner); ++n) {
    if (slot[at.at(NodeId(n))] == kUndecided) {
      candidate = NodeId(n);
      ++candidates;
    }
  }
  if (candidates == 1) return ed.own(candidate, p, why);
  if (candidates == 0) {
    std::string detail;
    std::vector<NodeId> nodes;
    for (int n = ctx.first_node(inner).value(); n < ctx.node_end(inner); ++n) {
      detail += (detail.empty() ? "" : ", ") + ctx.describe(NodeId(n)) +
                ed.explain(ctx.slot(NodeId(n), p));
      nodes.push_back(NodeId(n));
    }
    // Name the arc of the first arc-rule decline, which is usually the root cause.
    std::int32_t arc = -1;
    for (NodeId n : nodes) {
      if (ed.reason(n, p).arc >= 0) {
        arc = ed.reason(n, p).arc;
        break;
      }
    }
    return ed.fail(7, arc,
                   "patch " + std::to_string(p.value()) + " (inner cell " +
                       std::to_string(inner.value()) + ") can have no owner: every copy of cell " +
                       std::to_string(inner.value()) + " declines it: " + detail,
                   std::move(nodes), {p});
  }
  return true;
}

/// A node that declines a patch must be glued across it (Rule 2) to exactly one node (Rule 1) of
/// the cell on the other side, and that node must neither own the patch nor be glued to another
/// node across it. When a declined slot without an edge has a single possible partner, the edge
/// is forced; when it has none, the state is contradictory.
/// Paper: §5.2 Rules 1 and 2.
inline bool propagate_rule2(StateEditor& ed, PatchId p) {
  const RuleContext& ctx = ed.ctx();
  const CellId inner = ctx.inner[p], outer = ctx.outer[p];
  const std::vector<std::int32_t>& slot = ed.state().slot;
  const auto process_side = [&](CellId side, CellId other) {
    // The possible partners are the same for every declined node of the side: counted once, and
    // again only after an edge was made (which takes one of them).
    NodeId only;
    int options = -1;
    const RuleContext::CopySlots side_at = ctx.copy_slots(side, p);
    for (int n = ctx.first_node(side).value(); n < ctx.node_end(side); ++n) {
      if (slot[side_at.at(NodeId(n))] != kDeclined) continue;
      if (options < 0) {
        options = 0;
        if (other.is_valid()) {
          const RuleContext::CopySlots other_at = ctx.copy_slots(other, p);
          for (int m = ctx.first_node(other).value(); m < ctx.node_end(other); ++m) {
            const std::int32_t v = slot[other_at.at(NodeId(m))];
            if (v == kDeclined || v == kUndecided) {
              only = NodeId(m);
              ++options;
            }
          }
        }
      }
      if (options == 0) {
        std::string msg = ctx.describe(NodeId(n)) + " declines patch " + std::to_string(p.value()) +
                          ed.explain(ctx.slot(NodeId(n), p));
        if (!other.is_valid()) {
          msg += ", but the other side of the patch has winding number 0 (Rule 2)";
        } else {
          msg += ", but every copy of cell " + std::to_string(other.value()) +
                 " across it already owns it or is glued to another node (Rules 1, 2)";
        }
        return ed.fail(2, ed.reason(NodeId(n), p).arc, msg, {NodeId(n)}, {p});
      }
      if (options == 1) {
        if (!ed.connect(NodeId(n), only, p, Reason{2, -1})) return false;
        options = -1;
      }
    }
    return true;
  };
  return process_side(inner, outer) && (!outer.is_valid() || process_side(outer, inner));
}

/// Not a rule but a symmetry reduction, used by the search only (SearchOptions::continue_sheets):
/// a node n that already belongs to a partial sheet (it owns a patch or has an edge) and
/// declines p without an edge must be glued to a copy m of the cell across p. When every
/// candidate m (undecided or declined on p, no edge) is a FREE copy (owns nothing, no edge) and
/// all candidates have identical slots, any two of them are exchanged by an automorphism of the
/// state that fixes every other node, so gluing n to the first loses no immersion up to copy
/// permutation (paper §6: the search may start from any copy). This lets propagation grow a
/// sheet into the pool of untouched copies without a search decision per node.
inline bool propagate_sheet_continuation(StateEditor& ed, PatchId p) {
  const RuleContext& ctx = ed.ctx();
  const SearchState& st = ed.state();
  const auto is_free = [&](NodeId n) {
    const int b = ctx.slot_base[n];
    const int e = b + static_cast<int>(ctx.b_patches[ctx.layout.cell(n)].size());
    for (int s = b; s < e; ++s) {
      if (st.slot[s] == kOwned || st.slot[s] >= 0) return false;
    }
    return true;
  };
  const auto process_side = [&](CellId side, CellId other) {
    if (!other.is_valid()) return true;
    // The candidates are the same for every node of the side: examined once, and again only
    // after an edge was made (which takes the first of them).
    NodeId first;
    bool symmetric = true, examined = false;
    const RuleContext::CopySlots side_at = ctx.copy_slots(side, p), other_at = ctx.copy_slots(other, p);
    for (int n = ctx.first_node(side).value(); n < ctx.node_end(side); ++n) {
      if (st.slot[side_at.at(NodeId(n))] != kDeclined || is_free(NodeId(n))) continue;
      if (!examined) {
        examined = true;
        first = NodeId();
        symmetric = true;
        const std::size_t width = ctx.b_patches[other].size();
        for (int m = ctx.first_node(other).value(); m < ctx.node_end(other) && symmetric; ++m) {
          const std::int32_t v = st.slot[other_at.at(NodeId(m))];
          if (v != kDeclined && v != kUndecided) continue;
          if (!is_free(NodeId(m))) {
            symmetric = false;
          } else if (!first.is_valid()) {
            first = NodeId(m);
          } else {
            const auto a = st.slot.begin() + ctx.slot_base[first];
            symmetric = std::equal(a, a + static_cast<long>(width), st.slot.begin() + ctx.slot_base[NodeId(m)]);
          }
        }
      }
      if (!symmetric || !first.is_valid()) continue;  // a choice, or Rule 2's conflict
      if (!ed.connect(NodeId(n), first, p, Reason{0, -1})) return false;
      examined = false;
    }
    return true;
  };
  return process_side(ctx.inner[p], ctx.outer[p]) &&
         (!ctx.outer[p].is_valid() || process_side(ctx.outer[p], ctx.inner[p]));
}

// ---- arc propagators ---------------------------------------------------------------------------

/// A node cannot own both B-patches bounding one of its wedges (its two geometric neighbours w.r.t.
/// the cell at this arc): the local piece would be a single wedge, which is not a manifold
/// neighbourhood. When both junctions of the wedge are the same patch (a B-patch that is its own
/// geometric neighbour, §4.2), no node of the wedge's cell can own it.
/// Paper: §5.2 Rule 5, §4.2 (a patch is a geometric neighbour of itself), §4.2.1.
inline bool propagate_rule5(StateEditor& ed, ArcId a) {
  const RuleContext& ctx = ed.ctx();
  const ArcView& arc = ctx.arcs[a];
  const Reason why{5, a.value()};
  for (int k = 0; k < 4; ++k) {
    const CellId c = arc.cell[k];
    if (!c.is_valid()) continue;
    const PatchId left = arc.patch[k], right = arc.patch[(k + 1) % 4];
    if (left == right) {
      for (int n = ctx.first_node(c).value(); n < ctx.node_end(c); ++n) {
        if (!ed.decline(NodeId(n), left, why)) return false;
      }
      continue;
    }
    // A slot is Owned exactly when its node is the patch's recorded owner (StateEditor::own), so
    // only the owners of the two junctions can own one of them: no scan of the wedge's copies.
    // Declines create no owner, so the owners stay the same during the loop; they are handled
    // in node order, as a scan of the copies would.
    NodeId owns_left = ed.state().owner[left], owns_right = ed.state().owner[right];
    if (owns_left.is_valid() && ctx.layout.cell(owns_left) != c) owns_left = NodeId();
    if (owns_right.is_valid() && ctx.layout.cell(owns_right) != c) owns_right = NodeId();
    if (owns_left.is_valid() && owns_right.is_valid() && owns_right < owns_left) {
      if (!ed.decline(owns_right, left, why)) return false;
      owns_right = NodeId();
    }
    if (owns_left.is_valid() && !ed.decline(owns_left, right, why)) return false;
    if (owns_right.is_valid() && owns_right != owns_left && !ed.decline(owns_right, left, why)) return false;
  }
  return true;
}

/// Across junction k+1 (patch q = P_{k+1}), wedge k of cell C_k meets wedge k+1 of cell C_{k+1}.
/// If x in C_k is glued to y in C_{k+1} across q, then x owns P_k iff y owns P_{k+2}, since P_k
/// and P_{k+2} are the same sheet (topological neighbours) and both are geometric neighbours of q.
/// Conversely, if x in C_k owns P_k and y in C_{k+1} owns P_{k+2}, then x and y are glued across q
/// (they are the two halves of the half-disk bounded by that sheet).
/// Paper: §5.2 Rule 4.
inline bool propagate_rule4(StateEditor& ed, ArcId a) {
  const RuleContext& ctx = ed.ctx();
  const ArcView& arc = ctx.arcs[a];
  const Reason why{4, a.value()};
  for (int k = 0; k < 4; ++k) {
    const int k1 = (k + 1) % 4, k2 = (k + 2) % 4;
    const CellId ck = arc.cell[k], ck1 = arc.cell[k1];
    if (!ck.is_valid() || !ck1.is_valid()) continue;
    const PatchId pk = arc.patch[k], q = arc.patch[k1], pk2 = arc.patch[k2];
    // Forward direction: along every edge across q.
    const RuleContext::CopySlots x_q = ctx.copy_slots(ck, q), x_pk = ctx.copy_slots(ck, pk),
                                 y_pk2 = ctx.copy_slots(ck1, pk2);
    const std::vector<std::int32_t>& slot = ed.state().slot;
    for (int n = ctx.first_node(ck).value(); n < ctx.node_end(ck); ++n) {
      const NodeId x(n);
      const std::int32_t vq = slot[x_q.at(x)];
      if (vq < 0) continue;
      const NodeId y(vq);  // a copy of C_{k+1}, the other side of q
      const std::int32_t vx = slot[x_pk.at(x)], vy = slot[y_pk2.at(y)];
      if (vx == kUndecided && vy == kUndecided) continue;
      if (vx != kUndecided && vy != kUndecided) {
        if ((vx == kOwned) != (vy == kOwned)) {
          const NodeId owner = vx == kOwned ? x : y;
          const NodeId other = vx == kOwned ? y : x;
          const PatchId owned = vx == kOwned ? pk : pk2;
          const PatchId declined = vx == kOwned ? pk2 : pk;
          return ed.fail(4, a.value(),
                         ctx.describe(x) + " and " + ctx.describe(y) + " are glued across patch " +
                             std::to_string(q.value()) + ", but " + ctx.describe(owner) +
                             " owns patch " + std::to_string(owned.value()) + " while " +
                             ctx.describe(other) + " declines patch " +
                             std::to_string(declined.value()) + " on the same sheet" +
                             ed.explain(ctx.slot(other, declined)),
                         {x, y}, {pk, q, pk2});
        }
        continue;
      }
      if (vx == kUndecided) {
        if (!(vy == kOwned ? ed.own(x, pk, why) : ed.decline(x, pk, why))) return false;
      } else {
        if (!(vx == kOwned ? ed.own(y, pk2, why) : ed.decline(y, pk2, why))) return false;
      }
    }
    // Converse: the owners of P_k (in C_k) and P_{k+2} (in C_{k+1}) are glued across q.
    const NodeId x = ed.state().owner[pk], y = ed.state().owner[pk2];
    if (x.is_valid() && y.is_valid() && ctx.layout.cell(x) == ck && ctx.layout.cell(y) == ck1) {
      if (!ed.connect(x, y, q, why)) return false;
    }
  }
  return true;
}

/// Around an arc, a chain of three edges x0 –P1– x1 –P2– x2 –P3– x3 through four consecutive
/// wedges (any rotation; nodes repeat when wedges share a cell) must close with the edge
/// x3 –P0– x0: otherwise the local sheets would wind around the arc more than once.
/// Paper: §5.2 Rule 6, Fig. 15.
inline bool propagate_rule6(StateEditor& ed, ArcId a) {
  const RuleContext& ctx = ed.ctx();
  const ArcView& arc = ctx.arcs[a];
  for (int k = 0; k < 4; ++k) {
    if (!arc.cell[k].is_valid()) return true;  // a wedge of winding 0: no node goes around
  }
  const Reason why{6, a.value()};
  const std::vector<std::int32_t>& slot = ed.state().slot;
  for (int s = 0; s < 4; ++s) {
    const CellId c0 = arc.cell[s];
    // x_i is a copy of the cell of wedge s + i; the edge x_i - x_{i+1} crosses P_{s+i+1}.
    const RuleContext::CopySlots at0 = ctx.copy_slots(c0, arc.patch[(s + 1) % 4]),
                                 at1 = ctx.copy_slots(arc.cell[(s + 1) % 4], arc.patch[(s + 2) % 4]),
                                 at2 = ctx.copy_slots(arc.cell[(s + 2) % 4], arc.patch[(s + 3) % 4]),
                                 at3 = ctx.copy_slots(arc.cell[(s + 3) % 4], arc.patch[s]);
    for (int n = ctx.first_node(c0).value(); n < ctx.node_end(c0); ++n) {
      const NodeId x0(n);
      const std::int32_t v1 = slot[at0.at(x0)];
      if (v1 < 0) continue;
      const std::int32_t v2 = slot[at1.at(NodeId(v1))];
      if (v2 < 0) continue;
      const std::int32_t v3 = slot[at2.at(NodeId(v2))];
      if (v3 < 0 || slot[at3.at(NodeId(v3))] == n) continue;  // closed already (edges are mutual)
      if (!ed.connect(NodeId(v3), x0, arc.patch[s], why)) return false;
    }
  }
  return true;
}

// ---- predicates on a complete state -----------------------------------------------------------
// Each takes a group (RuleContext::group_cells): only the patches, slots and arcs of that group
// are checked, so a group can be accepted before the others are solved; -1 checks everything.

/// Rule 1: every edge is symmetric and joins the two sides of its patch (a slot holds at most one
/// partner by construction). Paper: §5.2 Rule 1.
inline std::optional<Conflict> check_rule1(const RuleContext& ctx, const SearchState& st, int group);
/// Rule 2: no slot is undecided and every declined slot has an edge. Paper: §5.2 Rule 2.
inline std::optional<Conflict> check_rule2(const RuleContext& ctx, const SearchState& st, int group);
/// Rule 3: only copies of the inner cell own a patch. Paper: §5.2 Rule 3.
inline std::optional<Conflict> check_rule3(const RuleContext& ctx, const SearchState& st, int group);
/// Rule 4 (both directions) at every junction of every arc. Paper: §5.2 Rule 4.
inline std::optional<Conflict> check_rule4(const RuleContext& ctx, const SearchState& st, int group);
/// Rule 5 at every wedge of every arc. Paper: §5.2 Rule 5.
inline std::optional<Conflict> check_rule5(const RuleContext& ctx, const SearchState& st, int group);
/// Rule 6 for every start wedge of every arc whose four wedges are cells. Paper: §5.2 Rule 6.
inline std::optional<Conflict> check_rule6(const RuleContext& ctx, const SearchState& st, int group);
/// Rule 7: exactly one owner per patch, recorded in `owner`. Paper: §5.2 Rule 7.
inline std::optional<Conflict> check_rule7(const RuleContext& ctx, const SearchState& st, int group);

inline Conflict make_conflict(int rule, std::string message, std::vector<NodeId> nodes,
                              std::vector<PatchId> patches, ArcId arc = ArcId()) {
  Conflict c;
  c.rule = rule;
  c.message = "Rule " + std::to_string(rule) + (arc.is_valid() ? " at arc " + std::to_string(arc.value()) : "") +
              ": " + std::move(message);
  c.nodes = std::move(nodes);
  c.patches = std::move(patches);
  c.arc = arc;
  return c;
}

inline std::optional<Conflict> check_rule1(const RuleContext& ctx, const SearchState& st, int group) {
  for (std::size_t s = 0; s < ctx.slot_count(); ++s) {
    const std::int32_t v = st.slot[s];
    if (v < 0 || (group >= 0 && ctx.patch_group[ctx.slot_patch[s]] != group)) continue;
    const NodeId n = ctx.slot_node[s], m(v);
    const PatchId p = ctx.slot_patch[s];
    const CellId cn = ctx.layout.cell(n);
    const CellId other = cn == ctx.inner[p] ? ctx.outer[p] : ctx.inner[p];
    if (m.index() >= ctx.node_count() || ctx.layout.cell(m) != other ||
        st.slot[ctx.slot(m, p)] != n.value()) {
      return make_conflict(1, "edge of " + ctx.describe(n) + " across patch " +
                                  std::to_string(p.value()) + " is not mirrored",
                           {n}, {p});
    }
  }
  return std::nullopt;
}

inline std::optional<Conflict> check_rule2(const RuleContext& ctx, const SearchState& st, int group) {
  for (std::size_t s = 0; s < ctx.slot_count(); ++s) {
    if (group >= 0 && ctx.patch_group[ctx.slot_patch[s]] != group) continue;
    if (st.slot[s] == kUndecided || st.slot[s] == kDeclined) {
      return make_conflict(2, ctx.describe(ctx.slot_node[s]) + " has no edge across patch " +
                                  std::to_string(ctx.slot_patch[s].value()) + " and does not own it",
                           {ctx.slot_node[s]}, {ctx.slot_patch[s]});
    }
  }
  return std::nullopt;
}

inline std::optional<Conflict> check_rule3(const RuleContext& ctx, const SearchState& st, int group) {
  for (std::size_t s = 0; s < ctx.slot_count(); ++s) {
    const NodeId n = ctx.slot_node[s];
    const PatchId p = ctx.slot_patch[s];
    if (group >= 0 && ctx.patch_group[p] != group) continue;
    if (st.slot[s] == kOwned && ctx.layout.cell(n) != ctx.inner[p]) {
      return make_conflict(3, ctx.describe(n) + " owns patch " + std::to_string(p.value()) +
                                  ", which disagrees with its cell",
                           {n}, {p});
    }
  }
  return std::nullopt;
}

// Rules 4–6 are checked from the paper's statements over the complete graph, with the relations
// the complex states (geometric neighbours per arc and wedge; the patches of opposite junctions
// as topological neighbours), and share no code with the propagators above: a propagator that
// misses a consequence of its rule leaves a complete state that these predicates refuse
// (SearchStats::rejected counts them). Read on a state that satisfies Rule 1 (check_rule1 runs
// first), so every partner is a node of the cell across its patch.

/// @return true when n owns p. @pre p is a B-patch of n's cell.
inline bool owns(const RuleContext& ctx, const SearchState& st, NodeId n, PatchId p) {
  return st.slot[ctx.slot(n, p)] == kOwned;
}
/// @return the node glued to n across p (an edge n–p–m), or an invalid id.
inline NodeId glued(const RuleContext& ctx, const SearchState& st, NodeId n, PatchId p) {
  const std::int32_t v = st.slot[ctx.slot(n, p)];
  return v >= 0 ? NodeId(v) : NodeId();
}
/// The nodes of a cell, as a range of ids (no allocation: the predicates run over every arc of
/// every accepted graph, a million nodes on the largest piles of issue 19).
struct NodeRange {
  struct iterator {
    int n;
    NodeId operator*() const { return NodeId(n); }
    iterator& operator++() {
      ++n;
      return *this;
    }
    bool operator!=(const iterator& o) const { return n != o.n; }
  };
  int first, last;
  [[nodiscard]] iterator begin() const { return {first}; }
  [[nodiscard]] iterator end() const { return {last}; }
};
inline NodeRange nodes_of(const RuleContext& ctx, CellId c) {
  return NodeRange{ctx.first_node(c).value(), ctx.node_end(c)};
}

inline std::optional<Conflict> check_rule4(const RuleContext& ctx, const SearchState& st, int group) {
  // "If nodes c1, c2 from cells C1, C2 are connected across patch q, and p_i is a B-patch of C_i
  // and geometric neighbour of q, for i = 1, 2, and p1, p2 are topological neighbours, then either
  // both c_i own p_i, or both decline p_i. Conversely, if c_i owns p_i for both i = 1, 2, and p1,
  // p2 are topological neighbours, then c1 and c2 must be connected across q."
  // At an arc, q is the junction two adjacent wedges share: g1 = (p1, q) bounds C1's wedge and
  // g2 = (q, p2) the next wedge, C2's. p1 is the junction before q and p2 the one after it:
  // opposite junctions, one sheet, i.e. topological neighbours (CellComplex::
  // topological_neighbors). Pairs at different arcs are never combined: the neighbourhoods the
  // rule speaks of are those of one arc point.
  for (ArcId a : ids<ArcId>(ctx.arc_count())) {
    if (group >= 0 && ctx.arc_group[a] != group) continue;
    const std::vector<GeometricNeighbors>& pairs = ctx.arc_geometric_neighbors[a];
    for (const GeometricNeighbors& g1 : pairs) {
      for (const GeometricNeighbors& g2 : pairs) {
        if (g2.wedge != (g1.wedge + 1) % 4) continue;
        const PatchId q = g1.second, p1 = g1.first, p2 = g2.second;
        IMM_ASSERT(q == g2.first, "adjacent wedges do not share their junction");
        // The slots of the copies of C1 at q and p1 and of C2 at p2 (Rule 1 holds: a partner
        // across q is a copy of C2).
        const RuleContext::CopySlots c1_q = ctx.copy_slots(g1.cell, q), c1_p1 = ctx.copy_slots(g1.cell, p1),
                                     c2_p2 = ctx.copy_slots(g2.cell, p2);
        for (NodeId c1 : nodes_of(ctx, g1.cell)) {
          const std::int32_t v = st.slot[c1_q.at(c1)];
          if (v < 0) continue;
          const NodeId c2(v);
          if ((st.slot[c1_p1.at(c1)] == kOwned) != (st.slot[c2_p2.at(c2)] == kOwned)) {
            const NodeId owner = owns(ctx, st, c1, p1) ? c1 : c2;
            const NodeId other = owner == c1 ? c2 : c1;
            return make_conflict(4, ctx.describe(c1) + " and " + ctx.describe(c2) +
                                        " are connected across patch " + std::to_string(q.value()) +
                                        ", but only " + ctx.describe(owner) + " owns its side (patches " +
                                        std::to_string(p1.value()) + " and " +
                                        std::to_string(p2.value()) + " are one sheet); " +
                                        ctx.describe(other) + " declines its side",
                                 {c1, c2}, {p1, q, p2}, a);
          }
        }
        for (NodeId c1 : nodes_of(ctx, g1.cell)) {
          if (st.slot[c1_p1.at(c1)] != kOwned) continue;
          for (NodeId c2 : nodes_of(ctx, g2.cell)) {
            if (st.slot[c2_p2.at(c2)] != kOwned || glued(ctx, st, c1, q) == c2) continue;
            return make_conflict(4, ctx.describe(c1) + " owns patch " + std::to_string(p1.value()) +
                                        " and " + ctx.describe(c2) + " owns patch " +
                                        std::to_string(p2.value()) +
                                        " (one sheet), but they are not connected across patch " +
                                        std::to_string(q.value()),
                                 {c1, c2}, {p1, q, p2}, a);
          }
        }
      }
    }
  }
  return std::nullopt;
}

inline std::optional<Conflict> check_rule5(const RuleContext& ctx, const SearchState& st, int group) {
  // "If a node c from cell C owns a patch p1, and p1 is a geometric neighbour of p2 on C, then c
  // must decline p2." A pair (p, p) is a patch that is its own geometric neighbour (§4.2): no node
  // can own it.
  for (ArcId a : ids<ArcId>(ctx.arc_count())) {
    if (group >= 0 && ctx.arc_group[a] != group) continue;
    for (const GeometricNeighbors& g : ctx.arc_geometric_neighbors[a]) {
      const RuleContext::CopySlots at_first = ctx.copy_slots(g.cell, g.first),
                                   at_second = ctx.copy_slots(g.cell, g.second);
      for (NodeId c : nodes_of(ctx, g.cell)) {
        for (const auto& [p1, p2, at1, at2] : {std::tuple{g.first, g.second, at_first, at_second},
                                               std::tuple{g.second, g.first, at_second, at_first}}) {
          if (st.slot[at1.at(c)] == kOwned && !is_declined(st.slot[at2.at(c)])) {
            return make_conflict(5, ctx.describe(c) + " owns patch " + std::to_string(p1.value()) +
                                        (p1 == p2 ? ", which is its own geometric neighbour"
                                                  : " and does not decline its geometric neighbour " +
                                                        std::to_string(p2.value())),
                                 {c}, {p1, p2}, a);
          }
        }
      }
    }
  }
  return std::nullopt;
}

inline std::optional<Conflict> check_rule6(const RuleContext& ctx, const SearchState& st, int group) {
  // "If four nodes c, d, e, f surround the same arc A, and x connects to y across a patch that
  // neighbours A, for (x, y) equalling (c, d) and (d, e) and (e, f), then c must connect to f
  // across a patch that neighbours A" (also when c = e and/or d = f). Nodes surround A when the
  // four wedges around it lie in cells; with a wedge of winding number 0 the rule does not apply
  // (Fig. 15, blue circles). c, d, e, f are taken in the order of the wedges, each connection
  // across the junction between consecutive wedges, starting at every wedge.
  for (ArcId a : ids<ArcId>(ctx.arc_count())) {
    if (group >= 0 && ctx.arc_group[a] != group) continue;
    const std::vector<GeometricNeighbors>& pairs = ctx.arc_geometric_neighbors[a];
    if (pairs.size() != 4) continue;
    std::array<const GeometricNeighbors*, 4> around{};
    for (const GeometricNeighbors& g : pairs) around[g.wedge] = &g;
    for (int s = 0; s < 4; ++s) {
      // The junction after wedge k is the second patch of its geometric-neighbour pair.
      const auto after = [&](int k) { return around[k % 4]->second; };
      // The slots of the copies of the cell of wedge s + i at the junction after it.
      const auto at = [&](int i) { return ctx.copy_slots(around[(s + i) % 4]->cell, after(s + i)); };
      const RuleContext::CopySlots at0 = at(0), at1 = at(1), at2 = at(2), at3 = at(3);
      for (NodeId c : nodes_of(ctx, around[s]->cell)) {
        const std::int32_t vd = st.slot[at0.at(c)];
        if (vd < 0) continue;
        const NodeId d(vd);
        const std::int32_t ve = st.slot[at1.at(d)];
        if (ve < 0) continue;
        const NodeId e(ve);
        const std::int32_t vf = st.slot[at2.at(e)];
        if (vf < 0) continue;
        const NodeId f(vf);
        if (st.slot[at3.at(f)] == c.value()) continue;
        return make_conflict(6, ctx.describe(c) + ", " + ctx.describe(d) + ", " + ctx.describe(e) +
                                    " and " + ctx.describe(f) +
                                    " are connected in turn around the arc, but the last is not "
                                    "connected back to the first across patch " +
                                    std::to_string(after(s + 3).value()),
                             {c, d, e, f}, {after(s), after(s + 1), after(s + 2), after(s + 3)}, a);
      }
    }
  }
  return std::nullopt;
}

inline std::optional<Conflict> check_rule7(const RuleContext& ctx, const SearchState& st, int group) {
  for (PatchId p : ids<PatchId>(ctx.patch_count())) {
    if (group >= 0 && ctx.patch_group[p] != group) continue;
    const CellId c = ctx.inner[p];
    int owners = 0;
    for (int n = ctx.first_node(c).value(); n < ctx.node_end(c); ++n) {
      if (st.slot[ctx.slot(NodeId(n), p)] == kOwned) {
        ++owners;
        if (st.owner[p] != NodeId(n)) {
          return make_conflict(7, "owner record of patch " + std::to_string(p.value()) + " is stale",
                               {NodeId(n)}, {p});
        }
      }
    }
    if (owners != 1) {
      return make_conflict(7, "patch " + std::to_string(p.value()) + " has " +
                                  std::to_string(owners) + " owners",
                           {}, {p});
    }
  }
  return std::nullopt;
}

/// Every rule on a state that is complete on `group` (-1: on everything); the first violated one.
inline std::optional<Conflict> check_all_rules(const RuleContext& ctx, const SearchState& st,
                                               int group = -1) {
  if (auto c = check_rule1(ctx, st, group)) return c;
  if (auto c = check_rule2(ctx, st, group)) return c;
  if (auto c = check_rule3(ctx, st, group)) return c;
  if (auto c = check_rule7(ctx, st, group)) return c;
  if (auto c = check_rule5(ctx, st, group)) return c;
  if (auto c = check_rule4(ctx, st, group)) return c;
  if (auto c = check_rule6(ctx, st, group)) return c;
  return std::nullopt;
}

}  // namespace imm::detail
