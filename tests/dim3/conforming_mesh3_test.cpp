// Conforming immersed tet meshes (issue 18, dim3/conforming_mesh3.h), proven on the OUTPUT with
// checkers written here, independent of the mesher (they read the output TetMesh, its node
// references and embedding, the complex's rounded cut mesh, the immersion graph and the input):
//  1. orientation: every output tet positive (CGAL Epick orientation on the doubles is exact);
//  2. manifold: every face of the output (by output vertex ids) has one or two tets, two tets on
//     opposite sides of it;
//  3. boundary = the cut mesh: the boundary faces, oriented outward, are exactly the user's cut
//     triangles in the complex's rounded points and orientation, each exactly once (multisets of
//     coordinate triples compared with ==); no boundary face lies on a helper box;
//  4. gluing: an interior face on a cut triangle of patch p joins the copies of two nodes glued
//     by an immersion-graph edge across p (inner node on the triangle's negative side); an
//     interior face on no cut triangle joins two tets of one node;
//  5. copies: the tets of every kept node fill its cell's volume (the complex's cell volume, in
//     doubles: relative 1e-9 of the input's total volume, the only tolerance, on output volumes);
//     no tet references a node of a helper box's solid;
//  6. topology: the Euler characteristic V - E + F - T of the output equals half that of the
//     user's surface (a 3-manifold with boundary bounded by it);
//  7. coverage: at sample points (tet centroids), the output tets containing the point
//     (exact side tests) number the generalized winding number of the input there;
//  8. embedding: every used user vertex is the corner of weight 1 of its tet, at exactly its
//     input position, on a boundary face of that tet;
//  9. quality report: the minimum dihedral angle is at most the narrowest cell wedge at a cut edge
//     (the bound no mesh bounded by the surface can beat), and the slivers' causes add up to at
//     most the slivers.
#include "dim3/conforming_mesh3.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "dim3/generators3.h"
#include "dim3/self_connecting.h"

