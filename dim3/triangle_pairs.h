// Candidate pairs for a surface's self-intersection: the triangle pairs whose closed bounding
// boxes meet (a uniform grid on all threads; CGAL box_self_intersection_d when the boxes' sizes
// vary too much for one grid). One pairing for every exact pass over the
// surface's self-contacts: the refinement (dim3/refine.cpp) and the genericity check of
// generated inputs (dim3/surface_genericity.h). CGAL-free header.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dim3/surface.h"

namespace imm::dim3 {

/// Every pair {a, b}, a < b, of triangles whose closed axis-aligned bounding boxes intersect,
/// sorted (so what is derived from them does not depend on the box algorithm's order). A pair
/// that touches or crosses is always among them; most pairs here do neither. The same list for
/// every `threads` (0 = all cores).
std::vector<std::array<std::uint32_t, 2>> overlapping_triangle_pairs(const Surface& surface, unsigned threads = 1);

}  // namespace imm::dim3
