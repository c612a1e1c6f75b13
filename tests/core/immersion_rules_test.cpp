// The predicates of the search's final check (check_rules, core/immersion_rules.h), written from
// the statements of Rules 1–7 (paper §5.2), against the independent checker (tests/support,
// written from the local-manifold characterisation of §5.3). By Corollary 6 the two must agree on
// every graph; the candidates of the brute force (every ownership times every gluing) include
// graphs that break each arc rule alone, so a predicate that accepts too much or too little shows
// up as a disagreement.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "core/graph_search.h"
#include "support/brute_force.h"
#include "support/hand_complexes.h"
#include "support/immersion_checker.h"

namespace imm {
namespace {

using test_support::build;
using test_support::ComplexSpec;

/// How often each rule was the first one check_rules reported, over all candidates compared.
struct Tally {
  std::array<int, 8> first_violation{};
  int valid = 0;
  int candidates = 0;
};

/// check_rules refuses the graph iff the independent checker does. @return whether they agree.
bool expect_agreement(const CellComplex<2>& complex, const Immersion& im, Tally& tally) {
  ++tally.candidates;
  const std::optional<Conflict> broken = check_rules(complex, im);
  const std::vector<std::string> violations = test_support::check_immersion(complex, im);
  if (broken) {
    ++tally.first_violation[static_cast<std::size_t>(std::clamp(broken->rule, 0, 7))];
  } else {
    ++tally.valid;
  }
  if (broken.has_value() != violations.empty()) return true;
  ADD_FAILURE() << "check_rules says " << (broken ? broken->message : "valid")
                << "; the independent checker says "
                << (violations.empty() ? "valid" : test_support::join_violations(violations));
  return false;
}

/// Every candidate graph of the complex (every ownership times every gluing).
void expect_agreement_on_every_candidate(const ComplexSpec& spec, Tally& tally) {
  SCOPED_TRACE(spec.name);
  const CellComplex<2> complex = build<2>(spec);
  int disagreements = 0;
  test_support::for_each_candidate(complex, [&](const Immersion& im) {
    if (disagreements < 3 && !expect_agreement(complex, im, tally)) ++disagreements;
  });
}

TEST(ImmersionRules, AgreeWithTheIndependentCheckerOnHandMadeComplexes) {
  Tally tally;
  for (const ComplexSpec& spec :
       {test_support::circle(), test_support::nested_circles(), test_support::nested_annulus_choice(),
        test_support::limacon(), test_support::double_limacon_ring(), test_support::band(),
        test_support::fig9(), test_support::enclosed(test_support::band()),
        test_support::enclosed(test_support::limacon()),
        test_support::enclosed(test_support::enclosed(test_support::band()))}) {
    expect_agreement_on_every_candidate(spec, tally);
  }
  std::cout << tally.candidates << " candidates, " << tally.valid << " valid; first violated rule:";
  for (int r = 1; r <= 7; ++r) std::cout << ' ' << r << ":" << tally.first_violation[static_cast<std::size_t>(r)];
  std::cout << '\n';
  EXPECT_GT(tally.valid, 0);
}

/// The graphs one transposition away from a valid immersion: across one patch, two copies of the
/// inner cell exchange their partners (or one takes over the ownership from the other). These keep
/// Rules 1, 2, 3 and 7 and break the arc rules in every way a nearly right graph can, most often
/// one rule alone.
std::vector<Immersion> neighbours(const Immersion& im, std::size_t patch_count) {
  std::vector<Immersion> out;
  for (std::size_t i = 0; i < patch_count; ++i) {
    const PatchId p(i);
    std::vector<std::size_t> across;
    for (std::size_t e = 0; e < im.edges.size(); ++e) {
      if (im.edges[e].patch == p) across.push_back(e);
    }
    for (std::size_t a = 0; a < across.size(); ++a) {
      Immersion owner_moved = im;  // the owner and a glued inner copy exchange roles
      ImmersionEdge& edge = owner_moved.edges[across[a]];
      std::swap(owner_moved.owner[p], edge.inner);
      std::sort(owner_moved.edges.begin(), owner_moved.edges.end());
      out.push_back(std::move(owner_moved));
      for (std::size_t b = a + 1; b < across.size(); ++b) {
        Immersion swapped = im;  // two inner copies exchange their outer partners
        std::swap(swapped.edges[across[a]].outer, swapped.edges[across[b]].outer);
        std::sort(swapped.edges.begin(), swapped.edges.end());
        out.push_back(std::move(swapped));
      }
    }
  }
  return out;
}

/// Arcs whose four wedges are cells with two copies or more (random_enclosed_complex, and
/// random_complex inside two circles), at sizes the brute force cannot afford: every immersion
/// the search finds and every graph one transposition away from it.
TEST(ImmersionRules, AgreeWithTheIndependentCheckerNearRandomEnclosedImmersions) {
  Tally tally;
  int immersible = 0;
  for (std::uint64_t seed = 0; seed < 120; ++seed) {
    for (const ComplexSpec& spec :
         {test_support::random_enclosed_complex(seed, 2 + static_cast<int>(seed % 2)),
          test_support::enclosed(test_support::enclosed(
              test_support::random_complex(seed, 2, 1 + static_cast<int>(seed % 3))))}) {
      SCOPED_TRACE(testing::Message() << spec.name << ", seed=" << seed);
      const CellComplex<2> complex = build<2>(spec);
      SearchOptions options;
      options.max_immersions = 0;
      const SearchResult r = find_immersions(complex, options);
      immersible += r.immersions.empty() ? 0 : 1;
      for (const Immersion& im : r.immersions) {
        expect_agreement(complex, im, tally);
        for (const Immersion& near : neighbours(im, complex.patch_count())) {
          expect_agreement(complex, near, tally);
        }
      }
    }
  }
  std::cout << immersible << " immersible complexes, " << tally.candidates << " graphs, "
            << tally.valid << " valid; first violated rule:";
  for (int r = 1; r <= 7; ++r) std::cout << ' ' << r << ":" << tally.first_violation[static_cast<std::size_t>(r)];
  std::cout << '\n';
  EXPECT_GE(immersible, 40);
  // Each arc rule is the first violated one of some graph (check order 1, 2, 3, 7, 5, 4, 6), so
  // none of the three predicates is idle here.
  for (int r : {4, 5, 6}) EXPECT_GT(tally.first_violation[static_cast<std::size_t>(r)], 0) << "Rule " << r;
}

/// Graphs that do not fit the slots at all are refused with the rule they break, never read out
/// of bounds.
TEST(ImmersionRules, RefuseGraphsThatDoNotFitTheComplex) {
  const CellComplex<2> complex = build<2>(test_support::band());
  // The band: cell 0 = body (node 0), cell 1 = overlap (nodes 1, 2); patches 0..3.
  Immersion valid;
  valid.layout = NodeLayout(complex);
  valid.owner = IdMap<PatchId, NodeId>(4);
  valid.owner[PatchId(0)] = NodeId(0);
  valid.owner[PatchId(1)] = NodeId(1);
  valid.owner[PatchId(2)] = NodeId(0);
  valid.owner[PatchId(3)] = NodeId(2);
  valid.edges = {{NodeId(1), NodeId(0), PatchId(3)}, {NodeId(2), NodeId(0), PatchId(1)}};
  std::sort(valid.edges.begin(), valid.edges.end());
  ASSERT_TRUE(test_support::check_immersion(complex, valid).empty());
  EXPECT_FALSE(check_rules(complex, valid));

  Immersion no_owner = valid;
  no_owner.owner[PatchId(2)] = NodeId();
  EXPECT_EQ(check_rules(complex, no_owner)->rule, 7);

  Immersion short_table = valid;
  short_table.owner = IdMap<PatchId, NodeId>(3);
  EXPECT_EQ(check_rules(complex, short_table)->rule, 7);

  Immersion wrong_layout = valid;
  wrong_layout.layout = NodeLayout(build<2>(test_support::circle()));
  EXPECT_EQ(check_rules(complex, wrong_layout)->rule, 7);

  Immersion swapped = valid;
  swapped.edges.push_back({NodeId(0), NodeId(1), PatchId(1)});  // inner and outer exchanged
  EXPECT_EQ(check_rules(complex, swapped)->rule, 1);

  Immersion owned_and_glued = valid;
  owned_and_glued.edges.push_back({NodeId(1), NodeId(0), PatchId(1)});
  EXPECT_EQ(check_rules(complex, owned_and_glued)->rule, 2);

  Immersion two_edges = valid;
  two_edges.edges.push_back({NodeId(1), NodeId(0), PatchId(3)});
  two_edges.edges.push_back({NodeId(2), NodeId(0), PatchId(3)});
  const std::optional<Conflict> twice = check_rules(complex, two_edges);
  ASSERT_TRUE(twice);
  EXPECT_TRUE(twice->rule == 1 || twice->rule == 2) << twice->message;

  Immersion outer_owner = valid;
  outer_owner.owner[PatchId(1)] = NodeId(0);  // the body is the outer side of patch 1
  outer_owner.edges = {{NodeId(1), NodeId(0), PatchId(3)}};
  const std::optional<Conflict> outer = check_rules(complex, outer_owner);
  ASSERT_TRUE(outer);
  EXPECT_TRUE(outer->rule == 2 || outer->rule == 3) << outer->message;
}

}  // namespace
}  // namespace imm
