// The curve generators by name (`immerse generate`): dim2/generators.h's shapes registered in
// the dimension-generic registry (core/generator_registry.h). To add a generator, add one entry
// below; the tests (tests/dim2/generators_test.cpp) hold the answers it is checked against.
#include <cstdint>

#include "dim2/generators.h"

namespace imm::dim2 {
namespace {

constexpr long kMaxSeed = 9223372036854775807L;

int as_int(long v) { return static_cast<int>(v); }

GeneratorRegistry<CurveSet> make_registry() {
  GeneratorRegistry<CurveSet> r;
  r.add_fixed("fig5", "Fig. 5: a band hooked over its own start; the largest cell self-touches",
              "1 immersion", fig5);
  r.add_fixed("fig6",
              "Fig. 6: Milnor-type doodle with two lobes (= doodle 2), 6 crossings, windings 0..3",
              "2 immersions", fig6);
  r.add_fixed("fig7",
              "Fig. 7: two components around an egg-shaped hole, overlapping at their ends",
              "1 immersion", fig7);
  r.add_fixed("fig8",
              "Fig. 8: a curve going around twice; windings >= 0 but not the boundary of an "
              "immersion",
              "not immersible (exit 3)", fig8);
  r.add_fixed("fig9", "Fig. 9/11: 4 cells, 8 patches, 4 arcs; cell 0 self-touches at arc 0",
              "1 immersion", fig9);
  r.add_fixed("fig12-simple",
              "Fig. 12 top: a disk immersed with windings up to 3 (band curled at both ends)",
              "1 immersion", fig12_simple);
  r.add_fixed("fig12-ring",
              "Fig. 12 bottom: annulus boundary winding twice; self-connecting ring cell",
              "self-connecting cell (exit 3)", fig12_ring);
  r.add_fixed("fig15",
              "Fig. 15/16: Rule 6 in its three-patch form (a kink inside a winding-2 annulus)",
              "1 immersion", fig15);
  r.add({"convex",
         "regular convex polygon with N vertices",
         {{"n", "vertices", 12, 3, 1000000}},
         "1 immersion"},
        [](const std::vector<long>& p) { return convex_polygon(as_int(p[0])); });
  r.add({"figure-eight",
         "lemniscate with one crossing (windings +1/-1, turning number 0)",
         {{"samples", "vertices (even)", 32, 8, 1000000, /*even=*/true}},
         "inversion (exit 3)"},
        [](const std::vector<long>& p) { return figure_eight(as_int(p[0])); });
  r.add({"limacon",
         "limacon r = 1 + 2 cos(t) with its inner loop (turning number 2)",
         {{"samples", "vertices", 48, 12, 1000000}},
         "not immersible (exit 3)"},
        [](const std::vector<long>& p) { return limacon(as_int(p[0])); });
  r.add_fixed("curl",
              "a band that curls once over itself (turning number 1, a region of winding 2)",
              "1 immersion", curl);
  r.add({"doodle",
         "rotationally symmetric Milnor-type doodle with K lobes, K(K+1) crossings",
         {{"k", "lobes", 2, 1, 12}},
         "Catalan(K) immersions: 1, 2, 5, 14, 42, 132, 429 for K = 1..7"},
        [](const std::vector<long>& p) { return doodle(as_int(p[0])); });
  r.add({"doodle-chain",
         "K doodles (two lobes by default) in a row joined by thin bands",
         {{"k", "doodles", 3, 1, 1000}, {"lobes", "lobes per doodle", 2, 1, 12}},
         "Catalan(lobes)^K immersions (2^K for 2 lobes)"},
        [](const std::vector<long>& p) { return doodle_chain(as_int(p[0]), as_int(p[1])); });
  r.add({"spiral",
         "a band coiled K times over itself (windings up to K + 1)",
         {{"k", "turns", 3, 1, 100}},
         "1 immersion"},
        [](const std::vector<long>& p) { return spiral(as_int(p[0])); });
  r.add({"random",
         "random polygon with N vertices (seeded; often an inversion)",
         {{"n", "vertices", 20, 3, 5000}, {"seed", "random seed", 1, 0, kMaxSeed}},
         "varies"},
        [](const std::vector<long>& p) {
          return random_polygon(as_int(p[0]), static_cast<std::uint64_t>(p[1]));
        });
  r.add({"random-multi",
         "C random star-shaped components with N vertices each, overlapping (seeded)",
         {{"c", "components", 4, 1, 10000},
          {"n", "vertices per component", 16, 3, 10000},
          {"seed", "random seed", 1, 0, kMaxSeed}},
         "at least 1 immersion"},
        [](const std::vector<long>& p) {
          return random_multi(as_int(p[0]), as_int(p[1]), static_cast<std::uint64_t>(p[2]));
        });
  r.add({"circles-pile",
         "K circles with centres in a box of 0.8 radius: every pair overlaps (seeded)",
         {{"k", "circles", 16, 1, 10000},
          {"seed", "random seed", 1, 0, kMaxSeed},
          {"n", "vertices per circle", 32, 8, 100000}},
         "at least 1 immersion (the disks)"},
        [](const std::vector<long>& p) {
          return circles_pile(as_int(p[0]), static_cast<std::uint64_t>(p[1]), as_int(p[2]));
        });
  return r;
}

}  // namespace

const GeneratorRegistry<CurveSet>& curve_registry() {
  static const GeneratorRegistry<CurveSet> kRegistry = make_registry();
  return kRegistry;
}

GenerateResult generate(std::string_view name, const std::vector<std::string>& arguments) {
  GenerateResult result;
  result.error = curve_registry().generate(name, arguments, result.curves);
  return result;
}

}  // namespace imm::dim2