namespace imm::dim3 {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using KP = Kernel::Point_3;
using Coords = std::array<Point3, 3>;

KP kpoint(const Point3& p) { return {p[0], p[1], p[2]}; }

/// Rotates an oriented triangle so that its smallest corner comes first (orientation kept).
Coords canonical(Coords c) {
  const auto smallest = std::min_element(c.begin(), c.end()) - c.begin();
  std::rotate(c.begin(), c.begin() + smallest, c.end());
  return c;
}
/// An unoriented triangle: its corners sorted.
Coords unordered(Coords c) {
  std::sort(c.begin(), c.end());
  return c;
}

double winding_number_at(const Surface& s, std::size_t triangles, const Point3& q) {
  double total = 0.0;
  for (std::size_t i = 0; i < triangles; ++i) {
    const Triangle& t = s.triangles[i];
    double a[3], b[3], c[3];
    for (int d = 0; d < 3; ++d) {
      a[d] = s.vertices[t[0]][d] - q[d];
      b[d] = s.vertices[t[1]][d] - q[d];
      c[d] = s.vertices[t[2]][d] - q[d];
    }
    const auto dot = [](const double* x, const double* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    const double la = std::sqrt(dot(a, a)), lb = std::sqrt(dot(b, b)), lc = std::sqrt(dot(c, c));
    const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                       a[2] * (b[0] * c[1] - b[1] * c[0]);
    const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    total += 2.0 * std::atan2(det, den);
  }
  return total / (4.0 * std::acos(-1.0));
}

struct Conformed {
  Immersed im;
  ConformingResult mesh;
};

Conformed conform(const Surface& surface, double edge_fraction, double radius_edge = 2.0, double min_dihedral = 0.0) {
  Conformed c;
  ImmerseOptions io;
  io.build.exact_volumes = false;
  c.im = immerse_surface(surface, io);
  EXPECT_TRUE(c.im.build.report.ok()) << c.im.build.report.summary();
  if (!c.im.build.complex || c.im.search.immersions.empty()) {
    ADD_FAILURE() << "no immersion (" << to_string(c.im.search.status) << ")";
    return c;
  }
  const Box3 box = bounding_box(surface);
  double longest = 0.0;
  for (int d = 0; d < 3; ++d) longest = std::max(longest, box.hi[d] - box.lo[d]);
  ConformingOptions options;
  options.edge_length = longest * edge_fraction;
  options.radius_edge = radius_edge;
  options.min_dihedral = min_dihedral;
  c.mesh = mesh_conforming(*c.im.build.complex, c.im.search.immersions[0], options, c.im.input_vertices,
                            c.im.input_triangles);
  return c;
}

/// Checks 1-8 of the header. `samples`: centroids tested for coverage (every k-th tet).
void check_conforming(const Conformed& c, std::size_t samples = 40) {
  ASSERT_TRUE(c.mesh.report.ok()) << c.mesh.report.summary();
  const Complex& cx = *c.im.build.complex;
  const CellComplex<3>& cc = cx.complex;
  const Immersion& immersion = c.im.search.immersions[0];
  const TetMesh& out = c.mesh.mesh;
  const std::size_t user_triangles = c.im.input_triangles;
  ASSERT_GT(out.tets.size(), 0u);
  ASSERT_EQ(out.reference.size(), out.tets.size());
  const auto P = [&](int v) { return kpoint(out.vertices[static_cast<std::size_t>(v)]); };

  // 1. Orientation.
  for (std::size_t t = 0; t < out.tets.size(); ++t) {
    const Tet& q = out.tets[t];
    ASSERT_EQ(CGAL::orientation(P(q[0]), P(q[1]), P(q[2]), P(q[3])), CGAL::POSITIVE) << "tet " << t;
  }

  // 2. Faces with one or two tets, on opposite sides.
  struct Side {
    std::size_t tet;
    int apex;
  };
  std::map<std::array<int, 3>, std::vector<Side>> faces;
  for (std::size_t t = 0; t < out.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> f = {out.tets[t][(k + 1) % 4], out.tets[t][(k + 2) % 4], out.tets[t][(k + 3) % 4]};
      std::sort(f.begin(), f.end());
      faces[f].push_back({t, out.tets[t][k]});
    }
  // The user's cut triangles, in rounded points, by unordered key -> (oriented, patch).
  const auto cut_coords = [&](std::size_t x) {
    Coords co;
    for (int k = 0; k < 3; ++k) co[k] = cx.points[cx.cut_point[cx.cut_triangles[x][k]]];
    return co;
  };
  std::map<Coords, std::size_t> cut_of;  // unordered coordinates -> cut triangle
  std::multiset<Coords> expected_boundary;
  for (std::size_t x = 0; x < cx.cut_triangles.size(); ++x) {
    cut_of[unordered(cut_coords(x))] = x;
    if (cx.cut_triangle_source[x] < user_triangles) expected_boundary.insert(canonical(cut_coords(x)));
  }
  std::set<std::tuple<int, int, int>> edges;  // (inner node, outer node, patch)
  for (const ImmersionEdge& e : immersion.edges) edges.insert({e.inner.value(), e.outer.value(), e.patch.value()});
  std::multiset<Coords> boundary;
  std::vector<char> on_boundary(out.vertices.size(), 0);
  std::set<std::array<int, 2>> edge_set;
  std::size_t interior_on_cut = 0;
  for (const auto& [f, sides] : faces) {
    ASSERT_LE(sides.size(), 2u) << "a face with " << sides.size() << " tets";
    Coords co = {out.vertices[f[0]], out.vertices[f[1]], out.vertices[f[2]]};
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b) edge_set.insert({f[a], f[b]});
    if (sides.size() == 1) {
      // Oriented outward: the apex on the negative side of (a, b, c).
      std::array<int, 3> o = f;
      if (CGAL::orientation(P(o[0]), P(o[1]), P(o[2]), P(sides[0].apex)) == CGAL::POSITIVE) std::swap(o[1], o[2]);
      boundary.insert(canonical({out.vertices[o[0]], out.vertices[o[1]], out.vertices[o[2]]}));
      for (int v : f) on_boundary[static_cast<std::size_t>(v)] = 1;
      continue;
    }
    const CGAL::Orientation s0 = CGAL::orientation(P(f[0]), P(f[1]), P(f[2]), P(sides[0].apex));
    const CGAL::Orientation s1 = CGAL::orientation(P(f[0]), P(f[1]), P(f[2]), P(sides[1].apex));
    ASSERT_NE(s0, s1) << "two tets on one side of a face";
    const int n0 = out.reference[sides[0].tet], n1 = out.reference[sides[1].tet];
    const auto found = cut_of.find(unordered(co));
    if (found == cut_of.end()) {
      EXPECT_EQ(n0, n1) << "tets of two nodes share a face off the surface";
      continue;
    }
    // 4. Glued across a patch: through an immersion edge, inner node on the negative side.
    ++interior_on_cut;
    const std::size_t x = found->second;
    const Coords oc = cut_coords(x);
    const CGAL::Orientation side0 =
        CGAL::orientation(kpoint(oc[0]), kpoint(oc[1]), kpoint(oc[2]), P(sides[0].apex));
    const int inner = side0 == CGAL::NEGATIVE ? n0 : n1, outer = side0 == CGAL::NEGATIVE ? n1 : n0;
    EXPECT_TRUE(edges.count({inner, outer, cx.cut_triangle_patch[x].value()}))
        << "nodes " << inner << " and " << outer << " glued across patch " << cx.cut_triangle_patch[x]
        << " without a graph edge";
  }
  // 3. Boundary faces = user cut triangles, each once (multisets; helper triangles excluded).
  EXPECT_EQ(boundary.size(), expected_boundary.size());
  EXPECT_TRUE(boundary == expected_boundary) << "the boundary is not exactly the cut mesh";

  // 5. Volumes per node.
  std::vector<double> node_volume(immersion.layout.node_count(), 0.0);
  double total = 0.0;
  for (std::size_t t = 0; t < out.tets.size(); ++t) {
    const Tet& q = out.tets[t];
    const double v = CGAL::to_double(CGAL::volume(P(q[0]), P(q[1]), P(q[2]), P(q[3])));
    node_volume[static_cast<std::size_t>(out.reference[t])] += v;
    total += v;
  }
  // Helper nodes: components of the graph owning no patch of a user triangle.
  std::set<int> user_owners;
  for (std::size_t x = 0; x < cx.cut_triangles.size(); ++x)
    if (cx.cut_triangle_source[x] < user_triangles) user_owners.insert(immersion.owner[cx.cut_triangle_patch[x]].value());
  std::size_t helper = 0;
  for (const auto& component : immersion.components()) {
    bool user = false;
    for (NodeId n : component) user = user || user_owners.count(n.value());
    for (NodeId n : component) {
      const double cell = to_double(cc.measure(cc.region_of(immersion.layout.cell(n))));
      if (!user) {
        ++helper;
        EXPECT_EQ(node_volume[n.index()], 0.0) << "a tet of helper node " << n << " was kept";
      } else {
        EXPECT_NEAR(node_volume[n.index()], cell, 1e-9 * total) << "node " << n;
      }
    }
  }
  if (c.im.helper_boxes.empty()) {
    EXPECT_EQ(helper, 0u);
  }

  // 6. Euler characteristic: V - E + F - T = chi(user surface) / 2.
  {
    std::set<std::array<std::uint32_t, 2>> surface_edges;
    std::set<std::uint32_t> surface_vertices;
    for (std::size_t i = 0; i < user_triangles; ++i) {
      const Triangle& t = c.im.surface.triangles[i];
      for (int k = 0; k < 3; ++k) {
        surface_vertices.insert(t[k]);
        surface_edges.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
      }
    }
    const long chi_surface = static_cast<long>(surface_vertices.size()) - static_cast<long>(surface_edges.size()) +
                             static_cast<long>(user_triangles);
    const long chi_solid = static_cast<long>(out.vertices.size()) - static_cast<long>(edge_set.size()) +
                           static_cast<long>(faces.size()) - static_cast<long>(out.tets.size());
    EXPECT_EQ(2 * chi_solid, chi_surface);
  }

  // 7. Coverage at tet centroids.
  const std::size_t step = std::max<std::size_t>(1, out.tets.size() / std::max<std::size_t>(samples, 1));
  for (std::size_t t = 0; t < out.tets.size() && samples > 0; t += step) {
    const Tet& q = out.tets[t];
    Point3 centroid{};
    for (int d = 0; d < 3; ++d) {
      for (int k = 0; k < 4; ++k) centroid[d] += out.vertices[static_cast<std::size_t>(q[k])][d];
      centroid[d] /= 4.0;
    }
    const KP z = kpoint(centroid);
    int containing = 0;
    for (const Tet& r : out.tets) {
      const Kernel::Tetrahedron_3 tet(P(r[0]), P(r[1]), P(r[2]), P(r[3]));
      const CGAL::Bounded_side side = tet.bounded_side(z);
      ASSERT_NE(side, CGAL::ON_BOUNDARY) << "a sample centroid on a tet face";
      if (side == CGAL::ON_BOUNDED_SIDE) ++containing;
    }
    const double w = winding_number_at(c.im.surface, user_triangles, centroid);
    EXPECT_EQ(containing, static_cast<int>(std::lround(w))) << "at the centroid of tet " << t << " (winding " << w << ")";
  }

  // 8. Embedding.
  ASSERT_EQ(c.mesh.embedding.size(), c.im.input_vertices);
  std::vector<char> used(c.im.input_vertices, 0);
  for (std::size_t i = 0; i < user_triangles; ++i)
    for (std::uint32_t v : c.im.surface.triangles[i]) used[v] = 1;
  for (std::size_t v = 0; v < c.mesh.embedding.size(); ++v) {
    const EmbeddedVertex3& e = c.mesh.embedding[v];
    if (!used[v]) {
      EXPECT_EQ(e.element, -1);
      continue;
    }
    ASSERT_GE(e.element, 0);
    ASSERT_LT(static_cast<std::size_t>(e.element), out.tets.size());
    int corner = -1, ones = 0;
    for (int k = 0; k < 4; ++k) {
      if (e.weights[k] == 1.0) {
        corner = k, ++ones;
      } else {
        EXPECT_EQ(e.weights[k], 0.0);
      }
    }
    ASSERT_EQ(ones, 1) << "vertex " << v;
    const int ov = out.tets[static_cast<std::size_t>(e.element)][corner];
    EXPECT_EQ(out.vertices[static_cast<std::size_t>(ov)], c.im.surface.vertices[v]) << "vertex " << v;
    EXPECT_TRUE(on_boundary[static_cast<std::size_t>(ov)]) << "vertex " << v << " embedded off the boundary";
  }

  // 9. Quality report (doubles).
  const ConformingStats& st = c.mesh.stats;
  EXPECT_LE(st.min_dihedral, st.min_cell_wedge + 1e-9);
  EXPECT_LE(st.slivers_in_narrow_wedge + st.slivers_on_cap + st.slivers_on_needle, st.slivers);
}

/// A closed triangular prism along z (outward triangles) whose cross-section has the angle
/// `apex_deg` at the edge on the z axis: its only cell has that dihedral wedge there.
Surface wedge_prism(double apex_deg) {
  const double half = apex_deg * std::acos(-1.0) / 360.0;
  Surface s;
  for (double z : {0.0, 1.0}) {
    s.vertices.push_back({0.0, 0.0, z});
    s.vertices.push_back({std::cos(half), -std::sin(half), z});
    s.vertices.push_back({std::cos(half), std::sin(half), z});
  }
  // Bottom (0, 1, 2) seen from below, top (3, 4, 5) from above, three sides as two triangles.
  s.triangles = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}, {2, 0, 3}, {2, 3, 5}};
  return s;
}

