// Template definitions of find_immersions<D> and canonical_form<D>; included only by
// core/instantiate.cpp. Paper: §6, Algorithm 1, §6.2.
//
// The search is a depth-first search over partial immersion graphs (immersion_rules.h):
//  - groups: cells linked by a patch or by a common arc form independent subproblems
//    (RuleContext::group_cells). Each group is searched on its own and the immersions are the
//    Cartesian product of the groups' solutions. Without this, a refutation in one group would
//    be re-derived under every choice made in another, and symmetric choices in k groups would
//    multiply into 2^k duplicate leaves; it also lets SelfConnectingCell look only at the cells of
//    the refuted group;
//  - propagation: after every decision, the rule propagators run to a fixpoint over a worklist of
//    the patches and arcs whose slots changed (one "state" in the statistics);
//  - branching: the variables are owner(q) for every patch without an owner and partner(n, q) for
//    every declined slot without an edge. The variable with the fewest options is decided next
//    (ties: lowest patch id, owner before partners, lowest node). Alternatives are pushed on an
//    explicit stack as copies of the state, so a state is copied only at a real branch point;
//  - sheets first (SearchOptions::sheets_first, issue 19): a variable that involves a node
//    already in a partial sheet (it owns a patch or has an edge) is decided before any variable
//    that would start a new sheet from untouched copies; within each tier, fewest options first.
//    With the fewest options over all variables, the search started a new sheet whenever a
//    patch of untouched copies offered a single (symmetric) owner, interleaved dozens of partial
//    sheets on piles of overlapping parts and paid for every wrong interleaving deep in the
//    tree: a 12-sphere pile exhausted 50 000 states (31 449 dead ends), a 32-circle pile needed
//    53 s. Finishing one sheet before starting the next keeps the untouched copies of every
//    cell interchangeable, so the symmetry below stays visible;
//  - sheet continuation (SearchOptions::continue_sheets; immersion_rules.h,
//    propagate_sheet_continuation): when a node of a partial sheet must be glued across a patch
//    and every candidate is an untouched copy identical to the others, propagation glues it to
//    the first one. That choice is a symmetry, not a deduction, but it is one every search
//    decision would make the same way; doing it in the propagation fixpoint removes one search
//    state (and one scan of all variables) per node: 14 589 states became 326 on 32 circles;
//  - the choice of the next variable is kept in an index (a min segment tree of per-patch keys,
//    SearchOptions::incremental_choice; see "the choice of the next variable" below): each step
//    refreshes it for the B-patches of the cells whose slots it changed (Worklist::dirty_cells),
//    and the variable chosen is exactly the one a rescan of every open variable would choose.
//    Before (issue 19), every state rescanned every patch and recomputed the copy classes of
//    every cell: 62-70 % of the search on 64 circles and 24 spheres, whose states (814, 1828)
//    have no branch and no dead end; a search is now about as costly as its propagation;
//  - trial connections (Algorithm 1, "connectNodes"; failed-literal probing): at a real branch
//    point (two or more options left after the symmetry reduction below), every option of the
//    chosen variable is first tried with full propagation on a scratch copy (each trial counts
//    as a state, SearchStats::probes), and so are the options of a few candidates more: the
//    *duals* of partner(n, q), i.e. partner(m, q) for every option m that declines q without an
//    edge, and up to max_ties_ other variables with the same option count. Refuted options are
//    dropped. A candidate with no surviving option refutes the state; one with a single
//    survivor is made at once, without branching; a refuted owner option n of owner(q) is
//    recorded as "n declines q". Otherwise the search branches on the candidate with the
//    fewest survivors and continues with the first one's already propagated state. Without
//    trials, a wrong option is refuted only deep in its subtree: on deep overlaps the search
//    thrashed (dead ends ~ branches) and found nothing in 20 000 states where trials need ~1 000;
//  - symmetry: two copies of a cell that own nothing, have no edge and have identical slots are
//    interchangeable, so only the first of them is offered as an option (this replaces the
//    paper's "pick any node a, make it own any B-patch p" seed and extends it to every component,
//    §6.2: a new component is started by an owner(q) decision, never greedily). At a real branch
//    point, options whose partial components have equal breadth-first codes are exchanged by an
//    automorphism of the state and are also offered once. That automorphism must fix the
//    declined node n of partner(n, q), so it cannot see a symmetry between n and another copy n'
//    of its cell, which is common: two copies whose partial sheets are still interchangeable
//    (the same code) must each be glued to one of two distinct, non-interchangeable copies m1,
//    m2 across q. Branching on n then yields n–m1 and n–m2, whose completions are isomorphic
//    (swap n and n'): `--all` enumerated 2^k labelled copies of one immersion (6073 of 6077
//    branches ended in duplicates on 256 sparse disks). The dual partner(m1, q) has options n
//    and n', which the code comparison identifies: a single option, made without branching.
//    Symmetries that no partial state shows remain possible, so duplicates are still dropped at
//    acceptance (below); none were left on the benchmark families;
//  - acceptance: a state complete on its group is checked against every rule again
//    (check_all_rules), then de-duplicated by its canonical form.
#pragma once

#include <algorithm>
#include <chrono>
#include <limits>
#include <sstream>
#include <string>
#include <unordered_set>
#include <vector>

#include "core/graph_search.h"
#include "core/immersion_graph.h"
#include "core/immersion_rules.h"
#include "core/text_io.h"

