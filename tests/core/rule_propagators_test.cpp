// The propagators of core/immersion_rules.h, each against its own postcondition. The search's
// results cannot guard every propagator: Rule 2's deductions are also variables of the search
// (partner(n, q) with one option is decided at once, with none it is a dead end), so switching
// Rule 2's propagator off changes only the search's effort and, on a few inputs, which valid
// immersion comes first, never the immersions found up to isomorphism (tests/MUTATIONS.md). These
// tests look at the propagator itself: from partial states read off known immersions, where the
// expected deductions are known without running any rule code, it must make exactly those.
#include <gtest/gtest.h>

#include <cstdint>
#include <iostream>
#include <optional>
#include <vector>

#include "core/graph_search.h"
#include "core/immersion_rules.h"
#include "support/hand_complexes.h"

namespace imm {
namespace {

using detail::kDeclined;
using detail::kOwned;
using detail::kUndecided;
using detail::RuleContext;
using detail::SearchState;
using detail::StateEditor;
using detail::Worklist;
using test_support::build;
using test_support::ComplexSpec;

/// The complete search state of an immersion: the owner owns, every other slot holds its partner.
/// Written from the graph alone, not from any rule.
SearchState state_of(const RuleContext& ctx, const Immersion& im) {
  SearchState st;
  st.slot.assign(ctx.slot_count(), kUndecided);
  st.reason.assign(ctx.slot_count(), detail::Reason{});
  st.owner = im.owner;
  for (std::size_t s = 0; s < ctx.slot_count(); ++s) {
    const NodeId n = ctx.slot_node[s];
    const PatchId p = ctx.slot_patch[s];
    if (im.owner[p] == n) {
      st.slot[s] = kOwned;
    } else {
      const NodeId m = im.partner(n, p);
      EXPECT_TRUE(m.is_valid()) << "node " << n << " neither owns nor crosses patch " << p;
      if (m.is_valid()) st.slot[s] = m.value();
    }
  }
  return st;
}

/// The complexes: hand-made ones and random ones whose arcs are enclosed (every wedge a cell
/// with two copies or more), so that patches have several edges across them.
std::vector<ComplexSpec> complexes() {
  std::vector<ComplexSpec> out = {test_support::nested_circles(), test_support::nested_annulus_choice(),
                                  test_support::band(), test_support::fig9(),
                                  test_support::enclosed(test_support::band()),
                                  test_support::enclosed(test_support::enclosed(test_support::band()))};
  for (std::uint64_t seed = 0; seed < 40; ++seed)
    out.push_back(test_support::random_enclosed_complex(seed, 2 + static_cast<int>(seed % 2)));
  return out;
}

struct Counts {
  int forced = 0;     ///< single-candidate edges the propagator had to restore
  int free = 0;       ///< states with a real choice left, where it had to do nothing
  int conflicts = 0;  ///< states where a declined node has no candidate
};

/// Rule 2 (with Rule 1): a node that declines a patch is glued across it to exactly one copy of
/// the cell on the other side that neither owns the patch nor is glued to another node across it.
/// Three kinds of partial state, each one patch of a complete immersion with some of its slots
/// reopened, and the propagator run on that patch:
///  1. one edge a–b across p forgotten (both slots Declined): every other copy of both cells is
///     settled across p, so a and b are each other's only candidate and the edge is forced;
///  2. k >= 2 edges across p forgotten: every forgotten node has k candidates, nothing is forced,
///     and the state must stay as it is;
///  3. the owner of p declines it instead: every copy of the outer cell is glued to another node
///     (or p bounds winding 0), so the owner has no candidate: a Rule 2 conflict.
TEST(RulePropagators, Rule2ForcesTheOnlyPartnerAndNothingElse) {
  Counts counts;
  for (const ComplexSpec& spec : complexes()) {
    SCOPED_TRACE(spec.name);
    const CellComplex<2> complex = build<2>(spec);
    SearchOptions options;
    options.max_immersions = 0;
    const SearchResult found = find_immersions(complex, options);
    const RuleContext ctx(complex);
    for (const Immersion& im : found.immersions) {
      const SearchState complete = state_of(ctx, im);
      for (PatchId p : ids<PatchId>(complex.patch_count())) {
        std::vector<ImmersionEdge> across;
        for (const ImmersionEdge& e : im.edges)
          if (e.patch == p) across.push_back(e);
        const auto run = [&](SearchState& st) {
          Worklist worklist(ctx);
          StateEditor ed(ctx, st, worklist);
          const bool ok = detail::propagate_rule2(ed, p);
          return std::pair{ok, ed.conflict()};
        };
        // 1. One edge forgotten: restored.
        for (const ImmersionEdge& e : across) {
          SearchState st = complete;
          st.slot[ctx.slot(e.inner, p)] = kDeclined;
          st.slot[ctx.slot(e.outer, p)] = kDeclined;
          const auto [ok, conflict] = run(st);
          EXPECT_TRUE(ok) << (conflict ? conflict->message : "");
          EXPECT_EQ(st.slot, complete.slot) << "patch " << p << ": the edge " << e.inner << " - " << e.outer
                                            << " is the only one left and must be made";
          ++counts.forced;
        }
        // 2. Every edge forgotten, two or more: a choice, nothing forced.
        if (across.size() >= 2) {
          SearchState st = complete;
          for (const ImmersionEdge& e : across) {
            st.slot[ctx.slot(e.inner, p)] = kDeclined;
            st.slot[ctx.slot(e.outer, p)] = kDeclined;
          }
          const SearchState before = st;
          const auto [ok, conflict] = run(st);
          EXPECT_TRUE(ok) << (conflict ? conflict->message : "");
          EXPECT_EQ(st.slot, before.slot) << "patch " << p << ": " << across.size()
                                          << " candidates each, nothing is forced";
          ++counts.free;
        }
        // 3. The owner declines: no candidate left.
        {
          SearchState st = complete;
          const NodeId owner = im.owner[p];
          st.slot[ctx.slot(owner, p)] = kDeclined;
          st.owner[p] = NodeId();
          const auto [ok, conflict] = run(st);
          EXPECT_FALSE(ok) << "patch " << p << ": the owner " << owner << " declines it with no copy of "
                           << "the outer cell left to glue to";
          if (!ok) {
            EXPECT_TRUE(conflict.has_value());
            if (conflict) { EXPECT_EQ(conflict->rule, 2) << conflict->message; }
          }
          ++counts.conflicts;
        }
      }
    }
  }
  std::cout << counts.forced << " forced edges, " << counts.free << " free choices, " << counts.conflicts
            << " conflicts\n";
  EXPECT_GT(counts.forced, 100);
  EXPECT_GT(counts.free, 10);
  EXPECT_GT(counts.conflicts, 100);
}

}  // namespace
}  // namespace imm
