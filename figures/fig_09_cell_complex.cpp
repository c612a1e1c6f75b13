// Paper Fig. 9 / Fig. 11: cells, patches and arcs in 2D, listed like the caption: the B-patches
// of every cell (* = orientation disagrees with the cell), the topological neighbours at every
// arc, and the geometric-neighbour pairs of the self-touching cell.
#include "figures/figure_common.h"

using namespace imm;

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_09_cell_complex");
    figures::describe("Fig. 9 / Fig. 11", "a 2D curve has 4 cells, 8 patches and 4 arcs; cell 0 self-touches at an arc.");
    const auto run = figures::run_curve("fig9");
    const CellComplex<2>& cx = run.built.complex->complex;
    figures::expect(cx.cell_count() == 4 && cx.patch_count() == 8 && cx.arc_count() == 4,
                    "Fig. 9 has 4 cells, 8 patches, 4 arcs");
    std::ostringstream md;
    md << "# Fig. 9: cells, patches and arcs\n\n";
    for (CellId c : ids<CellId>(cx.cell_count())) {
      md << "- Cell " << c << " (winding " << cx.winding_number(c) << "):";
      for (const BPatch& b : cx.b_patches(c)) md << " P" << b.patch << (b.agrees ? "" : "*");
      const auto touching = cx.self_touching_arcs(c);
      if (!touching.empty()) md << " — self-touching at arc " << touching.front();
      md << '\n';
    }
    md << '\n';
    for (ArcId a : ids<ArcId>(cx.arc_count())) {
      const auto tn = cx.topological_neighbors(a);
      md << "- Arc " << a << ": (P" << tn[0][0] << ", P" << tn[0][1] << "), (P" << tn[1][0] << ", P"
         << tn[1][1] << ")\n";
    }
    md << "\nGeometric neighbours (cell: pair at arc):\n\n";
    for (const GeometricNeighbors& g : cx.geometric_neighbors()) {
      md << "- Cell " << g.cell << ": (P" << g.first << ", P" << g.second << ") at arc " << g.arc << '\n';
    }
    md << "\nImmersions: " << run.search.immersions.size() << '\n';
    figures::expect(run.search.immersions.size() == 1, "Fig. 9 bounds one immersed disk");
    figures::write(args, "fig9.md", md.str());
    figures::write(args, "fig9_cells.svg", dim2::format_complex_svg(*run.built.complex, {.title = "Fig. 9"}));
  });
}
