// 3D meshing of an immersion (paper §7): local regions of the background tets
// (dim3/virtual_tets.cpp) become per-node atoms, glued through the immersion graph, and the
// dimension-generic driver (core/unglue.h) duplicates and connects the tets.
// CGAL-free: the exact work happens in virtual_tets.cpp.
#include "dim3/mesh3.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <utility>

#include "core/huge_pages.h"
#include "core/parallel.h"
#include "core/unglue.h"
#include "dim3/mesh3_detail.h"

namespace imm::dim3 {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
/// Attempts at a generic contact before a non-generic one is reported: generated grids (each
/// shifted), or translations of the input relative to a read background.
constexpr int kMaxAttempts = 5;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The box of the vertices the triangles use: an unused vertex (issue 13) neither stretches a
/// generated grid nor needs covering. @pre s has a triangle.
Box3 used_bounding_box(const Surface& s) {
  const Point3& first = s.vertices[s.triangles.front()[0]];
  Box3 b{first, first};
  for (const Triangle& t : s.triangles)
    for (std::uint32_t v : t)
      for (int d = 0; d < 3; ++d) {
        b.lo[d] = std::min(b.lo[d], s.vertices[v][d]);
        b.hi[d] = std::max(b.hi[d], s.vertices[v][d]);
      }
  return b;
}

}  // namespace

