// The immersion search (paper §6, Algorithm 1) on hand-built complexes, cross-checked against the
// independent checker and a brute-force enumeration (DESIGN §4 invariants 3 and 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <optional>
#include <set>
#include <string>
#include <type_traits>

#include "core/graph_search.h"
#include "support/brute_force.h"
#include "support/hand_complexes.h"
#include "support/immersion_checker.h"

namespace imm {
namespace {

using test_support::build;
using test_support::ComplexSpec;

template <class T>
class Search : public ::testing::Test {};
using Dimensions = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(Search, Dimensions);

SearchOptions all_immersions() {
  SearchOptions options;
  options.max_immersions = 0;
  return options;
}

/// Runs the full enumeration and checks everything that must hold for any complex: every
/// immersion passes the independent checker, canonical forms are pairwise distinct, the count
/// matches brute force (when small enough) and survives relabelling. @return the result.
template <int D>
SearchResult expect_consistent(const ComplexSpec& spec, bool with_brute_force = true) {
  SCOPED_TRACE(spec.name);
  const CellComplex<D> complex = build<D>(spec);
  const SearchResult result = find_immersions(complex, all_immersions());
  EXPECT_TRUE(result.complete);
  EXPECT_EQ(result.status == ImmersionStatus::Immersible, !result.immersions.empty());
  // Every complete state is a fixpoint of the propagators; one that breaks a rule means a
  // propagator missed a consequence of it, even if the final check then dropped the graph.
  EXPECT_EQ(result.stats.rejected, 0u)
      << "complete graphs refused by the final rule check (a propagator is incomplete); last: "
      << result.conflict.message;
  std::set<std::string> forms;
  for (const Immersion& im : result.immersions) {
    const auto violations = test_support::check_immersion(complex, im);
    EXPECT_TRUE(violations.empty()) << test_support::join_violations(violations);
    const std::optional<Conflict> broken = check_rules(complex, im);
    EXPECT_FALSE(broken) << broken->message;
    forms.insert(canonical_form(complex, im));
  }
  EXPECT_EQ(forms.size(), result.immersions.size()) << "isomorphic immersions returned";
  if (with_brute_force) {
    const test_support::BruteForceResult brute = test_support::brute_force_immersions(complex);
    EXPECT_EQ(brute.classes.size(), result.immersions.size())
        << brute.valid << " labelled graphs out of " << brute.candidates << " candidates";
    for (const Immersion& im : brute.classes) {
      EXPECT_EQ(forms.count(canonical_form(complex, im)), 1u)
          << "a brute-force immersion is missing from the search: " << canonical_form(complex, im);
    }
  }
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const ComplexSpec other = test_support::shuffled(spec, seed);
    const SearchResult again = find_immersions(build<D>(other), all_immersions());
    EXPECT_EQ(again.status, result.status) << other.name;
    EXPECT_EQ(again.immersions.size(), result.immersions.size()) << other.name;
  }
  return result;
}

TYPED_TEST(Search, CircleHasOneImmersion) {
  constexpr int D = TypeParam::value;
  const SearchResult r = expect_consistent<D>(test_support::circle());
  ASSERT_EQ(r.immersions.size(), 1u);
  EXPECT_EQ(r.immersions[0].owner[PatchId(0)], NodeId(0));
  EXPECT_TRUE(r.immersions[0].edges.empty());
}

TYPED_TEST(Search, NestedCirclesGiveTwoDisks) {
  constexpr int D = TypeParam::value;
  const SearchResult r = expect_consistent<D>(test_support::nested_circles());
  ASSERT_EQ(r.immersions.size(), 1u);
  // One disk per circle: the ring's copy is glued to one copy of the inner disk, the other copy
  // of the inner disk owns the inner circle alone.
  EXPECT_EQ(r.immersions[0].components().size(), 2u);
  EXPECT_EQ(r.immersions[0].edges.size(), 1u);
}

TYPED_TEST(Search, NestedAnnulusHasTwoDistinctImmersions) {
  constexpr int D = TypeParam::value;
  const SearchResult r = expect_consistent<D>(test_support::nested_annulus_choice());
  ASSERT_EQ(r.immersions.size(), 2u);
  EXPECT_GE(r.stats.branches, 1u);
  // {big disk, annulus} and {middle disk, wide annulus}: both have two components.
  for (const Immersion& im : r.immersions) EXPECT_EQ(im.components().size(), 2u);
}

TYPED_TEST(Search, LimaconIsNotImmersible) {
  constexpr int D = TypeParam::value;
  const SearchResult r = expect_consistent<D>(test_support::limacon());
  EXPECT_EQ(r.status, ImmersionStatus::NotImmersible);
  EXPECT_TRUE(r.immersions.empty());
  // The inner loop's patch is its own geometric neighbour (Rule 5), so neither copy of the inner
  // loop can own it (Rule 7).
  EXPECT_EQ(r.conflict.rule, 7) << r.conflict.message;
  EXPECT_NE(r.conflict.message.find("Rule 5"), std::string::npos) << r.conflict.message;
  ASSERT_EQ(r.conflict.patches.size(), 1u);
  EXPECT_EQ(r.conflict.patches[0], PatchId(1));
  EXPECT_EQ(r.conflict.arc, ArcId(0));
  EXPECT_EQ(r.stats.branches, 0u);
}

TYPED_TEST(Search, DoublyWrappedRingIsSelfConnecting) {
  constexpr int D = TypeParam::value;
  const SearchResult r = expect_consistent<D>(test_support::double_limacon_ring());
  EXPECT_EQ(r.status, ImmersionStatus::SelfConnectingCell) << r.conflict.message;
  ASSERT_FALSE(r.conflict.cells.empty());
  EXPECT_EQ(r.conflict.cells.front(), CellId(1));  // region 2, the ring of winding number 2
  EXPECT_NE(r.conflict.message.find("cell 1"), std::string::npos) << r.conflict.message;
}

TYPED_TEST(Search, BandHasOneImmersion) {
  constexpr int D = TypeParam::value;
  const SearchResult r = expect_consistent<D>(test_support::band());
  ASSERT_EQ(r.immersions.size(), 1u);
  EXPECT_EQ(r.immersions[0].components().size(), 1u);  // one immersed disk
}

TYPED_TEST(Search, Figure9) {
  constexpr int D = TypeParam::value;
  const SearchResult r = expect_consistent<D>(test_support::fig9());
  ASSERT_EQ(r.immersions.size(), 1u);
  EXPECT_EQ(r.immersions[0].components().size(), 1u);
}

TYPED_TEST(Search, EnclosedExamplesExerciseRule6) {
  constexpr int D = TypeParam::value;
  // Inside a large circle every wedge of every arc is a cell, so full disks go around the arcs.
  for (const ComplexSpec& spec :
       {test_support::enclosed(test_support::band()), test_support::enclosed(test_support::fig9()),
        test_support::enclosed(test_support::limacon()),
        test_support::enclosed(test_support::nested_annulus_choice()),
        test_support::enclosed(test_support::enclosed(test_support::band()))}) {
    // The brute force of these (up to 41 472 candidates) runs in one dimension only: the search
    // code is the same template for both.
    expect_consistent<D>(spec, /*with_brute_force=*/D == 2);
  }
}

TYPED_TEST(Search, DisjointCopiesMultiplyTheCount) {
  constexpr int D = TypeParam::value;
  const ComplexSpec two = test_support::nested_annulus_choice();
  const SearchResult r = expect_consistent<D>(test_support::disjoint_union(two, two));
  EXPECT_EQ(r.immersions.size(), 4u);
  EXPECT_EQ(r.stats.groups, 2u);  // solved independently, then combined
  const SearchResult s = expect_consistent<D>(test_support::disjoint_union(test_support::band(), two));
  EXPECT_EQ(s.immersions.size(), 2u);
  const SearchResult t =
      expect_consistent<D>(test_support::disjoint_union(test_support::limacon(), two));
  // The annulus cell of winding 2 is not simply connected, but it lies in the other, solvable
  // group: the refutation is the limaçon's, so no self-connecting cell is blamed.
  EXPECT_EQ(t.status, ImmersionStatus::NotImmersible) << t.conflict.message;
}

TYPED_TEST(Search, RandomComplexesAgreeWithBruteForce) {
  constexpr int D = TypeParam::value;
  int compared = 0, immersible = 0;
  for (std::uint64_t seed = 0; seed < 400 && compared < 60; ++seed) {
    const ComplexSpec spec = test_support::random_complex(seed, 3 + static_cast<int>(seed % 2),
                                                          1 + static_cast<int>(seed % 4));
    const CellComplex<D> complex = build<D>(spec);
    if (test_support::brute_force_candidate_count(complex) > 3000) continue;
    SCOPED_TRACE(testing::Message() << "seed=" << seed);
    const SearchResult r = expect_consistent<D>(spec);
    ++compared;
    if (!r.immersions.empty()) ++immersible;
  }
  EXPECT_GE(compared, 40);
  EXPECT_GE(immersible, 5);  // the property test is not vacuous
}

/// The number of arcs of a spec whose four wedges are cells of winding number 2 or more: there
/// every wedge's cell has two copies, so local sheets could go around the arc twice.
int deep_enclosed_arcs(const ComplexSpec& spec) {
  int deep = 0;
  for (const ComplexSpec::Arc& arc : spec.arcs) {
    int lowest = 1 << 20;
    for (int r : arc.wedge) lowest = std::min(lowest, spec.regions[static_cast<std::size_t>(r)].winding);
    deep += lowest >= 2 ? 1 : 0;
  }
  return deep;
}

TYPED_TEST(Search, RandomEnclosedComplexesKeepEveryRule) {
  constexpr int D = TypeParam::value;
  // Arcs whose four wedges are cells, most with two copies of every wedge's cell: only there can
  // a graph satisfy Rules 1-5 and 7 and still wind twice around an arc (Rule 6). random_complex
  // above rarely has them within the brute-force size, so here every complex is searched and
  // checked (independent checker, the rule predicates, no complete graph refused by the final
  // check), and the small ones are also brute-forced. Two generators: random_enclosed_complex
  // (arcs at winding 1 and 2, several regions per level) and random_complex inside two circles.
  int searched = 0, brute_forced = 0, with_deep_arcs = 0, immersible = 0, several = 0;
  for (std::uint64_t seed = 0; seed < 160; ++seed) {
    for (const ComplexSpec& spec :
         {test_support::random_enclosed_complex(seed, 2 + static_cast<int>(seed % 2)),
          test_support::enclosed(test_support::enclosed(
              test_support::random_complex(seed, 2, 1 + static_cast<int>(seed % 3))))}) {
      SCOPED_TRACE(testing::Message() << spec.name << ", seed=" << seed);
      const CellComplex<D> complex = build<D>(spec);
      if (test_support::brute_force_candidate_count(complex) <= 3000) {
        expect_consistent<D>(spec);
        ++brute_forced;
      }
      const SearchResult r = find_immersions(complex, all_immersions());
      ASSERT_TRUE(r.complete);
      EXPECT_EQ(r.stats.rejected, 0u)
          << "complete graphs refused by the final rule check (a propagator is incomplete); last: "
          << r.conflict.message;
      for (const Immersion& im : r.immersions) {
        const auto violations = test_support::check_immersion(complex, im);
        EXPECT_TRUE(violations.empty()) << test_support::join_violations(violations);
      }
      ++searched;
      with_deep_arcs += deep_enclosed_arcs(spec) > 0 ? 1 : 0;
      immersible += r.immersions.empty() ? 0 : 1;
      several += r.immersions.size() >= 2 ? 1 : 0;
    }
  }
  std::cout << "searched " << searched << ", brute-forced " << brute_forced
            << ", with arcs of winding >= 2 all around " << with_deep_arcs << ", immersible "
            << immersible << ", several immersions " << several << '\n';
  // Not vacuous: immersible complexes with deep arcs, where the search completes graphs.
  EXPECT_GE(with_deep_arcs, 200);
  EXPECT_GE(immersible, 40);
  EXPECT_GE(brute_forced, 20);
}

TYPED_TEST(Search, BudgetEndsWithSearchBudgetExhausted) {
  constexpr int D = TypeParam::value;
  const CellComplex<D> complex = build<D>(test_support::nested_annulus_choice());
  SearchOptions options = all_immersions();
  options.max_states = 2;  // the root and one decision; the owner of the inner circle branches
  const SearchResult r = find_immersions(complex, options);
  EXPECT_EQ(r.status, ImmersionStatus::SearchBudgetExhausted);
  EXPECT_TRUE(r.immersions.empty());
  EXPECT_FALSE(r.complete);
  EXPECT_EQ(r.stats.states, 2u);
  EXPECT_NE(r.conflict.message.find("budget"), std::string::npos);

  // Enough for the first immersion, not for the second: the root, the owner of the ring's outer
  // circle (its two copies are interchangeable: no branch), then two trial propagations, one per
  // owner of the inner circle (both survive: a branch). Exploring the second alternative after
  // the first immersion is one more state.
  options.max_states = 4;
  const SearchResult partial = find_immersions(complex, options);
  EXPECT_EQ(partial.status, ImmersionStatus::Immersible);
  EXPECT_EQ(partial.immersions.size(), 1u);
  EXPECT_FALSE(partial.complete);
  EXPECT_EQ(partial.stats.probes, 2u);
}

TYPED_TEST(Search, MaxImmersionsStopsEarly) {
  constexpr int D = TypeParam::value;
  const CellComplex<D> complex = build<D>(test_support::nested_annulus_choice());
  const SearchResult r = find_immersions(complex);  // default: the first immersion only
  EXPECT_EQ(r.status, ImmersionStatus::Immersible);
  EXPECT_EQ(r.immersions.size(), 1u);
  EXPECT_FALSE(r.complete);
}

TYPED_TEST(Search, IsDeterministic) {
  constexpr int D = TypeParam::value;
  const CellComplex<D> complex = build<D>(test_support::enclosed(test_support::fig9()));
  const SearchResult a = find_immersions(complex, all_immersions());
  const SearchResult b = find_immersions(complex, all_immersions());
  ASSERT_EQ(a.immersions.size(), b.immersions.size());
  for (std::size_t i = 0; i < a.immersions.size(); ++i) {
    EXPECT_EQ(a.immersions[i].owner.raw(), b.immersions[i].owner.raw());
    EXPECT_EQ(a.immersions[i].edges, b.immersions[i].edges);
  }
  EXPECT_EQ(a.stats.states, b.stats.states);
}

TYPED_TEST(Search, ManyComponentsAndHighWindingStayCheap) {
  constexpr int D = TypeParam::value;
  // Seven nested counter-clockwise circles (winding numbers 1..7) next to 40 enclosed bands:
  // one immersion, found by propagation and symmetry alone.
  ComplexSpec spec = test_support::circle();
  for (int level = 2; level <= 7; ++level) {
    spec.regions.push_back({level, true});
    spec.regions[spec.regions.size() - 2].simply_connected = false;
    spec.patches.push_back({level, level - 1});
  }
  const ComplexSpec unit = test_support::enclosed(test_support::enclosed(test_support::band()));
  for (int i = 0; i < 40; ++i) spec = test_support::disjoint_union(spec, unit);
  const CellComplex<D> complex = build<D>(spec);
  const SearchResult r = find_immersions(complex, all_immersions());
  ASSERT_EQ(r.status, ImmersionStatus::Immersible);
  EXPECT_EQ(r.immersions.size(), 1u);
  EXPECT_TRUE(r.complete);
  EXPECT_EQ(r.stats.dead_ends, 0u);
  const auto violations = test_support::check_immersion(complex, r.immersions[0]);
  EXPECT_TRUE(violations.empty()) << test_support::join_violations(violations);
}

/// Issue 19: the sheets-first order and sheet continuation (the defaults) change the order and
/// the cost of the search, never its result: the same immersions up to copy permutation as the
/// fewest-options order without continuation, on the random complexes of the brute-force test.
TYPED_TEST(Search, SearchOrdersAgreeOnRandomComplexes) {
  constexpr int D = TypeParam::value;
  int compared = 0, several = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const ComplexSpec spec = test_support::random_complex(seed, 3 + static_cast<int>(seed % 2),
                                                          1 + static_cast<int>(seed % 4));
    const CellComplex<D> complex = build<D>(spec);
    SCOPED_TRACE(testing::Message() << "seed=" << seed);
    SearchOptions options = all_immersions();
    options.max_states = 200'000;
    const SearchResult fast = find_immersions(complex, options);
    options.sheets_first = false;
    options.continue_sheets = false;
    const SearchResult classic = find_immersions(complex, options);
    if (!fast.complete || !classic.complete) continue;
    EXPECT_EQ(fast.status, classic.status);
    std::set<std::string> a, b;
    for (const Immersion& im : fast.immersions) a.insert(canonical_form(complex, im));
    for (const Immersion& im : classic.immersions) b.insert(canonical_form(complex, im));
    EXPECT_EQ(a.size(), fast.immersions.size());
    EXPECT_EQ(a, b);
    ++compared;
    several += b.size() >= 2;
  }
  EXPECT_GE(compared, 150);
  EXPECT_GE(several, 5);
}

