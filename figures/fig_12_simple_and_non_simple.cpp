// Paper Fig. 12: a simple immersion (top) and a ring whose cell of winding 2 is self-connecting
// (bottom): the search proves there is no simple immersion and names the cell.
#include "figures/figure_common.h"

using namespace imm;

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_12_simple_and_non_simple");
    figures::describe("Fig. 12", "a disk immersion is simple; a ring immersion that wraps a cell twice is not.");
    const auto simple = figures::run_curve("fig12-simple");
    figures::expect(simple.search.immersions.size() == 1, "Fig. 12 top has one simple immersion");
    figures::write(args, "fig12_simple.svg",
                   dim2::format_immersion_svg(*simple.built.complex, simple.search.immersions.front(),
                                              {.title = "Fig. 12 top: simple immersion"}));
    const auto ring = figures::run_curve("fig12-ring");
    figures::expect(ring.search.status == ImmersionStatus::SelfConnectingCell,
                    "Fig. 12 bottom has a self-connecting cell");
    figures::write(args, "fig12_ring.svg",
                   dim2::format_complex_svg(*ring.built.complex, {.title = "Fig. 12 bottom: self-connecting cell"}));
    std::ostringstream md;
    md << "# Fig. 12\n\n- top: " << to_string(simple.search.status) << ", "
       << simple.search.immersions.size() << " immersion\n- bottom: " << to_string(ring.search.status)
       << ": " << ring.search.conflict.message << '\n';
    figures::write(args, "fig12.md", md.str());
  });
}
