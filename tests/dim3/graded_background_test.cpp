// Graded backgrounds (issue 17 item 3), checked exactly on the integer lattice the generator
// reports, with checkers written here (not the generator's closure):
//  - the doubles are the lattice points exactly (origin + index * unit);
//  - every tet is positively oriented (integer determinant);
//  - conforming: every face (vertex triple) belongs to one or two tets; a face of one tet lies on
//    the box boundary; the two tets of a shared face lie on opposite sides of it; no vertex lies
//    inside an edge (every lattice point inside every edge is looked up); the volumes sum to the
//    box's exactly. Opposite sides + matched faces make the union locally one sheet across every
//    face, the volume makes it exactly one sheet over the box, so no vertex can sit inside a face
//    either (that face would be matched by two smaller ones, i.e. not at all);
//  - the minimum dihedral angle is at least the bound of the three Kuhn-bisection shapes;
//  - graded: tets that meet the surface are at the surface size, and the tet count is far below
//    the uniform grid of the same smallest size.
// The meshes built on graded backgrounds are checked by the invariant suite of mesh3_test.cpp
// (coverage, embedding, unglued, separation) through its graded inputs; here, 1 vs 2 threads.
#include "dim3/graded_background.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "dim3/generators3.h"
#include "dim3/mesh3.h"
#include "dim3/self_connecting.h"