std::string real_path(const std::string& name) { return std::string(IMM_SHARED_DATA_DIR) + "/3d/" + name; }

Surface generated(const std::string& name, const std::vector<std::string>& args) {
  SurfaceGenerateResult g = generate_surface(name, args);
  EXPECT_TRUE(g.ok()) << g.error;
  return g.surface;
}

TEST(Conforming3, EmbeddedSphereIsOneCopy) {
  const Conformed c = conform(generated("sphere", {"8"}), 0.2);
  check_conforming(c);
  EXPECT_EQ(c.mesh.stats.copies_per_cell.size(), 1u);
}

TEST(Conforming3, TwoOverlappingToriAreGluedOnlyAcrossDeclinedPatches) {
  const Conformed c = conform(generated("two-tori", {"10"}), 0.1);
  check_conforming(c);
  EXPECT_GT(c.im.build.complex->complex.max_winding_number(), 1);
}

TEST(Conforming3, TubeOverlap) {
  const Conformed c = conform(generated("tube-overlap", {"12"}), 0.08);
  check_conforming(c);
}

TEST(Conforming3, MouthAndCombNearContacts) {
  // Lips and teeth nearly touch: the boundary is exactly the surface, so no tet bridges the
  // gaps (a bridging tet would make faces on the surface interior, or change the volume).
  check_conforming(conform(generated("mouth", {"16"}), 0.1));
  check_conforming(conform(generated("comb", {"8"}), 0.05));
}

