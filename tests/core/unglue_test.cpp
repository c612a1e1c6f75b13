// The dimension-generic duplicate-and-connect driver (core/unglue.h; paper §7.1.2, Teran et al.
// 2005 §6), on hand-made triangle and tetrahedron inputs: the same code for D = 2 and D = 3.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
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
  input.adjacencies = {{0, 1}};  // across their shared edge (1, 2)
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
  input.adjacencies = {{0, 1}, {1, 2}, {2, 3}};  // across spokes (0, 2), (0, 3), (0, 4)
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
  input.adjacencies = {{0, 1}};  // across their shared face (1, 2, 3)
  const UnglueResult<3> r = unglue<3>(input);
  ASSERT_EQ(r.copies.size(), 3u);
  // Copy of atom 2 (node 1, another local region of tet 1) is on its own: 4 fresh vertices.
  EXPECT_EQ(r.vertex_source.size(), 5u + 4u);
  EXPECT_EQ(r.copy_element, (std::vector<std::uint32_t>{0, 1, 1}));
}

TEST(Unglue, RejectsFusionAcrossElements) {
  UnglueInput<2> input;
  input.elements = {{0, 1, 2}, {2, 1, 3}, {2, 3, 4}, {2, 0, 1}};
  input.atoms = {{0, NodeId(0), 0}, {1, NodeId(0), 0}, {2, NodeId(0), 0}, {3, NodeId(0), 0}};
  input.fusions = {{0, 1}};
  EXPECT_THROW(unglue<2>(input), InvariantError);
  input.fusions.clear();
  for (const std::pair<std::uint32_t, std::uint32_t> pair : {std::pair<std::uint32_t, std::uint32_t>{0, 2},  // one vertex
                                                             {0, 3}}) {  // all three: one triangle twice
    input.adjacencies = {{pair.first, pair.second}};
    EXPECT_THROW(unglue<2>(input), InvariantError);
    EXPECT_THROW(unglue<2>(input, 3), InvariantError);
  }
}

/// The driver as it was written sequentially (one plain union-find, numbering by a walk in
/// element order): the independent reference the concurrent driver must reproduce exactly.
template <int D>
UnglueResult<D> sequential_unglue(const UnglueInput<D>& input) {
  constexpr int kArity = D + 1;
  constexpr std::uint32_t kNone = 0xffffffffu;
  UnionFind atoms(input.atoms.size());
  for (const auto& [a, b] : input.fusions) atoms.unite(a, b);
  std::vector<std::uint32_t> order(input.atoms.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t x, std::uint32_t y) { return input.atoms[x].element < input.atoms[y].element; });
  UnglueResult<D> out;
  out.atom_copy.assign(input.atoms.size(), kNone);
  std::vector<std::uint32_t> root_copy(input.atoms.size(), kNone);
  for (std::uint32_t a : order) {
    const std::uint32_t root = atoms.find(a);
    if (root_copy[root] == kNone) {
      root_copy[root] = static_cast<std::uint32_t>(out.copy_element.size());
      out.copy_element.push_back(input.atoms[a].element);
      out.copy_node.push_back(input.atoms[a].node);
    }
    out.atom_copy[a] = root_copy[root];
    out.copy_node[root_copy[root]] = std::min(out.copy_node[root_copy[root]], input.atoms[a].node);
  }
  UnionFind vertices(out.copy_element.size() * kArity);
  const auto position = [&](std::uint32_t element, int v) {
    const auto& e = input.elements[element];
    return static_cast<std::uint32_t>(std::find(e.begin(), e.end(), v) - e.begin());
  };
  for (const UnglueAdjacency<D>& adjacency : input.adjacencies) {
    const std::uint32_t ea = input.atoms[adjacency.first].element, eb = input.atoms[adjacency.second].element;
    std::set<int> face(input.elements[ea].begin(), input.elements[ea].end());  // the vertices both have
    std::set<int> other(input.elements[eb].begin(), input.elements[eb].end());
    for (int v : face)
      if (other.count(v) > 0)
        vertices.unite(out.atom_copy[adjacency.first] * kArity + position(ea, v),
                       out.atom_copy[adjacency.second] * kArity + position(eb, v));
  }
  std::vector<std::int32_t> class_id(vertices.size(), -1);
  out.copies.resize(out.copy_element.size());
  for (std::uint32_t c = 0; c < out.copies.size(); ++c)
    for (int k = 0; k < kArity; ++k) {
      const std::uint32_t root = vertices.find(c * kArity + static_cast<std::uint32_t>(k));
      if (class_id[root] < 0) {
        class_id[root] = static_cast<std::int32_t>(out.vertex_source.size());
        out.vertex_source.push_back(input.elements[out.copy_element[c]][k]);
      }
      out.copies[c][k] = class_id[root];
    }
  return out;
}

