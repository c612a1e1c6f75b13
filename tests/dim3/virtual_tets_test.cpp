// The virtual tets' decisions do not depend on how they are computed: the interval fast path with
// exact fallback, pure Epeck arithmetic, one thread or two, give byte-identical meshes and
// embeddings. And a background that touches the input non-generically (an input vertex on a tet
// face, an input edge along a tet edge) is handled by an explicit translation whose size the
// result reports, with every output tet still accounted for.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include "dim3/generators3.h"
#include "dim3/graded_background.h"
#include "dim3/mesh3.h"
#include "dim3/mesh3_detail.h"
#include "dim3/self_connecting.h"

namespace imm::dim3 {
namespace {

struct Prepared {
  Immersed im;
  [[nodiscard]] const Complex& complex() const { return *im.build.complex; }
  [[nodiscard]] const Immersion& immersion() const { return im.search.immersions.front(); }
};

Prepared prepare(const Surface& surface) {
  ImmerseOptions options;
  options.build.exact_volumes = false;
  Prepared p{immerse_surface(surface, options)};
  EXPECT_TRUE(p.im.build.report.ok()) << p.im.build.report.summary();
  EXPECT_TRUE(p.im.build.complex != nullptr);
  EXPECT_FALSE(p.im.search.immersions.empty());
  return p;
}

MeshResult mesh(const Prepared& p, MeshOptions options) {
  MeshResult m = mesh_immersion(p.complex(), p.immersion(), options, p.im.input_vertices, p.im.input_triangles);
  EXPECT_TRUE(m.report.ok()) << m.report.summary();
  return m;
}

/// Everything a user receives, as text.
std::string fingerprint(const MeshResult& m) {
  return format_medit_3d(m.mesh) + format_embedding(m.embedding);
}

struct Case {
  const char* name;
  std::vector<std::string> args;
  int resolution;
};

class VirtualTetsEquivalence : public testing::TestWithParam<Case> {};

TEST_P(VirtualTetsEquivalence, IntervalsExactAndThreadsGiveTheSameMesh) {
  const Case& c = GetParam();
  const SurfaceGenerateResult g = generate_surface(c.name, c.args);
  ASSERT_TRUE(g.ok()) << g.error;
  const Prepared p = prepare(g.surface);
  if (p.im.search.immersions.empty()) return;
  MeshOptions fast;
  fast.resolution = c.resolution;
  fast.threads = 1;
  const MeshResult reference = mesh(p, fast);
  ASSERT_GT(reference.stats.output_tets, 0u);
  ASSERT_GT(reference.stats.cut_tets, 0u);

  MeshOptions exact = fast;
  exact.interval_filter = false;
  const MeshResult exact_mesh = mesh(p, exact);
  // Without the filter every tet that meets a cut triangle's box runs in Epeck.
  EXPECT_GT(exact_mesh.stats.exact_tets, reference.stats.exact_tets);
  EXPECT_EQ(fingerprint(exact_mesh), fingerprint(reference)) << c.name;

  for (unsigned threads : {2u, 3u}) {
    MeshOptions more = fast;
    more.threads = threads;
    EXPECT_EQ(fingerprint(mesh(p, more)), fingerprint(reference)) << c.name << " on " << threads << " threads";
  }
}

INSTANTIATE_TEST_SUITE_P(
    Generators, VirtualTetsEquivalence,
    testing::Values(Case{"sphere", {}, 8}, Case{"two-spheres", {}, 10}, Case{"tube-overlap", {}, 10},
                    Case{"comb", {}, 10}, Case{"mouth", {}, 10}, Case{"random-blobs", {"3", "5"}, 9},
                    Case{"perturbed-torus", {"24", "2"}, 9}),
    [](const testing::TestParamInfo<Case>& info) {
      std::string name = info.param.name;
      for (char& ch : name)
        if (ch == '-') ch = '_';
      return name + "_" + std::to_string(info.index);
    });

/// Near self-intersection (paper §7.1): the comb's teeth are 1/64 apart, far less than a tet, so
/// the tets at the gap hold two local regions of one region (the comb's only cell): a piece of
/// each tooth, separated by the gap, which is outside. They must become two tet copies. Checked
/// through the embedding, independently of how local regions are found: the tips of neighbouring
/// teeth (input vertices, 1/64 apart, their gap running 6 units up to the bar) are never
/// connected inside one tet, so when both lie in one background tet they are embedded in two
/// different copies of it.
TEST(VirtualTets, TeethInOneTetGetSeparateCopies) {
  constexpr int kTeeth = 3;
  const Surface comb_surface = comb(kTeeth);
  const Prepared p = prepare(comb_surface);
  MeshOptions options;
  options.resolution = 8;
  options.threads = 1;
  const MeshResult m = mesh(p, options);
  ASSERT_EQ(m.embedding.size(), comb_surface.vertex_count());
  // comb(): per z level, 2D points bottom(k) = k, base(k) = b + k, top(k) = 2 b + k for the
  // b = 2 t breakpoints; tooth i spans breakpoints 2 i (left) and 2 i + 1 (right); the z = 1
  // level follows the z = 0 level.
  const std::size_t breakpoints = 2 * kTeeth, per_level = 3 * breakpoints;
  int shared = 0;
  for (int gap = 0; gap + 1 < kTeeth; ++gap) {
    for (std::size_t level : {std::size_t{0}, per_level}) {
      const std::size_t right_tip = level + static_cast<std::size_t>(2 * gap + 1);
      const std::size_t left_tip = level + static_cast<std::size_t>(2 * gap + 2);
      ASSERT_DOUBLE_EQ(comb_surface.vertices[left_tip][0] - comb_surface.vertices[right_tip][0], 1.0 / 64);
      ASSERT_EQ(comb_surface.vertices[left_tip][1], -6.0);
      const int a = m.embedding[right_tip].element, b = m.embedding[left_tip].element;
      ASSERT_GE(a, 0);
      ASSERT_GE(b, 0);
      if (m.background_tet[static_cast<std::size_t>(a)] != m.background_tet[static_cast<std::size_t>(b)]) continue;
      ++shared;
      EXPECT_NE(a, b) << "the tips of teeth " << gap << " and " << gap + 1
                      << " are embedded in one copy of background tet "
                      << m.background_tet[static_cast<std::size_t>(a)];
    }
  }
  EXPECT_GE(shared, 2);  // not vacuous: the gap lies inside tets
  EXPECT_GT(m.stats.cut_tets, 0u);
}

/// The Kuhn grid of [lo, lo + n h]^3 as a background file would give it: lattice points at
/// exact multiples of h (so a box input with vertices on the lattice touches it everywhere).
TetMesh aligned_grid(double lo, double h, int n) {
  TetMesh grid = make_grid_background(Box3{{lo, lo, lo}, {lo + n * h, lo + n * h, lo + n * h}}, n, 0);
  // Snap every vertex to the lattice it approximates (the generator shifts by an odd fraction).
  for (Point3& v : grid.vertices)
    for (double& x : v) x = lo + h * std::round((x - lo) / h);
  return grid;
}

TEST(VirtualTets, BackgroundTouchingTheInputIsMeshedUnderAnExplicitTranslation) {
  // A unit cube whose vertices, edges and faces all lie on lattice planes of the background.
  Surface cube = box_surface(Box3{{0, 0, 0}, {1, 1, 1}});
  const Prepared p = prepare(cube);
  const std::string path = testing::TempDir() + "/aligned_grid.veg";
  {
    std::ofstream out(path);
    out << format_veg(aligned_grid(-1.0, 0.5, 6));
  }
  MeshOptions options;
  options.background_path = path;
  const MeshResult m = mesh(p, options);
  ASSERT_TRUE(m.report.ok());
  EXPECT_GE(m.stats.attempts, 2);
  double shift = 0.0;
  for (double x : m.stats.input_shift) shift = std::max(shift, std::abs(x));
  EXPECT_GT(shift, 0.0);
  EXPECT_LT(shift, 1e-8);
  // The cube covers 8 lattice cubes of side 0.5, each 6 tets; every one lies inside the
  // (translated) cube except for slivers: the tets meeting the cube are exactly those 48 plus the
  // ones the translation makes the cube poke into, each with one copy (winding number 1).
  std::size_t inside = 0;
  for (std::size_t t = 0; t < m.mesh.tets.size(); ++t) {
    double c[3] = {0, 0, 0};
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < 3; ++d) c[d] += 0.25 * m.mesh.vertices[static_cast<std::size_t>(m.mesh.tets[t][k])][d];
    if (c[0] > 0 && c[0] < 1 && c[1] > 0 && c[1] < 1 && c[2] > 0 && c[2] < 1) ++inside;
  }
  EXPECT_EQ(inside, 48u);
  EXPECT_GE(m.stats.output_tets, 48u);
  // Every input vertex is embedded, reproducing the translated vertex.
  ASSERT_EQ(m.embedding.size(), cube.vertex_count());
  for (std::size_t v = 0; v < cube.vertex_count(); ++v) {
    const EmbeddedVertex3& e = m.embedding[v];
    ASSERT_GE(e.element, 0);
    Point3 q{0, 0, 0};
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < 3; ++d)
        q[d] += e.weights[k] * m.mesh.vertices[static_cast<std::size_t>(m.mesh.tets[static_cast<std::size_t>(e.element)][k])][d];
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(q[d], cube.vertices[v][d] + m.stats.input_shift[d], 1e-12);
  }
}

