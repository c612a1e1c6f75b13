// The exact 3D cell complex (paper §4 with d = 3) and the geometry downstream steps need.
// CGAL-free facade: the exact cut geometry sits behind `CutMesh` (dim3/cut_mesh.h, CGAL inside).
//
// How it is built (dim3/refine.cpp, dim3/complex3.cpp):
//  1. candidate triangle pairs (dim3/triangle_pairs.h); every pair is classified with exact
//     orientation predicates on the input doubles (CGAL Epick predicates are exact): a generic
//     intersection is a segment whose two ends are each an input edge crossing the interior of
//     the other triangle. Anything else that touches (a vertex on a triangle, two edges meeting,
//     coplanar overlap, an intersection curve through a vertex) is a defect (exit 2).
//  2. per cut triangle: the intersection segments in its plane (Epeck constructions), their
//     crossings (triple points), and a constrained triangulation of the triangle with them;
//     every intersection point has a symbolic key (input edge x input triangle, or three input
//     triangles), so the sheets agree on it without comparing coordinates.
//  3. patches = connected sub-triangles across uncut edges; arcs = chains of cut edges between
//     triple points (or closed loops), counted once geometrically; at each arc the cyclic order
//     of the four junctions follows from the two sheets' normals (exact signs only).
//  4. regions: patch sides glued through the wedges of every arc give the regions of each
//     connected group of sheets; groups nested inside one another are placed by exact ray
//     casting; winding numbers follow from "+1 across a patch against its normal".
#pragma once

#include <algorithm>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/cell_complex.h"
#include "core/perturbation.h"
#include "dim3/repair_folds.h"
#include "dim3/surface.h"

namespace imm::dim3 {

struct CutMesh;  // exact cut geometry, dim3/cut_mesh.h

/// Axis-aligned box in doubles (display and helper-box placement only).
struct Box3 {
  Point3 lo{0, 0, 0};
  Point3 hi{0, 0, 0};
};

/// The box of a surface's vertices (e.g. for a generated background grid). @pre s has vertices.
inline Box3 bounding_box(const Surface& s) {
  Box3 b{s.vertices.front(), s.vertices.front()};
  for (const Point3& p : s.vertices)
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = std::min(b.lo[d], p[d]);
      b.hi[d] = std::max(b.hi[d], p[d]);
    }
  return b;
}

/// The 3D cell complex with its geometry.
struct Complex {
  CellComplex<3> complex;
  /// The input as the complex sees it: every triangle flipped (v0, v2, v1) when the input was
  /// inside-out (all winding numbers <= 0). Vertex and triangle ids are the file's.
  Surface surface;
  bool reversed = false;

  // ---- the cut mesh in doubles (output and display; never used for decisions) ----
  /// Per-sheet vertices: an intersection point is one vertex per sheet through it (2, or 3 at a
  /// triple point); `cut_point[v]` is its geometric point (the stitch map).
  std::vector<Point3> cut_vertices;
  std::vector<std::uint32_t> cut_point;
  std::vector<Triangle> cut_triangles;               ///< oriented like their input triangle
  std::vector<std::uint32_t> cut_triangle_source;    ///< input triangle of each cut triangle
  std::vector<PatchId> cut_triangle_patch;
  /// Per arc, its geometric points in order along the arc (closed loops repeat the first).
  IdMap<ArcId, std::vector<std::uint32_t>> arc_points;
  std::vector<Point3> points;                        ///< geometric points (rounded)
  IdMap<RegionId, Box3> region_box;                  ///< bounding box of each region's boundary
  IdMap<PatchId, std::size_t> patch_triangle_count;
  IdMap<RegionId, int> region_genus;                 ///< total genus of the region's boundary
  /// True when complex.measure() holds exact volumes (BuildOptions::exact_volumes); false when
  /// it holds the volumes computed in doubles.
  bool exact_volumes = true;

  // ---- counts for reports ----
  std::size_t intersecting_pairs = 0;   ///< input triangle pairs that cross
  std::size_t intersection_points = 0;  ///< edge-triangle crossing points (geometric)
  std::size_t triple_points = 0;
  std::size_t cut_edges = 0;            ///< geometric cut edges (each once, not per sheet)
  std::size_t components = 0;           ///< connected components of the input surface
  std::size_t groups = 0;               ///< connected groups of mutually intersecting components

