// The independent checker must reject each way a graph can fail to be a manifold with the input as
// boundary; otherwise the search tests that rely on it would prove nothing.
#include <gtest/gtest.h>

#include <string>

#include "support/hand_complexes.h"
#include "support/immersion_checker.h"

namespace imm {
namespace {

using test_support::build;
using test_support::check_immersion;
using test_support::join_violations;

bool mentions(const std::vector<std::string>& violations, const std::string& text) {
  for (const std::string& v : violations) {
    if (v.find(text) != std::string::npos) return true;
  }
  return false;
}

// The band (hand_complexes.h): cell 0 = body (node 0), cell 1 = overlap (nodes 1, 2);
// patches Pa = 0, Pb = 1, Pc = 2, Pd = 3.
Immersion band_immersion(const CellComplex<2>& complex) {
  Immersion im;
  im.layout = NodeLayout(complex);
  im.owner = IdMap<PatchId, NodeId>(4);
  im.owner[PatchId(0)] = NodeId(0);
  im.owner[PatchId(1)] = NodeId(1);
  im.owner[PatchId(2)] = NodeId(0);
  im.owner[PatchId(3)] = NodeId(2);
  im.edges = {{NodeId(1), NodeId(0), PatchId(3)}, {NodeId(2), NodeId(0), PatchId(1)}};
  std::sort(im.edges.begin(), im.edges.end());
  return im;
}

TEST(ImmersionChecker, AcceptsTheBandImmersion) {
  const CellComplex<2> complex = build<2>(test_support::band());
  const auto violations = check_immersion(complex, band_immersion(complex));
  EXPECT_TRUE(violations.empty()) << join_violations(violations);
}

TEST(ImmersionChecker, RejectsOneCopyOwningBothSidesOfAWedge) {
  // Node 1 owns Pb and Pd (both bound the overlap's wedge at each arc); node 2 is glued to the
  // body across both. The overlap copy is then a lone wedge, and the other copy runs through
  // three wedges: neither is a manifold neighbourhood of the crossing.
  const CellComplex<2> complex = build<2>(test_support::band());
  Immersion im = band_immersion(complex);
  im.owner[PatchId(3)] = NodeId(1);
  im.edges = {{NodeId(2), NodeId(0), PatchId(1)}, {NodeId(2), NodeId(0), PatchId(3)}};
  const auto violations = check_immersion(complex, im);
  EXPECT_TRUE(mentions(violations, "path over 1 wedge")) << join_violations(violations);
  EXPECT_TRUE(mentions(violations, "path over 3 wedge")) << join_violations(violations);
}

TEST(ImmersionChecker, RejectsMissingAndExtraEdges) {
  const CellComplex<2> complex = build<2>(test_support::band());
  Immersion missing = band_immersion(complex);
  missing.edges.pop_back();
  auto violations = check_immersion(complex, missing);
  EXPECT_TRUE(mentions(violations, "0 times instead of once")) << join_violations(violations);
  EXPECT_TRUE(mentions(violations, "neither owned nor glued")) << join_violations(violations);

  Immersion extra = band_immersion(complex);
  extra.edges.push_back({NodeId(1), NodeId(0), PatchId(1)});  // node 1 owns Pb and is glued across it
  violations = check_immersion(complex, extra);
  EXPECT_TRUE(mentions(violations, "owns patch 1 but is also glued")) << join_violations(violations);
}

TEST(ImmersionChecker, RejectsAnOwnerOnTheOuterSide) {
  const CellComplex<2> complex = build<2>(test_support::band());
  Immersion im = band_immersion(complex);
  im.owner[PatchId(1)] = NodeId(0);  // the body is the outer side of Pb
  const auto violations = check_immersion(complex, im);
  EXPECT_TRUE(mentions(violations, "only a copy of its inner cell")) << join_violations(violations);
}

TEST(ImmersionChecker, RejectsWrongCopyCounts) {
  const CellComplex<2> complex = build<2>(test_support::band());
  Immersion im = band_immersion(complex);
  im.layout = NodeLayout(build<2>(test_support::circle()));
  const auto violations = check_immersion(complex, im);
  EXPECT_TRUE(mentions(violations, "copies but winding number")) << join_violations(violations);
}

TEST(ImmersionChecker, RejectsPiecesWindingTwiceAroundAnArc) {
  // One arc, four distinct cells A (w 2), B (w 3), C (w 4), D (w 3) and patches p0 (D|A),
  // p1 (B|A), p2 (C|B), p3 (C|D). The local pieces are glued into a cycle through eight wedges.
  test_support::ComplexSpec spec;
  spec.name = "double turn";
  spec.regions = {{0, true}, {2, true}, {3, true}, {4, true}, {3, true}};
  spec.patches = {{4, 1}, {2, 1}, {3, 2}, {3, 4}};
  spec.arcs = {{{0, 1, 2, 3}, {1, 2, 3, 4}}};
  const CellComplex<2> complex = build<2>(spec);
  const NodeLayout layout(complex);
  const auto a = [&](int k) { return layout.node(CellId(0), k); };
  const auto b = [&](int k) { return layout.node(CellId(1), k); };
  const auto c = [&](int k) { return layout.node(CellId(2), k); };
  const auto d = [&](int k) { return layout.node(CellId(3), k); };
  Immersion im;
  im.layout = layout;
  im.owner = IdMap<PatchId, NodeId>(4);
  im.owner[PatchId(0)] = d(2);
  im.owner[PatchId(1)] = b(2);
  im.owner[PatchId(2)] = c(3);
  im.owner[PatchId(3)] = c(3);
  im.edges = {{d(0), a(1), PatchId(0)}, {d(1), a(0), PatchId(0)}, {b(0), a(0), PatchId(1)},
              {b(1), a(1), PatchId(1)}, {c(0), b(0), PatchId(2)}, {c(1), b(1), PatchId(2)},
              {c(2), b(2), PatchId(2)}, {c(0), d(0), PatchId(3)}, {c(1), d(1), PatchId(3)},
              {c(2), d(2), PatchId(3)}};
  std::sort(im.edges.begin(), im.edges.end());
  const auto violations = check_immersion(complex, im);
  EXPECT_TRUE(mentions(violations, "cycle over 8 wedges")) << join_violations(violations);
  EXPECT_TRUE(mentions(violations, "path over 3 wedge")) << join_violations(violations);
  EXPECT_TRUE(mentions(violations, "path over 1 wedge")) << join_violations(violations);
  EXPECT_EQ(violations.size(), 3u) << join_violations(violations);
}

}  // namespace
}  // namespace imm
