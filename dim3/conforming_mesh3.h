// Conforming immersed tet meshes (issue 18; the paper's future work, §9): a tet mesh of the
// immersed solid whose boundary faces are exactly the triangles of the cut mesh (the input
// refined along its intersection curves), one copy of each cell's tets per graph node, copies
// glued across declined patches, nothing glued across owned ones. The 3D counterpart of
// `immerse mesh --conforming` in 2D (dim2/background.cpp inserts the cut curve as constraints;
// dim2/mesh2.cpp glues copies with the same AtomExpansion / unglue driver used here).
//
// The tets come from TetGen 1.5 (Debian libtet1.5-dev, AGPL-3+): a constrained Delaunay
// tetrahedralization of the cut mesh as a piecewise linear complex with the surface preserved
// (`-pY`: no Steiner point on any cut triangle), refined to a radius-edge bound, an optional
// minimum dihedral angle and a volume bound from the target edge length.
//
// Exactness. The cut mesh's intersection points are rationals; TetGen takes doubles. Before it
// runs, the rounded cut mesh is checked exactly (CGAL Epick predicates on the doubles): distinct
// points stay distinct, no rounded cut triangle is flat, and two cut triangles meet only in
// their shared vertices or edge. A failure is reported (exit 2), never meshed. After TetGen, every
// decision is exact on its output doubles: tets are oriented by the exact orientation predicate,
// each face-connected component of tets (across faces that are not cut triangles) takes the
// region on the side of each cut triangle it touches (exact orientation of the opposite vertex),
// and a component seeing two regions is reported instead of guessed.
// CGAL-free facade; the work happens in dim3/conforming_mesh3.cpp (CGAL predicates + TetGen).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/immersion_graph.h"
#include "dim3/complex3.h"
#include "dim3/mesh3.h"
#include "dim3/tet_mesh.h"