TEST(Conforming3, SelfConnectingShapeDropsTheHelperBoxSolid) {
  const Conformed c = conform(generated("double-loop-torus", {"24"}), 0.08);
  ASSERT_FALSE(c.im.helper_boxes.empty());
  check_conforming(c, 20);
  EXPECT_GT(c.mesh.stats.helper_tets, 0u);
}

TEST(Conforming3, QualityBoundsAreRequested) {
  const Conformed c = conform(generated("two-tori", {"10"}), 0.1, 1.5, 10.0);
  check_conforming(c);
  EXPECT_GT(c.mesh.stats.min_dihedral, 0.0);
  EXPECT_LE(c.mesh.stats.median_radius_edge, 1.5);
}

TEST(Conforming3, DoubleLoopWithCube) {
  const std::string path = real_path("doubleLoopWithCube.obj");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not present";
  SurfaceReadResult r = read_surface(path);
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  check_conforming(conform(r.surface, 0.1), 10);
}

TEST(Conforming3, NarrowCellWedgeBoundsTheMinimumDihedral) {
  // A 3-degree wedge of the solid at one edge: every tet at that edge has a dihedral angle of at
  // most 3 degrees there, whatever the mesher does; the report says so and blames the wedge.
  const Conformed c = conform(wedge_prism(3.0), 0.2);
  check_conforming(c);
  const ConformingStats& st = c.mesh.stats;
  EXPECT_NEAR(st.min_cell_wedge, 3.0, 1e-6);
  EXPECT_EQ(st.narrow_wedge_edges, 1u);
  EXPECT_LE(st.min_dihedral, 3.0 + 1e-9);
  EXPECT_GT(st.slivers_in_narrow_wedge, 0u);
  // A 60-degree wedge is no bound at the sliver threshold; the other edges have 60 and 90 degrees.
  const Conformed wide = conform(wedge_prism(60.0), 0.2);
  check_conforming(wide);
  EXPECT_NEAR(wide.mesh.stats.min_cell_wedge, 60.0, 1e-6);
  EXPECT_EQ(wide.mesh.stats.narrow_wedge_edges, 0u);
  EXPECT_EQ(wide.mesh.stats.slivers_in_narrow_wedge, 0u);
}