namespace imm {
namespace detail {

/// Runs every propagator until nothing changes. @return false on a conflict (kept in `ed`); the
/// worklist is empty on return either way.
inline bool propagate_to_fixpoint(StateEditor& ed, Worklist& worklist) {
  while (true) {
    if (worklist.has_patch()) {
      const PatchId p = worklist.pop_patch();
      if (!propagate_rule7(ed, p) || !propagate_rule2(ed, p)) {
        worklist.clear();
        return false;
      }
    } else if (worklist.has_arc()) {
      const ArcId a = worklist.pop_arc();
      if (!propagate_rule5(ed, a) || !propagate_rule4(ed, a) || !propagate_rule6(ed, a)) {
        worklist.clear();
        return false;
      }
    } else if (worklist.has_sheet()) {
      // Only when the rules are at a fixpoint: a symmetry step, not a deduction.
      if (!propagate_sheet_continuation(ed, worklist.pop_sheet())) {
        worklist.clear();
        return false;
      }
    } else {
      return true;
    }
  }
}

/// The complete graph of slot values and owners whose every slot is Owned or Connected.
inline Immersion extract_immersion(const RuleContext& ctx, const std::vector<std::int32_t>& slot,
                                   const IdMap<PatchId, NodeId>& owner) {
  Immersion im;
  im.layout = ctx.layout;
  im.owner = owner;
  // Slots are grouped by node in increasing node order, so the edges come out sorted by their
  // inner node; only each node's few edges need sorting (by outer node, then patch), not the
  // whole list (millions of edges on the largest piles).
  for (NodeId n : ids<NodeId>(ctx.node_count())) {
    const std::size_t first = im.edges.size();
    const int b = ctx.slot_base[n];
    const int e = b + static_cast<int>(ctx.b_patches[ctx.layout.cell(n)].size());
    for (int s = b; s < e; ++s) {
      const std::int32_t v = slot[s];
      const PatchId p = ctx.slot_patch[s];
      if (v >= 0 && ctx.layout.cell(n) == ctx.inner[p]) im.edges.push_back({n, NodeId(v), p});
    }
    std::sort(im.edges.begin() + static_cast<long>(first), im.edges.end());
  }
  IMM_ASSERT(std::is_sorted(im.edges.begin(), im.edges.end()), "extract_immersion: edges out of order");
  return im;
}
inline Immersion extract_immersion(const RuleContext& ctx, const SearchState& st) {
  return extract_immersion(ctx, st.slot, st.owner);
}

/// canonical_form over the flattened tables (see immersion_graph.h for the definition). With
/// group >= 0 only the nodes of that group's cells are encoded.
inline std::string canonical_form_impl(const RuleContext& ctx, const Immersion& im, int group = -1) {
  constexpr std::int32_t kMissing = -4;
  const std::size_t nodes = ctx.node_count();
  std::vector<std::int32_t> table(ctx.slot_count(), kMissing);
  for (PatchId p : ids<PatchId>(std::min(ctx.patch_count(), im.owner.size()))) {
    const NodeId o = im.owner[p];
    if (o.is_valid() && o.index() < nodes && ctx.layout.cell(o) == ctx.inner[p]) {
      table[ctx.slot(o, p)] = kOwned;
    }
  }
  const auto is_side = [&](NodeId n, PatchId p) {
    if (!n.is_valid() || n.index() >= nodes || !p.is_valid() || p.index() >= ctx.patch_count()) {
      return false;
    }
    const CellId c = ctx.layout.cell(n);
    return c == ctx.inner[p] || c == ctx.outer[p];
  };
  for (const ImmersionEdge& e : im.edges) {
    if (!is_side(e.inner, e.patch) || !is_side(e.outer, e.patch)) continue;
    table[ctx.slot(e.inner, e.patch)] = e.outer.value();
    table[ctx.slot(e.outer, e.patch)] = e.inner.value();
  }
  const auto slots_of = [&](NodeId n) {
    const int begin = ctx.slot_base[n];
    return std::pair{begin, begin + static_cast<int>(ctx.b_patches[ctx.layout.cell(n)].size())};
  };

  // Connected components over the edges.
  std::vector<int> component(nodes, -1);
  std::vector<std::vector<NodeId>> components;
  for (NodeId start : ids<NodeId>(nodes)) {
    if (component[start.index()] >= 0) continue;
    if (group >= 0 && ctx.cell_group[ctx.layout.cell(start)] != group) continue;
    const int id = static_cast<int>(components.size());
    components.emplace_back();
    std::vector<NodeId>& members = components.back();
    component[start.index()] = id;
    members.push_back(start);
    for (std::size_t i = 0; i < members.size(); ++i) {
      const auto [b, e] = slots_of(members[i]);
      for (int s = b; s < e; ++s) {
        if (table[s] >= 0 && component[table[s]] < 0) {
          component[table[s]] = id;
          members.push_back(NodeId(table[s]));
        }
      }
    }
  }

  // Per component: the least breadth-first encoding over the copies of its smallest cell.
  std::vector<std::int32_t> label(nodes, -1);
  std::vector<std::string> forms;
  std::vector<std::int32_t> code, best;
  std::vector<NodeId> order;
  for (const std::vector<NodeId>& members : components) {
    CellId smallest = ctx.layout.cell(members.front());
    for (NodeId n : members) smallest = std::min(smallest, ctx.layout.cell(n));
    best.clear();
    for (NodeId start : members) {
      if (ctx.layout.cell(start) != smallest) continue;
      code.clear();
      order.assign(1, start);
      label[start.index()] = 0;
      for (std::size_t i = 0; i < order.size(); ++i) {
        const NodeId u = order[i];
        code.push_back(ctx.layout.cell(u).value());
        const auto [b, e] = slots_of(u);
        for (int s = b; s < e; ++s) {
          const std::int32_t v = table[s];
          if (v < 0) {
            code.push_back(v == kOwned ? -1 : -2);
            continue;
          }
          if (label[v] < 0) {
            label[v] = static_cast<std::int32_t>(order.size());
            order.push_back(NodeId(v));
          }
          code.push_back(label[v]);
        }
      }
      for (NodeId n : order) label[n.index()] = -1;
      if (best.empty() || code < best) best.swap(code);
    }
    // Decode the least code into text.
    std::ostringstream os;
    std::size_t i = 0;
    int node_label = 0;
    while (i < best.size()) {
      const CellId c(best[i++]);
      if (node_label++ > 0) os << ';';
      os << 'c' << c.value() << '{';
      const auto& patches = ctx.b_patches[c];
      for (std::size_t k = 0; k < patches.size(); ++k, ++i) {
        if (k > 0) os << ',';
        os << patches[k].value() << ':';
        if (best[i] == -1) {
          os << "own";
        } else if (best[i] == -2) {
          os << "none";
        } else {
          os << best[i];
        }
      }
      os << '}';
    }
    forms.push_back(os.str());
  }
  std::sort(forms.begin(), forms.end());
  std::string out;
  for (const std::string& f : forms) {
    if (!out.empty()) out += " | ";
    out += f;
  }
  return out;
}

/// One search variable and its options. Paper: §6 (Algorithm 1: "incomplete B-patches").
struct Variable {
  bool is_owner = true;  ///< owner(patch) when true, partner(node, patch) otherwise
  PatchId patch;
  NodeId node;                 ///< the declined node, for partner variables
  std::vector<NodeId> options; ///< owners, or partners, to try in this order
};

struct Decision {
  bool is_owner = true;
  PatchId patch;
  NodeId node;
  NodeId option;
};

/// The solutions of one group: the values of its slots and the owners of its patches.
struct GroupSolutions {
  std::vector<int> slots;                        ///< the group's slots, in order
  std::vector<std::vector<std::int32_t>> values; ///< per solution, one value per slot
  std::vector<std::vector<NodeId>> owners;       ///< per solution, one owner per group patch
  bool exhausted = false;                        ///< every solution of the group was enumerated
  std::optional<Conflict> conflict;              ///< shallowest refutation, when none was found
  int conflict_depth = 0;
};

/// Algorithm 1 as a depth-first search with an explicit stack. See the file comment.
class ImmersionSearch {
 public:
  ImmersionSearch(const RuleContext& ctx, const SearchOptions& options)
      : ctx_(ctx), options_(options), worklist_(ctx), representative_(ctx.node_count()) {
    worklist_.set_continue_sheets(options.continue_sheets);
  }

