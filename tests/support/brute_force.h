// Brute-force enumeration of immersions of a small cell complex, for cross-checking the search.
//
// Every ownership (one copy of the inner cell per patch) times every gluing (a bijection between
// the remaining inner copies and the outer copies, per patch) is built and filtered by the
// independent checker (immersion_checker.h). Isomorphism classes are found by trying every
// permutation of the copies of every cell, with no use of canonical_form. Neither step shares
// code with core/immersion_rules.h or the search.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "core/cell_complex.h"
#include "core/immersion_graph.h"

namespace imm::test_support {

struct BruteForceResult {
  std::size_t candidates = 0;       ///< graphs built (ownership x gluing choices)
  std::size_t valid = 0;            ///< graphs accepted by the checker (labelled)
  std::vector<Immersion> classes;   ///< one representative per isomorphism class
};

/// Number of candidate graphs: the product over patches of w(inner)!.
template <int D>
double brute_force_candidate_count(const CellComplex<D>& complex);

/// Calls `visit` on every candidate graph: per patch, every choice of its owner among the copies
/// of its inner cell times every bijection between the other inner copies and the outer copies.
/// These are exactly the eligible graphs that satisfy Rules 1, 2, 3 and 7 by construction; Rules
/// 4–6 (the arc rules) hold for some of them only. @return the number of candidates visited.
/// @pre brute_force_candidate_count(complex) <= max_candidates (IMM_ASSERT otherwise).
template <int D>
std::size_t for_each_candidate(const CellComplex<D>& complex,
                               const std::function<void(const Immersion&)>& visit,
                               std::size_t max_candidates = 2'000'000);

/// @pre brute_force_candidate_count(complex) <= max_candidates (IMM_ASSERT otherwise), and the
///      product over cells of w(c)! is at most 100 000.
template <int D>
BruteForceResult brute_force_immersions(const CellComplex<D>& complex,
                                        std::size_t max_candidates = 2'000'000);

extern template std::size_t for_each_candidate<2>(const CellComplex<2>&,
                                                  const std::function<void(const Immersion&)>&,
                                                  std::size_t);
extern template std::size_t for_each_candidate<3>(const CellComplex<3>&,
                                                  const std::function<void(const Immersion&)>&,
                                                  std::size_t);
extern template double brute_force_candidate_count<2>(const CellComplex<2>&);
extern template double brute_force_candidate_count<3>(const CellComplex<3>&);
extern template BruteForceResult brute_force_immersions<2>(const CellComplex<2>&, std::size_t);
extern template BruteForceResult brute_force_immersions<3>(const CellComplex<3>&, std::size_t);

}  // namespace imm::test_support