// The cut tets run in blocks, each merged while the next one runs (on one thread in one buffer):
// a contact found only in a middle block must stop the run there and lead to the translated input
// as one in the first block does, with the same mesh on every thread count. The box's face x = 1
// lies on a lattice plane; the background's tets are sorted by x, except that those beyond
// x = 0.9 come at x = 0.5, so that the tets touching that face come after blocks of the other
// faces' cut tets and before more of them.
TEST(VirtualTets, ContactInAMiddleBlockIsResolvedLikeAnEarlyOne) {
  // No two coordinates of a corner differ by a multiple of 1/32 (the Kuhn tets' diagonal planes).
  const Surface box = box_surface(Box3{{0.0100001, 0.0200003, 0.0300007}, {1.0, 0.9700001, 0.9500003}});
  const Prepared p = prepare(box);
  const TetMesh grid = aligned_grid(-0.125, 1.0 / 32, 40);  // lattice planes at -0.125 + k / 32
  std::vector<double> x(grid.tets.size(), 0.0);
  for (std::size_t t = 0; t < grid.tets.size(); ++t) {
    for (int k = 0; k < 4; ++k) x[t] += 0.25 * grid.vertices[static_cast<std::size_t>(grid.tets[t][k])][0];
    if (x[t] > 0.9) x[t] = 0.5;
  }
  std::vector<std::size_t> order(grid.tets.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return x[a] < x[b]; });
  TetMesh sorted;
  sorted.vertices = grid.vertices;
  for (const std::size_t t : order) sorted.tets.push_back(grid.tets[t]);
  // Every tet with a corner on the plane x = 1 comes after the first third and before the last
  // quarter of the order.
  for (std::size_t i = 0; i < sorted.tets.size(); ++i)
    for (int k = 0; k < 4; ++k)
      if (sorted.vertices[static_cast<std::size_t>(sorted.tets[i][k])][0] == 1.0) {
        ASSERT_GT(i, sorted.tets.size() / 3);
        ASSERT_LT(i, sorted.tets.size() * 3 / 4);
      }
  const std::string path = testing::TempDir() + "/late_contact_grid.veg";
  {
    std::ofstream out(path);
    out << format_veg(sorted);
  }
  // The progress log names the contact that stopped each attempt: the first in tet order.
  std::vector<std::string> log;
  MeshOptions options;
  options.background_path = path;
  options.progress = [&log](const std::string& message) { log.push_back(message); };
  options.threads = 1;
  const MeshResult one = mesh(p, options);
  const std::vector<std::string> one_log = log;
  ASSERT_TRUE(one.report.ok()) << one.report.summary();
  EXPECT_GE(one.stats.attempts, 2);
  EXPECT_GT(one.stats.cut_tets, 3u * 4096u);  // several blocks
  ASSERT_GE(one_log.size(), 2u);
  EXPECT_TRUE(one_log[1].find("meets the input non-generically") != std::string::npos) << one_log[1];
  for (const unsigned threads : {2u, 3u}) {
    options.threads = threads;
    log.clear();
    const MeshResult m = mesh(p, options);
    EXPECT_EQ(log, one_log) << threads << " threads";
    EXPECT_EQ(m.stats.attempts, one.stats.attempts) << threads << " threads";
    EXPECT_EQ(m.stats.input_shift, one.stats.input_shift) << threads << " threads";
    EXPECT_EQ(fingerprint(m), fingerprint(one)) << threads << " threads";
  }
}