  SearchResult run() {
    start_ = Clock::now();
    last_progress_ = start_;
    SearchResult result;

    SearchState root = initial_state(ctx_);
    {
      ++stats_.states;
      StateEditor ed(ctx_, root, worklist_);
      worklist_.push_everything();
      if (!propagate_to_fixpoint(ed, worklist_)) {
        result.status = ImmersionStatus::NotImmersible;
        result.conflict = *ed.take_conflict();
        result.complete = true;
        ++stats_.dead_ends;
        failed_group_ = conflict_group(result.conflict);
        return finish(std::move(result));
      }
    }

    // Independent groups one by one; the immersions are the products of their solutions.
    stats_.groups = ctx_.group_count();
    std::vector<GroupSolutions> groups(ctx_.group_count());
    bool all_exhausted = true;
    for (std::size_t g = 0; g < ctx_.group_count(); ++g) {
      group_index_ = g;
      groups[g] = solve_group(static_cast<int>(g), root);
      all_exhausted = all_exhausted && groups[g].exhausted;
      if (groups[g].values.empty()) {
        if (budget_hit_) break;
        result.status = ImmersionStatus::NotImmersible;
        result.complete = true;
        failed_group_ = static_cast<int>(g);
        const GroupSolutions& failed = groups[g];
        if (failed.conflict) {
          result.conflict = *failed.conflict;
          std::ostringstream os;
          os << "all " << failed_dead_ends_ << " search branches were refuted; shallowest conflict "
             << "(after " << failed.conflict_depth << " branch decisions): " << result.conflict.message;
          result.conflict.message = os.str();
        } else {
          result.conflict.message = "no immersion exists";
        }
        return finish(std::move(result));
      }
      if (budget_hit_) break;
    }
    if (budget_hit_) {
      bool every_group_solved = true;
      for (const GroupSolutions& g : groups) every_group_solved = every_group_solved && !g.values.empty();
      if (!every_group_solved) {
        result.status = ImmersionStatus::SearchBudgetExhausted;
        std::ostringstream os;
        os << "search budget exhausted after " << stats_.states << " states (" << budget_reason_
           << ") before an immersion was found or refuted";
        result.conflict.message = os.str();
        result.complete = false;
        return finish(std::move(result));
      }
    }

    // Cartesian product, first solutions first.
    // Every slot and patch lies in one group, so each product element overwrites all of them:
    // one buffer of slot values and owners serves them all (no copy of the root state's reasons).
    std::vector<std::size_t> pick(groups.size(), 0);
    bool product_done = false;
    std::vector<std::int32_t> slots;
    IdMap<PatchId, NodeId> owners;
    while (!product_done) {
      if (options_.max_immersions != 0 && result.immersions.size() >= options_.max_immersions) break;
      if (slots.empty()) {
        slots = root.slot;
        owners = root.owner;
      }
      for (std::size_t g = 0; g < groups.size(); ++g) {
        const GroupSolutions& sol = groups[g];
        for (std::size_t i = 0; i < sol.slots.size(); ++i) slots[sol.slots[i]] = sol.values[pick[g]][i];
        const auto& patches = ctx_.group_patches[g];
        for (std::size_t i = 0; i < patches.size(); ++i) owners[patches[i]] = sol.owners[pick[g]][i];
      }
      result.immersions.push_back(extract_immersion(ctx_, slots, owners));
      std::size_t g = 0;
      while (g < groups.size() && ++pick[g] == groups[g].values.size()) pick[g++] = 0;
      product_done = g == groups.size();
    }
    result.status = ImmersionStatus::Immersible;
    result.complete = all_exhausted && product_done;
    return finish(std::move(result));
  }

  /// The group a conflict lies in (-1 if it names nothing).
  [[nodiscard]] int conflict_group(const Conflict& c) const {
    if (!c.patches.empty()) return ctx_.patch_group[c.patches.front()];
    if (!c.cells.empty()) return ctx_.cell_group[c.cells.front()];
    if (c.arc.is_valid()) return ctx_.arc_group[c.arc];
    return -1;
  }
  /// The group whose refutation proved NotImmersible (-1 when not applicable).
  [[nodiscard]] int failed_group() const { return failed_group_; }

 private:
  using Clock = std::chrono::steady_clock;
  enum class Outcome { Ok, Conflict, Budget };

