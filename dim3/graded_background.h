// A graded background tet mesh (issue 17 item 3): the Kuhn grid of dim3/tet_mesh.h, refined by
// conforming longest-edge bisection toward the input surface and further toward near
// self-intersections (two separate pieces of the surface within about one element of each other:
// the comb's teeth, the mouth's lips), so that elements are small where the input needs them and
// large inside and outside. CGAL-free.
//
// Scheme: Maubach's bisection of tagged simplices (Maubach 1995; Traxler 1997; Stevenson 2008),
// which on the Kuhn (Freudenthal) grid is newest-vertex bisection of 3D: every tet is
// (x0, x1, x2, x3) with a tag k = 3 - level mod 3, bisected at the edge x0-xk. Three bisections
// turn a Kuhn tet of cube side h into 8 Kuhn tets of side h/2, so every tet is similar to one of
// three shapes (levels 0, 1, 2 mod 3) and the dihedral angles stay bounded below
// (kGradedMinDihedralBound). Conformity comes from the closure step: any tet with a vertex at the
// midpoint of one of its edges is bisected again, until none is; the result has no hanging vertex
// (tests/dim3/graded_background_test.cpp checks it exactly on the integer lattice).
//
// Exactness: all vertices are points of an integer lattice (spacing `unit`, a 12-bit mantissa
// times a power of two), and `origin` is a multiple of a power of two small enough that
// origin + i * unit is a double exactly for every lattice index i. So the doubles ARE the lattice
// points, every tet's orientation is the sign of an integer determinant (made positive), and the
// mesher's exact predicates see exactly the conforming mesh built here.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "dim3/tet_mesh.h"

namespace imm::dim3 {

/// Sizes of a graded background, as grid resolutions (cubes along the longest side of the input's
/// box, like MeshOptions::resolution), so that a graded mesh and a uniform grid compare directly.
struct GradedOptions {
  /// Cube side far from the surface: longest / far_resolution, rounded to the surface cube side
  /// times the nearest power of two (at least 1).
  int far_resolution = 8;
  /// Cube side of the tets that meet the surface: exactly longest / surface_resolution.
  int surface_resolution = 32;
  /// Cube side where two pieces of the surface that are not connected near each other come
  /// within about one element (near self-intersections): surface side / 2^j with 2^j the power of
  /// two nearest to gap_resolution / surface_resolution. 0 = surface_resolution (no extra level).
  int gap_resolution = 0;
  /// Stop with an OutOfRange defect instead of building more tets than this.
  std::size_t max_tets = 50'000'000;
  /// Progress while building (a large background takes tens of seconds before it is done or
  /// refused): the sizes at the start, then every `progress_every` tets counted (the count
  /// before building, when it runs) or made (with the base tets refined, or the closure sweep).
  LogCallback progress;
  std::size_t progress_every = 4'000'000;
};

/// How a front end names the three resolutions (the program's flags or the library's fields).
struct GradedOptionNames {
  const char* far;      ///< "--resolution"
  const char* surface;  ///< "--surface-resolution"
  const char* gap;      ///< "--gap-resolution"
};

/// The order the sizes keep (finer toward the surface, finer again at gaps): 1 <= far_resolution
/// <= surface_resolution <= gap_resolution (gap 0: not given). @return empty when kept, else the
/// first bound broken, in `names` ("--surface-resolution 4 is coarser than --resolution 8").
std::string graded_order_error(const GradedOptions& options, const GradedOptionNames& names);

struct GradedStats {
  double far_size = 0.0;      ///< cube side of the base grid
  double surface_size = 0.0;  ///< cube side at the surface
  double gap_size = 0.0;      ///< cube side at near self-intersections
  int surface_levels = 0;     ///< halvings of the cube side from far to surface
  int gap_levels = 0;         ///< further halvings from surface to gap
  std::size_t base_tets = 0;  ///< tets of the base Kuhn grid
  std::size_t tets = 0;
  std::size_t vertices = 0;
  std::size_t surface_tets = 0;  ///< tets whose box meets an input triangle
  std::size_t gap_tets = 0;      ///< tets at the gap size (refined for a near self-intersection)
  std::size_t closure_bisections = 0;  ///< bisections made only to remove hanging vertices
  int closure_sweeps = 0;              ///< passes over all tets until none had a hanging vertex
  double min_dihedral_deg = 0.0;
  double max_dihedral_deg = 0.0;
  double seconds = 0.0;
};

struct GradedBackground {
  ValidationReport report;  ///< OutOfRange: too many tets, or a box too far from the origin
  TetMesh mesh;             ///< positively oriented, conforming
  /// Per vertex: its lattice index; mesh.vertices[v][d] == origin[d] + lattice[v][d] * unit
  /// exactly (in doubles).
  std::vector<std::array<std::int32_t, 3>> lattice;
  Point3 origin{0, 0, 0};
  double unit = 0.0;
  std::int32_t base_cube = 0;  ///< lattice units per base grid cube
  std::vector<std::uint8_t> level;  ///< per tet: bisections from its base Kuhn tet
  GradedStats stats;
};

/// The smallest dihedral angle, in degrees, of the three tet shapes Kuhn bisection produces (the
/// Kuhn tet and its two bisection descendants before the cube halves): every graded background
/// has all its dihedral angles at least this: 45 degrees (and at most 120).
double graded_min_dihedral_bound();

/// Builds the graded background of `surface` (its triangles decide the refinement; vertices no
/// triangle uses are ignored) over `box`, with a margin of at least one base cube, shifted per
/// `attempt` like make_grid_background so that a retry after a non-generic contact lands
/// elsewhere. Deterministic: the same input gives the same mesh, vertex and tet order included.
/// @pre far_resolution >= 1, surface_resolution >= 1, box finite with positive size.
GradedBackground make_graded_background(const Surface& surface, const Box3& box, const GradedOptions& options,
                                        int attempt = 0);

/// `v` times the power of two that brings its largest component into [1, 2) (unchanged when it is
/// zero or not finite): angles and signs of products computed from it neither overflow nor
/// underflow at any input scale (|x| from 1e-300 to 1e300). Exact unless a much smaller component
/// becomes subnormal (report-only quantities: dihedral angles, radius-edge ratios).
Point3 scaled_to_unit(Point3 v);

/// Smallest and largest dihedral angle (degrees) over the tets of `mesh` (doubles; for reports).
std::array<double, 2> dihedral_range(const TetMesh& mesh);

}  // namespace imm::dim3
