// The answers the procedural surfaces (dim3/generators3.h) are built to have, derived by hand
// from each construction (the derivations are in the generators' documentation), kept here
// beside the tests that check them against the exact cell complex and the search
// (tests/dim3/generators3_test.cpp) and used by the Table 1 program (figures/table_1.cpp).
// Header-only: it needs dim3 (the registry parses the arguments), which the core-only test
// support library does not link.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "dim3/generators3.h"

namespace imm::test_support {

/// What the construction of a generated shape implies; -1 where it is not derived by hand.
struct ExpectedSurfaceCounts {
  long regions = -1;  ///< all regions, the unbounded outside one included
  long cells = -1;    ///< regions with non-zero winding number
  long patches = -1;
  long arcs = -1;        ///< geometric arcs, each once (closed intersection loops here)
  int min_winding = 0;   ///< smallest winding number (negative: an inversion)
  int max_winding = -1;  ///< largest winding number; -1 = not derived
  /// 0 = none (exit 3); -1 = not derived (at least 1 when `at_least_one`); with a
  /// self-connecting cell: the count once helper boxes have cut it (paper §6.2).
  long immersions = -1;
  bool at_least_one = false;     ///< an immersion is known to exist (e.g. the components' solids)
  bool self_connecting = false;  ///< has a self-connecting cell (cut by helper boxes, paper §6.2)
  /// A vertex star crosses itself: a local fold (exit 3 before any complex; --repair-folds).
  bool local_fold = false;
  std::string error;             ///< unknown generator or bad arguments (as generate_surface)
};

namespace detail {

inline ExpectedSurfaceCounts counts(long regions, long cells, long patches, long arcs, int min_w,
                                    int max_w, long immersions) {
  ExpectedSurfaceCounts e;
  e.regions = regions;
  e.cells = cells;
  e.patches = patches;
  e.arcs = arcs;
  e.min_winding = min_w;
  e.max_winding = max_w;
  e.immersions = immersions;
  e.at_least_one = immersions > 0;
  return e;
}

/// A union of embedded components: at least one immersion, nothing else derived.
inline ExpectedSurfaceCounts at_least_one() {
  ExpectedSurfaceCounts c;
  c.at_least_one = true;
  return c;
}

using Derivation = ExpectedSurfaceCounts (*)(const std::vector<long>&);

/// Per generator: its answer from its parsed parameters (dim3/generators3.h states each).
inline const std::map<std::string, Derivation, std::less<>>& derivations() {
  using P = const std::vector<long>&;
  // An embedded surface: outside and inside, one patch, no arc, one immersion.
  static constexpr Derivation kEmbedded = [](P) { return counts(2, 1, 1, 0, 0, 1, 1); };
  // One closed intersection loop on a single immersed ball (tube-overlap, helix, head).
  static constexpr Derivation kOneOverlap = [](P) { return counts(3, 2, 3, 1, 0, 2, 1); };
  static const std::map<std::string, Derivation, std::less<>> kDerivations{
      {"sphere", kEmbedded},
      {"torus", kEmbedded},
      {"two-spheres", [](P) { return counts(4, 3, 4, 1, 0, 2, 1); }},
      {"two-tori", [](P) { return counts(5, 4, 6, 2, 0, 2, 1); }},
      {"tube-overlap", kOneOverlap},
      {"helix", kOneOverlap},
      {"double-loop-torus",
       [](P) {
         ExpectedSurfaceCounts c = counts(3, 2, 2, 1, 0, 2, 1);  // after the helper-box cut
         c.self_connecting = true;
         return c;
       }},
      {"sacht-torus",
       [](P p) {
         return p[1] != 0 ? counts(34, 33, 53, 20, 0, 2, 1) : counts(14, 13, 21, 8, 0, 2, 1);
       }},
      {"quintuple-torus",
       [](P) {
         ExpectedSurfaceCounts c = at_least_one();
         c.max_winding = 7;
         return c;
       }},
      {"tree",
       [](P p) {
         const long b = p[0];
         return counts(2 * b, 2 * b - 1, 3 * b - 2, b - 1, 0, b > 1 ? 2 : 1, 1);
       }},
      {"head", kOneOverlap},
      {"limacon-torus", [](P) { return counts(3, 2, 2, 1, 0, 2, 0); }},
      {"figure-eight-torus", [](P) { return counts(3, 2, 2, 1, -1, 1, 0); }},
      {"poke-through", [](P) { return counts(3, 2, 3, 1, -1, 1, 0); }},
      {"comb", kEmbedded},
      // Percent 0: apexes straight above and below a zig-zag hexagon that is star-shaped from its
      // centre: embedded. Percent >= 100: the top apex beyond ring vertices 3 and 4, where
      // (3, 4, 6) and (5, 0, 6) cross (generators3.h). In between: not derived.
      {"folded-bipyramid",
       [](P p) {
         if (p[0] == 0) return kEmbedded(p);
         ExpectedSurfaceCounts c;
         c.local_fold = p[0] >= 100;
         return c;
       }},
      {"mouth", kEmbedded},
      {"random-blobs", [](P) { return at_least_one(); }},
      {"perturbed-torus", [](P) { return at_least_one(); }},
      // Piles of overlapping closed parts: the disjoint union of the parts' solids.
      {"spheres-pile", [](P) { return at_least_one(); }},
      {"tori-pile", [](P) { return at_least_one(); }},
      {"helix-spheres", [](P) { return at_least_one(); }},
  };
  return kDerivations;
}

}  // namespace detail

/// True when the tests hold a hand-derived answer for this generator.
inline bool has_expected_surface_counts(std::string_view name) {
  return detail::derivations().count(name) > 0;
}

/// The hand-derived answer for a generator and its arguments (same argument rules as
/// dim3::generate_surface). Paper: §4 (regions, cells, patches, arcs), §5 (immersions).
inline ExpectedSurfaceCounts expected_surface_counts(std::string_view name,
                                                     const std::vector<std::string>& arguments) {
  ExpectedSurfaceCounts counts;
  std::vector<long> values;
  counts.error = dim3::surface_registry().parse(name, arguments, values);
  if (!counts.error.empty()) return counts;
  const auto found = detail::derivations().find(name);
  if (found == detail::derivations().end()) {
    counts.error = "no hand-derived answer for generator '" + std::string(name) + "'";
    return counts;
  }
  return found->second(values);
}

}  // namespace imm::test_support
