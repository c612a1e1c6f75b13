// The exact 2D cell complex (paper §4 with d = 2) and the geometry downstream steps need.
// CGAL-free facade: the exact geometry sits behind `CutCurve` (dim2/cut_curve.h, CGAL inside).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/cell_complex.h"
#include "core/perturbation.h"
#include "dim2/curves.h"

namespace imm::dim2 {

struct CutCurve;  // exact cut geometry, dim2/cut_curve.h

/// A closed polyline in doubles, for drawing only.
using Loop = std::vector<Point>;

/// The 2D cell complex with its geometry.
struct Complex2 {
  CellComplex<2> complex;
  /// The input curves as the complex sees them: reversed when the input was clockwise. A
  /// reversed curve keeps its first vertex: original (v0, v1, ..., vn-1) becomes
  /// (v0, vn-1, ..., v1). Ids in messages, CutCurve and vertex_patch always refer to the original
  /// (file) order.
  CurveSet curves;
  /// True when every winding number of the input was <= 0 and every curve was reversed
  /// (the paper's figures draw curves clockwise).
  bool reversed = false;

  // ---- display geometry (doubles; never used for decisions) ----
  IdMap<RegionId, std::vector<Loop>> region_boundary;  ///< outer loop first, then holes (empty for region 0)
  /// In curve direction, both ends included: from arc to arc, or for a patch without arc (a
  /// curve without crossings) a closed loop whose first point is repeated at the end.
  IdMap<PatchId, std::vector<Point>> patch_polyline;
  IdMap<ArcId, Point> arc_point;
  /// A point strictly inside each region (computed exactly, then rounded): for labels and tests.
  IdMap<RegionId, Point> region_sample;

  /// Size of the exact arrangement (vertices = input vertices + arcs, edges = cut segments,
  /// faces = regions), for reports and the Euler check V - E + F = 1 + #components.
  std::size_t arrangement_vertices = 0;
  std::size_t arrangement_edges = 0;
  std::size_t arrangement_faces = 0;

  /// Exact geometry (cut segments per patch, arc points, input points), for meshing.
  std::shared_ptr<const CutCurve> exact;
};

/// A region with negative winding number: the input inverts space (paper §3, Fig. 8): exit 3.
struct Inversion {
  RegionId region;
  int winding_number = 0;
  Point sample;  ///< a point inside the region
  std::string message;
};

/// Exact contacts of the input (a vertex on a segment, coincident vertices, collinear overlaps,
/// three segments through one point) and how they were resolved (DESIGN §5): the input was
/// replaced by a perturbed copy (core/perturbation.h) on which every exact decision is generic.
struct Contacts2 {
  ValidationReport found;  ///< the contacts of the input, as the arrangement found them, with ids
  std::vector<std::pair<DefectKind, std::size_t>> counts;  ///< per kind
  std::optional<PerturbationSummary> perturbation;        ///< set when resolved
  std::size_t attempts = 0;                               ///< perturbations tried
  CurveSet resolved;  ///< the perturbed curves (same ids), the ones the complex was built from
};

struct BuildOptions2 {
  /// Refuse exact contacts (exit 2, every contact listed) instead of resolving them.
  bool strict = false;
};

struct BuildResult {
  ValidationReport report;            ///< non-empty: invalid input (exit 2)
  std::optional<Inversion> inversion; ///< set: valid input, not immersible (exit 3)
  std::optional<Contacts2> contacts;  ///< set when the input had exact contacts
  std::shared_ptr<Complex2> complex;  ///< set when the complex was built
  double seconds = 0.0;
};

/// Builds the exact arrangement of all segments (CGAL Arrangement_2 over Epeck), validates
/// genericity (no collinear overlaps, no touching without crossing, no triple points), and
/// extracts regions, winding numbers, patches, arcs and the cyclic junction order at each arc.
/// Exact contacts are resolved by an explicit, reproducible perturbation of at most 2^-30 of the
/// diagonal (the first attempt of perturbation_schedule() on which every decision is generic;
/// Complex2::curves then holds the perturbed curves), unless `options.strict`; a generic input
/// is never perturbed.
/// Paper: §4.1–4.3.
BuildResult build_complex(const CurveSet& curves, const BuildOptions2& options = {});

}  // namespace imm::dim2
