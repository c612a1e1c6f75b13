// 3D meshing of an immersion (paper §7): a background tet mesh, virtual tets for near
// self-intersections (§7.1), one copy of each cell's tets per graph node, copies fused across
// graph edges, vertices merged by union-find (Teran et al. 2005, §6) — the same
// duplicate-and-connect driver as 2D (core/unglue.h).
// CGAL-free facade; the exact work happens in dim3/virtual_tets.cpp.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/embedding.h"
#include "core/immersion_graph.h"
#include "core/unglue.h"
#include "dim3/complex3.h"
#include "dim3/graded_background.h"
#include "dim3/tet_mesh.h"

namespace imm::dim3 {

/// Largest generated grid resolution (cubes along the longest side of the input's box): 6 x 152^3
/// tets is about 21 million. The program (`mesh --resolution`) and the C++ API refuse larger ones.
inline constexpr int kMaxGridResolution = 150;

struct MeshOptions {
  /// Cubes of the generated background grid along the longest side of the input's box.
  int resolution = 16;
  /// Use this background mesh (.veg, .mesh, .node/.ele) instead of generating one.
  std::optional<std::string> background_path;
  /// Generate a graded background (dim3/graded_background.h) instead of the uniform grid;
  /// `resolution` is then unused.
  std::optional<GradedOptions> graded;
  /// Fill MeshResult::contents (what every output tet holds; for tests and diagnostics).
  bool record_contents = false;
  /// Threads for the virtual tets, clipping or CSG (0 = all cores). The output is identical for
  /// every value.
  unsigned threads = 0;
  /// Decide each tet in interval arithmetic first, exactly only where the intervals cannot
  /// (default). False runs every tet with Epeck: slower, the output is identical (tests compare).
  bool interval_filter = true;
  /// Exact clipping (default) or the CSG baseline (Nef polyhedron booleans per tet, orders of
  /// magnitude slower, the same duplication; for comparisons, Table 2).
  MeshMethod method = MeshMethod::Clip;
  LogCallback progress;
};

/// Where an input vertex sits in the output: tet (0-based, output order) and barycentric weights
/// of its background tet that reproduce its position. DESIGN §3 ".emb".
using EmbeddedVertex3 = imm::EmbeddedVertex<3>;

/// Wall and process CPU seconds (summed over threads) of one stage, and the CPU seconds of the
/// calling thread outside its parallel loops (core/parallel.h, loop_cpu_seconds): the stage's
/// serial part when it ran on two threads or more, so Amdahl's model follows from one run.
struct StageSeconds {
  double wall = 0.0;
  double cpu = 0.0;
  double serial = 0.0;
};

struct MeshStats {
  std::size_t background_tets = 0;
  /// (tet, cut triangle) pairs with overlapping boxes, the tet not certainly on one side of the
  /// triangle's plane (clipping: interval signs; CSG: boxes only)
  std::size_t candidate_pairs = 0;
  std::size_t polygons = 0;         ///< clipped polygons
  std::size_t pieces = 0;
  std::size_t cut_tets = 0;         ///< background tets with two or more local regions
  std::size_t side_tests = 0;
  std::size_t exact_tets = 0;       ///< tets the interval fast path could not decide (redone exactly)
  std::size_t output_tets = 0;
  std::size_t output_vertices = 0;
  /// Attempts at a generic contact: generated grids tried (each shifted), or, with a read
  /// background, translations of the input tried.
  int attempts = 1;
  /// The translation of the input relative to a read background under which every contact is
  /// generic ((0, 0, 0) unless a first attempt met a non-generic contact; then tiny, about
  /// 2^-32 of the input's diagonal). The output mesh is exact for the translated input, and the
  /// embedding reproduces the translated vertices.
  Point3 input_shift{0, 0, 0};
  std::size_t helper_tets = 0;      ///< tets of helper-box solids, dropped from the output
  /// Input vertices no triangle uses: on no patch, so in no copy; their embedding is element -1
  /// (written `-1 0 0 0 0` in the .emb) and the program reports them as a note.
  std::vector<std::size_t> unused_vertices;
  /// The largest distance, relative to the input's bounding-box diagonal, between an input
  /// vertex (translated by input_shift) and its reproduction from the embedding in doubles
  /// (sum of weights times output vertices). DESIGN §4.6 promises at most 1e-9; a background
  /// far larger than the input can pass it (the program then warns).
  double embedding_error = 0.0;
  std::vector<std::size_t> copies_per_cell;  ///< output tets per cell (by CellId)
  GradedStats graded;  ///< sizes and quality of the graded background (MeshOptions::graded)
  double seconds_background = 0.0;
  double seconds_virtual = 0.0;   ///< clipping, pieces, local regions
  double seconds_assembly = 0.0;  ///< atoms, fusion, union-find, outputs
  /// Within seconds_virtual (clipping path; wall): candidate (tet, cut triangle) pairs, the tets
  /// that have candidates (clipping, pieces, sides) and their merge, face pairing, the regions
  /// of the local regions no piece bounds. Within seconds_assembly: atoms and their gluing,
  /// duplicate-and-connect (unglue), output tets and vertices.
  /// Each as wall and process CPU seconds (all threads; on a loaded machine the CPU is the
  /// reliable one).
  StageSeconds seconds_candidates, seconds_tets, seconds_faces, seconds_regions;
  StageSeconds seconds_atoms, seconds_unglue, seconds_emit;
  /// Within the virtual tets, CPU seconds summed over threads (so they can exceed
  /// seconds_virtual): in exact arithmetic (clipping: the tets the intervals could not decide;
  /// CSG: every tet a cut triangle meets, booleans included) and in Nef booleans (CSG only).
  double cpu_seconds_exact = 0.0;
  double cpu_seconds_booleans = 0.0;
};

/// What one output tet (an element copy) holds: local regions of its background tet as seen by
/// graph nodes (several when copies are fused across a graph edge inside the tet), and the cut
/// triangles whose pieces in the tet it embeds as boundary (it holds the owner node of the
/// piece's patch on its inner side).
struct CopyContent {
  struct Atom {
    NodeId node;
    RegionId region;
    int local_region = 0;  ///< index within its background tet
  };
  std::vector<Atom> atoms;
  std::vector<std::uint32_t> owned_cut_triangles;  ///< sorted
};

struct MeshResult {
  ValidationReport report;  ///< unreadable background, not covering, non-generic contact (exit 2)
  TetMesh mesh;
  std::vector<EmbeddedVertex3> embedding;  ///< per input vertex, original input order
  MeshStats stats;
  TetMesh background;                     ///< the background mesh used
  std::vector<int> background_tet;         ///< per output tet: the background tet it copies
  std::vector<CopyContent> contents;      ///< per output tet, when record_contents is set
};

/// Meshes one immersion of the complex.
/// Helper boxes (dim3/self_connecting.h) come after the user's input: `input_vertices` and
/// `input_triangles` count the user's leading vertices and triangles (default: all). Only the
/// user's vertices are embedded, and the tets of every immersion-graph component that owns only
/// helper patches (the solid of a helper box) are dropped: the paper's "discard the cube's
/// component" (§6.2, §8). The user's solid keeps its tets across the box faces, fused through
/// the graph edges there.
/// @pre `immersion` satisfies Rules 1–7 for `complex.complex`; options.resolution >= 1.
/// Paper: §7, §7.1.
MeshResult mesh_immersion(const Complex& complex, const Immersion& immersion, const MeshOptions& options,
                            std::size_t input_vertices = static_cast<std::size_t>(-1),
                            std::size_t input_triangles = static_cast<std::size_t>(-1));

/// .emb text: number of input vertices, then `tet w0 w1 w2 w3` per vertex (max_digits10); an
/// unused input vertex (MeshStats::unused_vertices) is `-1 0 0 0 0`.
using imm::format_embedding;

}  // namespace imm::dim3
