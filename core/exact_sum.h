// The exact sum of many rationals, shared by the measures of the 2D and 3D cell complexes
// (dim2/arrangement.cpp: face areas; dim3/complex3.cpp: region volumes). Kept out of
// core/rational.h, which every translation unit includes through core/cell_complex.h.
#pragma once

#include <utility>
#include <vector>

#include "core/rational.h"

namespace imm {

/// The exact sum of `terms` by pairwise (balanced-tree) reduction. The exact area of a large 2D
/// face or the volume of a large 3D region sums many terms with distinct denominators, so the
/// total has a denominator with O(n) digits: a left-to-right sum costs O(n^2) digit operations,
/// the balanced tree O(M(n) log n).
inline Rational tree_sum(std::vector<Rational> terms) {
  if (terms.empty()) return Rational(0);
  while (terms.size() > 1) {
    const std::size_t half = terms.size() / 2;
    for (std::size_t i = 0; i < half; ++i) terms[i] = terms[2 * i] + terms[2 * i + 1];
    if (terms.size() % 2 == 1) {
      terms[half] = std::move(terms.back());
      terms.resize(half + 1);
    } else {
      terms.resize(half);
    }
  }
  return std::move(terms.front());
}

}  // namespace imm
