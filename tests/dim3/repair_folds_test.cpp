// --repair-folds (issue 16): local folds moved away by the least step of a fixed schedule, checked
// here by an independent exact test of every vertex star (CGAL's triangle-triangle intersection:
// two triangles of one star meet exactly in their common vertex, two sharing an edge exactly in
// that edge), not by the refinement step the repair itself uses.
#include <gtest/gtest.h>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>

#include "dim3/complex3.h"
#include "dim3/generators3.h"
#include "dim3/repair_folds.h"

namespace imm::dim3 {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;

/// Every pair of triangles sharing one vertex meets only there; sharing an edge, only along it.
/// @return the first vertex whose star is not embedded, or -1.
long first_folded_star(const Surface& s) {
  const auto point = [&](std::uint32_t v) { return K::Point_3(s.vertices[v][0], s.vertices[v][1], s.vertices[v][2]); };
  const auto triangle = [&](const Triangle& t) { return K::Triangle_3(point(t[0]), point(t[1]), point(t[2])); };
  for (std::size_t a = 0; a < s.triangle_count(); ++a) {
    for (std::size_t b = a + 1; b < s.triangle_count(); ++b) {
      const Triangle &ta = s.triangles[a], &tb = s.triangles[b];
      std::vector<std::uint32_t> shared;
      for (std::uint32_t v : ta)
        if (std::find(tb.begin(), tb.end(), v) != tb.end()) shared.push_back(v);
      if (shared.empty()) continue;
      const auto x = CGAL::intersection(triangle(ta), triangle(tb));
      if (!x) return shared.front();  // impossible: they share a vertex
      if (shared.size() == 1) {
        const K::Point_3* p = boost::get<K::Point_3>(&*x);
        if (p == nullptr || *p != point(shared[0])) return shared[0];
      } else {
        const K::Segment_3* e = boost::get<K::Segment_3>(&*x);
        if (e == nullptr || !(*e == K::Segment_3(point(shared[0]), point(shared[1])) ||
                              *e == K::Segment_3(point(shared[1]), point(shared[0]))))
          return shared[0];
      }
    }
  }
  return -1;
}

double move_of(const Surface& a, const Surface& b, std::size_t v) {
  return std::hypot(a.vertices[v][0] - b.vertices[v][0], a.vertices[v][1] - b.vertices[v][1],
                    a.vertices[v][2] - b.vertices[v][2]);
}

TEST(RepairFolds, TheIndependentStarCheckSeesTheGeneratedFold) {
  EXPECT_EQ(first_folded_star(folded_bipyramid(0)), -1);
  EXPECT_EQ(first_folded_star(folded_bipyramid(50)), -1);
  EXPECT_NE(first_folded_star(folded_bipyramid(100)), -1);
  EXPECT_FALSE(build_complex(folded_bipyramid(100)).folds.ok());
}

TEST(RepairFolds, MovesFoldVerticesWithinTheBudgetAndEmbedsEveryStar) {
  for (int percent : {95, 100, 105}) {
    SCOPED_TRACE(percent);
    const Surface in = folded_bipyramid(percent);
    const FoldRepair r = repair_folds(in, 3.0);
    ASSERT_TRUE(r.ok) << r.failure;
    EXPECT_EQ(first_folded_star(r.surface), -1);
    // Only the reported vertices moved, each by what is reported, at most the budget; the top
    // vertex (the one pulled across its ring) is among them; ids and triangles unchanged.
    ASSERT_EQ(r.surface.triangles, in.triangles);
    double largest = 0.0;
    for (std::size_t v = 0; v < in.vertex_count(); ++v) {
      const auto it = std::find_if(r.moved.begin(), r.moved.end(), [&](const MovedVertex& m) { return m.vertex == v; });
      if (it == r.moved.end()) {
        EXPECT_EQ(r.surface.vertices[v], in.vertices[v]) << v;
        continue;
      }
      EXPECT_DOUBLE_EQ(it->distance, move_of(in, r.surface, v));
      EXPECT_LE(it->distance, 3.0);
      EXPECT_GT(it->distance, 0.0);
      largest = std::max(largest, it->distance);
    }
    EXPECT_EQ(r.max_displacement, largest);
    EXPECT_TRUE(std::any_of(r.moved.begin(), r.moved.end(), [](const MovedVertex& m) { return m.vertex == 6; }));
  }
}

TEST(RepairFolds, RefusesWhenTheBudgetIsTooSmallAndChangesNothing) {
  const Surface in = folded_bipyramid(100);
  const FoldRepair r = repair_folds(in, 0.01);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("vertex 6 "), std::string::npos) << r.failure;
  EXPECT_NE(r.failure.find("not repaired within --repair-folds 0.01"), std::string::npos) << r.failure;
  EXPECT_EQ(r.surface.vertices, in.vertices);
}

TEST(RepairFolds, TheBuildRepairsOnlyWhenAskedAndDescribesTheRepairedSurface) {
  const Surface in = folded_bipyramid(100);
  const BuildResult refused = build_complex(in);
  EXPECT_FALSE(refused.folds.ok());
  EXPECT_FALSE(refused.repair);
  EXPECT_FALSE(refused.contacts) << "folds alone are no exact contacts";
  BuildOptions options;
  options.repair_folds = 3.0;
  const BuildResult repaired = build_complex(in, options);
  ASSERT_TRUE(repaired.repair && repaired.repair->ok);
  ASSERT_TRUE(repaired.complex);
  EXPECT_TRUE(repaired.folds.ok());
  EXPECT_EQ(repaired.complex->surface.vertices, repaired.repair->surface.vertices);
  EXPECT_EQ(repaired.complex->complex.cell_count(), 1u);
  options.repair_folds = 0.01;
  const BuildResult too_far = build_complex(in, options);
  EXPECT_FALSE(too_far.folds.ok());
  ASSERT_TRUE(too_far.repair);
  EXPECT_FALSE(too_far.repair->ok);
  EXPECT_FALSE(too_far.complex);
}

TEST(RepairFolds, GenericInputsAreNeverTouched) {
  BuildOptions options;
  options.repair_folds = 1.0;
  const BuildResult r = build_complex(two_spheres(6), options);
  EXPECT_FALSE(r.repair);
  ASSERT_TRUE(r.complex);
  EXPECT_EQ(r.complex->surface.vertices, two_spheres(6).vertices);
}

}  // namespace
}  // namespace imm::dim3
