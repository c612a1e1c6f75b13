// Paper Fig. 7: an input of two components forming an egg-shaped hole. One immersion (two
// overlapping disks); the unglued mesh separates the overlapping ends (pulled-apart SVG).
#include "figures/figure_common.h"

using namespace imm;

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_07_two_components");
    figures::describe("Fig. 7", "an input of two components forming an egg-shaped hole has one immersion, meshed unglued.");
    const auto run = figures::run_curve("fig7");
    const dim2::Complex2& complex = *run.built.complex;
    figures::expect(run.search.complete && run.search.immersions.size() == 1, "Fig. 7 has one immersion");
    const Immersion& im = run.search.immersions.front();
    figures::expect(im.components().size() == 2, "the immersion is two overlapping disks");
    figures::write(args, "fig7_input.svg", dim2::format_complex_svg(complex, {.title = "Fig. 7: input and cells"}));
    figures::write(args, "fig7_immersion.svg", dim2::format_immersion_svg(complex, im, {.title = "Fig. 7: immersion"}));
    const dim2::MeshResult mesh = figures::mesh_and_write(args, complex, im, args.quick ? 16 : 64, "fig7_mesh");
    figures::write(args, "fig7_mesh.emb", dim2::format_embedding(mesh.embedding));
    std::ostringstream md;
    md << "# Fig. 7\n\ncells " << complex.complex.cell_count() << ", patches " << complex.complex.patch_count()
       << ", arcs " << complex.complex.arc_count() << ", immersions " << run.search.immersions.size()
       << ", graph components " << im.components().size() << ", background triangles "
       << mesh.stats.background_triangles << ", cut " << mesh.stats.cut_triangles << ", output triangles "
       << mesh.mesh.triangles.size() << "\n";
    figures::write(args, "fig7.md", md.str());
  });
}