namespace detail {

std::vector<char> helper_nodes(const Complex& complex, const Immersion& immersion, std::size_t input_triangles) {
  const NodeLayout& layout = immersion.layout;
  std::vector<char> helper_node(layout.node_count(), 0);
  if (input_triangles >= complex.surface.triangle_count()) return helper_node;
  const std::vector<std::vector<NodeId>> components = immersion.components();
  std::vector<std::size_t> component_of(layout.node_count(), 0);
  for (std::size_t k = 0; k < components.size(); ++k)
    for (NodeId n : components[k]) component_of[n.index()] = k;
  std::vector<char> owns_user_patch(components.size(), 0);
  for (std::size_t x = 0; x < complex.cut_triangles.size(); ++x)
    if (complex.cut_triangle_source[x] < input_triangles)
      owns_user_patch[component_of[immersion.owner[complex.cut_triangle_patch[x]].index()]] = 1;
  for (std::size_t n = 0; n < helper_node.size(); ++n) helper_node[n] = owns_user_patch[component_of[n]] ? 0 : 1;
  return helper_node;
}

EmittedCopies emit_copies(const UnglueResult<3>& unglued, const std::vector<char>& helper_node,
                          const NodeLayout& layout, std::size_t cell_count, const std::vector<Point3>& vertices,
                          TetMesh& mesh, std::size_t& helper_tets, std::vector<std::size_t>& copies_per_cell,
                          unsigned threads) {
  EmittedCopies out;
  const std::size_t copy_count = unglued.copies.size();
  std::size_t dropped = 0;
  for (std::size_t c = 0; c < copy_count; ++c) dropped += helper_node[unglued.copy_node[c].index()] ? 1 : 0;
  if (dropped == 0) {
    // Every copy is kept (no helper solid): the loop below would number the vertices in order of
    // first use over all copies, which is unglue's own numbering (each class is numbered at its
    // smallest vertex copy, core/unglue.cpp), so every array is a copy of unglue's, made on all
    // threads (this stage was serial, BENCHMARKS.md issue 17).
    const std::size_t tet_base = mesh.tets.size(), vertex_base = mesh.vertices.size();
    const std::size_t vertex_count = unglued.vertex_source.size();
    IMM_ASSERT(tet_base + copy_count < kNone && vertex_base + vertex_count < static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()),
               "too many output tets or vertices");
    out.copy_index.resize(copy_count);
    out.source_element.resize(copy_count);
    out.vertex_source.resize(vertex_count);
    mesh.tets.resize(tet_base + copy_count);
    mesh.reference.resize(tet_base + copy_count);
    mesh.vertices.resize(vertex_base + vertex_count);
    const unsigned workers = std::max(1u, threads);
    std::vector<std::vector<std::size_t>> per_cell(workers, std::vector<std::size_t>(cell_count, 0));
    constexpr std::size_t kBlock = 1 << 14;
    parallel_for(workers, (copy_count + kBlock - 1) / kBlock, [&](std::size_t b, unsigned worker) {
      for (std::size_t c = b * kBlock; c < std::min(copy_count, (b + 1) * kBlock); ++c) {
        out.copy_index[c] = static_cast<std::uint32_t>(tet_base + c);
        Tet& tet = mesh.tets[tet_base + c];
        for (int k = 0; k < 4; ++k) tet[k] = static_cast<int>(vertex_base) + unglued.copies[c][k];
        mesh.reference[tet_base + c] = unglued.copy_node[c].value();
        out.source_element[c] = static_cast<int>(unglued.copy_element[c]);
        ++per_cell[worker][layout.cell(unglued.copy_node[c]).index()];
      }
    }, 1);
    parallel_blocks(workers, vertex_count, kBlock, [&](std::size_t begin, std::size_t end) {
      for (std::size_t v = begin; v < end; ++v) {
        out.vertex_source[v] = unglued.vertex_source[v];
        mesh.vertices[vertex_base + v] = vertices[static_cast<std::size_t>(unglued.vertex_source[v])];
      }
    });
    copies_per_cell.assign(cell_count, 0);
    for (const std::vector<std::size_t>& counts : per_cell)
      for (std::size_t cell = 0; cell < cell_count; ++cell) copies_per_cell[cell] += counts[cell];
    return out;
  }
  out.copy_index.assign(unglued.copies.size(), kNone);
  std::vector<std::int32_t> vertex_index(unglued.vertex_source.size(), -1);
  copies_per_cell.assign(cell_count, 0);
  for (std::size_t c = 0; c < unglued.copies.size(); ++c) {
    if (helper_node[unglued.copy_node[c].index()]) {
      ++helper_tets;
      continue;
    }
    out.copy_index[c] = static_cast<std::uint32_t>(mesh.tets.size());
    Tet tet{};
    for (int k = 0; k < 4; ++k) {
      std::int32_t& v = vertex_index[static_cast<std::size_t>(unglued.copies[c][k])];
      if (v < 0) {
        v = static_cast<std::int32_t>(mesh.vertices.size());
        out.vertex_source.push_back(static_cast<std::int32_t>(unglued.vertex_source[unglued.copies[c][k]]));
        mesh.vertices.push_back(vertices[static_cast<std::size_t>(out.vertex_source.back())]);
      }
      tet[k] = v;
    }
    mesh.tets.push_back(tet);
    mesh.reference.push_back(unglued.copy_node[c].value());
    out.source_element.push_back(static_cast<int>(unglued.copy_element[c]));
    ++copies_per_cell[layout.cell(unglued.copy_node[c]).index()];
  }
  return out;
}