TEST(Conforming3, CutTrianglesOfEachInputTriangleComeInACanonicalOrder) {
  // TetGen meshes the cut mesh as a PLC in its order, and its output depends on that order: the
  // cut triangles must come out the same on every run and thread count. The triangulations of
  // the cut input triangles run on several threads, and the order the CDT hands out its faces
  // was not reproducible there (the quintuple torus swapped two faces between runs). So every
  // input triangle cut into several sub-triangles lists them canonically, an order that depends
  // only on the set: each starts at its smallest geometric point, and they increase.
  ImmerseOptions io;
  io.build.exact_volumes = false;
  io.build.threads = 4;
  const Immersed im = immerse_surface(generated("quintuple-torus", {"24"}), io);
  ASSERT_TRUE(im.build.complex) << im.build.report.summary();
  const Complex& c = *im.build.complex;
  ASSERT_EQ(c.cut_triangle_source.size(), c.cut_triangles.size());
  std::size_t checked = 0;
  for (std::size_t x = 0; x < c.cut_triangles.size();) {
    std::size_t end = x + 1;
    while (end < c.cut_triangles.size() && c.cut_triangle_source[end] == c.cut_triangle_source[x]) ++end;
    if (end - x >= 2) {
      std::array<std::uint32_t, 3> previous{};
      for (std::size_t y = x; y < end; ++y) {
        const Triangle& t = c.cut_triangles[y];
        const std::array<std::uint32_t, 3> g{c.cut_point[t[0]], c.cut_point[t[1]], c.cut_point[t[2]]};
        EXPECT_TRUE(g[0] < g[1] && g[0] < g[2]) << "cut triangle " << y << " does not start at its smallest point";
        if (y > x) EXPECT_LT(previous, g) << "cut triangles " << y - 1 << " and " << y << " of input triangle "
                                          << c.cut_triangle_source[x] << " out of order";
        previous = g;
      }
      ++checked;
    }
    x = end;
  }
  EXPECT_GT(checked, 1000u);
}

