// The immersion search of paper §6 (Algorithm 1), one template for d = 2 and d = 3.
//
// It reads only the combinatorial complex: B-patches and their agreement, and the junction
// cycles of the arcs. The problem is NP-complete (§6.1), so the search has budgets.
#pragma once

#include <cstddef>
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
};

struct SearchStats {
  std::size_t states = 0;      ///< propagations run (search states explored)
  std::size_t branches = 0;    ///< decisions with two or more alternatives
  std::size_t dead_ends = 0;   ///< states refuted by propagation
  std::size_t duplicates = 0;  ///< complete graphs dropped as isomorphic to one already found
  std::size_t probes = 0;      ///< trial propagations of branch options (included in `states`)
  std::size_t groups = 0;      ///< independent subproblems (cells linked by patches and arcs)
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

extern template SearchResult find_immersions<2>(const CellComplex<2>&, const SearchOptions&);
extern template SearchResult find_immersions<3>(const CellComplex<3>&, const SearchOptions&);

}  // namespace imm