/// A triangulated n x n grid (two triangles per square) with 1-3 atoms per triangle on random
/// nodes, random fusions inside triangles and random adjacencies across shared edges: large
/// enough (tens of thousands of atoms) that every loop of the driver runs in several blocks.
UnglueInput<2> random_grid_input(int n, std::uint32_t seed, bool shuffle_atoms) {
  std::mt19937 rng(seed);
  UnglueInput<2> input;
  const auto vertex = [n](int i, int j) { return i * (n + 1) + j; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      input.elements.push_back({vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)});
      input.elements.push_back({vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
    }
  std::vector<std::vector<std::uint32_t>> atoms_of(input.elements.size());
  for (std::uint32_t e = 0; e < input.elements.size(); ++e) {
    const int count = 1 + static_cast<int>(rng() % 3);
    for (int k = 0; k < count; ++k) {
      atoms_of[e].push_back(static_cast<std::uint32_t>(input.atoms.size()));
      input.atoms.push_back({e, NodeId(static_cast<int>(rng() % 5)), k});
    }
  }
  if (shuffle_atoms) {  // atoms in no particular order: the driver sorts them by element itself
    std::vector<std::uint32_t> perm(input.atoms.size());
    std::iota(perm.begin(), perm.end(), 0u);
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<UnglueAtom> shuffled(input.atoms.size());
    for (std::uint32_t a = 0; a < perm.size(); ++a) shuffled[perm[a]] = input.atoms[a];
    input.atoms = shuffled;
    for (auto& list : atoms_of)
      for (std::uint32_t& a : list) a = perm[a];
  }
  const auto pick = [&](std::uint32_t e) { return atoms_of[e][rng() % atoms_of[e].size()]; };
  for (std::uint32_t e = 0; e < input.elements.size(); ++e)
    if (atoms_of[e].size() > 1 && rng() % 2 == 0) input.fusions.emplace_back(pick(e), pick(e));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const auto lower = static_cast<std::uint32_t>(2 * (i * n + j));  // its diagonal: the upper one
      const auto connect = [&](std::uint32_t a, std::uint32_t b) {  // across the edge a and b share
        for (int k = 0; k < 2; ++k)
          if (rng() % 4 != 0) input.adjacencies.push_back({pick(a), pick(b)});
      };
      connect(lower, lower + 1);
      if (i + 1 < n) connect(lower, lower + 2 * static_cast<std::uint32_t>(n) + 1);
      if (j + 1 < n) connect(lower + 1, lower + 2);
    }
  return input;
}

// The unions run concurrently and the copies and vertices are numbered on all threads
// (core/unglue.cpp): the result is the sequential driver's, field by field, on 1, 2 and 3
// threads, with atoms listed element by element (as the meshers do) or shuffled.
TEST(Unglue, SameResultOnEveryThreadCountAsTheSequentialDriver) {
  for (const bool shuffled : {false, true}) {
    const UnglueInput<2> input = random_grid_input(120, shuffled ? 7u : 3u, shuffled);
    const UnglueResult<2> reference = sequential_unglue<2>(input);
    ASSERT_GT(reference.copies.size(), 20000u);
    ASSERT_LT(reference.vertex_source.size(), reference.copies.size() * 3);  // some vertices merged
    for (unsigned threads : {1u, 2u, 3u}) {
      SCOPED_TRACE("threads " + std::to_string(threads) + (shuffled ? ", shuffled atoms" : ""));
      const UnglueResult<2> r = unglue<2>(input, threads);
      EXPECT_EQ(r.copy_element, reference.copy_element);
      EXPECT_EQ(r.copy_node, reference.copy_node);
      EXPECT_EQ(r.atom_copy, reference.atom_copy);
      EXPECT_EQ(r.copies, reference.copies);
      EXPECT_EQ(r.vertex_source, reference.vertex_source);
    }
  }
}

}  // namespace
}  // namespace imm
