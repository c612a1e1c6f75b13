// core/local_regions.h: the regions of local regions (resolve_regions, on several threads) and
// the face of an adjacency, derived from its two elements rather than stored.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/local_regions.h"

namespace imm {
namespace {

/// Local regions in hidden groups, each group connected by a random tree of input-free
/// adjacencies (listed in random order), plus adjacencies on patches between groups (which must
/// not join them). Some groups have members whose region is known; the others must be located.
struct RandomRegions {
  LocalRegions<3> local;
  std::vector<std::uint32_t> group;  ///< per local region
  std::vector<bool> known_group;     ///< per group: some member's region is known
};

RandomRegions random_regions(std::uint32_t n, std::uint32_t groups, std::uint32_t seed) {
  std::mt19937 rng(seed);
  RandomRegions r;
  r.group.resize(n);
  for (std::uint32_t& g : r.group) g = static_cast<std::uint32_t>(rng() % groups);
  r.known_group.resize(groups);
  for (std::uint32_t g = 0; g < groups; ++g) r.known_group[g] = rng() % 3 != 0;
  r.local.region.resize(n);
  r.local.element.resize(n);
  std::vector<std::vector<std::uint32_t>> members(groups);
  for (std::uint32_t lr = 0; lr < n; ++lr) {
    members[r.group[lr]].push_back(lr);
    if (r.known_group[r.group[lr]] && rng() % 4 == 0) r.local.region[lr] = RegionId(static_cast<int>(r.group[lr]));
  }
  for (std::uint32_t g = 0; g < groups; ++g) {
    if (!r.known_group[g] || members[g].empty()) continue;
    const std::uint32_t lr = members[g][rng() % members[g].size()];  // at least one known member
    r.local.region[lr] = RegionId(static_cast<int>(g));
  }
  for (const std::vector<std::uint32_t>& list : members)
    for (std::size_t k = 1; k < list.size(); ++k) {
      const std::uint32_t other = list[rng() % k];
      r.local.adjacencies.push_back({other, list[k], PatchId()});
      if (rng() % 5 == 0) r.local.adjacencies.push_back({list[k], other, PatchId()});  // repeated
    }
  for (std::uint32_t k = 0; k < n / 4; ++k)
    r.local.adjacencies.push_back({static_cast<std::uint32_t>(rng() % n), static_cast<std::uint32_t>(rng() % n),
                                   PatchId(static_cast<int>(rng() % 7))});
  std::shuffle(r.local.adjacencies.begin(), r.local.adjacencies.end(), rng);
  return r;
}

// Every local region gets its component's known region; a component with none is located once,
// on its smallest member (the located id is that member's, so a different member shows). The
// same regions and the same located members on 1, 2 and 3 threads: the unions run concurrently
// (MinRootUnionFind) over many blocks.
TEST(LocalRegions, ResolveRegionsOnEveryThreadCountLocatesEachUnknownComponentOnceAtItsSmallestMember) {
  constexpr std::uint32_t kN = 200000, kGroups = 3000;
  constexpr int kLocated = 1000000;  // located ids: kLocated + the member located
  const RandomRegions input = random_regions(kN, kGroups, 11);
  std::vector<std::uint32_t> smallest(kGroups, kN);
  for (std::uint32_t lr = 0; lr < kN; ++lr) smallest[input.group[lr]] = std::min(smallest[input.group[lr]], lr);
  std::size_t unknown = 0;
  for (std::uint32_t g = 0; g < kGroups; ++g) unknown += !input.known_group[g] && smallest[g] < kN ? 1 : 0;
  ASSERT_GT(unknown, 100u);
  for (unsigned threads : {1u, 2u, 3u}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    LocalRegions<3> local = input.local;
    std::vector<std::uint32_t> located;
    local.resolve_regions(
        [&](std::uint32_t lr) {
          located.push_back(lr);
          return RegionId(kLocated + static_cast<int>(lr));
        },
        threads);
    EXPECT_EQ(local.point_locations, unknown);
    EXPECT_TRUE(std::is_sorted(located.begin(), located.end()));
    for (std::uint32_t lr = 0; lr < kN; ++lr) {
      const std::uint32_t g = input.group[lr];
      const RegionId expected =
          input.known_group[g] ? RegionId(static_cast<int>(g)) : RegionId(kLocated + static_cast<int>(smallest[g]));
      ASSERT_EQ(local.region[lr], expected) << "local region " << lr;
    }
  }
}

// Two known regions in one component across an input-free adjacency: a bug, on any thread count.
TEST(LocalRegions, ResolveRegionsRefusesTwoRegionsInOneComponent) {
  RandomRegions input = random_regions(50000, 500, 5);
  std::uint32_t a = 0;
  while (!input.local.region[a].is_valid()) ++a;
  std::uint32_t b = a + 1;
  while (!input.local.region[b].is_valid() || input.group[b] == input.group[a]) ++b;
  input.local.adjacencies.push_back({a, b, PatchId()});
  for (unsigned threads : {1u, 2u, 3u}) {
    LocalRegions<3> local = input.local;
    EXPECT_THROW(local.resolve_regions([](std::uint32_t) { return RegionId(0); }, threads), InvariantError);
  }
}

// The face of an adjacency is the vertices its two elements share, ascending, in either order;
// elements sharing all their vertices (one element twice) or fewer than a face are refused.
TEST(LocalRegions, FaceIsTheSharedVerticesOfTheTwoElements) {
  LocalRegions<3> local;
  local.element = {0, 0, 1, 2, 3};
  const std::vector<std::array<int, 4>> tets = {{7, 3, 9, 5}, {9, 2, 3, 7}, {5, 9, 7, 3}, {1, 2, 3, 4}};
  using Face = std::array<int, 3>;
  EXPECT_EQ(local.face({1, 2, PatchId()}, tets), (Face{3, 7, 9}));
  EXPECT_EQ(local.face({2, 0, PatchId(2)}, tets), (Face{3, 7, 9}));
  EXPECT_THROW((void)local.face({0, 3, PatchId()}, tets), InvariantError);  // the same vertices
  EXPECT_THROW((void)local.face({0, 4, PatchId()}, tets), InvariantError);  // one vertex in common
  LocalRegions<2> flat;
  flat.element = {0, 1};
  const std::vector<std::array<int, 3>> triangles = {{4, 1, 6}, {6, 8, 4}};
  EXPECT_EQ(flat.face({0, 1, PatchId()}, triangles), (std::array<int, 2>{4, 6}));
}

}  // namespace
}  // namespace imm