/// The incremental choice of the next variable (SearchOptions::incremental_choice, issue 19) must
/// choose exactly what the rescan of every open variable chooses: the same states in the same
/// order, so the same labelled immersions in the same order and the same statistics, on random
/// complexes with branches, dead ends and several immersions (in both search orders). A dirty
/// cell that is not refreshed, a wrong tie-break in the index or a stale symmetry class changes
/// the choice somewhere, and with it the states or the immersions.
TYPED_TEST(Search, IncrementalChoiceFollowsTheFullScan) {
  constexpr int D = TypeParam::value;
  int compared = 0, branching = 0, incremental = 0;
  for (std::uint64_t seed = 0; seed < 160; ++seed) {
    for (const ComplexSpec& spec :
         {test_support::random_complex(seed, 3 + static_cast<int>(seed % 2), 1 + static_cast<int>(seed % 4)),
          test_support::random_enclosed_complex(seed, 2 + static_cast<int>(seed % 2))}) {
      const CellComplex<D> complex = build<D>(spec);
      for (const bool sheets_first : {true, false}) {
        SCOPED_TRACE(testing::Message() << spec.name << ", seed=" << seed << ", sheets_first=" << sheets_first);
        SearchOptions options = all_immersions();
        options.max_states = 20'000;
        options.sheets_first = options.continue_sheets = sheets_first;
        const SearchResult fast = find_immersions(complex, options);
        options.incremental_choice = false;
        const SearchResult scan = find_immersions(complex, options);
        EXPECT_EQ(fast.status, scan.status);
        EXPECT_EQ(fast.complete, scan.complete);
        EXPECT_EQ(fast.stats.states, scan.stats.states);
        EXPECT_EQ(fast.stats.branches, scan.stats.branches);
        EXPECT_EQ(fast.stats.dead_ends, scan.stats.dead_ends);
        EXPECT_EQ(fast.stats.probes, scan.stats.probes);
        EXPECT_EQ(fast.stats.duplicates, scan.stats.duplicates);
        EXPECT_EQ(fast.conflict.message, scan.conflict.message);
        ASSERT_EQ(fast.immersions.size(), scan.immersions.size());
        for (std::size_t i = 0; i < fast.immersions.size(); ++i) {
          EXPECT_EQ(fast.immersions[i].owner.raw(), scan.immersions[i].owner.raw()) << "immersion " << i;
          EXPECT_EQ(fast.immersions[i].edges, scan.immersions[i].edges) << "immersion " << i;
        }
        EXPECT_EQ(scan.stats.choice_rebuilds, 0u);
        ++compared;
        branching += fast.stats.branches > 0 ? 1 : 0;
        // The index is refreshed, not rebuilt, on states reached without a branch alternative.
        incremental += fast.stats.choice_rebuilds < fast.stats.states ? 1 : 0;
      }
    }
  }
  EXPECT_GE(compared, 600);
  EXPECT_GE(branching, 50) << "too few searches with branch points: the comparison is weak";
  EXPECT_GE(incremental, 300);
}

TEST(SearchStatus, NamesAreStable) {
  EXPECT_STREQ(to_string(ImmersionStatus::Immersible), "immersible");
  EXPECT_STREQ(to_string(ImmersionStatus::NotImmersible), "not-immersible");
  EXPECT_STREQ(to_string(ImmersionStatus::SelfConnectingCell), "self-connecting-cell");
  EXPECT_STREQ(to_string(ImmersionStatus::SearchBudgetExhausted), "search-budget-exhausted");
}

}  // namespace
}  // namespace imm
