// The exact cut mesh of a self-intersecting surface (paper §4.1, d = 3): every input triangle
// split along its intersections with the others, with per-sheet vertices and a stitch map.
// CGAL inside: include only from dim3/*.cpp (and, later, the 3D meshing step).
//
// Every intersection point is identified *symbolically*, by the input features that meet there,
// never by comparing constructed coordinates:
//  - an input edge crossing the interior of an input triangle (EdgeTriangle), or
//  - the common point of three input triangles (TriplePoint).
// Each sheet through a point gets its own vertex (2 for an edge-triangle point, 3 for a triple
// point); `vertex_point` maps them back to the geometric point (the stitch map).
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/diagnostics.h"
#include "core/rational.h"
#include "dim3/surface.h"

namespace imm::dim3 {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;

/// What a geometric point of the cut mesh is.
struct PointOrigin {
  enum class Kind : std::uint8_t { InputVertex, EdgeTriangle, TriplePoint };
  Kind kind = Kind::InputVertex;
  /// InputVertex: {vertex}; EdgeTriangle: {edge, triangle}; TriplePoint: three triangles, sorted.
  std::array<std::uint32_t, 3> ids{0, 0, 0};
};

/// An undirected input edge with its two triangles (the input is a closed 2-manifold).
struct InputEdge {
  std::uint32_t v0 = 0, v1 = 0;  ///< v0 < v1
  std::array<std::uint32_t, 2> triangles{0, 0};
};

/// One geometric cut edge: the piece of the intersection segment of input triangles
/// `triangles[0] < triangles[1]` between two consecutive points of the intersection curve.
/// `side[s][k]` is the sub-triangle of sheet s (the sheet of triangles[s]) adjacent to the piece
/// on the positive (k = 0) or negative (k = 1) side of the *other* sheet's plane.
struct CutPiece {
  std::array<std::uint32_t, 2> points{0, 0};
  std::array<std::uint32_t, 2> triangles{0, 0};
  std::array<std::array<std::uint32_t, 2>, 2> side{};
};

struct CutMesh {
  // ---- geometric points: input vertices first (point id = vertex id) ----
  std::vector<EK::Point_3> points;
  std::vector<PointOrigin> origins;

  // ---- the input's combinatorics ----
  std::vector<InputEdge> edges;
  std::vector<std::array<std::uint32_t, 3>> triangle_edges;  ///< edge k joins corners k and k+1

  // ---- the cut mesh over per-sheet vertices ----
  std::vector<std::uint32_t> vertex_point;  ///< sheet vertex -> geometric point (stitch map)
  std::vector<Triangle> triangles;          ///< oriented like their input triangle
  std::vector<std::uint32_t> triangle_source;
  std::vector<std::uint32_t> first_sub_triangle;  ///< per input triangle (size T + 1)
  /// Pairs of sub-triangles sharing an edge that is not cut (same sheet, same patch).
  std::vector<std::array<std::uint32_t, 2>> uncut_adjacent;
  std::vector<CutPiece> pieces;

  std::size_t intersecting_pairs = 0;
  std::size_t edge_triangle_points = 0;
  std::size_t triple_points = 0;
};

struct RefineResult {
  /// Non-generic contacts and local folds (DefectKind::LocalFold), listed up to a cap per kind;
  /// empty when the mesh was cut.
  ValidationReport report;
  std::vector<std::pair<DefectKind, std::size_t>> counts;  ///< every defect found, per kind
  std::shared_ptr<CutMesh> mesh;
};

/// Intersects the (validated: closed, manifold, oriented, no degenerate triangle) surface with
/// itself exactly and cuts every triangle along the intersection curves. The per-triangle
/// triangulations run on `threads` threads (0 = all cores); the result does not depend on it.
RefineResult refine_surface(const Surface& surface, const LogCallback& progress = {}, unsigned threads = 0);

/// Exact signed volume of the tetrahedron (origin, a, b, c) times 6.
Rational six_signed_volume(const EK::Point_3& a, const EK::Point_3& b, const EK::Point_3& c);

}  // namespace imm::dim3