namespace {

/// assemble(), releasing `*release` (local's adjacencies, or null to keep them) once glued.
void assemble_releasing(const Complex& complex, const Immersion& immersion, const TetMesh& background,
                        const LocalRegions& local, std::vector<LocalRegions::Adjacency>* release,
                        std::size_t input_vertices, std::size_t input_triangles, bool record_contents,
                        MeshResult& result, unsigned threads) {
  const CellComplex<3>& cc = complex.complex;
  const NodeLayout& layout = immersion.layout;
  StageClock clock;
  // 3. Atoms, fusions and adjacencies for the driver.
  // On all threads, in element order (the same lists for every thread count): at millions of
  // background tets this stage was the largest serial one (BENCHMARKS.md, issue 17).
  std::vector<std::array<std::int32_t, 4>> elements;
  elements.reserve(background.tets.size());
  advise_huge_pages(elements);  // written whole below (core/huge_pages.h)
  elements.resize(background.tets.size());
  parallel_blocks(threads, elements.size(), 1 << 16, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      const Tet& tet = background.tets[t];
      elements[t] = {tet[0], tet[1], tet[2], tet[3]};
    }
  });
  AtomExpansion<3> expansion(cc, immersion, local.first, local.region, std::move(elements), threads);
  local.glue(expansion, threads);
  if (release != nullptr) std::vector<LocalRegions::Adjacency>().swap(*release);
  const UnglueInput<3>& input = expansion.input();
  const auto atom_of = [&](std::uint32_t lr, NodeId node) { return expansion.atom(lr, node); };

  result.stats.seconds_atoms = clock.next();
  // 4. Duplicate and connect.
  const UnglueResult<3> unglued = unglue<3>(input, threads);
  result.stats.seconds_unglue = clock.next();
  const std::vector<char> helper_node = helper_nodes(complex, immersion, input_triangles);
  TetMesh& mesh = result.mesh;
  EmittedCopies emitted = emit_copies(unglued, helper_node, layout, cc.cell_count(), background.vertices, mesh,
                                      result.stats.helper_tets, result.stats.copies_per_cell, threads);
  const std::vector<std::uint32_t>& copy_index = emitted.copy_index;
  result.background_tet = std::move(emitted.source_element);
  result.stats.output_tets = mesh.tets.size();
  result.stats.output_vertices = mesh.vertices.size();
  result.stats.seconds_emit = clock.next();

  // 5. Embedding: each input vertex goes into the copy holding the owner of its patch, on the
  // patch's inner side (the owner's copy of the patch is the boundary of the immersed solid).
  result.embedding.resize(input_vertices);
  std::vector<char> used(input_vertices, 0);
  for (const Triangle& t : complex.surface.triangles)
    for (std::uint32_t v : t)
      if (v < input_vertices) used[v] = 1;
  for (std::size_t v = 0; v < input_vertices; ++v) {
    const auto& location = local.vertices[v];
    if (!used[v]) {
      // Not on the surface, so on no patch and in no copy's boundary: left out of the embedding
      // (element -1), listed in the stats and reported as a note by the caller.
      result.stats.unused_vertices.push_back(v);
      continue;
    }
    if (location.local_region == kNone) {
      const Point3& p = complex.surface.vertices[v];
      Defect d;
      d.kind = DefectKind::NotCovered;
      d.stage = "mesh";
      d.message = "the background mesh does not cover input vertex " + std::to_string(v) + " " + format_point(p);
      d.vertices = {static_cast<long>(v)};
      d.points = {{p[0], p[1], p[2]}};
      result.report.add(std::move(d));
      continue;
    }
    const std::uint32_t atom = atom_of(location.local_region, immersion.owner[location.patch]);
    const std::uint32_t copy = copy_index[unglued.atom_copy[atom]];
    IMM_ASSERT(copy != kNone, "an input vertex embedded in a helper box's solid");
    result.embedding[v] = {static_cast<int>(copy), location.weights};
  }

  if (record_contents) {
    result.contents.resize(mesh.tets.size());
    for (std::uint32_t a = 0; a < input.atoms.size(); ++a) {
      const UnglueAtom& atom = input.atoms[a];
      const std::uint32_t copy = copy_index[unglued.atom_copy[a]];
      if (copy == kNone) continue;
      const std::uint32_t lr = local.first[atom.element] + static_cast<std::uint32_t>(atom.local_region);
      result.contents[copy].atoms.push_back({atom.node, local.region[lr], atom.local_region});
    }
    for (const auto& piece : local.embedded) {
      if (!piece.inner) continue;
      const NodeId owner = immersion.owner[complex.cut_triangle_patch[piece.cut_triangle]];
      const std::uint32_t copy = copy_index[unglued.atom_copy[atom_of(piece.local_region, owner)]];
      if (copy != kNone) result.contents[copy].owned_cut_triangles.push_back(piece.cut_triangle);
    }
    for (CopyContent& content : result.contents) {
      auto& s = content.owned_cut_triangles;
      std::sort(s.begin(), s.end());
      s.erase(std::unique(s.begin(), s.end()), s.end());
    }
  }
}

}  // namespace

