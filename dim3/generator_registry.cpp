// The surface generators by name (`immerse generate`): dim3/generators3.h's shapes registered
// in the dimension-generic registry (core/generator_registry.h). To add a generator, add one
// entry below; the answers it is checked against live in the tests
// (tests/support/expected_surface_counts.h).
#include <cstdint>
#include <string>
#include <utility>

#include "dim3/generators3.h"

namespace imm::dim3 {
namespace {

constexpr long kMaxSeed = 9223372036854775807L;

int as_int(long v) { return static_cast<int>(v); }
std::uint64_t as_seed(long v) { return static_cast<std::uint64_t>(v); }

GeneratorRegistry<Surface> make_registry() {
  using P = const std::vector<long>&;
  GeneratorRegistry<Surface> r;
  r.add({"sphere", "UV sphere (embedded control)", {{"n", "latitude bands", 12, 3, 2000}},
         "1 cell, 1 immersion"},
        [](P p) { return sphere(as_int(p[0])); });
  r.add({"torus",
         "torus (embedded control)",
         {{"n", "segments around the axis (n/2 around the tube)", 24, 6, 4000}},
         "1 cell, 1 immersion"},
        [](P p) { return torus(as_int(p[0])); });
  r.add({"two-spheres",
         "two overlapping spheres as one input (windings 1, 1, 2)",
         {{"n", "latitude bands per sphere", 12, 3, 2000}},
         "3 cells, 1 immersion"},
        [](P p) { return two_spheres(as_int(p[0])); });
  r.add({"two-tori",
         "two overlapping tori as one input, tubes crossing twice (windings 1, 1, 2, 2)",
         {{"n", "segments around the axis and the tube (4n^2 triangles)", 32, 3, 1000}},
         "4 cells, 1 immersion"},
        [](P p) { return two_tori(as_int(p[0])); });
  r.add({"tube-overlap",
         "a capped tube along a looping path, passing through itself once",
         {{"sides", "vertices per ring", 12, 6, 2000}},
         "2 cells (windings 1, 2), 1 immersion"},
        [](P p) { return tube_overlap(as_int(p[0])); });
  r.add({"helix",
         "Fig. 1: capped tube along a helix, consecutive loops overlapping",
         {{"loops", "turns (100, 20 = 200k triangles)", 4, 1, 100000},
          {"sides", "vertices per ring (even)", 20, 6, 1000, /*even=*/true}},
         "2 cells (windings 1, 2), 1 immersion"},
        [](P p) { return helix(as_int(p[0]), as_int(p[1])); });
  r.add({"double-loop-torus",
         "Fig. 13: a torus whose core winds twice around the axis",
         {{"n", "rings per turn (n/2 sides)", 32, 8, 4000}},
         "self-connecting cell; 1 immersion after a helper-box cut"},
        [](P p) { return double_loop_torus(as_int(p[0])); });
  r.add({"sacht-torus",
         "Fig. 24: torus with vertical columns through it (large = 1: more)",
         {{"n", "torus segments around the axis", 36, 12, 4000},
          {"large", "0 small, 1 large", 0, 0, 1}},
         "max winding 2, 1 immersion"},
        [](P p) { return sacht_torus(as_int(p[0]), p[1] != 0); });
  r.add({"quintuple-torus",
         "Fig. 22: five overlapping tori and seven colliding cylinders",
         {{"n", "torus segments around the axis", 24, 8, 2000}},
         "max winding 7, at least 1 immersion (the components)"},
        [](P p) { return quintuple_torus(as_int(p[0])); });
  r.add({"tree",
         "Fig. 3: procedural tree, each branch buried in its parent (120 triangles each)",
         {{"branches", "branches (2500 = 300k triangles)", 40, 1, 200000},
          {"seed", "random seed", 1, 0, kMaxSeed}},
         "2B - 1 cells, 1 immersion"},
        [](P p) { return tree(as_int(p[0]), as_seed(p[1])); });
  r.add({"head",
         "Fig. 2: head-like sphere whose lip curls down and pierces the chin",
         {{"n", "vertices per ring", 24, 16, 2000}},
         "2 cells (windings 1, 2), 1 immersion"},
        [](P p) { return head(as_int(p[0])); });
  r.add({"limacon-torus",
         "Fig. 8: the limacon with inner loop revolved (windings 0..2)",
         {{"n", "profile samples and ring sides", 48, 12, 2000}},
         "not immersible (exit 3)"},
        [](P p) { return limacon_torus(as_int(p[0])); });
  r.add({"figure-eight-torus",
         "Fig. 8: a figure-eight revolved (windings +1 and -1)",
         {{"n", "profile samples and ring sides", 32, 12, 2000}},
         "inversion (exit 3)"},
        [](P p) { return figure_eight_torus(as_int(p[0])); });
  r.add({"poke-through",
         "Fig. 8: a sphere dented from below until the dent pokes out on top",
         {{"n", "ring sides", 24, 8, 2000}},
         "inversion (exit 3)"},
        [](P p) { return poke_through(as_int(p[0])); });
  r.add({"folded-bipyramid",
         "a bipyramid whose top vertex is pulled across its own ring: a local fold (issue 16)",
         {{"percent", "how far the top vertex is pulled (100: the fold of the tests)", 100, 0, 200}},
         "local fold at vertex 6 (exit 3); --repair-folds repairs it"},
        [](P p) { return folded_bipyramid(as_int(p[0])); });
  r.add({"comb",
         "comb whose teeth are 1/64 apart (nearly touching, no intersection)",
         {{"teeth", "teeth", 12, 1, 100000}},
         "1 cell, 1 immersion"},
        [](P p) { return comb(as_int(p[0])); });
  r.add({"mouth",
         "the head with its lip 0.004 short of the chin (no intersection)",
         {{"n", "vertices per ring", 24, 16, 2000}},
         "1 cell, 1 immersion"},
        [](P p) { return mouth(as_int(p[0])); });
  r.add({"random-blobs",
         "K random star-shaped ellipsoids, overlapping (seeded)",
         {{"k", "blobs", 8, 1, 10000},
          {"seed", "random seed", 1, 0, kMaxSeed},
          {"n", "latitude bands per blob", 10, 4, 200}},
         "at least 1 immersion"},
        [](P p) { return random_blobs(as_int(p[0]), as_seed(p[1]), as_int(p[2])); });
  r.add({"perturbed-torus",
         "randomly bumped torus around a self-crossing core (seeded)",
         {{"n", "size (4n rings of n/2 sides)", 16, 12, 2000}, {"seed", "random seed", 1, 0, kMaxSeed}},
         "at least 1 immersion"},
        [](P p) { return perturbed_torus(as_int(p[0]), as_seed(p[1])); });
  const auto pile = [&](std::string name, std::string description, std::string part, long k,
                        long n, long n_min, Surface (*make)(int, std::uint64_t, int)) {
    r.add({std::move(name),
           std::move(description),
           {{"k", std::move(part), k, 1, 10000},
            {"seed", "random seed", 1, 0, kMaxSeed},
            {"n", "resolution of each part", n, n_min, 200}},
           "at least 1 immersion (the parts' solids)"},
          [make](P p) { return make(as_int(p[0]), as_seed(p[1]), as_int(p[2])); });
  };
  pile("spheres-pile", "K spheres of radius 0.5, centres in a cube of side 0.6 (seeded)", "spheres",
       12, 8, 3, spheres_pile);
  pile("tori-pile", "K tori (radii 0.5, 0.18), random axes, centres in a cube of side 0.6", "tori",
       6, 16, 6, tori_pile);
  r.add({"helix-spheres",
         "helix (Fig. 13 tube, L loops) inside a pile of K spheres of radius 0.5",
         {{"k", "spheres", 8, 0, 10000},
          {"seed", "random seed", 1, 0, kMaxSeed},
          {"loops", "helix loops", 2, 1, 100}},
         "at least 1 immersion (the helix tube's and the balls' solids)"},
        [](P p) { return helix_in_spheres(as_int(p[0]), as_seed(p[1]), as_int(p[2])); });
  return r;
}

}  // namespace

const GeneratorRegistry<Surface>& surface_registry() {
  static const GeneratorRegistry<Surface> kRegistry = make_registry();
  return kRegistry;
}

SurfaceGenerateResult generate_surface(std::string_view name,
                                       const std::vector<std::string>& arguments) {
  SurfaceGenerateResult result;
  result.error = surface_registry().generate(name, arguments, result.surface);
  return result;
}

}  // namespace imm::dim3