  /// Depth-first search of one group from the root fixpoint.
  GroupSolutions solve_group(int group, const SearchState& root) {
    GroupSolutions out;
    for (CellId c : ctx_.group_cells[group]) {
      for (int n = ctx_.first_node(c).value(); n < ctx_.node_end(c); ++n) {
        const int b = ctx_.slot_base[NodeId(n)];
        for (std::size_t i = 0; i < ctx_.b_patches[c].size(); ++i) out.slots.push_back(b + static_cast<int>(i));
      }
    }
    group_forms_.clear();
    failed_dead_ends_ = 0;
    invalidate_choice(group);

    struct Frame {
      SearchState state;
      Decision decision;
      int depth;
    };
    std::vector<Frame> stack;
    SearchState current = root;
    bool have_current = true;
    int depth = 0;
    Variable var;
    while (true) {
      if (!have_current) {
        if (stack.empty()) {
          out.exhausted = true;
          break;
        }
        Frame frame = std::move(stack.back());
        stack.pop_back();
        current = std::move(frame.state);
        invalidate_choice(group);  // a state from a branch point: its changes were not logged
        depth = frame.depth;
        const Outcome o = apply(current, frame.decision, depth, out);
        if (o == Outcome::Budget) break;
        have_current = o == Outcome::Ok;
        continue;
      }
      if (!select_variable(current, group, var)) {
        have_current = false;
        if (accept(current, group, depth, out) && options_.max_immersions != 0 &&
            out.values.size() >= options_.max_immersions) {
          out.exhausted = stack.empty();
          break;
        }
        continue;
      }
      if (var.options.empty()) {
        ++stats_.dead_ends;
        have_current = false;
        continue;
      }
      if (var.options.size() == 1) {
        // A decision without alternatives (the other options are symmetric to this one).
        const Outcome o = apply(current, Decision{var.is_owner, var.patch, var.node, var.options[0]}, depth, out);
        if (o == Outcome::Budget) break;
        have_current = o == Outcome::Ok;
        continue;
      }
      // A branch point: trial connections first (see the file comment).
      const Trial t = try_options(current, group, var, depth, out);
      if (t == Trial::Budget) break;
      if (t == Trial::Dead) {
        have_current = false;
      } else if (t == Trial::Branch) {
        ++stats_.branches;
        ++depth;
        for (std::size_t i = var.options.size() - 1; i >= 1; --i) {
          stack.push_back(Frame{current, Decision{var.is_owner, var.patch, var.node, var.options[i]}, depth});
        }
        std::swap(current, best_first_);
      }
      // Trial::Single and Trial::Forced have already updated `current`.
    }
    return out;
  }

  enum class Trial {
    Branch,  ///< `var` keeps >= 2 surviving options; best_first_ holds the first one, propagated
    Single,  ///< one option survived and was made: `current` is its propagated state
    Forced,  ///< failed owner trials became declines, propagated into `current`
    Dead,    ///< no option of some candidate survived: the state is refuted
    Budget,
  };

  /// Trial connections (paper Algorithm 1, "connectNodes"): every option of `var`, and of the
  /// dual partner variables (see partner_duals), is applied with full propagation on a scratch
  /// copy; refuted options are dropped. A candidate left with no option refutes `st`, one left
  /// with a single option is made at once without branching, and a refuted owner option n of
  /// owner(q) means that n declines q in every completion, which is recorded in `st`. Otherwise
  /// `var` becomes the candidate with the fewest surviving options.
  Trial try_options(SearchState& st, int group, Variable& var, int depth, GroupSolutions& out) {
    candidates_.assign(1, var);
    if (!var.is_owner) partner_duals(st, var, candidates_);
    for (Variable& t : ties_) {
      fill_options(st, t);
      candidates_.push_back(std::move(t));
    }
    std::size_t best = 0, best_survivors = std::numeric_limits<std::size_t>::max();
    std::vector<NodeId> survivors, refuted;
    for (std::size_t c = 0; c < candidates_.size(); ++c) {
      Variable& cand = candidates_[c];
      if (c > 0 && cand.options.size() > 1) drop_symmetric_options(st, cand);
      if (cand.options.size() >= best_survivors) continue;  // cannot do better than `best`
      survivors.clear();
      refuted.clear();
      for (NodeId o : cand.options) {
        scratch_.slot.assign(st.slot.begin(), st.slot.end());
        scratch_.reason.assign(st.reason.begin(), st.reason.end());
        scratch_.owner = st.owner;
        ++stats_.probes;
        const Outcome r = apply(scratch_, Decision{cand.is_owner, cand.patch, cand.node, o}, depth + 1, out);
        if (r == Outcome::Budget) return Trial::Budget;
        if (r == Outcome::Conflict) {
          refuted.push_back(o);
          continue;
        }
        if (survivors.empty()) std::swap(first_, scratch_);
        survivors.push_back(o);
      }
      if (survivors.empty()) return Trial::Dead;
      if (survivors.size() == 1) {
        std::swap(st, first_);
        return Trial::Single;
      }
      if (cand.is_owner && !refuted.empty()) {
        const Outcome r = decline_all(st, cand.patch, refuted, depth, out);
        if (r == Outcome::Budget) return Trial::Budget;
        return r == Outcome::Ok ? Trial::Forced : Trial::Dead;
      }
      if (survivors.size() < best_survivors) {
        best = c;
        best_survivors = survivors.size();
        cand.options = survivors;
        std::swap(best_first_, first_);
      }
    }
    var = std::move(candidates_[best]);
    return Trial::Branch;
  }

  /// The duals of partner(n, q): partner(m, q) for every option m of n that declines q and has
  /// no edge across it yet. Their options are the copies of n's cell, so a symmetry between n and
  /// another copy of its cell (which partner(n, q) cannot see: it fixes n) reduces them.
  void partner_duals(const SearchState& st, const Variable& var, std::vector<Variable>& out) {
    const CellId side = ctx_.layout.cell(var.node);
    for (NodeId m : var.options) {
      if (st.slot[ctx_.slot(m, var.patch)] != kDeclined) continue;
      Variable dual{false, var.patch, m, {}};
      partner_options(st, var.patch, side, &dual.options);
      out.push_back(std::move(dual));
    }
  }

  /// Records that every node of `nodes` declines p (each was refuted as its owner) and
  /// propagates. Counts one state.
  Outcome decline_all(SearchState& st, PatchId p, const std::vector<NodeId>& nodes, int depth,
                      GroupSolutions& out) {
    return run_step(st, depth, out, [&](StateEditor& ed) {
      for (NodeId n : nodes) {
        if (!ed.decline(n, p, Reason{0, -1})) return false;
      }
      return true;
    });
  }

  /// Applies one decision and propagates. Counts one state.
  Outcome apply(SearchState& st, const Decision& d, int depth, GroupSolutions& out) {
    return run_step(st, depth, out, [&](StateEditor& ed) {
      const Reason why{0, -1};
      return d.is_owner ? ed.own(d.option, d.patch, why) : ed.connect(d.node, d.option, d.patch, why);
    });
  }

