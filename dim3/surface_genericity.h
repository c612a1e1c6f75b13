// The exact genericity check of a surface (paper §3 "non-degenerate"): every self-contact is a
// generic crossing. Used on the procedural inputs (dim3/generators3.h), which are re-drawn or
// built until it passes, and by the tests. CGAL-free header (CGAL predicates inside the .cpp).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "dim3/surface.h"

namespace imm::dim3 {

struct SurfaceGenericity {
  std::size_t intersecting_pairs = 0;  ///< triangle pairs (no shared vertex) that cross
  bool generic = true;
  std::string problem;  ///< the first defect found, when not generic
  /// The crossing triangle pairs (i < j), when asked for.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
};

/// Exact test (CGAL Epick predicates on the doubles, candidate pairs from dim3/triangle_pairs.h) that
/// the surface meets itself only in generic crossings: triangles without a shared vertex
/// either miss each other or cross with every vertex strictly off the other's plane and no edge
/// meeting an edge of the other; triangles sharing one vertex meet only there; triangles
/// sharing an edge do not fold onto each other; no two triangles have the same three vertices.
/// Paper: §3 (non-degenerate input).
/// @param[in] surface   any triangle mesh with valid indices
/// @param[in] keep_pairs  fill `pairs`
SurfaceGenericity check_generic_surface(const Surface& surface, bool keep_pairs = false);

}  // namespace imm::dim3
