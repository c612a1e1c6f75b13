// SVG drawings of 2D inputs, cell complexes and immersions (CONVENTIONS "Figures": 2D figures
// as SVG from a small writer of our own). CGAL-free: reads only the double display geometry of
// Complex2 (region_boundary, patch_polyline, arc_point, region_sample).
//
// Output is deterministic: fixed number formatting, fixed palette, no timestamps.
#pragma once

#include <string>
#include <vector>

#include "core/immersion_graph.h"
#include "dim2/complex2.h"
#include "dim2/curves.h"

namespace imm::dim2 {

/// A hollow marker drawn around an arc (the paper's Fig. 15 circles and squares the arcs where
/// Rule 6 takes one form or another).
struct ArcMark {
  enum class Shape { Circle, Square };
  ArcId arc;
  Shape shape = Shape::Circle;
  std::string colour = "#d00";
};

struct SvgOptions {
  /// Width of the drawing area in SVG user units (the height follows the aspect ratio).
  double width = 800.0;
  /// Draw ids (cells C#, patches P#, arcs A#) next to the geometry.
  bool labels = true;
  /// Title drawn above the picture (escaped); empty for none.
  std::string title;
  /// Markers around arcs (format_complex_svg only).
  std::vector<ArcMark> arc_marks;
};

/// The raw input: every curve as a closed polyline with direction arrows and its first vertex
/// marked. Works on any curve set, also an invalid one (nothing is computed).
std::string format_curves_svg(const CurveSet& curves, const SvgOptions& options = {});

/// The cell complex (paper Fig. 9): regions shaded by winding number, the curves (in the
/// direction the complex uses) with arrows, crossing points (arcs), and labels for cells,
/// patches and arcs; a legend lists every cell with its winding number.
std::string format_complex_svg(const Complex2& complex, const SvgOptions& options = {});

/// One immersion, drawn like the middle of the paper's Fig. 6: every graph node is drawn as its
/// cell (the region's boundary loops with even-odd fill) in its own colour, the copies of one
/// cell shifted slightly so that all of them are visible; the B-patches of a node are solid when
/// the node owns them and dashed when it declines them; graph edges are thin lines from node to
/// node through the patch they cross. A legend gives every node's cell, copy, winding number and
/// colour, and the connected components of the graph.
/// @pre `immersion` was computed for `complex.complex`.
/// Paper: Fig. 6 (middle), Fig. 5 (top right), §5.
std::string format_immersion_svg(const Complex2& complex, const Immersion& immersion,
                                 const SvgOptions& options = {});

}  // namespace imm::dim2