  /// Budget check, progress, then `edit` and propagation to a fixpoint. Counts one state.
  template <class Edit>
  Outcome run_step(SearchState& st, int depth, GroupSolutions& out, Edit&& edit) {
    if (options_.max_states != 0 && stats_.states >= options_.max_states) {
      budget_hit_ = true;
      budget_reason_ = "max_states = " + std::to_string(options_.max_states);
      return Outcome::Budget;
    }
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    if (options_.time_limit_seconds > 0 && elapsed >= options_.time_limit_seconds) {
      budget_hit_ = true;
      budget_reason_ = "time limit " + text::format_number(options_.time_limit_seconds) + " s";  // 1e-300, not 0.000000
      return Outcome::Budget;
    }
    if (options_.progress && std::chrono::duration<double>(now - last_progress_).count() >= 0.25) {
      last_progress_ = now;
      std::ostringstream os;
      os << "immersion search: group " << group_index_ + 1 << " of " << ctx_.group_count() << ", "
         << stats_.states << " states, " << stats_.branches << " branches, " << stats_.dead_ends
         << " dead ends";
      options_.progress(os.str());
    }
    ++stats_.states;
    StateEditor ed(ctx_, st, worklist_);
    if (edit(ed) && propagate_to_fixpoint(ed, worklist_)) return Outcome::Ok;
    worklist_.clear();
    record_dead_end(*ed.take_conflict(), depth, out);
    return Outcome::Conflict;
  }

  void record_dead_end(Conflict c, int depth, GroupSolutions& out) {
    ++stats_.dead_ends;
    ++failed_dead_ends_;
    if (!out.conflict || depth < out.conflict_depth) {
      out.conflict = std::move(c);
      out.conflict_depth = depth;
    }
  }

  /// A state complete on the group: full rule check, canonical form, de-duplication.
  /// @return true if it is a new solution.
  bool accept(const SearchState& st, int group, int depth, GroupSolutions& out) {
    if (std::optional<Conflict> c = check_all_rules(ctx_, st, group)) {
      ++stats_.rejected;
      record_dead_end(std::move(*c), depth, out);
      return false;
    }
    // De-duplication. When one immersion per group is asked for, the group's first solution is
    // its last and cannot be a duplicate: its canonical form (linear in the graph, but a large
    // share of a first-immersion search on big inputs) is not needed.
    if (options_.max_immersions != 1 &&
        !group_forms_.insert(canonical_form_impl(ctx_, extract_immersion(ctx_, st), group)).second) {
      ++stats_.duplicates;
      return false;
    }
    std::vector<std::int32_t> values(out.slots.size());
    for (std::size_t i = 0; i < out.slots.size(); ++i) values[i] = st.slot[out.slots[i]];
    out.values.push_back(std::move(values));
    std::vector<NodeId> owners;
    for (PatchId p : ctx_.group_patches[group]) owners.push_back(st.owner[p]);
    out.owners.push_back(std::move(owners));
    return true;
  }

  static IdMap<PatchId, int> positions_in_groups(const RuleContext& ctx) {
    IdMap<PatchId, int> pos(ctx.patch_count(), -1);
    for (const std::vector<PatchId>& patches : ctx.group_patches) {
      for (std::size_t i = 0; i < patches.size(); ++i) pos[patches[i]] = static_cast<int>(i);
    }
    return pos;
  }

  [[nodiscard]] bool is_free(NodeId n, const SearchState& st) const {
    const int b = ctx_.slot_base[n];
    const int e = b + static_cast<int>(ctx_.b_patches[ctx_.layout.cell(n)].size());
    for (int s = b; s < e; ++s) {
      if (st.slot[s] == kOwned || st.slot[s] >= 0) return false;
    }
    return true;
  }

  /// representative_[n]: the first copy of n's cell interchangeable with n (n itself if none),
  /// and touched_[n]. Cached per cell for the search's current state: ensure_cell recomputes a
  /// cell whose stamp is stale. refresh_choice makes stale every cell the worklist logged as
  /// dirty (dirty_cells()), invalidate_choice every cell.
  void make_all_cells_stale() {
    if (++epoch_ == 0) {  // wrapped: forget every stamp
      std::fill(cell_epoch_.begin(), cell_epoch_.end(), 0);
      epoch_ = 1;
    }
  }

  /// Fills touched_ and representative_ for the nodes of c, once per epoch. Two free copies
  /// (owning nothing, no edge) with identical slots are interchangeable.
  void ensure_cell(CellId c, const SearchState& st) const {
    if (cell_epoch_[c.index()] == epoch_) return;
    cell_epoch_[c.index()] = epoch_;
    const int first = ctx_.first_node(c).value(), end = ctx_.node_end(c);
    const std::size_t width = ctx_.b_patches[c].size();
    for (int n = first; n < end; ++n) touched_[n] = !is_free(NodeId(n), st);
    for (int n = first; n < end; ++n) {
      representative_[n] = NodeId(n);
      if (end - first < 2 || touched_[n]) continue;
      const auto slots_n = st.slot.begin() + ctx_.slot_base[NodeId(n)];
      for (int m = first; m < n; ++m) {
        if (representative_[m] != NodeId(m) || touched_[m]) continue;
        if (std::equal(slots_n, slots_n + width, st.slot.begin() + ctx_.slot_base[NodeId(m)])) {
          representative_[n] = NodeId(m);
          break;
        }
      }
    }
  }

  /// The copies of p's inner cell that may still own p, one per class of free identical copies
  /// (ensure_cell). @return their number; appended to `out` when given.
  std::size_t owner_options(const SearchState& st, PatchId p, std::vector<NodeId>* out,
                            bool* touched = nullptr) const {
    std::size_t count = 0;
    const CellId c = ctx_.inner[p];
    ensure_cell(c, st);
    const RuleContext::CopySlots at = ctx_.copy_slots(c, p);
    for (int n = ctx_.first_node(c).value(); n < ctx_.node_end(c); ++n) {
      if (st.slot[at.at(NodeId(n))] == kUndecided && representative_[n] == NodeId(n)) {
        ++count;
        if (out) out->push_back(NodeId(n));
        if (touched && touched_[n]) *touched = true;
      }
    }
    return count;
  }

  /// The copies of `other` (a side of p) that may still be glued across p, one per class of free
  /// identical copies. @return their number; appended to `out` when given.
  std::size_t partner_options(const SearchState& st, PatchId p, CellId other, std::vector<NodeId>* out) const {
    std::size_t count = 0;
    if (!other.is_valid()) return count;
    ensure_cell(other, st);
    const RuleContext::CopySlots at = ctx_.copy_slots(other, p);
    for (int m = ctx_.first_node(other).value(); m < ctx_.node_end(other); ++m) {
      const std::int32_t v = st.slot[at.at(NodeId(m))];
      if ((v == kUndecided || v == kDeclined) && representative_[m] == NodeId(m)) {
        ++count;
        if (out) out->push_back(NodeId(m));
      }
    }
    return count;
  }

