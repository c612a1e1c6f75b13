// Immersion accessors and canonical forms (DESIGN §4 invariant 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <set>

#include "core/graph_search.h"
#include "support/hand_complexes.h"

namespace imm {
namespace {

using test_support::build;

SearchResult enumerate(const CellComplex<2>& complex) {
  SearchOptions options;
  options.max_immersions = 0;
  return find_immersions(complex, options);
}

/// The same immersion with the copies of every cell permuted by a seeded shuffle.
Immersion permute_copies(const CellComplex<2>& complex, const Immersion& im, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<NodeId> map(im.layout.node_count());
  for (CellId c : ids<CellId>(complex.cell_count())) {
    std::vector<int> perm(static_cast<std::size_t>(complex.winding_number(c)));
    std::iota(perm.begin(), perm.end(), 0);
    for (std::size_t i = perm.size(); i > 1; --i) std::swap(perm[i - 1], perm[rng() % i]);
    for (int k = 0; k < complex.winding_number(c); ++k) {
      map[im.layout.node(c, k).index()] = im.layout.node(c, perm[static_cast<std::size_t>(k)]);
    }
  }
  Immersion out;
  out.layout = im.layout;
  out.owner = im.owner;
  for (NodeId& o : out.owner) o = map[o.index()];
  for (const ImmersionEdge& e : im.edges) out.edges.push_back({map[e.inner.index()], map[e.outer.index()], e.patch});
  std::sort(out.edges.begin(), out.edges.end());
  return out;
}

TEST(Immersion, EdgeAcrossAndPartner) {
  const CellComplex<2> complex = build<2>(test_support::band());
  const SearchResult r = enumerate(complex);
  ASSERT_EQ(r.immersions.size(), 1u);
  const Immersion& im = r.immersions[0];
  // Node 0 (the body) owns Pa and Pc and is glued to both copies of the overlap, across Pb and Pd.
  EXPECT_EQ(im.edge_across(NodeId(0), PatchId(0)), nullptr);
  const NodeId across_b = im.partner(NodeId(0), PatchId(1));
  const NodeId across_d = im.partner(NodeId(0), PatchId(3));
  ASSERT_TRUE(across_b.is_valid());
  ASSERT_TRUE(across_d.is_valid());
  EXPECT_NE(across_b, across_d);
  EXPECT_EQ(im.partner(across_b, PatchId(1)), NodeId(0));
  EXPECT_EQ(im.owner[PatchId(3)], across_b);  // the copy glued across Pb owns Pd, and vice versa
  EXPECT_EQ(im.owner[PatchId(1)], across_d);
  const ImmersionEdge* e = im.edge_across(across_d, PatchId(3));
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->inner, across_d);
  EXPECT_EQ(e->outer, NodeId(0));
  EXPECT_FALSE(im.partner(NodeId(0), PatchId(2)).is_valid());
}

TEST(Immersion, ComponentsAreOrderedBySmallestNode) {
  const CellComplex<2> complex = build<2>(test_support::nested_circles());
  const SearchResult r = enumerate(complex);
  ASSERT_EQ(r.immersions.size(), 1u);
  const auto components = r.immersions[0].components();
  ASSERT_EQ(components.size(), 2u);
  EXPECT_EQ(components[0].front(), NodeId(0));
  std::size_t total = 0;
  for (const auto& c : components) {
    EXPECT_TRUE(std::is_sorted(c.begin(), c.end()));
    total += c.size();
  }
  EXPECT_EQ(total, 3u);
}

TEST(CanonicalForm, IsInvariantUnderCopyPermutations) {
  for (const test_support::ComplexSpec& spec :
       {test_support::nested_annulus_choice(), test_support::enclosed(test_support::fig9()),
        test_support::enclosed(test_support::enclosed(test_support::band())),
        test_support::enclosed(test_support::nested_annulus_choice())}) {
    SCOPED_TRACE(spec.name);
    const CellComplex<2> complex = build<2>(spec);
    const SearchResult r = enumerate(complex);
    ASSERT_FALSE(r.immersions.empty());
    std::set<std::string> forms;
    for (const Immersion& im : r.immersions) {
      const std::string form = canonical_form(complex, im);
      forms.insert(form);
      for (std::uint64_t seed = 0; seed < 8; ++seed) {
        EXPECT_EQ(canonical_form(complex, permute_copies(complex, im, seed)), form);
      }
    }
    EXPECT_EQ(forms.size(), r.immersions.size());
  }
}

TEST(CanonicalForm, SeparatesNonIsomorphicImmersions) {
  const CellComplex<2> complex = build<2>(test_support::nested_annulus_choice());
  const SearchResult r = enumerate(complex);
  ASSERT_EQ(r.immersions.size(), 2u);
  EXPECT_NE(canonical_form(complex, r.immersions[0]), canonical_form(complex, r.immersions[1]));
}

}  // namespace
}  // namespace imm