void assemble(const Complex& complex, const Immersion& immersion, const TetMesh& background,
              const LocalRegions& local, std::size_t input_vertices, std::size_t input_triangles,
              bool record_contents, MeshResult& result, unsigned threads) {
  assemble_releasing(complex, immersion, background, local, nullptr, input_vertices, input_triangles,
                     record_contents, result, threads);
}

void assemble(const Complex& complex, const Immersion& immersion, const TetMesh& background,
              LocalRegions&& local, std::size_t input_vertices, std::size_t input_triangles,
              bool record_contents, MeshResult& result, unsigned threads) {
  assemble_releasing(complex, immersion, background, local, &local.adjacencies, input_vertices,
                     input_triangles, record_contents, result, threads);
}

}  // namespace detail

MeshResult mesh_immersion(const Complex& complex, const Immersion& immersion, const MeshOptions& options,
                            std::size_t input_vertices, std::size_t input_triangles) {
  MeshResult result;
  const auto log = [&](const std::string& message) {
    if (options.progress) options.progress(message);
  };
  IMM_ASSERT(options.resolution >= 1, "resolution must be at least 1");
  input_vertices = std::min(input_vertices, complex.surface.vertex_count());

  // 1-2. Background and local regions. A contact of the input with the background that is not
  // generic is avoided, never guessed: a generated grid is shifted and rebuilt; a read background
  // is kept and the input is translated relative to it by a tiny explicit vector (about 2^-32 of
  // the input's diagonal), for which every decision is again exact.
  auto start = std::chrono::steady_clock::now();
  const Box3 box = used_bounding_box(complex.surface);
  if (options.background_path) {
    TetReadResult read = read_tet_mesh(*options.background_path, options.threads);
    result.report = std::move(read.report);
    result.background = std::move(read.mesh);
    // Tets of either orientation are accepted and turned: a file of negative tets follows the
    // other convention, and a mixed file is either ordered inconsistently (a valid mesh) or
    // folded, which the face pairing refuses (two tets on the same side of their face).
    if (read.reoriented > 0)
      log("meshing: " + std::to_string(read.reoriented) + " of " + std::to_string(result.background.tets.size()) +
          " background tets were negatively oriented and turned");
    if (!result.report.ok()) return result;
    if (options.method == MeshMethod::Csg) {
      result.report = detail::check_background_overlap(result.background);
      if (!result.report.ok()) return result;
    }
  }
  result.stats.seconds_background += seconds_since(start);
  detail::LocalRegions local;
  double diagonal = 0.0;
  for (int d = 0; d < 3; ++d) diagonal += (box.hi[d] - box.lo[d]) * (box.hi[d] - box.lo[d]);
  diagonal = std::sqrt(diagonal);
  for (int attempt = 0;; ++attempt) {
    start = std::chrono::steady_clock::now();
    Point3 shift{0, 0, 0};
    if (options.graded) {
      GradedOptions graded_options = *options.graded;
      if (!graded_options.progress) graded_options.progress = options.progress;
      GradedBackground graded = make_graded_background(complex.surface, box, graded_options, attempt);
      if (!graded.report.ok()) {
        result.report = std::move(graded.report);
        return result;
      }
      result.background = std::move(graded.mesh);
      result.stats.graded = graded.stats;
    } else if (!options.background_path) {
      result.background = make_grid_background(box, options.resolution, attempt);
    } else if (attempt > 0) {
      const double step = std::ldexp(diagonal, -32) * attempt;
      shift = {step, step * 0.6180339887498949, step * 0.41421356237309503};
    }
    result.stats.seconds_background += seconds_since(start);
    result.stats.background_tets = result.background.tets.size();
    log("meshing: " + std::to_string(result.background.tets.size()) + " background tets" +
        (attempt > 0 ? (options.background_path ? " (input shifted by " + format_point(shift) + ")"
                                                : " (grid shifted, attempt " + std::to_string(attempt + 1) + ")")
                     : ""));

    start = std::chrono::steady_clock::now();
    bool non_generic = false;
    ValidationReport report;
    if (options.method == MeshMethod::Csg) {
      IMM_ASSERT(shift == (Point3{0, 0, 0}), "the CSG baseline takes no translation");
      local = detail::compute_local_regions_csg(complex, result.background, options.record_contents, options.threads,
                                               options.progress, report, non_generic);
    } else {
      local = detail::compute_local_regions(complex, result.background, shift, options.record_contents,
                                           options.threads, options.interval_filter, report, non_generic);
    }
    result.stats.seconds_virtual += seconds_since(start);
    result.stats.attempts = attempt + 1;
    result.stats.input_shift = shift;
    // The CSG baseline has no translation: with a read background it reports the contact.
    const bool can_retry = !(options.method == MeshMethod::Csg && options.background_path);
    if (non_generic && can_retry && attempt + 1 < kMaxAttempts) {
      log("meshing: " + report.defects.front().message);
      continue;
    }
    result.report = std::move(report);
    break;
  }
  result.stats.candidate_pairs = local.candidate_pairs;
  result.stats.polygons = local.polygons;
  result.stats.pieces = local.pieces;
  result.stats.cut_tets = local.cut_elements;
  result.stats.side_tests = local.side_tests;
  result.stats.exact_tets = local.exact_tets;
  result.stats.cpu_seconds_exact = local.seconds_exact;
  result.stats.cpu_seconds_booleans = local.seconds_booleans;
  result.stats.seconds_candidates = local.seconds_candidates;
  result.stats.seconds_tets = local.seconds_tets;
  result.stats.seconds_faces = local.seconds_faces;
  result.stats.seconds_regions = local.seconds_regions;
  if (!result.report.ok()) return result;
  log("meshing: " + std::to_string(local.polygons) + " clipped polygons, " + std::to_string(local.cut_elements) +
      " cut tets");

  // 3.-5. Atoms, duplicate and connect, embedding.
  start = std::chrono::steady_clock::now();
  detail::assemble(complex, immersion, result.background, std::move(local), input_vertices, input_triangles,
                   options.record_contents, result, resolve_threads(options.threads));
  result.stats.seconds_assembly = seconds_since(start);
  // DESIGN §4.6: the .emb weights reproduce every vertex within 1e-9 of the diagonal. Measured
  // here, in the doubles a reader has, so a background far larger than the input (whose
  // weights lose digits) is reported instead of silently wrong.
  if (result.report.ok()) {
    double worst = 0.0;
    for (std::size_t v = 0; v < result.embedding.size(); ++v) {
      const EmbeddedVertex3& e = result.embedding[v];
      if (e.element < 0) continue;
      const Tet& tet = result.mesh.tets[static_cast<std::size_t>(e.element)];
      Point3 error{};
      for (int d = 0; d < 3; ++d) {
        double x = 0.0;
        for (int k = 0; k < 4; ++k) x += e.weights[k] * result.mesh.vertices[static_cast<std::size_t>(tet[k])][d];
        error[d] = x - (complex.surface.vertices[v][d] + result.stats.input_shift[d]);
      }
      worst = std::max(worst, std::hypot(error[0], error[1], error[2]));  // no overflow at 1e300
    }
    const double size = std::hypot(box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]);
    result.stats.embedding_error = size > 0 ? worst / size : worst;
  }
  log("meshing: " + std::to_string(result.mesh.tets.size()) + " output tets, " +
      std::to_string(result.mesh.vertices.size()) + " vertices");
  return result;
}

}  // namespace imm::dim3
