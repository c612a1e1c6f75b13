// Paper Fig. 15 (bottom right) / Fig. 16: the curve on which the paper traces its algorithm.
// Rule 6 applies in its three-patch form at one arc and in its four-patch form at another; at
// the arcs with an empty wedge it does not apply. The search finds the one immersion; the
// statistics show how much of it was forced (the paper's 11 iterations are all forced choices).
// The picture marks the arcs as the paper's Fig. 15 does: red circles where Rule 6 takes its
// four-patch form, red squares where it takes the three-patch form, blue circles where it does
// not apply (a wedge at the arc is outside every cell).
#include "figures/figure_common.h"

using namespace imm;

namespace {
constexpr const char* kRuleSixColour = "#d00000";
constexpr const char* kNoRuleColour = "#0050e0";

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}
}  // namespace

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_16_rule6_trace");
    figures::describe("Fig. 15 / Fig. 16", "Rule 6 at four-patch and three-patch arcs; the algorithm builds the immersion graph.");
    const auto run = figures::run_curve("fig15");
    const dim2::Complex2& complex = *run.built.complex;
    const CellComplex<2>& cx = complex.complex;
    figures::expect(run.search.complete && run.search.immersions.size() == 1, "Fig. 16 bounds one immersion");
    std::ostringstream md;
    md << "# Fig. 15 / 16\n\n| arc | junction patches (ccw) | wedges all cells | distinct patches | Rule 6 form |\n"
       << "|---|---|---|---|---|\n";
    int three = 0, four = 0;
  std::vector<dim2::ArcMark> marks;
    for (ArcId a : ids<ArcId>(cx.arc_count())) {
      const ArcJunctions& j = cx.arc(a);
      bool all_cells = true;
      for (RegionId w : j.wedge) all_cells = all_cells && cx.is_cell(w);
      std::vector<PatchId> distinct(j.patch.begin(), j.patch.end());
      std::sort(distinct.begin(), distinct.end());
      distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
      const char* form = !all_cells ? "does not apply" : distinct.size() == 3 ? "three-patch" : "four-patch";
      three += all_cells && distinct.size() == 3;
      four += all_cells && distinct.size() == 4;
      marks.push_back({a, all_cells && distinct.size() == 3 ? dim2::ArcMark::Shape::Square : dim2::ArcMark::Shape::Circle,
                       all_cells ? kRuleSixColour : kNoRuleColour});
      md << "| " << a << " | P" << j.patch[0] << " P" << j.patch[1] << " P" << j.patch[2] << " P" << j.patch[3]
         << " | " << (all_cells ? "yes" : "no") << " | " << distinct.size() << " | " << form << " |\n";
    }
    figures::expect(three >= 1 && four >= 1, "Fig. 16 has a three-patch and a four-patch Rule 6 arc");
    const SearchStats& st = run.search.stats;
    md << "\nsearch: " << st.states << " states, " << st.branches << " branches, " << st.dead_ends
       << " dead ends\n";
    figures::write(args, "fig16.md", md.str());
    const std::string marked = dim2::format_complex_svg(
        complex, {.title = "Fig. 15: Rule 6 four-patch (red circle), three-patch (red square), not applying (blue)",
                  .arc_marks = marks});
    // What the SVG draws, read back from its text: squares and circles by colour.
    const auto marks_drawn = [&](const char* size_attribute, const char* colour) {
      return count(marked, std::string(size_attribute) + " fill=\"none\" stroke=\"" + colour + "\"");
    };
    const std::size_t squares = marks_drawn("height=\"22.00\"", kRuleSixColour);
    const std::size_t red_circles = marks_drawn("r=\"11.00\"", kRuleSixColour);
    const std::size_t blue_circles = marks_drawn("r=\"11.00\"", kNoRuleColour);
    figures::expect(squares == static_cast<std::size_t>(three) && red_circles == static_cast<std::size_t>(four) &&
                        blue_circles == cx.arc_count() - static_cast<std::size_t>(three + four),
                    "Fig. 15's picture marks every arc by its Rule 6 form");
    figures::write(args, "fig15_rule6.svg", marked);
    figures::write(args, "fig16_immersion.svg",
                   dim2::format_immersion_svg(complex, run.search.immersions.front(), {.title = "Fig. 16"}));
  });
}