  // ---- the choice of the next variable ----
  // Every open variable has a key (tier, option count), smaller first, 0 for a variable without
  // options. Tier 0: the variable involves a node already touched (it owns a patch or has an
  // edge), i.e. it continues a partial sheet; tier 1: it would start a new one (focus_ only).
  // The variable chosen is, in the group's patch order (owner(p) first, then partner(n, p) for
  // the declined nodes of p's inner cell, then of its outer cell, lowest node first), the first
  // one with a key <= 1 if there is one, otherwise the first one with the least key.
  //
  // A variable of patch p reads only the slots of the copies of p's two sides (through the
  // symmetry classes of ensure_cell). So patch_key(p), the key of the variable p contributes
  // (the first of p's variables with key <= 1, else the first with p's least key), changes only
  // when a slot of a copy of inner(p) or outer(p) changes, and the choice is the first patch of
  // the group with a key <= 1, else the first with the least key: a minimum over a segment tree
  // of the patch keys (choice_tree_) that is refreshed for the B-patches of the cells the last
  // steps changed (Worklist::dirty_cells) instead of rescanning every patch per state: on piles
  // of overlapping parts that rescan was 60-70 % of the search (issue 19). States that were not
  // reached by logged edits of the indexed state (a branch alternative popped from the stack, a
  // new group) rebuild the tree from scratch. The rescan (scan_variables) is kept: with
  // SearchOptions::incremental_choice off it is the choice itself, and at a real branch point it
  // also collects the tied candidates try_options probes.
  static constexpr std::size_t kNoVariable = std::numeric_limits<std::size_t>::max();

  [[nodiscard]] std::size_t key_of(std::size_t count, bool touched) const {
    constexpr std::size_t kTier = std::size_t{1} << 40;
    if (count == 0) return 0;
    return (focus_ && !touched ? kTier : 0) + count;
  }

  /// The key of the variable patch p contributes (see above), kNoVariable when p has no open
  /// variable; that variable in `out` when given (options not filled).
  std::size_t patch_key(const SearchState& st, PatchId p, Variable* out) const {
    std::size_t best = kNoVariable;
    const auto consider = [&](std::size_t key, bool is_owner, NodeId n) {
      if (key >= best) return;
      best = key;
      if (out) *out = Variable{is_owner, p, n, {}};
    };
    if (!st.owner[p].is_valid()) {
      bool touched = false;
      const std::size_t count = owner_options(st, p, nullptr, focus_ ? &touched : nullptr);
      consider(key_of(count, touched), true, NodeId());
    }
    for (CellId side : {ctx_.inner[p], ctx_.outer[p]}) {
      if (best <= 1 || !side.is_valid()) break;
      const CellId other = side == ctx_.inner[p] ? ctx_.outer[p] : ctx_.inner[p];
      std::size_t count = 0;
      bool counted = false;
      const RuleContext::CopySlots at = ctx_.copy_slots(side, p);
      for (int n = ctx_.first_node(side).value(); n < ctx_.node_end(side) && best > 1; ++n) {
        if (st.slot[at.at(NodeId(n))] != kDeclined) continue;
        if (!counted) {
          count = partner_options(st, p, other, nullptr);  // the same for every n
          counted = true;
        }
        if (focus_) ensure_cell(side, st);
        consider(key_of(count, focus_ && touched_[n]), false, NodeId(n));
      }
    }
    return best;
  }

  /// The next state's choice must be recomputed from scratch (for `group`).
  void invalidate_choice(int group) {
    choice_valid_ = false;
    choice_group_ = group;
  }

  void set_choice_key(std::size_t pos, std::size_t key) {
    std::size_t i = pos + choice_leaves_;
    choice_tree_[i] = key;
    for (i /= 2; i >= 1; i /= 2) choice_tree_[i] = std::min(choice_tree_[2 * i], choice_tree_[2 * i + 1]);
  }

  /// Brings choice_tree_ up to date with `st`: a full rebuild when invalid, otherwise the patch
  /// keys of the group's B-patches of every dirty cell.
  void refresh_choice(const SearchState& st, int group) {
    const std::vector<PatchId>& patches = ctx_.group_patches[group];
    if (!choice_valid_ || choice_group_ != group) {
      worklist_.clear_dirty();
      make_all_cells_stale();
      choice_leaves_ = 1;
      while (choice_leaves_ < patches.size()) choice_leaves_ *= 2;
      choice_tree_.assign(2 * choice_leaves_, kNoVariable);
      for (std::size_t i = 0; i < patches.size(); ++i) {
        choice_tree_[choice_leaves_ + i] = patch_key(st, patches[i], nullptr);
      }
      for (std::size_t i = choice_leaves_ - 1; i >= 1; --i) {
        choice_tree_[i] = std::min(choice_tree_[2 * i], choice_tree_[2 * i + 1]);
      }
      choice_valid_ = true;
      choice_group_ = group;
      ++stats_.choice_rebuilds;
      return;
    }
    const std::vector<CellId>& dirty = worklist_.dirty_cells();
    for (CellId c : dirty) cell_epoch_[c.index()] = 0;  // stale (epochs start at 1)
    for (CellId c : dirty) {
      if (ctx_.cell_group[c] != group) continue;
      for (PatchId p : ctx_.b_patches[c]) {
        if (refreshed_[p.index()] == refresh_stamp_) continue;  // both sides dirty
        refreshed_[p.index()] = refresh_stamp_;
        set_choice_key(static_cast<std::size_t>(patch_position_[p]), patch_key(st, p, nullptr));
      }
    }
    if (++refresh_stamp_ == 0) {
      std::fill(refreshed_.begin(), refreshed_.end(), 0);
      refresh_stamp_ = 1;
    }
    worklist_.clear_dirty();
  }

