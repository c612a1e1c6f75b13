// The immersion search on piles of mutually overlapping circles (issue 19): every pair of the K
// circles overlaps, winding numbers reach about K, and every pile is immersible by construction
// (the disjoint union of the disks). Every result is checked by the independent checker
// (tests/support/immersion_checker, which shares no code with the search's rules), the node
// counts by the winding numbers, and the two search orders (sheets first with sheet
// continuation, and the fewest-options order before issue 19) must enumerate the same
// immersions up to copy permutation. Sizes are small: large piles are in bench/ (BENCHMARKS.md).
#include <gtest/gtest.h>

#include <iostream>
#include <set>
#include <utility>
#include <vector>
#include <string>

#include "core/graph_search.h"
#include "dim2/complex2.h"
#include "dim2/generators.h"
#include "support/immersion_checker.h"

namespace imm::dim2 {
namespace {

using test_support::check_immersion;
using test_support::join_violations;

/// Every immersion is valid (independent checker), has w(c) nodes per cell and is pairwise
/// non-isomorphic to the others. @return their canonical forms.
std::set<std::string> expect_valid(const CellComplex<2>& complex, const SearchResult& result) {
  std::set<std::string> forms;
  for (const Immersion& im : result.immersions) {
    std::size_t nodes = 0;
    for (CellId c : ids<CellId>(complex.cell_count())) nodes += complex.winding_number(c);
    EXPECT_EQ(im.layout.node_count(), nodes);
    const auto violations = check_immersion(complex, im);
    EXPECT_TRUE(violations.empty()) << join_violations(violations);
    EXPECT_TRUE(forms.insert(canonical_form(complex, im)).second) << "two isomorphic immersions";
  }
  return forms;
}

SearchOptions classic(SearchOptions options) {
  options.sheets_first = false;
  options.continue_sheets = false;
  return options;
}

TEST(PileSearch2, FirstImmersionOfEveryPileIsFoundAndValid) {
  for (int k : {4, 8, 12}) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      SCOPED_TRACE(testing::Message() << "circles-pile k=" << k << " seed=" << seed);
      const BuildResult built = build_complex(circles_pile(k, seed, 16));
      ASSERT_TRUE(built.report.ok()) << built.report.summary();
      ASSERT_FALSE(built.inversion);
      const CellComplex<2>& complex = built.complex->complex;
      int max_winding = 0;
      for (CellId c : ids<CellId>(complex.cell_count()))
        max_winding = std::max(max_winding, complex.winding_number(c));
      EXPECT_GE(max_winding, k / 2) << "not a pile: the circles hardly overlap";
      // A state budget, not a time: with the fewest-options order alone the 12-circle piles
      // need thousands of states (the 24- and 32-circle piles of the issue tens of thousands).
      SearchOptions options;
      options.max_states = 200;
      const SearchResult r = find_immersions(complex, options);
      ASSERT_EQ(r.status, ImmersionStatus::Immersible)
          << r.conflict.message << " after " << r.stats.states << " states";
      ASSERT_EQ(r.immersions.size(), 1u);
      expect_valid(complex, r);
      EXPECT_EQ(r.stats.dead_ends, 0u);
    }
  }
}

/// The same immersions, up to copy permutation, in both orders and with or without sheet
/// continuation: on piles small enough to enumerate, and on one where only the first is cheap.
TEST(PileSearch2, SearchOrdersEnumerateTheSameImmersions) {
  std::vector<std::pair<std::string, CurveSet>> inputs;
  for (int k : {3, 5, 7}) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      inputs.emplace_back("circles-pile k=" + std::to_string(k) + " seed=" + std::to_string(seed),
                          circles_pile(k, seed, 12));
    }
  }
  // Inputs with several immersions: Catalan(4) = 14 for the doodle, 2^3 for the chain.
  inputs.emplace_back("doodle 4", doodle(4));
  inputs.emplace_back("doodle-chain 3", doodle_chain(3));
  int multiple = 0;
  for (const auto& [label, curves] : inputs) {
    SCOPED_TRACE(label);
    const BuildResult built = build_complex(curves);
    ASSERT_TRUE(built.report.ok()) << built.report.summary();
    ASSERT_FALSE(built.inversion);
    const CellComplex<2>& complex = built.complex->complex;
    SearchOptions all;
    all.max_immersions = 0;
    all.max_states = 200'000;
    std::set<std::string> reference;
    for (int variant = 0; variant < 4; ++variant) {
      SearchOptions options = all;
      options.sheets_first = (variant & 1) != 0;
      options.continue_sheets = (variant & 2) != 0;
      const SearchResult r = find_immersions(complex, options);
      ASSERT_TRUE(r.complete) << "variant " << variant << ": " << r.stats.states << " states";
      ASSERT_EQ(r.status, ImmersionStatus::Immersible);
      const std::set<std::string> forms = expect_valid(complex, r);
      if (variant == 0) {
        reference = forms;
      } else {
        EXPECT_EQ(forms, reference) << "variant " << variant;
      }
    }
    std::cout << label << ": " << reference.size() << " immersion(s)\n";
    multiple += reference.size() >= 2;
  }
  EXPECT_GE(multiple, 2) << "too few inputs with several immersions: the comparison is weak";
}

