// The immersion search of paper §6 (Algorithm 1), one template for d = 2 and d = 3.
//
// It reads only the combinatorial complex: B-patches and their agreement, and the junction
// cycles of the arcs. The problem is NP-complete (§6.1), so the search has budgets.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/cell_complex.h"
#include "core/immersion_graph.h"

namespace imm {

/// The verdict (exit code 0 for Immersible, 3 otherwise; CONVENTIONS "Errors").
enum class ImmersionStatus {
  Immersible,             ///< at least one immersion found
  NotImmersible,          ///< proven: no graph satisfies Rules 1–7
  SelfConnectingCell,     ///< no simple immersion, and a cell that could be self-connecting exists
  SearchBudgetExhausted,  ///< stopped by --max-states / time limit before a proof either way
};
const char* to_string(ImmersionStatus status);

/// Why the search failed: the rule that could not be satisfied and what it involved.
struct Conflict {
  int rule = 0;                  ///< 1..7 (paper §5.2); 0 when no rule is involved
  std::string message;           ///< names cells, nodes, patches and the arc
  std::vector<CellId> cells;
  std::vector<NodeId> nodes;
  std::vector<PatchId> patches;
  ArcId arc;                     ///< invalid when the conflict is not at an arc
};

struct SearchOptions {
  /// Stop after this many distinct immersions (0 = enumerate all, `--all`).
  std::size_t max_immersions = 1;
  /// Budget on explored search states (each propagation to a fixpoint counts one).
  std::size_t max_states = 50'000'000;
  /// Wall-clock budget in seconds (0 = none).
  double time_limit_seconds = 0.0;
  /// Progress messages (explored states, solutions), called at most a few times per second.
  LogCallback progress;
  /// Branch on variables that continue a partial sheet (a node that owns a patch or has an edge)
  /// before variables that would start a new one; within a tier, fewest options first. Off: the
  /// fewest options over all variables (the order before issue 19). Either way the search is
  /// exhaustive and finds the same immersions up to copy permutation; only the order and the
  /// cost differ. On piles of overlapping parts the old order interleaves many partial sheets
  /// and gets lost (issue 19).
  bool sheets_first = true;
  /// Symmetry step during propagation: a node of a partial sheet that must be glued across a
  /// patch, and whose every candidate partner is an untouched copy identical to the others, is
  /// glued to the first of them (immersion_rules.h, propagate_sheet_continuation) instead of
  /// costing one search decision per node.
  bool continue_sheets = true;
  /// Keep the choice of the next variable in an index over the patches that is refreshed only
  /// where the last steps changed a slot, instead of rescanning every open variable per state
  /// (issue 19: on piles of overlapping parts the rescan was most of the search time). The same
  /// variable is chosen either way, so the search visits the same states and finds the same
  /// immersions in the same order; off only to compare the two (tests, benchmarks).
  bool incremental_choice = true;
};

struct SearchStats {
  std::size_t states = 0;      ///< propagations run (search states explored)
  std::size_t branches = 0;    ///< decisions with two or more alternatives
  std::size_t dead_ends = 0;   ///< states refuted by propagation
  std::size_t duplicates = 0;  ///< complete graphs dropped as isomorphic to one already found
  std::size_t probes = 0;      ///< trial propagations of branch options (included in `states`)
  std::size_t groups = 0;      ///< independent subproblems (cells linked by patches and arcs)
  /// Complete graphs the final rule check refused (they are dropped, not returned). Every
  /// complete state the search reaches is a fixpoint of the propagators, which then satisfies
  /// Rules 1–7: a non-zero count means a propagator missed a consequence of its rule (a bug;
  /// the tests require 0).
  std::size_t rejected = 0;
  /// Rebuilds of the choice index from scratch (SearchOptions::incremental_choice): once per
  /// group and once per branch alternative taken from the stack; every other state refreshes it
  /// only where the last steps changed a slot.
  std::size_t choice_rebuilds = 0;
  double seconds = 0.0;
};

struct SearchResult {
  ImmersionStatus status = ImmersionStatus::NotImmersible;
  std::vector<Immersion> immersions;  ///< pairwise non-isomorphic, in discovery order
  bool complete = false;              ///< every immersion was enumerated (the search ran out)
  Conflict conflict;                  ///< set when no immersion was found
  SearchStats stats;
};

/// Finds immersions of a cell complex. Deterministic for a given complex.
/// @pre complex is finalized and every winding number is >= 0.
/// @return up to options.max_immersions pairwise non-isomorphic immersions, each satisfying
///         Rules 1–7. Paper: §6, Algorithm 1, §6.2 (several components).
template <int D>
SearchResult find_immersions(const CellComplex<D>& complex, const SearchOptions& options = {});

/// Checks a complete immersion graph given from outside (another program, a file, a test) against
/// Rules 1–7 with the predicates of the search's final check, which are written from the rules'
/// statements and share no code with the search's propagation.
/// @return the first violated rule (in the order 1, 2, 3, 7, 5, 4, 6), with the nodes, patches
///         and arc involved; std::nullopt when the graph satisfies every rule. A graph that does
///         not fit the complex (node layout, ownership table size, an edge between cells that are
///         not the two sides of its patch) is reported as a violation of Rule 1, 2, 3 or 7.
/// Paper: §5.2 (Theorem 4), §5.3 (Theorem 5: such a graph gives an immersion).
template <int D>
std::optional<Conflict> check_rules(const CellComplex<D>& complex, const Immersion& immersion);

extern template SearchResult find_immersions<2>(const CellComplex<2>&, const SearchOptions&);
extern template SearchResult find_immersions<3>(const CellComplex<3>&, const SearchOptions&);
extern template std::optional<Conflict> check_rules<2>(const CellComplex<2>&, const Immersion&);
extern template std::optional<Conflict> check_rules<3>(const CellComplex<3>&, const Immersion&);

}  // namespace imm