  std::shared_ptr<const CutMesh> exact;
};

/// A region with negative winding number (or mixed signs): the input folds or inverts space
/// (paper §3, Fig. 8): valid input, not immersible, exit 3.
struct Inversion {
  RegionId region;
  int winding_number = 0;
  std::vector<long> triangles;  ///< some input triangles bounding the region
  std::string message;
};

struct BuildOptions {
  LogCallback progress;  ///< coarse progress messages (stage names, counts)
  /// Exact rational volumes (GMP) for every region. They are inherently large numbers (their
  /// denominators multiply those of every intersection point on the region's boundary) and cost
  /// more than the rest of the complex on inputs with thousands of intersection points; the
  /// search does not read them. When false, every measure is the volume computed in doubles
  /// (converted exactly to a Rational) and Complex::exact_volumes is false.
  bool exact_volumes = true;
  /// Threads for the per-triangle triangulations (0 = all cores). The result is the same for
  /// every value.
  unsigned threads = 0;
  /// Refuse exact contacts (exit 2, every contact listed) instead of resolving them by a
  /// perturbation (DESIGN §5). For users who want to fix their mesh, and for steps that place
  /// their own geometry (helper boxes move instead).
  bool strict = false;
  /// `--repair-folds MAX`: when the input has local folds, move fold vertices by at most MAX
  /// (model units) toward their ring's centroid until every star is embedded (dim3/repair_folds.h),
  /// then build from the repaired surface. Unset: local folds are a verdict (exit 3).
  std::optional<double> repair_folds;
};

/// Exact contacts of the input and how they were resolved (DESIGN §5): the input was replaced by
/// a perturbed copy (core/perturbation.h) on which every exact decision is generic.
struct Contacts {
  /// The contacts as the exact steps found them on the input (coincident vertices from the
  /// validator, then the intersection's contacts), listed up to a cap per kind, with ids.
  ValidationReport found;
  std::vector<std::pair<DefectKind, std::size_t>> counts;  ///< every contact found, per kind
  std::optional<PerturbationSummary> perturbation;  ///< set when resolved
  std::size_t attempts = 0;                         ///< perturbations tried
  /// The perturbed surface (same ids as the input), the one the complex was built from.
  Surface resolved;
};

struct BuildResult {
  ValidationReport report;               ///< non-empty: invalid input (exit 2)
  std::optional<Inversion> inversion;   ///< set: valid input, not immersible (exit 3)
  /// Non-empty: local folds (DefectKind::LocalFold), a not-immersible verdict (exit 3): two
  /// triangles of one vertex star cross beyond the vertex, which no perturbation removes.
  ValidationReport folds;
  /// Set when the input had exact contacts (resolved or not; see Contacts::perturbation).
  std::optional<Contacts> contacts;
  std::shared_ptr<Complex> complex;     ///< set when the complex was built
  /// Set when BuildOptions::repair_folds was given and the input had local folds: the vertices
  /// moved (ok), or why the folds could not be repaired (!ok; `folds` then holds the verdict).
  /// When ok, everything above describes the repaired surface (FoldRepair::surface).
  std::optional<FoldRepair> repair;
  double seconds = 0.0;
};

/// Validates (validate_surface), intersects exactly, and builds the complex. Paper §4.1–4.3.
/// Exact contacts (a vertex on a triangle, an edge through an edge, coplanar overlaps, coincident
/// vertices, an intersection curve through a vertex or an edge) are resolved by an explicit,
/// reproducible perturbation of at most 2^-30 of the diagonal (perturbation_schedule(), the first
/// attempt on which every exact decision is generic), unless `options.strict`; a generic input is
/// never perturbed. The complex then describes the perturbed surface (Complex::surface).
BuildResult build_complex(const Surface& surface, const BuildOptions& options = {});

/// The cut mesh as OBJ, one group `patch_K` per patch (per-sheet vertices), for viewers.
std::string format_cut_mesh_obj(const Complex& c3);

}  // namespace imm::dim3