TEST(Conforming3, RoundedCutMeshChecksAreExact) {
  // The checks run before TetGen on the rounded cut mesh, on hand-made configurations: each
  // improper contact is found, each proper one (a shared vertex or edge only) passes.
  const auto defects = [](std::vector<Point3> points, std::vector<std::array<std::int32_t, 3>> triangles) {
    return check_rounded_cut_mesh(points, triangles, std::vector<std::uint32_t>(triangles.size(), 0)).total();
  };
  const Point3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  // A shared edge: folded onto each other (coplanar, same side) is refused; opposite sides or
  // out of the plane pass; out of the plane by one ulp passes too (exact, no tolerance).
  EXPECT_GT(defects({o, x, y, {0.5, 0.25, 0}}, {{0, 1, 2}, {0, 1, 3}}), 0u);
  EXPECT_EQ(defects({o, x, y, {0.5, -0.25, 0}}, {{0, 1, 2}, {0, 3, 1}}), 0u);
  EXPECT_EQ(defects({o, x, y, {0.5, 0.25, 1e-300}}, {{0, 1, 2}, {0, 1, 3}}), 0u);
  // A shared vertex: the other triangle's far edge through this one is refused; a coplanar
  // triangle in this one's wedge is refused; a disjoint wedge passes.
  EXPECT_GT(defects({o, x, y, {0.2, 0.2, -1}, {0.2, 0.2, 1}}, {{0, 1, 2}, {0, 3, 4}}), 0u);
  EXPECT_GT(defects({o, x, y, {0.1, 0.05, 0}, {0.05, 0.1, 0}}, {{0, 1, 2}, {0, 3, 4}}), 0u);
  EXPECT_EQ(defects({o, x, y, {-1, -0.5, 0}, {-0.5, -1, 0}}, {{0, 1, 2}, {0, 3, 4}}), 0u);
  EXPECT_EQ(defects({o, x, y, z, {-1, 0, 1}}, {{0, 1, 2}, {0, 3, 4}}), 0u);
  // Nothing shared: crossing is refused, apart passes.
  EXPECT_GT(defects({o, x, y, {0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}}, {{0, 1, 2}, {3, 4, 5}}), 0u);
  EXPECT_EQ(defects({o, x, y, {2, 2, -1}, {3, 2, 1}, {2, 3, 1}}, {{0, 1, 2}, {3, 4, 5}}), 0u);
  // Two points rounded together, and a flat triangle.
  EXPECT_GT(defects({o, x, y, {1, 0, 0}}, {{0, 1, 2}, {0, 3, 2}}), 0u);
  EXPECT_GT(defects({o, x, {2, 0, 0}}, {{0, 1, 2}}), 0u);
  // The same triangle twice.
  EXPECT_GT(defects({o, x, y}, {{0, 1, 2}, {0, 2, 1}}), 0u);
}

