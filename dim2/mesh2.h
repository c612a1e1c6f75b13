// 2D meshing of an immersion (paper §7 with d = 2): a background triangulation, virtual
// triangles for near self-intersections (§7.1), one copy of each cell's submesh per graph node,
// copies fused across graph edges, vertices merged by union-find (Teran et al. 2005, §6).
// CGAL-free facade; the exact work happens in dim2/*.cpp.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/embedding.h"
#include "core/immersion_graph.h"
#include "core/unglue.h"
#include "dim2/complex2.h"

namespace imm::dim2 {

/// A plain triangle mesh in doubles (background input, or output).
struct TriangleMesh {
  std::vector<Point> vertices;
  std::vector<std::array<int, 3>> triangles;  ///< counter-clockwise
  std::vector<int> reference;                 ///< per triangle (output: the owning graph node)
};

struct MeshOptions {
  /// Target number of background triangle edges across the bounding-box diagonal.
  int resolution = 24;
  /// Insert the cut curve as constraints (a conforming mesh: no triangle is cut by the input).
  bool conforming = false;
  /// Use this background mesh (Medit .mesh, Dimension 2) instead of generating one.
  std::optional<std::string> background_path;
  /// Fill MeshResult::contents (what every output triangle holds; for tests and diagnostics).
  bool record_contents = false;
  /// Exact clipping (default) or the CSG baseline (exact polygon booleans, slower, same mesh).
  MeshMethod method = MeshMethod::Clip;
  LogCallback progress;
};

/// Where an input vertex sits in the output: triangle (0-based, output order) and barycentric
/// weights of its background triangle that reproduce its position. DESIGN §3 ".emb".
using EmbeddedVertex = imm::EmbeddedVertex<2>;

struct MeshStats {
  std::size_t background_triangles = 0;  ///< triangles of the background mesh
  std::size_t cut_triangles = 0;         ///< background triangles split by the input (2+ local regions)
  std::size_t output_triangles = 0;
  std::size_t output_vertices = 0;
  std::vector<std::size_t> copies_per_cell;  ///< output triangles per cell (by CellId)
  double seconds_background = 0.0;
  double seconds_virtual = 0.0;  ///< clipping + local regions
  double seconds_assembly = 0.0; ///< copies, fusion, union-find
  /// The largest distance, relative to the input's bounding-box diagonal, between an input
  /// vertex and its reproduction from the embedding in doubles. DESIGN §4.6 promises at most
  /// 1e-9; a --background far larger than the input can pass it (the program then warns).
  double embedding_error = 0.0;
};

/// What one output triangle (an element copy) holds. A copy is a union of "atoms": local regions
/// of its background triangle (the pieces of the triangle minus the input, each inside one region)
/// as seen by one graph node; atoms of several nodes share a copy when they are glued through
/// immersion-graph edges across a patch piece inside the triangle (paper §7).
struct CopyContent {
  struct Atom {
    NodeId node;
    RegionId region;        ///< the region the local region lies in (a cell of `node`)
    int local_region = 0;   ///< index of the local region within its background triangle
  };
  std::vector<Atom> atoms;
  /// Input segments (global ids, input order) with a piece in this triangle that this copy
  /// embeds as boundary: the copy holds the owner node of the piece's patch on its inner side.
  std::vector<std::size_t> owned_segments;
};

struct MeshResult {
  ValidationReport report;  ///< e.g. a background mesh that does not cover the input (exit 2)
  TriangleMesh mesh;
  std::vector<EmbeddedVertex> embedding;  ///< per input vertex, original input order
  MeshStats stats;
  /// The background triangulation used (vertices rounded to doubles when they were not exact).
  TriangleMesh background;
  /// Per output triangle: the background triangle it copies (output triangles are sorted by it).
  std::vector<int> background_triangle;
  /// Per output triangle, when MeshOptions::record_contents is set; empty otherwise.
  std::vector<CopyContent> contents;
};

/// Meshes one immersion: background triangulation (generated with CGAL's Delaunay mesher, or
/// read), virtual triangles (the exact local regions of every triangle cut by the input), one
/// copy of each cell's triangles per graph node, copies fused across graph edges, vertex copies
/// merged by union-find (core/unglue.h).
/// @pre `immersion` satisfies Rules 1–7 for `complex.complex`; options.resolution >= 1.
/// @return the mesh, or defects in `report` (unreadable background, background not covering the
///         input). Paper: §7, §7.1 with d = 2.
MeshResult mesh_immersion(const Complex2& complex, const Immersion& immersion,
                          const MeshOptions& options);

/// Reads a Medit .mesh with `Dimension 2`, `Vertices`, `Triangles` (reference numbers ignored).
/// Defects (unreadable, wrong dimension, bad indices) go to `report`.
TriangleMesh read_medit_2d(const std::string& path, ValidationReport& report);

/// Medit .mesh text (Dimension 2; each triangle's reference = its graph node).
std::string format_medit_2d(const TriangleMesh& mesh);
/// .emb text: number of input vertices, then `element w0 w1 w2` per vertex (max_digits10).
using imm::format_embedding;
/// SVG of the output mesh pulled apart: the copies of each graph node offset so the ungluing
/// is visible, coloured by node.
std::string format_mesh_svg(const Complex2& complex, const Immersion& immersion,
                            const MeshResult& result);

}  // namespace imm::dim2