/// A background read from a file comes in any order. The grid's tets shuffled and each rotated
/// by an even permutation (orientation kept), so that no tet order or vertex order of the
/// generator helps the face pairing or the candidate binning.
TetMesh shuffled(const TetMesh& grid, unsigned seed) {
  std::vector<std::size_t> order(grid.tets.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::mt19937 random(seed);
  std::shuffle(order.begin(), order.end(), random);
  TetMesh out;
  out.vertices = grid.vertices;
  for (std::size_t i : order) {
    Tet t = grid.tets[i];
    if (random() % 2) t = {t[1], t[0], t[3], t[2]};
    if (random() % 2) t = {t[2], t[3], t[0], t[1]};
    out.tets.push_back(t);
  }
  return out;
}

// Local regions: every interior face of the background (found independently, by a map of
// sorted face keys) carries an adjacency between local regions of its two tets, every adjacency
// lies on such a face, and boundary faces carry none; the whole result is the same field for
// field on 1, 2 and 3 threads.
TEST(VirtualTets, FacePairingMatchesAnIndependentPairingOnEveryThreadCount) {
  const SurfaceGenerateResult g = generate_surface("two-spheres", {});
  ASSERT_TRUE(g.ok()) << g.error;
  const Prepared p = prepare(g.surface);
  const TetMesh background = shuffled(make_grid_background(bounding_box(p.complex().surface), 9, 0), 7);
  std::map<std::array<int, 3>, std::vector<std::uint32_t>> tets_of_face;
  for (std::uint32_t t = 0; t < background.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> key{};
      for (int k = 0, n = 0; k < 4; ++k)
        if (k != f) key[static_cast<std::size_t>(n++)] = background.tets[t][static_cast<std::size_t>(k)];
      std::sort(key.begin(), key.end());
      tets_of_face[key].push_back(t);
    }
  std::vector<detail::LocalRegions> results;
  for (unsigned threads : {1u, 2u, 3u}) {
    ValidationReport report;
    bool non_generic = false;
    results.push_back(detail::compute_local_regions(p.complex(), background, {0, 0, 0}, /*record_embedded=*/true,
                                                    threads, /*interval_filter=*/true, report, non_generic));
    ASSERT_TRUE(report.ok()) << report.summary();
    ASSERT_FALSE(non_generic);
  }
  const detail::LocalRegions& r = results.front();
  ASSERT_GT(r.cut_elements, 0u);
  std::map<std::array<int, 3>, int> adjacencies_on;
  for (const auto& a : r.adjacencies) {
    const std::array<int, 3> key = r.face(a, background.tets);
    const auto it = tets_of_face.find(key);
    ASSERT_NE(it, tets_of_face.end()) << "an adjacency on no face of the background";
    ASSERT_EQ(it->second.size(), 2u) << "an adjacency on a boundary face";
    const std::uint32_t s = r.element[a.first], t = r.element[a.second];
    EXPECT_EQ(std::min(s, t), std::min(it->second[0], it->second[1]));
    EXPECT_EQ(std::max(s, t), std::max(it->second[0], it->second[1]));
    ++adjacencies_on[key];
  }
  for (const auto& [key, tets] : tets_of_face)
    if (tets.size() == 2) EXPECT_GE(adjacencies_on[key], 1) << "an interior face without an adjacency";
  for (std::size_t k = 1; k < results.size(); ++k) {
    const detail::LocalRegions& o = results[k];
    EXPECT_EQ(o.first, r.first);
    EXPECT_EQ(o.region, r.region);
    EXPECT_EQ(o.element, r.element);
    ASSERT_EQ(o.fusions.size(), r.fusions.size());
    for (std::size_t i = 0; i < r.fusions.size(); ++i) {
      EXPECT_EQ(o.fusions[i].inner, r.fusions[i].inner);
      EXPECT_EQ(o.fusions[i].outer, r.fusions[i].outer);
      EXPECT_EQ(o.fusions[i].patch, r.fusions[i].patch);
    }
    ASSERT_EQ(o.adjacencies.size(), r.adjacencies.size());
    for (std::size_t i = 0; i < r.adjacencies.size(); ++i) {
      EXPECT_EQ(o.adjacencies[i].first, r.adjacencies[i].first);
      EXPECT_EQ(o.adjacencies[i].second, r.adjacencies[i].second);
      EXPECT_EQ(o.adjacencies[i].patch, r.adjacencies[i].patch);
    }
    EXPECT_EQ(o.candidate_pairs, r.candidate_pairs);
    EXPECT_EQ(o.polygons, r.polygons);
  }
}

// The same input on the shuffled background and on the generator's order: the same tets cut,
// the same number of output tets and copies per cell (the candidate binning and the face
// pairing do not depend on the order they are handed the tets in).
TEST(VirtualTets, ShuffledBackgroundGivesTheSameMesh) {
  const SurfaceGenerateResult g = generate_surface("tube-overlap", {});
  ASSERT_TRUE(g.ok()) << g.error;
  const Prepared p = prepare(g.surface);
  const TetMesh grid = make_grid_background(bounding_box(p.complex().surface), 10, 0);
  std::vector<MeshResult> results;
  for (const TetMesh& background : {grid, shuffled(grid, 3)}) {
    const std::string path = testing::TempDir() + "/shuffled_or_not.veg";
    {
      std::ofstream out(path);
      out << format_veg(background);
    }
    MeshOptions options;
    options.background_path = path;
    results.push_back(mesh(p, options));
  }
  EXPECT_EQ(results[0].stats.cut_tets, results[1].stats.cut_tets);
  EXPECT_EQ(results[0].stats.polygons, results[1].stats.polygons);
  EXPECT_EQ(results[0].stats.output_tets, results[1].stats.output_tets);
  EXPECT_EQ(results[0].stats.output_vertices, results[1].stats.output_vertices);
  EXPECT_EQ(results[0].stats.copies_per_cell, results[1].stats.copies_per_cell);
  EXPECT_GT(results[0].stats.cut_tets, 0u);
}

// The candidate search bins tets on a hierarchy of grids, each tet once, on the finest level
// whose cells are as wide as it. A background graded around a small sphere in one corner (its
// tets from the surface size up to 16 times it) is cut by a large sphere that crosses tets of
// every size: the tets the clipping finds a polygon in are exactly those an independent exact
// test (CGAL's triangle-tetrahedron do_intersect, over all pairs whose boxes overlap) says the
// sphere's triangles meet, on 1, 2 and 3 threads.
TEST(VirtualTets, CandidatesOnAGradedBackgroundFindEveryTetATriangleMeets) {
  using EK = CGAL::Exact_predicates_exact_constructions_kernel;
  const SurfaceGenerateResult big = generate_surface("sphere", {});
  ASSERT_TRUE(big.ok()) << big.error;
  const Prepared p = prepare(big.surface);
  Surface small = big.surface;
  for (Point3& v : small.vertices)
    for (int d = 0; d < 3; ++d) v[d] = 0.1 * v[d] + 1.3;
  Box3 box = bounding_box(big.surface);
  for (int d = 0; d < 3; ++d) box.hi[d] = std::max(box.hi[d], 1.4);
  GradedOptions graded;
  graded.far_resolution = 1;
  graded.surface_resolution = 32;
  const GradedBackground g = make_graded_background(small, box, graded);
  ASSERT_TRUE(g.report.ok()) << g.report.summary();
  const TetMesh& background = g.mesh;
  // Brute force: every (tet, triangle) pair whose boxes overlap, decided exactly.
  const auto point = [](const Point3& q) { return EK::Point_3(q[0], q[1], q[2]); };
  std::size_t meeting = 0, meeting_wide = 0;
  double finest = std::numeric_limits<double>::infinity();
  std::vector<double> width(background.tets.size());
  std::vector<CGAL::Bbox_3> tet_box(background.tets.size());
  for (std::size_t t = 0; t < background.tets.size(); ++t) {
    for (int k = 0; k < 4; ++k) {
      const Point3& q = background.vertices[static_cast<std::size_t>(background.tets[t][static_cast<std::size_t>(k)])];
      tet_box[t] += CGAL::Bbox_3(q[0], q[1], q[2], q[0], q[1], q[2]);
    }
    width[t] = tet_box[t].xmax() - tet_box[t].xmin();
    finest = std::min(finest, width[t]);
  }
  for (const Triangle& tri : big.surface.triangles) {
    const Point3 &a = big.surface.vertices[tri[0]], &b = big.surface.vertices[tri[1]], &c = big.surface.vertices[tri[2]];
    CGAL::Bbox_3 tb;
    for (const Point3* q : {&a, &b, &c}) tb += CGAL::Bbox_3((*q)[0], (*q)[1], (*q)[2], (*q)[0], (*q)[1], (*q)[2]);
    const EK::Triangle_3 triangle(point(a), point(b), point(c));
    for (std::size_t t = 0; t < background.tets.size(); ++t) {
      if (!CGAL::do_overlap(tb, tet_box[t])) continue;
      const Tet& tet = background.tets[t];
      const EK::Tetrahedron_3 solid(point(background.vertices[static_cast<std::size_t>(tet[0])]),
                                    point(background.vertices[static_cast<std::size_t>(tet[1])]),
                                    point(background.vertices[static_cast<std::size_t>(tet[2])]),
                                    point(background.vertices[static_cast<std::size_t>(tet[3])]));
      if (!CGAL::do_intersect(triangle, solid)) continue;
      ++meeting;
      if (width[t] >= 8 * finest) ++meeting_wide;
    }
  }
  ASSERT_GT(meeting_wide, 0u) << "the sphere should cross tets 8 or more times the finest";
  for (const unsigned threads : {1u, 2u, 3u}) {
    ValidationReport report;
    bool non_generic = false;
    const detail::LocalRegions r = detail::compute_local_regions(p.complex(), background, {0, 0, 0}, false, threads,
                                                                 true, report, non_generic);
    ASSERT_TRUE(report.ok()) << report.summary();
    ASSERT_FALSE(non_generic);
    EXPECT_EQ(r.polygons, meeting) << threads << " threads";
    EXPECT_GE(r.candidate_pairs, meeting) << threads << " threads";
  }
}

// Three tets on one face: the background is not a manifold there; reported with the face's
// vertices and how many tets share it (found per vertex star, not by sorting every face).
TEST(VirtualTets, FaceSharedByThreeTetsIsReported) {
  const SurfaceGenerateResult g = generate_surface("sphere", {});
  ASSERT_TRUE(g.ok()) << g.error;
  const Prepared p = prepare(g.surface);
  TetMesh background;
  // Far from the sphere: no tet is cut, so the pairing alone speaks.
  background.vertices = {{10, 0, 0}, {11, 0, 0}, {10, 1, 0}, {10, 0, 1}, {10.2, 0.2, 2}, {10.3, 0.1, 3}};
  background.tets = {{0, 1, 2, 3}, {0, 1, 2, 4}, {0, 1, 2, 5}};
  ValidationReport report;
  bool non_generic = false;
  detail::compute_local_regions(p.complex(), background, {0, 0, 0}, false, 2, true, report, non_generic);
  ASSERT_FALSE(report.ok());
  bool found = false;
  for (const Defect& d : report.defects)
    if (d.message.find("background face (0, 1, 2) is shared by 3 tets") != std::string::npos) found = true;
  EXPECT_TRUE(found) << report.summary();
}

// One tet twice (the same four vertices, another even order): an adjacency's face is derived
// from its two tets (LocalRegions::face), which these do not determine, so both the clipping and
// the CSG path report the pair instead of pairing them across four faces.
TEST(VirtualTets, TwoTetsWithTheSameVerticesAreReported) {
  const SurfaceGenerateResult g = generate_surface("sphere", {});
  ASSERT_TRUE(g.ok()) << g.error;
  const Prepared p = prepare(g.surface);
  TetMesh background;
  background.vertices = {{10, 0, 0}, {11, 0, 0}, {10, 1, 0}, {10, 0, 1}};
  background.tets = {{0, 1, 2, 3}, {1, 0, 3, 2}};
  for (const bool csg : {false, true}) {
    SCOPED_TRACE(csg ? "csg" : "clipping");
    ValidationReport report;
    bool non_generic = false;
    if (csg)
      detail::compute_local_regions_csg(p.complex(), background, false, 2, {}, report, non_generic);
    else
      detail::compute_local_regions(p.complex(), background, {0, 0, 0}, false, 2, true, report, non_generic);
    std::size_t found = 0;
    for (const Defect& d : report.defects)
      if (d.kind == DefectKind::DuplicateFacet && d.message == "background tets 0 and 1 have the same vertices") ++found;
    EXPECT_EQ(found, 1u) << report.summary();
  }
}

// ---- backgrounds whose tets overlap ------------------------------------------------------------
// A background that covers some space twice would mesh it twice (the material doubled). Such a
// file is refused with the tets named: a fold (a vertex dragged across its neighbours: two tets
// on the same side of their shared face) and pieces that overlap (two grids in one file, an
// unglued output reused), on the clipping and the CSG path, the same message on every thread
// count. Files that only look unusual are still meshed: every tet negative (the other
// convention), some tets listed negatively in a valid mesh, separate pieces that only touch.

/// Meshes the unit sphere on the background written to a .veg file.
MeshResult mesh_on(const TetMesh& background, const std::string& name, unsigned threads,
                   MeshMethod method = MeshMethod::Clip) {
  static const Prepared p = [] {
    const SurfaceGenerateResult g = generate_surface("sphere", {});
    EXPECT_TRUE(g.ok()) << g.error;
    return prepare(g.surface);
  }();
  const std::string path = testing::TempDir() + "/" + name + ".veg";
  {
    std::ofstream out(path);
    out << format_veg(background);
  }
  MeshOptions options;
  options.background_path = path;
  options.threads = threads;
  options.method = method;
  return mesh_immersion(p.complex(), p.immersion(), options, p.im.input_vertices, p.im.input_triangles);
}

/// Two tet meshes in one: b's vertices after a's.
TetMesh concatenate(const TetMesh& a, const TetMesh& b) {
  TetMesh out = a;
  const int n = static_cast<int>(a.vertices.size());
  out.vertices.insert(out.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (Tet t : b.tets) {
    for (int& v : t) v += n;
    out.tets.push_back(t);
  }
  out.reference.assign(out.tets.size(), 0);
  return out;
}

TetMesh translated(TetMesh m, const Point3& d) {
  for (Point3& v : m.vertices)
    for (int k = 0; k < 3; ++k) v[k] += d[k];
  return m;
}

/// The one defect of a refused background, the same on 1, 2 and 3 threads (and on the CSG
/// path when `csg`).
Defect refused(const TetMesh& background, const std::string& name, bool csg = true) {
  std::vector<std::string> messages;
  Defect first;
  for (const unsigned threads : {1u, 2u, 3u}) {
    const MeshResult r = mesh_on(background, name, threads);
    EXPECT_FALSE(r.report.ok()) << "threads " << threads;
    if (r.report.defects.empty()) return first;
    EXPECT_EQ(r.report.defects.size(), 1u) << r.report.summary();
    if (threads == 1) first = r.report.defects.front();
    messages.push_back(r.report.defects.front().message);
  }
  if (csg) {
    const MeshResult r = mesh_on(background, name, 1, MeshMethod::Csg);
    EXPECT_FALSE(r.report.ok());
    if (!r.report.defects.empty()) EXPECT_EQ(r.report.defects.front().message.substr(0, 60), messages[0].substr(0, 60));
  }
  for (const std::string& m : messages) EXPECT_EQ(m, messages[0]);
  return first;
}

const TetMesh& grid() {
  static const TetMesh g = make_grid_background(Box3{{-2, -2, -2}, {2, 2, 2}}, 6, 0);
  return g;
}

/// Integers read from `text` after each of `marks`, in order.
std::vector<long> numbers_after(const std::string& text, const std::vector<std::string>& marks) {
  std::vector<long> out;
  std::size_t at = 0;
  for (const std::string& m : marks) {
    at = text.find(m, at);
    if (at == std::string::npos) return {};
    at += m.size();
    out.push_back(std::stol(text.substr(at)));
  }
  return out;
}

TEST(BackgroundOverlap, FoldedBackgroundIsRefusedNamingTwoTetsOnOneSideOfTheirFace) {
  // Drag the interior vertex nearest the origin past its neighbours: the tets around it fold.
  TetMesh folded = grid();
  std::size_t v = 0;
  for (std::size_t i = 0; i < folded.vertices.size(); ++i) {
    const auto norm = [](const Point3& p) { return std::abs(p[0]) + std::abs(p[1]) + std::abs(p[2]); };
    if (norm(folded.vertices[i]) < norm(folded.vertices[v])) v = i;
  }
  folded.vertices[v] = {folded.vertices[v][0] + 0.93, folded.vertices[v][1] + 0.117, folded.vertices[v][2] + 0.051};
  const Defect d = refused(folded, "folded");
  EXPECT_EQ(d.stage, "background");
  EXPECT_NE(d.message.find("background tets overlap"), std::string::npos) << d.message;
  // Independently: the named tets share the named face and their other vertices lie strictly on
  // the same side of it (exact orientation), as the file gives them (the reader only reorders).
  const std::vector<long> n = numbers_after(d.message, {": tets ", " and ", "face (", ", ", ", "});
  ASSERT_EQ(n.size(), 5u) << d.message;
  const TetReadResult read = read_tet_mesh(testing::TempDir() + "/folded.veg");
  ASSERT_TRUE(read.report.ok());
  EXPECT_GT(read.reoriented, 0u);
  EXPECT_LT(read.reoriented, read.mesh.tets.size());
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  const auto point = [&](long i) {
    const Point3& p = read.mesh.vertices[static_cast<std::size_t>(i)];
    return K::Point_3(p[0], p[1], p[2]);
  };
  std::vector<CGAL::Orientation> sides;
  for (const long t : {n[0], n[1]}) {
    const Tet& tet = read.mesh.tets[static_cast<std::size_t>(t)];
    int other = -1, shared = 0;
    for (int x : tet) {
      if (x == n[2] || x == n[3] || x == n[4]) ++shared;
      else other = x;
    }
    ASSERT_EQ(shared, 3) << "tet " << t << " does not have face " << d.message;
    sides.push_back(CGAL::orientation(point(n[2]), point(n[3]), point(n[4]), point(other)));
  }
  EXPECT_NE(sides[0], CGAL::COPLANAR);
  EXPECT_EQ(sides[0], sides[1]) << d.message;
}

TEST(BackgroundOverlap, OverlappingGridsAreRefusedNamingATetOfEach) {
  const TetMesh both = concatenate(grid(), translated(grid(), {0.1, 0.1, 0.1}));
  const Defect d = refused(both, "two_grids");
  EXPECT_NE(d.message.find("background tets overlap"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("different pieces"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("unglued"), std::string::npos) << d.message;
  const std::vector<long> n = numbers_after(d.message, {": tets ", " and "});
  ASSERT_EQ(n.size(), 2u) << d.message;
  const auto first_grid = static_cast<long>(grid().tets.size());
  EXPECT_LT(n[0], first_grid);
  EXPECT_GE(n[1], first_grid);
}

TEST(BackgroundOverlap, GridInsideAnotherIsRefused) {
  // Nothing crosses: the small grid lies wholly inside one big grid's tets' union.
  const TetMesh small = make_grid_background(Box3{{-1.7, -1.6, -1.5}, {-1.2, -1.3, -1.1}}, 2, 0);
  const Defect d = refused(concatenate(grid(), small), "nested");
  EXPECT_NE(d.message.find("different pieces"), std::string::npos) << d.message;
}

TEST(BackgroundOverlap, UnusualButValidBackgroundsAreMeshedAsTheGrid) {
  const MeshResult plain = mesh_on(grid(), "plain", 2);
  ASSERT_TRUE(plain.report.ok()) << plain.report.summary();
  const std::string expected = fingerprint(plain);
  // Every tet negative (the other convention), and every third one only (a valid mesh listed
  // with inconsistent vertex orders): turned on read, the same mesh.
  for (const int every : {1, 3}) {
    TetMesh turned = grid();
    for (std::size_t t = 0; t < turned.tets.size(); t += static_cast<std::size_t>(every))
      std::swap(turned.tets[t][2], turned.tets[t][3]);
    const MeshResult r = mesh_on(turned, "turned", 2);
    ASSERT_TRUE(r.report.ok()) << r.report.summary();
    EXPECT_EQ(fingerprint(r), expected) << "every " << every;
  }
  // A second grid touching a first along its x = 2 face, with vertices of its own (coincident,
  // not shared: lattice points, exact), and a third far away: pieces that do not overlap. The
  // input is in the first, which alone gives the same tets.
  const TetMesh lattice = aligned_grid(-2, 0.5, 8);
  const MeshResult alone = mesh_on(lattice, "lattice", 2);
  ASSERT_TRUE(alone.report.ok()) << alone.report.summary();
  double lo = lattice.vertices[0][0], hi = lo;
  for (const Point3& v : lattice.vertices) {
    lo = std::min(lo, v[0]);
    hi = std::max(hi, v[0]);
  }
  const TetMesh touching =
      concatenate(concatenate(lattice, translated(lattice, {hi - lo, 0, 0})), translated(lattice, {0, 0, 3 * (hi - lo)}));
  const MeshResult r = mesh_on(touching, "touching", 2);
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.mesh.tets.size(), alone.mesh.tets.size());
}

TEST(BackgroundOverlap, PiecesSeparatedOnlyByAPlaneThroughTwoEdgesAreTold) {
  // Two single-tet pieces far from the input: A's top edge (along x) and B's bottom edge (along
  // y) cross at one point; only the plane through both edges (z = 10) separates them, no face
  // plane does. Touching there: accepted. B lowered by 1/4: the edges pass through each other's
  // tet, the interiors overlap: refused.
  for (const double drop : {0.0, 0.25}) {
    TetMesh m = grid();
    const int n = static_cast<int>(m.vertices.size());
    const double z = 10, b = z - drop;
    m.vertices.insert(m.vertices.end(), {{-1, 0, z}, {1, 0, z}, {0, 1, z - 1}, {0, -1, z - 1},
                                         {0, -1, b}, {0, 1, b}, {1, 0, b + 1}, {-1, 0, b + 1}});
    for (const int first : {n, n + 4}) {
      Tet t{first, first + 1, first + 2, first + 3};
      m.tets.push_back(t);
      m.reference.push_back(0);
    }
    if (drop == 0.0) {
      const MeshResult r = mesh_on(m, "edges_touch", 2);
      EXPECT_TRUE(r.report.ok()) << r.report.summary();
    } else {
      const Defect d = refused(m, "edges_cross");
      EXPECT_NE(d.message.find("tets " + std::to_string(grid().tets.size()) + " and " +
                               std::to_string(grid().tets.size() + 1) + ", in different pieces"),
                std::string::npos)
          << d.message;
    }
  }
}

}  // namespace
}  // namespace imm::dim3
