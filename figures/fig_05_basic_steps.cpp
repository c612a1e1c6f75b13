// Paper Fig. 5: the basic steps on one curve — cells, patches and arcs (the largest cell
// self-touches, §4.2.1), the immersion graph of the disk, and the triangle mesh whose cell
// submeshes are duplicated so that the self-touching cell is not glued to itself.
#include "figures/figure_common.h"

using namespace imm;

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_05_basic_steps");
    figures::describe("Fig. 5", "basic steps in 2D: cells, patches and arcs; the largest cell self-touches; the triangulated cells are duplicated and connected into an immersed disk.");
    const auto run = figures::run_curve("fig5");
    const dim2::Complex2& complex = *run.built.complex;
    const CellComplex<2>& cx = complex.complex;
    bool self_touching = false;
    for (CellId c : ids<CellId>(cx.cell_count())) self_touching |= !cx.self_touching_arcs(c).empty();
    figures::expect(self_touching, "Fig. 5 has a self-touching cell");
    figures::expect(run.search.complete && run.search.immersions.size() == 1, "Fig. 5 bounds one disk");
    const Immersion& im = run.search.immersions.front();
    figures::write(args, "fig5_cells.svg", dim2::format_complex_svg(complex, {.title = "Fig. 5: cells, patches, arcs"}));
    figures::write(args, "fig5_immersion.svg", dim2::format_immersion_svg(complex, im, {.title = "Fig. 5: immersion"}));
    const dim2::MeshResult mesh = figures::mesh_and_write(args, complex, im, args.quick ? 12 : 40, "fig5_mesh");
    std::ostringstream md;
    md << "# Fig. 5\n\ncells " << cx.cell_count() << ", patches " << cx.patch_count() << ", arcs "
       << cx.arc_count() << ", immersions 1 (" << im.layout.node_count() << " nodes, " << im.edges.size()
       << " edges); mesh: " << mesh.stats.background_triangles << " background triangles, "
       << mesh.stats.cut_triangles << " cut, " << mesh.mesh.triangles.size() << " output triangles\n";
    figures::write(args, "fig5.md", md.str());
  });
}
