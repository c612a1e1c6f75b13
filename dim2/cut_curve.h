// Exact geometry of the cut curve: every input segment split at the crossings, grouped by patch.
// This is what meshing (dim2/clip, dim2/background) needs beyond the combinatorial complex.
#pragma once

#include <vector>

#include "core/ids.h"
#include "dim2/kernel.h"

namespace imm::dim2 {

/// A piece of an input segment between two consecutive vertices/crossings, oriented along the
/// (possibly reversed) curve. The patch's inner cell lies on its left.
struct CutSegment {
  Point_2 source;
  Point_2 target;
  PatchId patch;
  std::size_t input_segment;  ///< global input segment id (in the original, unreversed order)
};

struct CutCurve {
  std::vector<Point_2> input_points;           ///< per global input vertex (original order)
  std::vector<CutSegment> segments;            ///< all pieces
  IdMap<PatchId, std::vector<std::size_t>> patch_segments;  ///< indices into `segments`, in curve order
  IdMap<ArcId, Point_2> arc_points;
  /// For each input vertex (original order), the patch it lies on (input vertices are never at a
  /// crossing in valid input).
  std::vector<PatchId> vertex_patch;
};

}  // namespace imm::dim2