namespace imm::dim3 {
namespace {

using I128 = __int128;
using L3 = std::array<std::int64_t, 3>;

L3 lattice_point(const GradedBackground& g, int v) {
  const auto& p = g.lattice[static_cast<std::size_t>(v)];
  return {p[0], p[1], p[2]};
}

I128 det(const L3& a, const L3& b, const L3& c, const L3& d) {
  const I128 e[3][3] = {{b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                        {c[0] - a[0], c[1] - a[1], c[2] - a[2]},
                        {d[0] - a[0], d[1] - a[1], d[2] - a[2]}};
  return e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
         e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
}

struct Conformity {
  std::size_t interior_faces = 0, boundary_faces = 0;
};

/// The exact checks listed at the top; fails the test on any violation.
Conformity check_conforming(const GradedBackground& g) {
  Conformity result;
  const TetMesh& m = g.mesh;
  EXPECT_FALSE(m.tets.empty());
  EXPECT_EQ(g.lattice.size(), m.vertices.size());
  // Doubles are the lattice points, exactly.
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    for (int d = 0; d < 3; ++d)
      if (m.vertices[v][d] != g.origin[d] + static_cast<double>(g.lattice[v][d]) * g.unit) {
        ADD_FAILURE() << "vertex " << v << " is not its lattice point";
        return result;
      }
  // The box: the extent of the lattice (its base grid starts at 0).
  L3 hi{0, 0, 0};
  for (const auto& p : g.lattice)
    for (int d = 0; d < 3; ++d) {
      EXPECT_GE(p[d], 0);
      hi[d] = std::max<std::int64_t>(hi[d], p[d]);
    }
  for (int d = 0; d < 3; ++d) EXPECT_EQ(hi[d] % g.base_cube, 0);
  // Orientation and volume.
  I128 volume = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const auto& tet = m.tets[t];
    const I128 v = det(lattice_point(g, tet[0]), lattice_point(g, tet[1]), lattice_point(g, tet[2]),
                       lattice_point(g, tet[3]));
    if (v <= 0) {
      ADD_FAILURE() << "tet " << t << " is not positively oriented";
      return result;
    }
    volume += v;
  }
  EXPECT_TRUE(volume == I128{6} * hi[0] * hi[1] * hi[2]) << "volumes do not sum to the box's";
  // Faces.
  std::map<std::array<int, 3>, std::vector<std::pair<std::size_t, int>>> faces;  // face -> (tet, opposite vertex)
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> f{};
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != skip) f[j++] = m.tets[t][k];
      std::sort(f.begin(), f.end());
      faces[f].emplace_back(t, m.tets[t][skip]);
    }
  for (const auto& [f, tets] : faces) {
    const L3 a = lattice_point(g, f[0]), b = lattice_point(g, f[1]), c = lattice_point(g, f[2]);
    if (tets.size() == 1) {
      ++result.boundary_faces;
      bool on_box = false;
      for (int d = 0; d < 3; ++d)
        on_box |= (a[d] == b[d] && b[d] == c[d] && (a[d] == 0 || a[d] == hi[d]));
      if (!on_box) {
        ADD_FAILURE() << "face (" << f[0] << ", " << f[1] << ", " << f[2] << ") of one tet is inside the box";
        return result;
      }
    } else if (tets.size() == 2) {
      ++result.interior_faces;
      const I128 s0 = det(a, b, c, lattice_point(g, tets[0].second));
      const I128 s1 = det(a, b, c, lattice_point(g, tets[1].second));
      if (!((s0 > 0 && s1 < 0) || (s0 < 0 && s1 > 0))) {
        ADD_FAILURE() << "the two tets of a face lie on the same side";
        return result;
      }
    } else {
      ADD_FAILURE() << "a face of " << tets.size() << " tets";
      return result;
    }
  }
  // No vertex inside an edge: every lattice point strictly inside every edge is looked up.
  std::unordered_set<std::uint64_t> vertices;
  auto pack = [](const L3& p) {
    return static_cast<std::uint64_t>(p[0]) | (static_cast<std::uint64_t>(p[1]) << 21) |
           (static_cast<std::uint64_t>(p[2]) << 42);
  };
  for (std::size_t v = 0; v < g.lattice.size(); ++v) vertices.insert(pack(lattice_point(g, static_cast<int>(v))));
  std::set<std::pair<int, int>> edges;
  for (const auto& tet : m.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) edges.emplace(std::min(tet[i], tet[j]), std::max(tet[i], tet[j]));
  for (const auto& [u, w] : edges) {
    const L3 a = lattice_point(g, u), b = lattice_point(g, w);
    const L3 delta{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const std::int64_t steps = std::gcd(std::gcd(std::abs(delta[0]), std::abs(delta[1])), std::abs(delta[2]));
    for (std::int64_t s = 1; s < steps; ++s) {
      const L3 p{a[0] + delta[0] / steps * s, a[1] + delta[1] / steps * s, a[2] + delta[2] / steps * s};
      if (vertices.count(pack(p)) != 0) {
        ADD_FAILURE() << "a vertex lies inside edge (" << u << ", " << w << ")";
        return result;
      }
    }
  }
  return result;
}

GradedOptions sizes(int far, int surface, int gap = 0) {
  GradedOptions o;
  o.far_resolution = far;
  o.surface_resolution = surface;
  o.gap_resolution = gap;
  return o;
}

TEST(GradedBackground, MinimumDihedralBoundIsFortyFiveDegrees) {
  // The Kuhn tet has dihedral angles of 45, 60 and 90 degrees; its two bisection generations
  // before the cube halves have none smaller, so 45 bounds every graded background.
  EXPECT_NEAR(graded_min_dihedral_bound(), 45.0, 1e-9);
}

// The dihedral angles of the report are scale-free: products of coordinates near 1e300
// overflowed (every normal NaN: "min 180, max 0") and near 1e-300 underflowed.
TEST(GradedBackground, DihedralAnglesAreTheSameAtEveryScale) {
  // The Kuhn tet: 45, 60 and 90 degrees (acos of its unit normals' products, worked by hand).
  TetMesh kuhn;
  kuhn.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}};
  kuhn.tets = {{0, 1, 2, 3}};
  const Surface s = torus(12);
  const GradedBackground unit = make_graded_background(s, bounding_box(s), sizes(2, 8));
  ASSERT_TRUE(unit.report.ok()) << unit.report.summary();
  for (double scale : {1e300, 3e-300, 0x1p990, 0x1p-990}) {
    TetMesh m = kuhn;
    for (Point3& p : m.vertices)
      for (double& x : p) x *= scale;
    const auto range = dihedral_range(m);
    EXPECT_NEAR(range[0], 45.0, 1e-9) << scale;
    EXPECT_NEAR(range[1], 90.0, 1e-9) << scale;
    Surface scaled = s;
    for (Point3& p : scaled.vertices)
      for (double& x : p) x *= scale;
    const GradedBackground g = make_graded_background(scaled, bounding_box(scaled), sizes(2, 8));
    ASSERT_TRUE(g.report.ok()) << g.report.summary();
    EXPECT_EQ(g.mesh.tets.size(), unit.mesh.tets.size()) << scale;
    EXPECT_NEAR(g.stats.min_dihedral_deg, unit.stats.min_dihedral_deg, 1e-9) << scale;
    EXPECT_NEAR(g.stats.max_dihedral_deg, unit.stats.max_dihedral_deg, 1e-9) << scale;
    EXPECT_GE(g.stats.min_dihedral_deg, graded_min_dihedral_bound() - 1e-9) << scale;
  }
}

