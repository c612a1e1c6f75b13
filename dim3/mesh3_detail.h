// Internal interface between the translation units of 3D meshing (not for callers outside dim3/,
// except the stage benchmarks in bench/):
//  - dim3/virtual_tets.cpp cuts every background tet by the cut mesh exactly and returns its
//                          local regions and how they connect (CGAL Epeck inside);
//  - dim3/mesh3.cpp        expands local regions into per-node atoms and runs the
//                          dimension-generic duplicate-and-connect driver (core/unglue.h).
// CGAL-free on purpose: mesh3.cpp compiles without the exact kernel.
#pragma once

#include <time.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/ids.h"
#include "core/parallel.h"
#include "core/immersion_graph.h"
#include "core/local_regions.h"
#include "core/unglue.h"
#include "dim3/complex3.h"
#include "dim3/mesh3.h"
#include "dim3/tet_mesh.h"

namespace imm::dim3::detail {

/// The local regions of all background tets and how they connect (core/local_regions.h;
/// elements are tets, faces are triangles; the input meets a background face generically, so
/// every adjacency is input-free), the pieces of cut triangles inside each tet and what the
/// clipping cost.
struct LocalRegions : imm::LocalRegions<3> {
  /// A piece of cut triangle `cut_triangle` inside a tet, seen from one side: `local_region` is
  /// on its inner (negative) side when `inner`, else on its outer side. Filled on request.
  struct Embedded {
    std::uint32_t local_region;
    std::uint32_t cut_triangle;
    bool inner;
  };
  std::vector<Embedded> embedded;

  /// (tet, cut triangle) pairs with overlapping boxes, the tet not certainly on one side of the
  /// triangle's plane (clipping: interval signs; CSG: boxes only)
  std::size_t candidate_pairs = 0;
  std::size_t polygons = 0;         ///< clipped polygons of positive area
  std::size_t pieces = 0;           ///< connected components of the input inside tets
  std::size_t side_tests = 0;       ///< "which side of a piece" tests
  std::size_t exact_tets = 0;       ///< tets redone in exact arithmetic (intervals could not decide)
  /// CPU seconds (summed over threads) in exact arithmetic: clipping, the tets redone in Epeck;
  /// CSG, every tet a cut triangle meets (all of its work is exact; booleans included).
  double seconds_exact = 0.0;
  /// CPU seconds in Nef constructions and booleans (CSG only; clipping has none).
  double seconds_booleans = 0.0;
  /// Wall seconds of the clipping path's stages (zero for the CSG): candidate pairs, the tets
  /// (clipping and merge), face pairing, regions of the uncut local regions (flood fill).
  StageSeconds seconds_candidates, seconds_tets, seconds_faces, seconds_regions;
};

/// The defect of two background tets with the same four vertices (one tet twice): refused by
/// both meshing paths, since an adjacency's face is the three vertices its two tets share
/// (LocalRegions::face) and would be ambiguous.
inline Defect same_vertices_defect(std::uint32_t t, std::uint32_t s, const Tet& vertices) {
  Defect d;
  d.kind = DefectKind::DuplicateFacet;
  d.stage = "background";
  d.message = "background tets " + std::to_string(t) + " and " + std::to_string(s) + " have the same vertices";
  d.facets = {static_cast<long>(t), static_cast<long>(s)};
  d.vertices = {vertices[0], vertices[1], vertices[2], vertices[3]};
  return d;
}

/// Times stages: each call to next() returns the wall, process CPU and calling thread's CPU seconds
/// since the last (or since construction).
class StageClock {
 public:
  StageClock() : wall_(std::chrono::steady_clock::now()), cpu_(cpu(CLOCK_PROCESS_CPUTIME_ID)), serial_(serial()) {}
  StageSeconds next() {
    const auto wall = std::chrono::steady_clock::now();
    const double process = cpu(CLOCK_PROCESS_CPUTIME_ID), thread = serial();
    const StageSeconds s{std::chrono::duration<double>(wall - wall_).count(), process - cpu_, thread - serial_};
    wall_ = wall;
    cpu_ = process;
    serial_ = thread;
    return s;
  }

