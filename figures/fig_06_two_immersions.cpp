// Paper Fig. 6: a self-overlapping curve with two distinct immersions, the decomposition of each
// (middle of the figure) and an unglued triangle mesh of each (right). Also the family of
// DESIGN §6: rotationally symmetric doodles with K = 2, 3, 4 lobes have 2, 5, 14 immersions.
#include "figures/figure_common.h"

using namespace imm;

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_06_two_immersions");
    figures::describe("Fig. 6", "a self-overlapping curve with two distinct immersions; both are found and meshed.");
    const auto run = figures::run_curve("fig6");
    const dim2::Complex2& complex = *run.built.complex;
    figures::expect(run.search.complete && run.search.immersions.size() == 2,
                    "Fig. 6 has exactly two immersions");
    figures::write(args, "fig6_input.svg", dim2::format_complex_svg(complex, {.title = "Fig. 6: input and cells"}));
    std::ostringstream md;
    md << "# Fig. 6: two immersions\n\n| immersion | nodes | edges | components | output triangles |\n"
       << "|---|---|---|---|---|\n";
    for (std::size_t k = 0; k < run.search.immersions.size(); ++k) {
      const Immersion& im = run.search.immersions[k];
      const std::string title = "Fig. 6: immersion " + std::to_string(k);
      figures::write(args, "fig6_immersion_" + std::to_string(k) + ".svg",
                     dim2::format_immersion_svg(complex, im, {.title = title}));
      const dim2::MeshResult mesh =
          figures::mesh_and_write(args, complex, im, args.quick ? 12 : 48, "fig6_mesh_" + std::to_string(k));
      md << "| " << k << " | " << im.layout.node_count() << " | " << im.edges.size() << " | "
         << im.components().size() << " | " << mesh.mesh.triangles.size() << " |\n";
    }
    md << "\n## Symmetric doodles (DESIGN §6)\n\n| lobes K | immersions | expected (Catalan) |\n|---|---|---|\n";
    const int catalan[] = {1, 1, 2, 5, 14};
    for (int lobes = 2; lobes <= (args.quick ? 3 : 4); ++lobes) {
      const auto doodle = figures::run_curve("doodle", {std::to_string(lobes)});
      md << "| " << lobes << " | " << doodle.search.immersions.size() << " | " << catalan[lobes] << " |\n";
      figures::expect(doodle.search.immersions.size() == static_cast<std::size_t>(catalan[lobes]),
                      "doodle " + std::to_string(lobes) + " has Catalan(K) immersions");
    }
    figures::write(args, "fig6.md", md.str());
  });
}
