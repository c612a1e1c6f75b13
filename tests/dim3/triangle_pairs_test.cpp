// overlapping_triangle_pairs (dim3/triangle_pairs.h): the candidate pairs of every exact pass over
// a surface's self-contacts. Checked against the definition (every pair of closed boxes, O(n^2))
// on generated surfaces, on triangle soups whose boxes touch exactly (integer coordinates) and
// whose sizes span orders of magnitude, and on every thread count.
#include "dim3/triangle_pairs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "dim3/generators3.h"

namespace imm::dim3 {
namespace {

std::vector<std::array<std::uint32_t, 2>> brute_force(const Surface& s) {
  std::vector<std::array<double, 6>> box(s.triangle_count());
  for (std::size_t t = 0; t < s.triangle_count(); ++t)
    for (int d = 0; d < 3; ++d) {
      const double a = s.vertices[s.triangles[t][0]][d], b = s.vertices[s.triangles[t][1]][d],
                   c = s.vertices[s.triangles[t][2]][d];
      box[t][d] = std::min({a, b, c});
      box[t][3 + d] = std::max({a, b, c});
    }
  std::vector<std::array<std::uint32_t, 2>> pairs;
  for (std::uint32_t a = 0; a < box.size(); ++a)
    for (std::uint32_t b = a + 1; b < box.size(); ++b) {
      bool meet = true;
      for (int d = 0; d < 3; ++d) meet = meet && box[a][d] <= box[b][3 + d] && box[b][d] <= box[a][3 + d];
      if (meet) pairs.push_back({a, b});
    }
  return pairs;
}

/// Triangles with corners on a coarse integer lattice (boxes touching exactly along faces,
/// edges and corners), sizes from one lattice step to `largest` steps.
Surface lattice_soup(std::size_t count, int largest, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> pos(0, 40);
  std::uniform_int_distribution<int> size(0, largest);
  Surface s;
  for (std::size_t t = 0; t < count; ++t) {
    const int x = pos(rng), y = pos(rng), z = pos(rng);
    const auto id = static_cast<std::uint32_t>(s.vertices.size());
    s.vertices.push_back({double(x), double(y), double(z)});
    s.vertices.push_back({double(x + size(rng)), double(y + size(rng)), double(z)});
    s.vertices.push_back({double(x), double(y + size(rng)), double(z + size(rng))});
    s.triangles.push_back({id, id + 1, id + 2});
  }
  return s;
}

TEST(TrianglePairs, GeneratedSurfacesMatchTheDefinition) {
  for (const Surface& s : {helix(2, 12), tree(6), two_tori(10), quintuple_torus(12)}) {
    const auto expected = brute_force(s);
    ASSERT_FALSE(expected.empty());
    EXPECT_EQ(overlapping_triangle_pairs(s, 1), expected) << s.triangle_count() << " triangles";
  }
}

TEST(TrianglePairs, TouchingBoxesCountAndSizesMayVary) {
  for (int largest : {1, 4, 40}) {
    const Surface s = lattice_soup(1500, largest, 7 + static_cast<std::uint64_t>(largest));
    EXPECT_EQ(overlapping_triangle_pairs(s, 2), brute_force(s)) << "largest " << largest;
  }
  // A handful of triangles spanning everything among many small ones (the grid lists the large
  // ones in many cells), and more of them than the grid accepts (CGAL's segment tree instead).
  for (std::size_t large : {3, 400}) {
    Surface s = lattice_soup(1500, 1, 3);
    Surface big = lattice_soup(large, 40, 4);
    const auto offset = static_cast<std::uint32_t>(s.vertices.size());
    s.vertices.insert(s.vertices.end(), big.vertices.begin(), big.vertices.end());
    for (Triangle t : big.triangles) s.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    EXPECT_EQ(overlapping_triangle_pairs(s, 2), brute_force(s)) << large << " large triangles";
  }
}

// Inputs that crowd most boxes into a few grid cells (the scan would be quadratic there, so
// the segment tree takes over): a dense cluster of small triangles beside one triangle as large
// as the whole input, and long slivers side by side along one axis.
TEST(TrianglePairs, CrowdedInputsMatchTheDefinition) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Surface cluster;
  for (std::uint32_t t = 0; t < 3000; ++t) {
    const double x = unit(rng), y = unit(rng), z = unit(rng);
    cluster.vertices.push_back({x, y, z});
    cluster.vertices.push_back({x + 0.01, y, z});
    cluster.vertices.push_back({x, y + 0.01, z + 0.01});
    cluster.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  const auto big = static_cast<std::uint32_t>(cluster.vertices.size());
  cluster.vertices.push_back({-100, -100, 0.5});
  cluster.vertices.push_back({100, -100, 0.5});
  cluster.vertices.push_back({0, 100, 0.6});
  cluster.triangles.push_back({big, big + 1, big + 2});
  Surface slivers;
  for (std::uint32_t t = 0; t < 3000; ++t) {
    const double y = unit(rng), z = unit(rng);
    slivers.vertices.push_back({0.0, y, z});
    slivers.vertices.push_back({1000.0, y + 0.001, z});
    slivers.vertices.push_back({500.0, y, z + 0.001});
    slivers.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  for (const Surface* s : {&cluster, &slivers}) {
    const auto expected = brute_force(*s);
    ASSERT_FALSE(expected.empty());
    EXPECT_EQ(overlapping_triangle_pairs(*s, 2), expected) << s->triangle_count() << " triangles";
  }
}

TEST(TrianglePairs, SameOnEveryThreadCount) {
  const Surface s = quintuple_torus(20);
  const auto one = overlapping_triangle_pairs(s, 1);
  for (unsigned threads : {2u, 3u, 0u}) EXPECT_EQ(overlapping_triangle_pairs(s, threads), one) << threads;
}

TEST(TrianglePairs, TinyInputs) {
  Surface s = lattice_soup(1, 3, 1);
  EXPECT_TRUE(overlapping_triangle_pairs(s).empty());
  s = lattice_soup(2, 0, 1);  // degenerate (point) boxes
  EXPECT_EQ(overlapping_triangle_pairs(s), brute_force(s));
  EXPECT_TRUE(overlapping_triangle_pairs(Surface{}).empty());
}

}  // namespace
}  // namespace imm::dim3