 private:
  /// The calling thread's CPU outside parallel loops (inside them it is one of the workers).
  static double serial() { return cpu(CLOCK_THREAD_CPUTIME_ID) - loop_cpu_seconds(); }
  static double cpu(clockid_t clock) {
    timespec ts{};
    clock_gettime(clock, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }
  std::chrono::steady_clock::time_point wall_;
  double cpu_;
  double serial_;
};

/// Barycentric coordinates of point p in tet t of `mesh`, for the .emb output only (never for a
/// decision): ratios of determinants in long double. Shared by the clipping and CSG paths.
inline std::array<double, 4> tet_barycentric(const TetMesh& mesh, std::uint32_t t, const Point3& p) {
  std::array<std::array<long double, 3>, 4> v{};
  for (int k = 0; k < 4; ++k)
    for (int d = 0; d < 3; ++d) v[k][d] = mesh.vertices[static_cast<std::size_t>(mesh.tets[t][k])][d];
  const auto det = [](const std::array<std::array<long double, 3>, 4>& q) {
    long double a[3][3];
    for (int r = 0; r < 3; ++r)
      for (int d = 0; d < 3; ++d) a[r][d] = q[r + 1][d] - q[0][d];
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  const long double whole = det(v);
  std::array<double, 4> w{};
  for (int k = 0; k < 4; ++k) {
    auto q = v;
    for (int d = 0; d < 3; ++d) q[k][d] = p[d];
    w[k] = static_cast<double>(det(q) / whole);
  }
  return w;
}

/// Cuts every tet of `background` by the cut mesh of `complex` translated by `shift` (zero, or
/// the tiny translation that makes a read background meet the input generically; the embedding
/// weights then reproduce the translated vertices): exact Sutherland–Hodgman
/// clipping of the cut triangles, pieces, their sides, local regions, fusions, face adjacencies
/// and input-vertex locations, on `threads` threads (0 = all cores; the result does not depend on
/// it: tets are processed in blocks and merged in tet order).
/// A contact of the input with the background that is not generic (an input point on a tet
/// face, an input edge meeting a tet edge, a tet vertex on the input) sets `non_generic` and
/// adds a Touching defect (stage "mesh") naming the tet, the cut triangle and the point; a
/// background that does not cover the input adds NotCovered defects. Either way the result is
/// then incomplete and must not be used.
LocalRegions compute_local_regions(const Complex& complex, const TetMesh& background, const Point3& shift,
                                   bool record_embedded, unsigned threads, bool interval_filter,
                                   ValidationReport& report, bool& non_generic);

/// The CSG baseline (Sifakis et al. 2007, the paper's comparison in §7; dim3/virtual_tets_csg.cpp):
/// the same local regions, fusions, adjacencies and vertex locations as compute_local_regions
/// with a zero shift, from exact Nef polyhedron booleans per cut tet (each tet minus the cut
/// triangles that meet it; the bounded volumes are its local regions), on `threads` threads
/// (0 = all cores; merged in tet order as there, so the result does not depend on it). For
/// checking and timing the clipping path, not for production; `progress` (may be empty) hears
/// every few seconds how far it got. Non-generic contacts set `non_generic` and add a Touching
/// defect, as there; the result is then incomplete.
/// A read background whose tets overlap (dim3/virtual_tets.cpp): two tets on the same side of
/// their shared face (a fold, an inverted tet), or pieces (tets joined across faces) with
/// intersecting interiors; the first defect, or none. compute_local_regions checks the same while
/// it pairs the faces; the CSG baseline, which fails on such a background, is given it first.
ValidationReport check_background_overlap(const TetMesh& background);

LocalRegions compute_local_regions_csg(const Complex& complex, const TetMesh& background, bool record_embedded,
                                       unsigned threads, const LogCallback& progress, ValidationReport& report,
                                       bool& non_generic);

/// Per graph node: 1 when the node belongs to an immersion-graph component owning only patches of
/// helper triangles (ids >= input_triangles): the solid of a helper box, dropped from every
/// output (paper §6.2, §8). All zeros when there are no helper triangles. Shared by the
/// background mesher (assemble) and the conforming mesher (dim3/conforming_mesh3.cpp).
std::vector<char> helper_nodes(const Complex& complex, const Immersion& immersion, std::size_t input_triangles);

/// The kept copies of an unglued mesh as output tets, as both 3D meshers emit them.
struct EmittedCopies {
  std::vector<std::uint32_t> copy_index;   ///< per copy: its output tet, or max() (helper solid)
  std::vector<std::int32_t> vertex_source;  ///< per output vertex: its vertex in `vertices`
  std::vector<int> source_element;          ///< per output tet: the element it copies
};

/// Appends to `mesh` one tet per copy of `unglued` (reference = graph node), with vertices taken
/// from `vertices` (the element mesh's) in order of first use; copies of helper nodes
/// (helper_nodes) are dropped and counted in `helper_tets`; `copies_per_cell` (by CellId) counts
/// the output tets. Shared by assemble and the conforming mesher. On `threads` threads when no
/// copy is dropped (the same arrays for every count).
EmittedCopies emit_copies(const UnglueResult<3>& unglued, const std::vector<char>& helper_node,
                          const NodeLayout& layout, std::size_t cell_count, const std::vector<Point3>& vertices,
                          TetMesh& mesh, std::size_t& helper_tets, std::vector<std::size_t>& copies_per_cell,
                          unsigned threads = 1);

/// The assembly stage of meshing (dim3/mesh3.cpp): one atom per graph node per local region,
/// fused across the immersion graph's edges, duplicated and connected by unglue<3>, helper-box
/// solids dropped, input vertices embedded. Fills result.mesh, background_tet, embedding,
/// contents (when `record_contents`; `local` must then hold the embedded pieces) and the output
/// counts of result.stats; an input vertex the background does not cover adds a NotCovered
/// defect. Atoms, fusions, adjacencies and the unglued copies are built on `threads` threads (the
/// result does not depend on it). @pre `local` was computed on `background`.
void assemble(const Complex& complex, const Immersion& immersion, const TetMesh& background,
              const LocalRegions& local, std::size_t input_vertices, std::size_t input_triangles,
              bool record_contents, MeshResult& result, unsigned threads = 1);
/// The same for a caller done with `local` (mesh_immersion): its adjacencies, the largest array
/// of the meshing (12 bytes per background face), are released once glued, before the unglue
/// allocates, which lowers the peak memory by as much (BENCHMARKS.md, issue 17).
void assemble(const Complex& complex, const Immersion& immersion, const TetMesh& background,
              LocalRegions&& local, std::size_t input_vertices, std::size_t input_triangles,
              bool record_contents, MeshResult& result, unsigned threads = 1);

}  // namespace imm::dim3::detail