TEST(GradedBackground, SizeOrderIsCheckedOnceAndWordedInTheCallersNames) {
  const GradedOptionNames names{"far", "surface", "gap"};
  EXPECT_EQ(graded_order_error(sizes(8, 32, 0), names), "");
  EXPECT_EQ(graded_order_error(sizes(8, 8, 8), names), "");
  EXPECT_EQ(graded_order_error(sizes(0, 8, 0), names), "far must be at least 1");
  EXPECT_EQ(graded_order_error(sizes(8, 4, 0), names), "surface 4 is coarser than far 8");
  EXPECT_EQ(graded_order_error(sizes(8, 16, 12), names), "gap 12 is coarser than surface 16");
}

TEST(GradedBackground, TorusIsConformingAndGraded) {
  const Surface s = torus(24);
  const GradedBackground g = make_graded_background(s, bounding_box(s), sizes(4, 32));
  ASSERT_TRUE(g.report.ok()) << g.report.summary();
  const Conformity c = check_conforming(g);
  EXPECT_GT(c.interior_faces, 0u);
  EXPECT_GT(g.stats.closure_bisections, 0u) << "nothing for the closure to do: not a test of it";
  EXPECT_EQ(g.stats.surface_levels, 3);
  EXPECT_GE(g.stats.min_dihedral_deg, graded_min_dihedral_bound() - 1e-9);
  EXPECT_GE(*std::min_element(g.level.begin(), g.level.end()), 0);
  // Tets meeting the surface are at the surface size (level 3 * surface_levels or finer).
  std::size_t fine = 0, coarse = 0;
  for (std::uint8_t level : g.level) (level >= 9 ? fine : coarse) += 1;
  EXPECT_GT(coarse, 0u);
  EXPECT_GE(fine, g.stats.surface_tets);
}

TEST(GradedBackground, CombGapsAreRefinedFurther) {
  const Surface s = comb(3);
  const GradedBackground g = make_graded_background(s, bounding_box(s), sizes(4, 16, 64));
  ASSERT_TRUE(g.report.ok()) << g.report.summary();
  check_conforming(g);
  EXPECT_EQ(g.stats.gap_levels, 2);
  EXPECT_EQ(g.stats.surface_levels, 2);
  EXPECT_GT(g.stats.gap_tets, 0u);
  EXPECT_GE(g.stats.min_dihedral_deg, graded_min_dihedral_bound() - 1e-9);
  // Deterministic.
  const GradedBackground again = make_graded_background(s, bounding_box(s), sizes(4, 16, 64));
  EXPECT_EQ(again.mesh.vertices, g.mesh.vertices);
  EXPECT_EQ(again.mesh.tets, g.mesh.tets);
}

TEST(GradedBackground, ShiftedAttemptsStayConforming) {
  const Surface s = mouth(16);
  for (int attempt : {0, 1, 2}) {
    const GradedBackground g = make_graded_background(s, bounding_box(s), sizes(2, 8, 16), attempt);
    ASSERT_TRUE(g.report.ok()) << g.report.summary();
    check_conforming(g);
    EXPECT_GE(g.stats.min_dihedral_deg, graded_min_dihedral_bound() - 1e-9);
  }
}

TEST(GradedBackground, TooManyTetsIsReported) {
  const Surface s = torus(24);
  GradedOptions o = sizes(2, 512);
  o.max_tets = 10'000;
  const GradedBackground g = make_graded_background(s, bounding_box(s), o);
  EXPECT_FALSE(g.report.ok());
  EXPECT_TRUE(g.mesh.tets.empty());
}

// A background of 50 million tets took 35 s and 1.7 GB before it was refused, silently: the
// build reports its sizes first, then every progress_every tets made (refinement and closure),
// so a long build says where it is.
TEST(GradedBackground, ProgressIsReportedWhileBuilding) {
  const Surface s = torus(12);
  GradedOptions o = sizes(2, 16);
  o.progress_every = 1000;
  std::vector<std::string> messages;
  o.progress = [&](const std::string& m) { messages.push_back(m); };
  const GradedBackground g = make_graded_background(s, bounding_box(s), o);
  ASSERT_TRUE(g.report.ok()) << g.report.summary();
  ASSERT_GT(g.stats.tets, 3000u);
  ASSERT_FALSE(messages.empty());
  EXPECT_EQ(messages[0].rfind("graded background: " + std::to_string(g.stats.base_tets) + " base tets", 0), 0u)
      << messages[0];
  // Then one message per 1000 tets: 1000, 2000, ... up to the final count.
  ASSERT_EQ(messages.size(), 1 + g.stats.tets / 1000);
  bool closure_seen = false;
  for (std::size_t i = 1; i < messages.size(); ++i) {
    EXPECT_EQ(messages[i].rfind("graded background: " + std::to_string(1000 * i) + " tets so far (", 0), 0u)
        << messages[i];
    closure_seen = closure_seen || messages[i].find("closure sweep") != std::string::npos;
  }
  EXPECT_TRUE(closure_seen) << "no message from the closure: not a test of it";
  // A build refused at its last tet reports until it stops (after the count before building,
  // which the small maximum starts and which does not refuse it).
  o.max_tets = g.stats.tets - 1;
  messages.clear();
  const GradedBackground refused = make_graded_background(s, bounding_box(s), o);
  EXPECT_FALSE(refused.report.ok());
  std::size_t so_far = 0;
  for (const std::string& m : messages) so_far += m.find("tets so far") != std::string::npos;
  EXPECT_EQ(so_far, (g.stats.tets - 1) / 1000);
}