/// Issue 19: the incremental choice of the next variable picks exactly what a rescan of every
/// open variable picks, on piles (first immersion, where the index is refreshed and almost never
/// rebuilt) and on enumerations with branch points: the same states, statistics and labelled
/// immersions in the same order.
TEST(PileSearch2, IncrementalChoiceFollowsTheFullScan) {
  std::vector<std::pair<std::string, CurveSet>> inputs;
  for (int k : {4, 8, 12, 16}) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      inputs.emplace_back("circles-pile k=" + std::to_string(k) + " seed=" + std::to_string(seed),
                          circles_pile(k, seed, 16));
    }
  }
  inputs.emplace_back("doodle 4", doodle(4));
  inputs.emplace_back("doodle-chain 3", doodle_chain(3));
  for (const auto& [label, curves] : inputs) {
    const BuildResult built = build_complex(curves);
    ASSERT_TRUE(built.report.ok()) << built.report.summary();
    const CellComplex<2>& complex = built.complex->complex;
    for (const std::size_t max : {std::size_t{1}, std::size_t{0}}) {
      for (const bool sheets : {true, false}) {
        SCOPED_TRACE(testing::Message() << label << ", max_immersions=" << max << ", sheets=" << sheets);
        SearchOptions options;
        options.max_immersions = max;
        options.max_states = 20'000;
        options.sheets_first = options.continue_sheets = sheets;
        const SearchResult fast = find_immersions(complex, options);
        options.incremental_choice = false;
        const SearchResult scan = find_immersions(complex, options);
        EXPECT_EQ(fast.status, scan.status);
        EXPECT_EQ(fast.stats.states, scan.stats.states);
        EXPECT_EQ(fast.stats.branches, scan.stats.branches);
        EXPECT_EQ(fast.stats.probes, scan.stats.probes);
        EXPECT_EQ(fast.stats.dead_ends, scan.stats.dead_ends);
        ASSERT_EQ(fast.immersions.size(), scan.immersions.size());
        for (std::size_t i = 0; i < fast.immersions.size(); ++i) {
          EXPECT_EQ(fast.immersions[i].owner.raw(), scan.immersions[i].owner.raw());
          EXPECT_EQ(fast.immersions[i].edges, scan.immersions[i].edges);
        }
        if (fast.status == ImmersionStatus::Immersible && fast.complete) expect_valid(complex, fast);
        if (max == 1 && sheets && fast.stats.branches == 0) {
          // One group, no branch alternative: built once, refreshed on every other state.
          EXPECT_EQ(fast.stats.choice_rebuilds, fast.stats.groups) << fast.stats.states << " states";
        }
      }
    }
  }
}

/// The default search never needs more states than the order before issue 19 on these piles,
/// and the first immersion it finds is valid either way.
TEST(PileSearch2, SheetsFirstIsNeverWorseThanTheClassicOrderOnPiles) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE(testing::Message() << "circles-pile k=10 seed=" << seed);
    const BuildResult built = build_complex(circles_pile(10, seed, 16));
    ASSERT_TRUE(built.report.ok());
    const CellComplex<2>& complex = built.complex->complex;
    SearchOptions options;
    options.max_states = 100'000;
    const SearchResult fast = find_immersions(complex, options);
    const SearchResult slow = find_immersions(complex, classic(options));
    ASSERT_EQ(fast.status, ImmersionStatus::Immersible);
    ASSERT_EQ(slow.status, ImmersionStatus::Immersible);
    expect_valid(complex, fast);
    expect_valid(complex, slow);
    EXPECT_LT(fast.stats.states, slow.stats.states);
  }
}

}  // namespace
}  // namespace imm::dim2