  /// The open variable of the group chosen by the order above, with its options (one per
  /// symmetry class). @return false when the group is complete.
  bool select_variable(const SearchState& st, int group, Variable& best) {
    ties_.clear();
    if (!options_.incremental_choice) {
      make_all_cells_stale();
      return scan_variables(st, group, best);
    }
    refresh_choice(st, group);
    const std::size_t least = choice_tree_[1];
    if (least == kNoVariable) return false;
    // The leftmost patch whose key is <= max(1, least).
    const std::size_t bound = std::max<std::size_t>(least, 1);
    std::size_t i = 1;
    while (i < choice_leaves_) i = choice_tree_[2 * i] <= bound ? 2 * i : 2 * i + 1;
    const PatchId p = ctx_.group_patches[group][i - choice_leaves_];
    const std::size_t key = patch_key(st, p, &best);
    IMM_ASSERT(key == choice_tree_[i], "immersion search: stale key in the choice of the next variable");
    fill_options(st, best);
    if (best.options.size() > 1) {
      drop_symmetric_options(st, best);
      // A real branch point: try_options also probes the scan's tied candidates.
      if (best.options.size() > 1) return scan_variables(st, group, best);
    }
    return true;
  }

  /// The choice by a scan of every open variable of the group (the same variable as
  /// select_variable's index), collecting up to max_ties_ others with the same key in ties_.
  /// @return false when the group is complete.
  bool scan_variables(const SearchState& st, int group, Variable& best) {
    ties_.clear();
    std::size_t best_key = kNoVariable;
    const auto done = [&] { return best_key <= 1; };
    bool found = false;
    Variable choice;
    for (PatchId p : ctx_.group_patches[group]) {
      if (!st.owner[p].is_valid()) {
        bool touched = false;
        const std::size_t count = owner_options(st, p, nullptr, focus_ ? &touched : nullptr);
        const std::size_t key = key_of(count, touched);
        if (key < best_key) {
          best_key = key;
          choice = Variable{true, p, NodeId(), {}};
          found = true;
          ties_.clear();
        } else if (key == best_key && ties_.size() < max_ties_) {
          ties_.push_back(Variable{true, p, NodeId(), {}});
        }
      }
      for (CellId side : {ctx_.inner[p], ctx_.outer[p]}) {
        if (done() || !side.is_valid()) break;
        const CellId other = side == ctx_.inner[p] ? ctx_.outer[p] : ctx_.inner[p];
        std::size_t count = 0;
        bool counted = false;
        const RuleContext::CopySlots at = ctx_.copy_slots(side, p);
        for (int n = ctx_.first_node(side).value(); n < ctx_.node_end(side) && !done(); ++n) {
          if (st.slot[at.at(NodeId(n))] != kDeclined) continue;
          if (!counted) {
            count = partner_options(st, p, other, nullptr);  // the same for every n
            counted = true;
          }
          if (focus_) ensure_cell(side, st);
          const std::size_t key = key_of(count, focus_ && touched_[n]);
          if (key < best_key) {
            best_key = key;
            choice = Variable{false, p, NodeId(n), {}};
            found = true;
            ties_.clear();
          } else if (key == best_key && ties_.size() < max_ties_) {
            ties_.push_back(Variable{false, p, NodeId(n), {}});
          }
        }
      }
      if (done()) break;
    }
    if (!found) return false;
    best = std::move(choice);
    fill_options(st, best);
    if (best.options.size() > 1) drop_symmetric_options(st, best);
    return true;
  }

  void fill_options(const SearchState& st, Variable& var) {
    var.options.clear();
    if (var.is_owner) {
      owner_options(st, var.patch, &var.options);
    } else {
      const CellId side = ctx_.layout.cell(var.node);
      const CellId other = side == ctx_.inner[var.patch] ? ctx_.outer[var.patch] : ctx_.inner[var.patch];
      partner_options(st, var.patch, other, &var.options);
    }
  }

  /// Breadth-first encoding of the partial component of `start` (edges = Connected slots): per
  /// node its cell and its slot values, partners replaced by their BFS labels. Two nodes with
  /// equal codes are exchanged by an automorphism of the state (the label-to-label map), which
  /// swaps their components or maps one component onto itself. @return whether `watch` lies in
  /// the component.
  bool component_code(const SearchState& st, NodeId start, NodeId watch, std::vector<std::int32_t>& code) {
    code.clear();
    order_.assign(1, start);
    label_[start.index()] = 0;
    for (std::size_t i = 0; i < order_.size(); ++i) {
      const NodeId u = order_[i];
      code.push_back(ctx_.layout.cell(u).value());
      const int b = ctx_.slot_base[u];
      const int e = b + static_cast<int>(ctx_.b_patches[ctx_.layout.cell(u)].size());
      for (int s = b; s < e; ++s) {
        const std::int32_t v = st.slot[s];
        if (v < 0) {
          code.push_back(v);
          continue;
        }
        if (label_[v] < 0) {
          label_[v] = static_cast<std::int32_t>(order_.size());
          order_.push_back(NodeId(v));
        }
        code.push_back(label_[v]);
      }
    }
    const bool contains = watch.is_valid() && label_[watch.index()] >= 0;
    for (NodeId n : order_) label_[n.index()] = -1;
    return contains;
  }

  /// Keeps one option per class of options exchanged by an automorphism of the state (that also
  /// fixes the declined node of a partner variable). Generalises the free-copy symmetry.
  void drop_symmetric_options(const SearchState& st, Variable& var) {
    const NodeId fixed = var.is_owner ? NodeId() : var.node;
    kept_codes_.clear();
    std::vector<NodeId> kept;
    std::vector<std::int32_t> code;
    for (NodeId u : var.options) {
      const bool touches_fixed = component_code(st, u, fixed, code);
      bool equivalent = false;
      if (!touches_fixed) {
        for (const auto& k : kept_codes_) {
          if (k == code) {
            equivalent = true;
            break;
          }
        }
      }
      if (equivalent) continue;
      kept.push_back(u);
      if (!touches_fixed) kept_codes_.push_back(code);
    }
    var.options = std::move(kept);
  }

  SearchResult finish(SearchResult result) {
    stats_.seconds = std::chrono::duration<double>(Clock::now() - start_).count();
    result.stats = stats_;
    return result;
  }

