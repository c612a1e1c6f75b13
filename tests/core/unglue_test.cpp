// The dimension-generic duplicate-and-connect driver (core/unglue.h; paper §7.1.2, Teran et al.
// 2005 §6), on hand-made triangle and tetrahedron inputs: the same code for D = 2 and D = 3.
#include <gtest/gtest.h>

#include <set>

#include "core/diagnostics.h"
#include "core/unglue.h"
#include "core/union_find.h"

namespace imm {
namespace {

TEST(UnionFind, MergesAndFinds) {
  UnionFind sets(6);
  EXPECT_TRUE(sets.unite(0, 1));
  EXPECT_TRUE(sets.unite(2, 3));
  EXPECT_FALSE(sets.unite(1, 0));
  EXPECT_TRUE(sets.unite(1, 3));
  EXPECT_TRUE(sets.same(0, 2));
  EXPECT_FALSE(sets.same(0, 4));
  EXPECT_EQ(sets.add(), 6u);
  EXPECT_FALSE(sets.same(5, 6));
}

template <int D>
std::size_t distinct_vertices(const UnglueResult<D>& r) {
  std::set<int> used;
  for (const auto& copy : r.copies) used.insert(copy.begin(), copy.end());
  return used.size();
}

TEST(Unglue, TwoTrianglesSharingAnEdge) {
  UnglueInput<2> input;
  input.elements = {{0, 1, 2}, {2, 1, 3}};
  input.atoms = {{0, NodeId(0), 0}, {1, NodeId(0), 0}};
  const UnglueResult<2> apart = unglue<2>(input);
  EXPECT_EQ(apart.copies.size(), 2u);
  EXPECT_EQ(apart.vertex_source.size(), 6u);  // not connected: every vertex duplicated
  input.adjacencies = {{0, 1, {1, 2}}};
  const UnglueResult<2> joined = unglue<2>(input);
  EXPECT_EQ(joined.vertex_source.size(), 4u);
  EXPECT_EQ(distinct_vertices(joined), 4u);
  // The local vertex order of every copy is its element's, mapped to its background vertex.
  for (std::size_t c = 0; c < joined.copies.size(); ++c)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(joined.vertex_source[joined.copies[c][k]],
                input.elements[joined.copy_element[c]][k]);
}

TEST(Unglue, FusedAtomsShareOneCopyNamedByTheSmallestNode) {
  UnglueInput<2> input;
  input.elements = {{0, 1, 2}};
  // Three local regions seen by nodes 4, 1, 3: nodes 4 and 1 glued, node 3 apart.
  input.atoms = {{0, NodeId(4), 0}, {0, NodeId(1), 1}, {0, NodeId(3), 2}};
  input.fusions = {{0, 1}};
  const UnglueResult<2> r = unglue<2>(input);
  ASSERT_EQ(r.copies.size(), 2u);
  EXPECT_EQ(r.atom_copy[0], r.atom_copy[1]);
  EXPECT_NE(r.atom_copy[0], r.atom_copy[2]);
  EXPECT_EQ(r.copy_node[r.atom_copy[0]], NodeId(1));
  EXPECT_EQ(r.copy_node[r.atom_copy[2]], NodeId(3));
  EXPECT_EQ(r.vertex_source.size(), 6u);
}

TEST(Unglue, OpenFanDuplicatesOnlyTheCutVertex) {
  // Four triangles around vertex 0, connected across three of the four spokes (Teran §6): the
  // centre stays one vertex, the spoke that is not connected gets two copies of its outer end.
  UnglueInput<2> input;
  input.elements = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
  for (std::uint32_t e = 0; e < 4; ++e) input.atoms.push_back({e, NodeId(0), 0});
  input.adjacencies = {{0, 1, {0, 2}}, {1, 2, {0, 3}}, {2, 3, {0, 4}}};
  const UnglueResult<2> r = unglue<2>(input);
  EXPECT_EQ(r.vertex_source.size(), 6u);
  std::multiset<int> sources(r.vertex_source.begin(), r.vertex_source.end());
  EXPECT_EQ(sources.count(0), 1u);
  EXPECT_EQ(sources.count(1), 2u);
}

TEST(Unglue, TetrahedraUseTheSameDriver) {
  UnglueInput<3> input;
  input.elements = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  input.atoms = {{0, NodeId(0), 0}, {1, NodeId(0), 0}, {1, NodeId(1), 1}};
  input.adjacencies = {{0, 1, {1, 2, 3}}};
  const UnglueResult<3> r = unglue<3>(input);
  ASSERT_EQ(r.copies.size(), 3u);
  // Copy of atom 2 (node 1, another local region of tet 1) is on its own: 4 fresh vertices.
  EXPECT_EQ(r.vertex_source.size(), 5u + 4u);
  EXPECT_EQ(r.copy_element, (std::vector<std::uint32_t>{0, 1, 1}));
}

TEST(Unglue, RejectsFusionAcrossElements) {
  UnglueInput<2> input;
  input.elements = {{0, 1, 2}, {2, 1, 3}};
  input.atoms = {{0, NodeId(0), 0}, {1, NodeId(0), 0}};
  input.fusions = {{0, 1}};
  EXPECT_THROW(unglue<2>(input), InvariantError);
  input.fusions.clear();
  input.adjacencies = {{0, 1, {0, 2}}};  // vertex 0 is not in element 1
  EXPECT_THROW(unglue<2>(input), InvariantError);
}

}  // namespace
}  // namespace imm
