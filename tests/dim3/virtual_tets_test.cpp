// The virtual tets' decisions do not depend on how they are computed: the interval fast path with
// exact fallback, pure Epeck arithmetic, one thread or two, give byte-identical meshes and
// embeddings. And a background that touches the input non-generically (an input vertex on a tet
// face, an input edge along a tet edge) is handled by an explicit translation whose size the
// result reports, with every output tet still accounted for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "dim3/generators3.h"
#include "dim3/mesh3.h"
#include "dim3/self_connecting.h"

namespace imm::dim3 {
namespace {

struct Prepared {
  Immersed3 im;
  [[nodiscard]] const Complex3& complex() const { return *im.build.complex; }
  [[nodiscard]] const Immersion& immersion() const { return im.search.immersions.front(); }
};

Prepared prepare(const Surface& surface) {
  ImmerseOptions3 options;
  options.build.exact_volumes = false;
  Prepared p{immerse_surface(surface, options)};
  EXPECT_TRUE(p.im.build.report.ok()) << p.im.build.report.summary();
  EXPECT_TRUE(p.im.build.complex != nullptr);
  EXPECT_FALSE(p.im.search.immersions.empty());
  return p;
}

MeshResult3 mesh(const Prepared& p, MeshOptions3 options) {
  MeshResult3 m = mesh_immersion3(p.complex(), p.immersion(), options, p.im.input_vertices, p.im.input_triangles);
  EXPECT_TRUE(m.report.ok()) << m.report.summary();
  return m;
}

/// Everything a user receives, as text.
std::string fingerprint(const MeshResult3& m) {
  return format_medit_3d(m.mesh) + format_embedding3(m.embedding);
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
  MeshOptions3 fast;
  fast.resolution = c.resolution;
  fast.threads = 1;
  const MeshResult3 reference = mesh(p, fast);
  ASSERT_GT(reference.stats.output_tets, 0u);
  ASSERT_GT(reference.stats.cut_tets, 0u);

  MeshOptions3 exact = fast;
  exact.interval_filter = false;
  const MeshResult3 exact_mesh = mesh(p, exact);
  // Without the filter every tet that meets a cut triangle's box runs in Epeck.
  EXPECT_GT(exact_mesh.stats.exact_tets, reference.stats.exact_tets);
  EXPECT_EQ(fingerprint(exact_mesh), fingerprint(reference)) << c.name;

  MeshOptions3 two = fast;
  two.threads = 2;
  EXPECT_EQ(fingerprint(mesh(p, two)), fingerprint(reference)) << c.name;
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
  MeshOptions3 options;
  options.background_path = path;
  const MeshResult3 m = mesh(p, options);
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

}  // namespace
}  // namespace imm::dim3