  const RuleContext& ctx_;
  const SearchOptions& options_;
  Worklist worklist_;
  mutable std::vector<NodeId> representative_;
  mutable std::vector<char> touched_ = std::vector<char>(ctx_.node_count(), 0);
  mutable std::vector<std::uint32_t> cell_epoch_ = std::vector<std::uint32_t>(ctx_.cell_count(), 0);
  std::uint32_t epoch_ = 0;
  // The choice of the next variable (refresh_choice): a min segment tree over the patch keys of
  // the group, leaves in group order; patch_position_[p] is p's index in its group's patches.
  std::vector<std::size_t> choice_tree_;
  std::size_t choice_leaves_ = 1;
  bool choice_valid_ = false;
  int choice_group_ = -1;
  IdMap<PatchId, int> patch_position_ = positions_in_groups(ctx_);
  std::vector<std::uint32_t> refreshed_ = std::vector<std::uint32_t>(ctx_.patch_count(), 0);
  std::uint32_t refresh_stamp_ = 1;
  std::vector<std::int32_t> label_ = std::vector<std::int32_t>(ctx_.node_count(), -1);
  std::vector<NodeId> order_;
  std::vector<std::vector<std::int32_t>> kept_codes_;
  std::vector<Variable> candidates_;
  std::vector<Variable> ties_;
  /// How many other variables with the fewest options try_options also tries.
  static constexpr std::size_t max_ties_ = 4;     ///< try_options: the variable and its duals
  SearchState scratch_, first_, best_first_;  ///< try_options: trial states (buffers reused)
  SearchStats stats_;
  const bool focus_ = options_.sheets_first;
  std::unordered_set<std::string> group_forms_;
  std::size_t group_index_ = 0;
  std::size_t failed_dead_ends_ = 0;
  int failed_group_ = -1;
  bool budget_hit_ = false;
  std::string budget_reason_;
  Clock::time_point start_, last_progress_;
};

}  // namespace detail

template <int D>
std::string canonical_form(const CellComplex<D>& complex, const Immersion& immersion) {
  const detail::RuleContext ctx(complex);
  return detail::canonical_form_impl(ctx, immersion);
}

namespace detail {

/// The search state of a complete graph given from outside, in `st`, or the rule a graph breaks
/// that does not even fit the slots (a node of no side of the patch, two values for one slot).
inline std::optional<Conflict> state_of_immersion(const RuleContext& ctx, const Immersion& im,
                                                  SearchState& st) {
  bool same_layout = im.layout.node_count() == ctx.node_count();
  for (NodeId n : ids<NodeId>(ctx.node_count())) {
    same_layout = same_layout && im.layout.cell(n) == ctx.layout.cell(n);
  }
  if (!same_layout) {
    return make_conflict(7, "the graph's nodes are not the winding-number copies of the complex's "
                            "cells", {}, {});
  }
  if (im.owner.size() != ctx.patch_count()) {
    return make_conflict(7, "the ownership table has " + std::to_string(im.owner.size()) +
                                " entries for " + std::to_string(ctx.patch_count()) + " patches",
                         {}, {});
  }
  st.slot.assign(ctx.slot_count(), kUndecided);
  st.reason.assign(ctx.slot_count(), Reason{});
  st.owner = IdMap<PatchId, NodeId>(ctx.patch_count());
  const auto is_node = [&](NodeId n) { return n.is_valid() && n.index() < ctx.node_count(); };
  for (PatchId p : ids<PatchId>(ctx.patch_count())) {
    const NodeId o = im.owner[p];
    if (!is_node(o)) {
      return make_conflict(7, "patch " + std::to_string(p.value()) + " has no owner", {}, {p});
    }
    const CellId c = ctx.layout.cell(o);
    if (c != ctx.inner[p] && c != ctx.outer[p]) {
      return make_conflict(3, ctx.describe(o) + " owns patch " + std::to_string(p.value()) +
                                  ", which does not bound its cell",
                           {o}, {p});
    }
    st.slot[ctx.slot(o, p)] = kOwned;
    st.owner[p] = o;
  }
  for (const ImmersionEdge& e : im.edges) {
    const PatchId p = e.patch;
    if (!p.is_valid() || p.index() >= ctx.patch_count() || !is_node(e.inner) || !is_node(e.outer) ||
        ctx.layout.cell(e.inner) != ctx.inner[p] || ctx.layout.cell(e.outer) != ctx.outer[p]) {
      return make_conflict(1, "an edge does not join copies of the two sides of its patch", {}, {});
    }
    for (const auto& [x, y] : {std::pair{e.inner, e.outer}, std::pair{e.outer, e.inner}}) {
      std::int32_t& v = st.slot[ctx.slot(x, p)];
      if (v == kOwned) {
        return make_conflict(2, ctx.describe(x) + " owns patch " + std::to_string(p.value()) +
                                    " and has an edge across it",
                             {x, y}, {p});
      }
      if (v >= 0) {
        return make_conflict(1, ctx.describe(x) + " has two edges across patch " +
                                    std::to_string(p.value()),
                             {x, y, NodeId(v)}, {p});
      }
      v = y.value();
    }
  }
  return std::nullopt;
}

}  // namespace detail

template <int D>
std::optional<Conflict> check_rules(const CellComplex<D>& complex, const Immersion& immersion) {
  const detail::RuleContext ctx(complex);
  detail::SearchState st;
  if (std::optional<Conflict> c = detail::state_of_immersion(ctx, immersion, st)) return c;
  return detail::check_all_rules(ctx, st);
}

template <int D>
SearchResult find_immersions(const CellComplex<D>& complex, const SearchOptions& options) {
  for (RegionId r : ids<RegionId>(complex.region_count())) {
    IMM_ASSERT(complex.winding_number(r) >= 0,
               "find_immersions: negative winding number (the input inverts space; reject it first)");
  }
  const detail::RuleContext ctx(complex);
  detail::ImmersionSearch search(ctx, options);
  SearchResult result = search.run();
  if (result.status == ImmersionStatus::NotImmersible) {
    // Paper §5.1, Fig. 12 (bottom): without a simple immersion, a cell of winding number >= 2
    // with a non-trivial fundamental group may be wrapped onto itself by a non-simple one. Only
    // cells of the refuted group matter: other groups are independent of it.
    const int group = search.failed_group();
    for (CellId c : ids<CellId>(complex.cell_count())) {
      if (group >= 0 && ctx.cell_group[c] != group) continue;
      if (complex.winding_number(c) >= 2 && !complex.is_simply_connected(complex.region_of(c))) {
        result.status = ImmersionStatus::SelfConnectingCell;
        std::ostringstream os;
        os << "no simple immersion exists, and cell " << c << " (winding number "
           << complex.winding_number(c)
           << ") is not simply connected: it may be self-connecting (paper §5.1, Fig. 12); cut it "
              "and retry (paper §6.2). Search: "
           << result.conflict.message;
        result.conflict.message = os.str();
        result.conflict.cells.insert(result.conflict.cells.begin(), c);
        break;
      }
    }
  }
  return result;
}

}  // namespace imm