// A background beyond max_tets is refused by counting the surface refinement before building
// (the count is a lower bound of the tets, so the refusal is true), and a background that fits
// is never refused by the count: ten copies of one torus on top of each other have ten times the
// area (which starts the count) for about the tets of one.
TEST(GradedBackground, TooManyTetsIsCountedBeforeBuildingAndOnlyWhenTrue) {
  const Surface one = torus(8);
  Surface ten;
  for (int copy = 0; copy < 10; ++copy) {
    const auto base = static_cast<std::uint32_t>(ten.vertices.size());
    ten.vertices.insert(ten.vertices.end(), one.vertices.begin(), one.vertices.end());
    for (const Triangle& t : one.triangles) ten.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  const GradedBackground full = make_graded_background(ten, bounding_box(ten), sizes(2, 16));
  ASSERT_TRUE(full.report.ok()) << full.report.summary();
  std::vector<std::string> messages;
  GradedOptions o = sizes(2, 16);
  o.progress = [&](const std::string& m) { messages.push_back(m); };
  const auto counted = [&] {
    for (const std::string& m : messages)
      if (m.find("counted before building") != std::string::npos) return m;
    return std::string();
  };
  // Exactly the tets it needs: built, the same mesh, after a count that did not refuse.
  o.max_tets = full.stats.tets;
  const GradedBackground fits = make_graded_background(ten, bounding_box(ten), o);
  ASSERT_TRUE(fits.report.ok()) << fits.report.summary();
  EXPECT_EQ(fits.mesh.tets, full.mesh.tets);
  EXPECT_EQ(fits.mesh.vertices, full.mesh.vertices);
  EXPECT_NE(counted(), "") << "the count did not run: not a test of it";
  EXPECT_EQ(counted().find("more than"), std::string::npos) << counted();
  // A tenth of it: refused by the count, before any tet is built (no "tets so far"), which says
  // its progress.
  messages.clear();
  o.max_tets = full.stats.tets / 10;
  o.progress_every = 1;
  const GradedBackground refused = make_graded_background(ten, bounding_box(ten), o);
  EXPECT_FALSE(refused.report.ok());
  EXPECT_NE(refused.report.summary().find("more than " + std::to_string(o.max_tets) + " tets"), std::string::npos)
      << refused.report.summary();
  EXPECT_NE(counted().find("more than " + std::to_string(o.max_tets) + " tets"), std::string::npos) << counted();
  std::size_t counting = 0;
  for (const std::string& m : messages) {
    EXPECT_EQ(m.find("tets so far"), std::string::npos) << m;
    counting += m.find("tets counted") != std::string::npos;
  }
  EXPECT_GE(2 * counting, o.max_tets);  // one per count reached (they grow by 1 or 2)
}

TEST(GradedBackground, MeshIsTheSameOnOneAndTwoThreads) {
  const Surface s = comb(3);
  ImmerseOptions io;
  io.build.exact_volumes = false;
  const Immersed im = immerse_surface(s, io);
  ASSERT_TRUE(im.build.complex && !im.search.immersions.empty());
  std::vector<std::string> outputs;
  for (unsigned threads : {1u, 2u}) {
    MeshOptions o;
    o.graded = sizes(4, 16, 32);
    o.threads = threads;
    const MeshResult r = mesh_immersion(*im.build.complex, im.search.immersions[0], o, im.input_vertices,
                                        im.input_triangles);
    ASSERT_TRUE(r.report.ok()) << r.report.summary();
    EXPECT_GT(r.stats.graded.gap_tets, 0u);
    outputs.push_back(format_medit_3d(r.mesh) + format_embedding(r.embedding));
  }
  EXPECT_EQ(outputs[0], outputs[1]);
}

}  // namespace
}  // namespace imm::dim3
