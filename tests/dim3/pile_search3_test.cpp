// The immersion search on piles of mutually overlapping closed surfaces (issue 19): K spheres
// of radius 0.5 with centres in a cube of side 0.6, K tori with random axes, and the Fig. 13
// helix inside a pile of spheres. Each is immersible by construction (the parts' solids); every
// result is checked by the independent checker (tests/support/immersion_checker), and the two
// search orders must enumerate the same immersions up to copy permutation where enumeration
// is cheap. Large piles are benchmarked in bench/ (BENCHMARKS.md), not timed here.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "core/graph_search.h"
#include "dim3/complex3.h"
#include "dim3/generators3.h"
#include "support/immersion_checker.h"

namespace imm::dim3 {
namespace {

using test_support::check_immersion;
using test_support::join_violations;

struct Pile {
  std::string generator;
  std::vector<std::string> args;
};

std::string label(const Pile& p) {
  std::string out = p.generator;
  for (const std::string& a : p.args) out += " " + a;
  return out;
}

/// Builds the complex of a generated pile (volumes in doubles: the search does not read them).
BuildResult build(const Pile& p) {
  const SurfaceGenerateResult g = generate_surface(p.generator, p.args);
  EXPECT_TRUE(g.ok()) << g.error;
  BuildOptions options;
  options.exact_volumes = false;
  return build_complex(g.surface, options);
}

std::set<std::string> expect_valid(const CellComplex<3>& complex, const SearchResult& result) {
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

TEST(PileSearch3, FirstImmersionOfEveryPileIsFoundAndValid) {
  std::vector<Pile> piles;
  for (const char* seed : {"1", "2", "3"}) {
    piles.push_back({"spheres-pile", {"4", seed, "5"}});
    piles.push_back({"spheres-pile", {"7", seed, "5"}});
  }
  piles.push_back({"tori-pile", {"3", "1", "12"}});
  piles.push_back({"tori-pile", {"3", "2", "12"}});
  piles.push_back({"helix-spheres", {"3", "1", "1"}});
  for (const Pile& pile : piles) {
    SCOPED_TRACE(label(pile));
    const BuildResult built = build(pile);
    ASSERT_TRUE(built.report.ok()) << built.report.summary();
    ASSERT_FALSE(built.inversion.has_value());
    const CellComplex<3>& complex = built.complex->complex;
    SearchOptions options;
    options.max_states = 500;  // a budget in states, not a time
    const SearchResult r = find_immersions(complex, options);
    ASSERT_EQ(r.status, ImmersionStatus::Immersible)
        << r.conflict.message << " after " << r.stats.states << " states";
    ASSERT_EQ(r.immersions.size(), 1u);
    expect_valid(complex, r);
  }
}

TEST(PileSearch3, SearchOrdersEnumerateTheSameImmersions) {
  for (const Pile& pile : {Pile{"spheres-pile", {"3", "1", "4"}}, Pile{"spheres-pile", {"3", "2", "4"}},
                           Pile{"tori-pile", {"2", "1", "10"}}}) {
    SCOPED_TRACE(label(pile));
    const BuildResult built = build(pile);
    ASSERT_TRUE(built.report.ok()) << built.report.summary();
    const CellComplex<3>& complex = built.complex->complex;
    SearchOptions all;
    all.max_immersions = 0;
    all.max_states = 100'000;
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
  }
}

/// Issue 19: the incremental choice of the next variable picks what the rescan of every open
/// variable picks: the same states, statistics and labelled immersions in the same order, for
/// the first immersion and for the enumeration, in both search orders.
TEST(PileSearch3, IncrementalChoiceFollowsTheFullScan) {
  std::vector<Pile> piles;
  for (const char* seed : {"1", "2", "3"}) {
    piles.push_back({"spheres-pile", {"3", seed, "4"}});
    piles.push_back({"spheres-pile", {"6", seed, "5"}});
  }
  piles.push_back({"tori-pile", {"3", "1", "12"}});
  piles.push_back({"helix-spheres", {"3", "1", "1"}});
  for (const Pile& pile : piles) {
    const BuildResult built = build(pile);
    ASSERT_TRUE(built.report.ok()) << built.report.summary();
    const CellComplex<3>& complex = built.complex->complex;
    for (const std::size_t max : {std::size_t{1}, std::size_t{0}}) {
      for (const bool sheets : {true, false}) {
        SCOPED_TRACE(testing::Message() << label(pile) << ", max_immersions=" << max << ", sheets=" << sheets);
        SearchOptions options;
        options.max_immersions = max;
        options.max_states = 5'000;
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
        expect_valid(complex, fast);
      }
    }
  }
}

}  // namespace
}  // namespace imm::dim3