/// `surface` immersed (exact volumes: doubles overflow beyond 1e102) and meshed conformingly with
/// edge length `edge_length`.
Conformed conform_at(const Surface& surface, double edge_length) {
  Conformed c;
  c.im = immerse_surface(surface, ImmerseOptions{});
  EXPECT_TRUE(c.im.build.report.ok()) << c.im.build.report.summary();
  if (!c.im.build.complex || c.im.search.immersions.empty()) {
    ADD_FAILURE() << "no immersion (" << to_string(c.im.search.status) << ")";
    return c;
  }
  ConformingOptions options;
  options.edge_length = edge_length;
  c.mesh = mesh_conforming(*c.im.build.complex, c.im.search.immersions[0], options, c.im.input_vertices,
                            c.im.input_triangles);
  return c;
}

Surface scaled_by(Surface s, double factor) {
  for (Point3& p : s.vertices)
    for (double& x : p) x *= factor;
  return s;
}

/// The corner tet (0, e1, e2, e3), outward triangles.
Surface corner_tet() {
  Surface s;
  s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  s.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  return s;
}

// The documented coordinates reach 1e300 (and down to 1e-300). The work estimate computed h^3 and
// the enclosed volume in doubles (a box of 1e110: "about nan tets", refused whatever the edge
// length), TetGen's predicates overflowed, and the quality report said "min 90 deg,
// radius-edge max inf" at 1e100. Each scale must give the unit tet's mesh and statistics.
TEST(Conforming3, ExtremeScalesMeshLikeTheUnitScale) {
  // The corner tet: dihedral angles 90 (three) and acos(1/sqrt 3) (three); circumradius
  // sqrt(3)/2 over the shortest edge 1.
  const double corner_angle = std::acos(1.0 / std::sqrt(3.0)) * 180.0 / std::acos(-1.0);
  for (double scale : {1.0, 1e100, 1e110, 1e-110, 1e300, 1e-300}) {
    const Surface s = scaled_by(corner_tet(), scale);
    const Conformed c = conform_at(s, 0.5 * scale);
    ASSERT_TRUE(c.mesh.report.ok()) << scale << ": " << c.mesh.report.summary();
    ASSERT_EQ(c.mesh.mesh.tets.size(), 1u) << scale;
    EXPECT_NEAR(c.mesh.stats.min_dihedral, corner_angle, 1e-9) << scale;
    EXPECT_NEAR(c.mesh.stats.median_dihedral, 90.0, 1e-9) << scale;
    EXPECT_NEAR(c.mesh.stats.max_radius_edge, std::sqrt(3.0) / 2.0, 1e-12) << scale;
    EXPECT_NEAR(c.mesh.stats.min_cell_wedge, corner_angle, 1e-9) << scale;
  }
  // A refined mesh scaled by 2^+-365 (exact): the same tets on the same points times the factor,
  // the same statistics to the bit.
  const Surface tube = generated("tube-overlap", {"12"});
  const Box3 box = bounding_box(tube);
  const double edge = 0.08 * std::max({box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]});
  const Conformed unit = conform_at(tube, edge);
  check_conforming(unit);
  for (double factor : {0x1p365, 0x1p-365}) {
    const Conformed c = conform_at(scaled_by(tube, factor), edge * factor);
    ASSERT_TRUE(c.mesh.report.ok()) << factor << ": " << c.mesh.report.summary();
    EXPECT_EQ(c.mesh.mesh.tets, unit.mesh.mesh.tets) << factor;
    ASSERT_EQ(c.mesh.mesh.vertices.size(), unit.mesh.mesh.vertices.size()) << factor;
    for (std::size_t v = 0; v < c.mesh.mesh.vertices.size(); ++v)
      for (int d = 0; d < 3; ++d)
        ASSERT_EQ(c.mesh.mesh.vertices[v][d], unit.mesh.mesh.vertices[v][d] * factor) << factor << " vertex " << v;
    EXPECT_EQ(c.mesh.stats.min_dihedral, unit.mesh.stats.min_dihedral) << factor;
    EXPECT_EQ(c.mesh.stats.median_dihedral, unit.mesh.stats.median_dihedral) << factor;
    EXPECT_EQ(c.mesh.stats.max_radius_edge, unit.mesh.stats.max_radius_edge) << factor;
    EXPECT_EQ(c.mesh.stats.median_radius_edge, unit.mesh.stats.median_radius_edge) << factor;
    EXPECT_EQ(c.mesh.stats.min_cell_wedge, unit.mesh.stats.min_cell_wedge) << factor;
    EXPECT_EQ(c.mesh.stats.slivers, unit.mesh.stats.slivers) << factor;
  }
}

