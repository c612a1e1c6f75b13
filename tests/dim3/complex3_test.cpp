// The exact 3D cell complex on small shapes whose answers follow by hand (DESIGN §4 invariants
// 1-2 exactly, nesting, reversal, genericity defects).
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "dim3/complex3.h"

namespace imm::dim3 {
namespace {

/// An axis-aligned box [lo, hi] with outward triangles.
Surface box(Point3 lo, Point3 hi) {
  Surface s;
  for (int i = 0; i < 8; ++i) s.vertices.push_back({i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]});
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[1]), std::uint32_t(q[2])});
    s.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[2]), std::uint32_t(q[3])});
  }
  s.source_face.resize(s.triangles.size());
  std::iota(s.source_face.begin(), s.source_face.end(), 0u);
  return s;
}

/// A torus around the z axis, major radius R, minor r, n x m quads (outward).
Surface torus(double R, double r, int n, int m, Point3 c = {0, 0, 0}) {
  Surface s;
  const double pi = std::acos(-1.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * pi * (i + 0.1) / n, v = 2 * pi * (j + 0.3) / m;
      s.vertices.push_back(
          {c[0] + (R + r * std::cos(v)) * std::cos(u), c[1] + (R + r * std::cos(v)) * std::sin(u), c[2] + r * std::sin(v)});
    }
  auto id = [&](int i, int j) { return std::uint32_t(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  s.source_face.resize(s.triangles.size());
  std::iota(s.source_face.begin(), s.source_face.end(), 0u);
  return s;
}

Surface inside_out(Surface s) {
  for (Triangle& t : s.triangles) std::swap(t[1], t[2]);
  return s;
}

Rational exact(double x) { return Rational(x); }

/// Invariant 1: sum of winding x volume over the cells equals the input's signed volume, exactly.
Rational winding_volume(const CellComplex<3>& c) {
  Rational total(0);
  for (CellId cell : ids<CellId>(c.cell_count())) total += c.measure(c.region_of(cell)) * c.winding_number(cell);
  return total;
}

/// Invariant 2 (and the complex's own preconditions, re-checked from outside).
void expect_patch_sides(const CellComplex<3>& c) {
  for (PatchId p : ids<PatchId>(c.patch_count())) {
    EXPECT_EQ(c.winding_number(c.sides(p).negative), c.winding_number(c.sides(p).positive) + 1);
  }
}

TEST(Complex3, SingleBoxIsOneCellWithExactVolume) {
  const BuildResult r = build_complex(box({0, 0, 0}, {1.5, 2, 0.25}));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  ASSERT_TRUE(r.complex);
  const CellComplex<3>& c = r.complex->complex;
  EXPECT_EQ(c.cell_count(), 1u);
  EXPECT_EQ(c.patch_count(), 1u);
  EXPECT_EQ(c.arc_count(), 0u);
  EXPECT_EQ(c.measure(c.region_of(CellId(0))), exact(1.5) * 2 * exact(0.25));
  EXPECT_TRUE(c.is_simply_connected(c.region_of(CellId(0))));
  EXPECT_FALSE(r.complex->reversed);
}

TEST(Complex3, InsideOutBoxIsReversed) {
  const BuildResult r = build_complex(inside_out(box({0, 0, 0}, {1, 1, 1})));
  ASSERT_TRUE(r.complex) << r.report.summary();
  EXPECT_TRUE(r.complex->reversed);
  EXPECT_EQ(r.complex->complex.cell_count(), 1u);
  EXPECT_EQ(r.complex->complex.winding_number(CellId(0)), 1);
}

TEST(Complex3, TwoOverlappingBoxesGiveThreeCells) {
  // Generic overlap: no face plane shared, no crossing point on a diagonal.
  const Surface a = box({0, 0, 0}, {1, 1, 1});
  const Surface b = box({0.5, 0.25, 0.375}, {1.75, 1.625, 1.5});
  const BuildResult r = build_complex(merge(a, b));
  ASSERT_TRUE(r.complex) << r.report.summary();
  const CellComplex<3>& c = r.complex->complex;
  EXPECT_EQ(c.cell_count(), 3u);
  EXPECT_EQ(c.max_winding_number(), 2);
  EXPECT_EQ(c.patch_count(), 4u);  // each box split into an inner and an outer patch
  EXPECT_EQ(c.arc_count(), 1u);    // one closed intersection loop
  expect_patch_sides(c);
  const Rational va = 1, vb = exact(1.25) * exact(1.375) * exact(1.125);
  EXPECT_EQ(winding_volume(c), va + vb);
  for (CellId cell : ids<CellId>(c.cell_count())) {
    if (c.winding_number(cell) == 2) {
      EXPECT_EQ(c.measure(c.region_of(cell)), exact(0.5) * exact(0.75) * exact(0.625));
    }
  }
}

TEST(Complex3, NestedAndFarAwayComponentsArePlacedByRays) {
  const Surface outer = box({0, 0, 0}, {10, 10, 10});
  const Surface inner = box({2, 3, 4}, {5, 6, 7});
  const Surface far = box({20, 0, 0}, {21, 1, 1});
  const BuildResult r = build_complex(merge(merge(outer, inner), far));
  ASSERT_TRUE(r.complex) << r.report.summary();
  const CellComplex<3>& c = r.complex->complex;
  EXPECT_EQ(r.complex->groups, 3u);
  ASSERT_EQ(c.cell_count(), 3u);
  std::vector<std::pair<int, Rational>> cells;
  for (CellId cell : ids<CellId>(c.cell_count()))
    cells.emplace_back(c.winding_number(cell), c.measure(c.region_of(cell)));
  std::sort(cells.begin(), cells.end());
  EXPECT_EQ(cells[0], (std::pair<int, Rational>{1, Rational(1)}));
  EXPECT_EQ(cells[1], (std::pair<int, Rational>{1, Rational(1000 - 27)}));  // the shell around the inner box
  EXPECT_EQ(cells[2], (std::pair<int, Rational>{2, Rational(27)}));
  EXPECT_EQ(winding_volume(c), Rational(1000 + 27 + 1));
  // the shell's boundary is two spheres: simply connected
  for (CellId cell : ids<CellId>(c.cell_count())) EXPECT_TRUE(c.is_simply_connected(c.region_of(cell)));
}

TEST(Complex3, CavityOfAnInsideOutComponentIsAVoid) {
  // A box with an inside-out box inside: a hollow solid (winding 1 shell, winding 0 cavity).
  const BuildResult r = build_complex(merge(box({0, 0, 0}, {4, 4, 4}), inside_out(box({1, 1, 1}, {2, 3, 2}))));
  ASSERT_TRUE(r.complex) << r.report.summary();
  const CellComplex<3>& c = r.complex->complex;
  ASSERT_EQ(c.cell_count(), 1u);
  EXPECT_EQ(c.measure(c.region_of(CellId(0))), Rational(64 - 2));
  EXPECT_EQ(c.region_count(), 3u);  // outside, shell, cavity (winding 0, bounded)
  EXPECT_EQ(winding_volume(c), Rational(62));
}

TEST(Complex3, TorusCellIsNotSimplyConnected) {
  const BuildResult r = build_complex(torus(3, 1, 24, 12));
  ASSERT_TRUE(r.complex) << r.report.summary();
  const CellComplex<3>& c = r.complex->complex;
  ASSERT_EQ(c.cell_count(), 1u);
  EXPECT_FALSE(c.is_simply_connected(c.region_of(CellId(0))));
  EXPECT_EQ(r.complex->region_genus[c.region_of(CellId(0))], 1);
}

TEST(Complex3, ThreeOverlappingToriHaveTriplePoints) {
  // Three tori pushed into one another: three sheets cross at triple points.
  const Surface a = torus(3, 1, 24, 12), b = torus(3, 1, 24, 12, {2.5, 0.1, 0.05}),
                d = torus(3, 1, 24, 12, {1.2, 2.1, -0.07});
  const BuildResult r = build_complex(merge(merge(a, b), d));
  ASSERT_TRUE(r.complex) << r.report.summary();
  const CellComplex<3>& c = r.complex->complex;
  expect_patch_sides(c);
  EXPECT_EQ(c.max_winding_number(), 3);
  EXPECT_GT(r.complex->triple_points, 0u);
  // winding x volume equals the sum of the two tori's volumes (both computed exactly from the input)
  Rational expected(0);
  for (const Surface& s : {a, b, d}) {
    for (const Triangle& t : s.triangles) {
      const Point3 &p = s.vertices[t[0]], &q = s.vertices[t[1]], &w = s.vertices[t[2]];
      const Rational px(p[0]), py(p[1]), pz(p[2]), qx(q[0]), qy(q[1]), qz(q[2]), wx(w[0]), wy(w[1]), wz(w[2]);
      expected += (px * (qy * wz - qz * wy) - py * (qx * wz - qz * wx) + pz * (qx * wy - qy * wx)) / 6;
    }
  }
  EXPECT_EQ(winding_volume(c), expected);
}

BuildOptions strict() {
  BuildOptions o;
  o.strict = true;  // exact contacts are defects (by default resolved: tests/dim3/contacts3_test.cpp)
  return o;
}

TEST(Complex3, CoplanarOverlapIsADefect) {
  // Two boxes sharing the plane z = 1 with overlapping faces.
  const BuildResult r =
      build_complex(merge(box({0, 0, 0}, {1, 1, 1}), box({0.25, 0.375, 1}, {1.5, 1.5, 2})), strict());
  EXPECT_FALSE(r.report.ok());
  EXPECT_FALSE(r.complex);
  EXPECT_NE(r.report.summary().find("coplanar"), std::string::npos) << r.report.summary();
}

TEST(Complex3, VertexTouchingAFaceIsADefect) {
  // An octahedron-like spike: a box whose corner touches the other box's face.
  Surface a = box({0, 0, 0}, {1, 1, 1});
  Surface b = box({1, 0.25, 0.375}, {2, 0.75, 0.625});  // b's face x = 1 lies in a's face plane
  const BuildResult r = build_complex(merge(a, b), strict());
  EXPECT_FALSE(r.report.ok());
  EXPECT_FALSE(r.complex);
}

TEST(Complex3, InversionIsReported) {
  // A box with an inside-out box crossing its boundary: windings -1 appear outside.
  const BuildResult r =
      build_complex(merge(box({0, 0, 0}, {1, 1, 1}), inside_out(box({0.5, 0.25, 0.375}, {1.75, 1.625, 1.5}))));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  ASSERT_TRUE(r.inversion);
  EXPECT_EQ(r.inversion->winding_number, -1);
}

}  // namespace
}  // namespace imm::dim3
