// Paper Fig. 8 (2D): curves that are not boundaries of immersions, with the verdict and the
// conflict the search names (exit code 3 at the command line).
#include "figures/figure_common.h"

using namespace imm;

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_08_not_immersible");
    figures::describe("Fig. 8", "curves that are not boundaries of immersions.");
    std::ostringstream md;
    md << "# Fig. 8: not immersible\n\n| curve | verdict | reason |\n|---|---|---|\n";
    for (const char* name : {"fig8", "limacon", "figure-eight"}) {
      const auto run = figures::run_curve(name);
      std::string verdict, reason;
      if (run.built.inversion) {
        verdict = "inversion";
        reason = run.built.inversion->message;
      } else {
        verdict = to_string(run.search.status);
        reason = run.search.conflict.message;
        figures::expect(run.search.complete && run.search.immersions.empty(),
                        std::string(name) + " has no immersion");
        figures::write(args, std::string(name) + ".svg",
                       dim2::format_complex_svg(*run.built.complex, {.title = name}));
      }
      md << "| " << name << " | " << verdict << " | " << reason << " |\n";
    }
    figures::write(args, "fig8.md", md.str());
  });
}