// A refused edge length names the tets it would make as a finite number (README's example), not
// "inf": the estimate is the volume bound (for a tet: its own volume, the cones from its centroid)
// over the regular tet's volume h^3 / (6 sqrt 2), computed here in long double (to 1e4932).
TEST(Conforming3, RefusedEdgeLengthNamesAFiniteEstimate) {
  for (long double scale : {1.0L, 0x1p365L, 0x1p-365L}) {
    const Surface s = scaled_by(corner_tet(), static_cast<double>(scale));
    const Conformed c = conform_at(s, 1e-300);
    ASSERT_FALSE(c.mesh.report.ok()) << scale;
    const long double volume = scale * scale * scale / 6.0L;
    const long double h = 1e-300L;
    const long double estimate = volume / (h * h * h / (6.0L * std::sqrt(2.0L)));
    char expected[200];
    std::snprintf(expected, sizeof expected, "edge length 1e-300 would fill the input (volume at most %.6Lg) with about %.3Lg tets; at most 2e+07",
                  volume, estimate);
    EXPECT_NE(c.mesh.report.summary().find(expected), std::string::npos)
        << c.mesh.report.summary() << "\n  expected: " << expected;
  }
}

TEST(Conforming3, CheckerRejectsAWeldedOutput) {
  // The checker must fail a mesh whose copies were glued across an owned patch: weld every output
  // vertex to the first vertex at the same position (what gluing everything would give).
  Conformed c = conform(generated("two-tori", {"8"}), 0.15);
  ASSERT_TRUE(c.mesh.report.ok());
  std::map<Point3, int> first;
  for (Tet& t : c.mesh.mesh.tets)
    for (int& v : t) v = first.emplace(c.mesh.mesh.vertices[static_cast<std::size_t>(v)], v).first->second;
  testing::TestPartResultArray failures;
  {
    testing::ScopedFakeTestPartResultReporter intercept(
        testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &failures);
    check_conforming(c, 0);
  }
  EXPECT_GT(failures.size(), 0) << "the checker accepted a welded mesh";
}

}  // namespace
}  // namespace imm::dim3
