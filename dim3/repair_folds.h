// Opt-in repair of local folds (issue 16, `--repair-folds MAX`): a vertex whose star crosses
// itself beyond the vertex bounds no immersed solid there, and no infinitesimal perturbation
// removes the crossing. Such folds in real meshes are usually small (a sliver vertex pushed
// through its own ring), so a user may allow vertices to move by at most MAX to embed their
// stars. Every fold vertex is moved along the segment to the centroid of its ring, by the
// smallest fraction of a fixed schedule (1/64 .. 1) under which no fold remains at it; the
// decision "no fold" is the exact one the complex is built with (refine_surface's exact
// predicates on the moved double coordinates), re-checked on the whole surface after each step,
// and vertices whose moves create new folds elsewhere get the same treatment. The complex is
// then built from the repaired surface, whose positions the .emb embeds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "dim3/surface.h"

namespace imm::dim3 {

struct MovedVertex {
  std::uint32_t vertex = 0;
  Point3 from{}, to{};
  double distance = 0.0;  ///< |to - from|
};

struct FoldRepair {
  bool ok = false;                 ///< every fold removed within the allowed displacement
  Surface surface;                 ///< the repaired surface (same ids as the input)
  std::vector<MovedVertex> moved;  ///< by vertex id
  double max_displacement = 0.0;   ///< the largest move made
  std::size_t checks = 0;          ///< exact whole-surface fold checks run
  /// When !ok: why (the vertices that could not be repaired and the displacement they needed,
  /// or that moving to their ring's centroid does not embed their star).
  std::string failure;
};

/// The local-fold vertices of a (validated) surface, by the exact intersection step
/// (DefectKind::LocalFold); `complete` is false when the step listed only some of them.
std::vector<std::uint32_t> local_fold_vertices(const Surface& surface, unsigned threads, bool* complete = nullptr);

/// Moves fold vertices of `surface` (see above) by at most `max_displacement` each (model units).
/// @pre surface is valid (validate_surface) and has local folds.
FoldRepair repair_folds(const Surface& surface, double max_displacement, unsigned threads = 0);

/// The note every front end prints after a repair: "local folds repaired (--repair-folds 0.1): 1
/// vertex moved by at most 0.25: vertex 6 (...) -> (...); the complex, the mesh and the .emb
/// describe the repaired surface", or the failure.
std::string fold_repair_note(const FoldRepair& repair, double max_displacement);

}  // namespace imm::dim3