namespace imm::dim3 {

struct ConformingOptions {
  /// Target (largest) edge length inside the cells: TetGen's volume bound is the volume of the
  /// regular tet with this edge. Must be > 0. The cut triangles are kept as they are.
  double edge_length = 1.0;
  /// Radius-edge ratio bound of TetGen's quality refinement (`-q`); at least 1.0. 0 disables
  /// quality refinement (a constrained Delaunay mesh with the volume bound only).
  double radius_edge = 2.0;
  /// Minimum dihedral angle in degrees TetGen aims for (`-q ratio/angle`); 0: none. TetGen
  /// cannot move the preserved surface, so slivers touching it may stay (measured, reported).
  double min_dihedral = 0.0;
  LogCallback progress;
};

struct ConformingStats {
  std::size_t plc_points = 0;     ///< geometric cut-mesh points given to TetGen
  std::size_t plc_triangles = 0;  ///< cut triangles given to TetGen (helper boxes included)
  std::size_t tetgen_points = 0;
  std::size_t tetgen_tets = 0;    ///< tets of the tetrahedralization (before copies)
  std::size_t components = 0;     ///< face-connected tet components across non-surface faces
  std::size_t output_tets = 0;
  std::size_t output_vertices = 0;
  std::size_t helper_tets = 0;    ///< tet copies of helper-box solids, dropped
  std::vector<std::size_t> copies_per_cell;  ///< output tets per cell (by CellId)
  std::vector<std::size_t> unused_vertices;  ///< input vertices no triangle uses (element -1)
  /// Quality of the output tets (doubles, for the report): dihedral angles in degrees and
  /// circumradius / shortest edge.
  double min_dihedral = 0.0;
  double median_dihedral = 0.0;
  double max_radius_edge = 0.0;
  double median_radius_edge = 0.0;
  double sliver_bound = 5.0;      ///< options.min_dihedral, or 5 degrees when none was asked
  std::size_t slivers = 0;        ///< output tets with a dihedral angle below sliver_bound
  /// Of those, the tets with three or four corners on the cut mesh: TetGen may not move or split
  /// the preserved surface, so a skinny cut triangle (intersection curves cut input triangles
  /// into needles and caps) forces flat tets on it.
  std::size_t slivers_at_surface = 0;
  /// Why the slivers are there, each sliver counted once, in this order of precedence:
  ///  - in a narrow wedge: its smallest dihedral angle sits on an edge of the cut mesh where the
  ///    cell's wedge (see min_cell_wedge) is itself below sliver_bound: no mesh avoids it;
  ///  - on a cap: a face is a cut triangle with an angle above 180 - sliver_bound degrees (the
  ///    tets on such a face are nearly flat);
  ///  - on a needle: a face is a cut triangle with an angle below sliver_bound degrees;
  ///  - other: the rest (at the surface without a bad cut-triangle face, or inside).
  std::size_t slivers_in_narrow_wedge = 0;
  std::size_t slivers_on_cap = 0;
  std::size_t slivers_on_needle = 0;
  /// The smallest dihedral angle (degrees) of a cell at an edge of the cut mesh. Around each cut
  /// edge its cut triangles split space into wedges; the tets of a mesh of the cells that share
  /// a piece of that edge fill each cell wedge and their dihedral angles there sum to its angle.
  /// So no tet mesh bounded by the cut surface, with Steiner points anywhere, has a minimum
  /// dihedral angle above this: where sheets cross or fold at a smaller angle, a minimum dihedral
  /// bound is unattainable. 180 when no cut edge bounds a cell. Doubles (report only).
  double min_cell_wedge = 180.0;
  /// Cut-mesh edges whose smallest cell wedge is below sliver_bound.
  std::size_t narrow_wedge_edges = 0;
  double embedding_error = 0.0;   ///< as MeshStats::embedding_error (0: vertices are exact copies)
  double seconds_checks = 0.0;    ///< the exact checks of the rounded cut mesh
  double seconds_tetgen = 0.0;
  double seconds_assembly = 0.0;  ///< labels, copies, union-find, embedding, quality
};

struct ConformingResult {
  /// Non-empty: the rounded cut mesh is not a valid complex, TetGen failed, or its output breaks
  /// an invariant checked here (stage "conforming-mesh"; exit 2). The mesh is then empty.
  ValidationReport report;
  TetMesh mesh;                             ///< reference = graph node
  std::vector<EmbeddedVertex3> embedding;   ///< per user vertex: a tet with that vertex as corner, weight 1
  ConformingStats stats;
  /// TetGen's tets (positively oriented, reference = the region id of each tet's label): what
  /// the glued baseline of `immerse deform --glued` deforms, every copy glued back.
  TetMesh tetrahedralization;
  std::vector<int> source_tet;  ///< per output tet: its tet of `tetrahedralization`
};

/// The exact checks mesh_conforming runs on the rounded cut mesh before TetGen: no two points
/// equal, no flat triangle, two triangles meet only in their shared vertices or their shared
/// edge (exact predicates on the doubles; CGAL Epick). `source_triangle[x]` names the input
/// triangle of triangle x in messages. @return every defect (empty: TetGen may take it).
ValidationReport check_rounded_cut_mesh(const std::vector<Point3>& points,
                                        const std::vector<std::array<std::int32_t, 3>>& triangles,
                                        const std::vector<std::uint32_t>& source_triangle);

/// The default target edge length of a conforming mesh: the side of the background grid's cubes
/// at `resolution` (longest side of the surface's box / resolution). 0 for a flat or empty box.
double conforming_edge_length(const Surface& surface, int resolution);

/// Meshes one immersion of the complex conformingly. `input_vertices` / `input_triangles` count
/// the user's leading vertices and triangles (helper boxes come after them): the solids of graph
/// components owning only helper patches are dropped as in mesh_immersion.
/// @pre `immersion` satisfies Rules 1–7 for `complex.complex`; options.edge_length > 0.
ConformingResult mesh_conforming(const Complex& complex, const Immersion& immersion,
                                   const ConformingOptions& options,
                                   std::size_t input_vertices = static_cast<std::size_t>(-1),
                                   std::size_t input_triangles = static_cast<std::size_t>(-1));

}  // namespace imm::dim3
