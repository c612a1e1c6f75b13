// Internal interfaces between the three translation units of 2D meshing (not installed, not for
// callers outside dim2/, except the stage benchmarks in bench/):
//  - dim2/background.cpp       builds or reads the background triangulation (CGAL CDT + mesher);
//  - dim2/virtual_triangles.cpp cuts every background triangle by the input exactly and returns
//                               its local regions and how they connect (CGAL arrangements);
//  - dim2/mesh2.cpp            expands local regions into per-node atoms and runs the
//                               dimension-generic duplicate-and-connect driver (core/unglue.h).
// CGAL-free on purpose: mesh2.cpp compiles without the exact kernel.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/diagnostics.h"
#include "core/ids.h"
#include "core/local_regions.h"
#include "core/rational.h"
#include "dim2/complex2.h"
#include "dim2/mesh2.h"

namespace imm::dim2::detail {

/// A background triangulation. Triangles are counter-clockwise and non-degenerate.
struct Background {
  std::vector<Point> vertices;                  ///< rounded positions (exact when `exact_vertices` is empty)
  std::vector<std::array<int, 3>> triangles;
  /// Exact positions when some vertex is not a double (conforming meshes: crossing points and
  /// points on constraints); empty when `vertices` are exact.
  std::vector<std::array<Rational, 2>> exact_vertices;
};

/// Generates (CGAL Delaunay mesher) or reads (options.background_path) the background.
/// Defects (unreadable file, bad triangles) go to `report`.
Background make_background(const Complex2& complex, const MeshOptions& options,
                           ValidationReport& report);

/// The local regions of all background triangles and how they connect (core/local_regions.h;
/// elements are triangles, faces are edges, and an adjacency may lie on a patch when the input
/// runs along a background edge), and the curve pieces inside each triangle.
struct LocalRegions : imm::LocalRegions<2> {
  /// A curve piece inside a triangle: `local_region` is on its inner side (for diagnostics).
  struct InnerPiece {
    std::uint32_t local_region;
    PatchId patch;
    std::size_t input_segment;
  };
  std::vector<InnerPiece> inner_pieces;  ///< filled when `record_pieces` is set
};

/// Cuts every background triangle by the input: exact Sutherland–Hodgman clipping of the nearby
/// cut segments, exact local arrangement per cut triangle, region labels, fusions, adjacencies
/// and input-vertex locations. Defects (background not covering the input) go to `report`.
LocalRegions compute_local_regions(const Complex2& complex, const Background& background,
                                   bool record_pieces, ValidationReport& report);

/// CSG baseline (Sifakis et al. 2007, as the paper compares it; dim2/virtual_triangles_csg.cpp):
/// the same local regions computed with exact regularized booleans (CGAL Polygon_set_2) of each
/// nearby region of the complex with the triangle. Meshing uses it with MeshOptions::method = Csg.
LocalRegions compute_local_regions_csg(const Complex2& complex, const Background& background,
                                       bool record_pieces, ValidationReport& report);

/// The assembly stage of meshing (dim2/mesh2.cpp): one atom per graph node per local region,
/// fused across the immersion graph's edges, duplicated and connected by unglue<2>, input
/// vertices embedded. Fills result.mesh, background_triangle, embedding, contents (when
/// `record_contents`; `local` must then hold the inner pieces) and the output counts of
/// result.stats. @pre `local` was computed on `background`.
void assemble(const Complex2& complex, const Immersion& immersion, const Background& background,
              const LocalRegions& local, bool record_contents, MeshResult& result);

}  // namespace imm::dim2::detail
