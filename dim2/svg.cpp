#include "dim2/svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/diagnostics.h"

namespace imm::dim2 {
namespace {

// Colour-blind-friendly palette (Okabe–Ito, then Tableau), fixed for deterministic output.
constexpr const char* kPalette[] = {"#0072b2", "#e69f00", "#009e73", "#cc79a7",
                                    "#56b4e9", "#d55e00", "#f0e442", "#4e79a7",
                                    "#59a14f", "#af7aa1", "#9c755f", "#edc948"};
constexpr std::size_t kPaletteSize = sizeof(kPalette) / sizeof(kPalette[0]);

constexpr double kMargin = 24.0;
constexpr double kLegendWidth = 280.0;
constexpr double kLegendLine = 16.0;
constexpr std::size_t kMaxLegendRows = 48;

std::string num(double v) {
  if (!std::isfinite(v)) v = 0.0;
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", v);
  std::string s(buffer);
  if (s == "-0.00") s = "0.00";
  return s;
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

/// World (input coordinates, y up) to SVG (y down) with a uniform scale.
class Frame {
 public:
  Frame(const std::vector<const std::vector<Point>*>& polylines, double width, double top)
      : top_(top) {
    double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
    double max_x = -min_x, max_y = -min_x;
    for (const auto* line : polylines) {
      for (const Point& p : *line) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
        min_x = std::min(min_x, p.x);
        max_x = std::max(max_x, p.x);
        min_y = std::min(min_y, p.y);
        max_y = std::max(max_y, p.y);
      }
    }
    if (!(min_x <= max_x)) min_x = max_x = min_y = max_y = 0.0;
    const double span = std::max({max_x - min_x, max_y - min_y, 1e-300});
    scale_ = width / span;
    min_x_ = min_x;
    max_y_ = max_y;
    width_ = (max_x - min_x) * scale_;
    height_ = (max_y - min_y) * scale_;
  }
  [[nodiscard]] double x(const Point& p) const { return kMargin + (p.x - min_x_) * scale_; }
  [[nodiscard]] double y(const Point& p) const { return top_ + kMargin + (max_y_ - p.y) * scale_; }
  [[nodiscard]] double width() const { return width_; }
  [[nodiscard]] double height() const { return height_; }
  [[nodiscard]] std::string xy(const Point& p, double dx = 0.0, double dy = 0.0) const {
    return num(x(p) + dx) + "," + num(y(p) + dy);
  }

 private:
  double top_;
  double scale_ = 1.0;
  double min_x_ = 0.0, max_y_ = 0.0;
  double width_ = 0.0, height_ = 0.0;
};

class SvgDocument {
 public:
  void add(std::string element) {
    body_ += element;
    body_ += '\n';
  }
  [[nodiscard]] std::string finish(double width, double height) const {
    std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    out += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(width) + "\" height=\"" +
           num(height) + "\" viewBox=\"0 0 " + num(width) + " " + num(height) +
           "\" font-family=\"Helvetica, Arial, sans-serif\">\n";
    out += "<rect x=\"0\" y=\"0\" width=\"" + num(width) + "\" height=\"" + num(height) +
           "\" fill=\"white\"/>\n";
    out += body_;
    out += "</svg>\n";
    return out;
  }

 private:
  std::string body_;
};

std::string text_element(double x, double y, const std::string& text, double size,
                         const char* fill = "#222", const char* anchor = "start") {
  return "<text x=\"" + num(x) + "\" y=\"" + num(y) + "\" font-size=\"" + num(size) + "\" fill=\"" +
         fill + "\" text-anchor=\"" + anchor + "\">" + xml_escape(text) + "</text>";
}

/// Point at fraction t of the arc length of a polyline.
Point point_along(const std::vector<Point>& line, double t) {
  if (line.empty()) return {};
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < line.size(); ++i)
    total += std::hypot(line[i + 1].x - line[i].x, line[i + 1].y - line[i].y);
  double target = total * t;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const double len = std::hypot(line[i + 1].x - line[i].x, line[i + 1].y - line[i].y);
    if (target <= len && len > 0.0) {
      const double s = target / len;
      return {line[i].x + s * (line[i + 1].x - line[i].x),
              line[i].y + s * (line[i + 1].y - line[i].y)};
    }
    target -= len;
  }
  return line.back();
}

/// An SVG path for closed loops ("M ... Z" per loop), shifted by (dx, dy) SVG units.
std::string loops_path(const Frame& frame, const std::vector<Loop>& loops, double dx = 0.0,
                       double dy = 0.0) {
  std::string d;
  for (const Loop& loop : loops) {
    if (loop.empty()) continue;
    d += "M";
    for (std::size_t i = 0; i < loop.size(); ++i) {
      if (i > 0) d += " L";
      d += frame.xy(loop[i], dx, dy);
    }
    d += " Z ";
  }
  return d;
}

std::string polyline_points(const Frame& frame, const std::vector<Point>& line, double dx = 0.0,
                            double dy = 0.0) {
  std::string s;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (i > 0) s += ' ';
    s += frame.xy(line[i], dx, dy);
  }
  return s;
}

/// Direction arrows along a closed polyline: about `count` of them, evenly spaced by length.
void add_arrows(SvgDocument& svg, const Frame& frame, const std::vector<Point>& closed_loop,
                int count, const char* fill) {
  const std::size_t n = closed_loop.size();
  if (n < 2) return;
  std::vector<double> length(n);
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Point& a = closed_loop[i];
    const Point& b = closed_loop[(i + 1) % n];
    length[i] = std::hypot(frame.x(b) - frame.x(a), frame.y(b) - frame.y(a));
    total += length[i];
  }
  if (!(total > 0.0)) return;
  const double spacing = total / static_cast<double>(std::max(count, 1));
  double next = spacing * 0.5;
  double walked = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    while (next <= walked + length[i] && length[i] > 0.0) {
      const double s = (next - walked) / length[i];
      const Point& a = closed_loop[i];
      const Point& b = closed_loop[(i + 1) % n];
      const double ax = frame.x(a), ay = frame.y(a), bx = frame.x(b), by = frame.y(b);
      const double ux = (bx - ax) / length[i], uy = (by - ay) / length[i];
      const double cx = ax + s * (bx - ax), cy = ay + s * (by - ay);
      const double size = 6.0;
      // Triangle pointing along the curve.
      const double tipx = cx + ux * size, tipy = cy + uy * size;
      const double lx = cx - ux * size * 0.6 - uy * size * 0.6,
                   ly = cy - uy * size * 0.6 + ux * size * 0.6;
      const double rx = cx - ux * size * 0.6 + uy * size * 0.6,
                   ry = cy - uy * size * 0.6 - ux * size * 0.6;
      svg.add("<polygon points=\"" + num(tipx) + "," + num(tipy) + " " + num(lx) + "," + num(ly) +
              " " + num(rx) + "," + num(ry) + "\" fill=\"" + fill + "\"/>");
      next += spacing;
    }
    walked += length[i];
  }
}

/// Grey level for a winding number (white for 0, darker for higher).
std::string winding_fill(int winding, int max_winding) {
  if (winding <= 0 || max_winding <= 0) return "#ffffff";
  const int level = 235 - static_cast<int>(std::lround(120.0 * winding / max_winding));
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", level, level, std::min(255, level + 12));
  return buffer;
}

double title_height(const SvgOptions& options) { return options.title.empty() ? 0.0 : 28.0; }

void add_title(SvgDocument& svg, const SvgOptions& options) {
  if (!options.title.empty()) svg.add(text_element(kMargin, 22.0, options.title, 16.0));
}

}  // namespace

std::string format_curves_svg(const CurveSet& curves, const SvgOptions& options) {
  std::vector<const std::vector<Point>*> lines;
  for (const Curve& c : curves.curves) lines.push_back(&c.vertices);
  const double top = title_height(options);
  const Frame frame(lines, options.width, top);
  SvgDocument svg;
  add_title(svg, options);
  for (std::size_t ci = 0; ci < curves.curves.size(); ++ci) {
    const Curve& c = curves.curves[ci];
    if (c.vertices.empty()) continue;
    const char* colour = kPalette[ci % kPaletteSize];
    svg.add("<polygon points=\"" + polyline_points(frame, c.vertices) +
            "\" fill=\"none\" stroke=\"" + colour +
            "\" stroke-width=\"1.5\" stroke-linejoin=\"round\"/>");
    add_arrows(svg, frame, c.vertices, 24, colour);
    svg.add("<circle cx=\"" + num(frame.x(c.vertices.front())) + "\" cy=\"" +
            num(frame.y(c.vertices.front())) + "\" r=\"3.5\" fill=\"" + colour + "\"/>");
    if (options.labels) {
      svg.add(text_element(frame.x(c.vertices.front()) + 5.0, frame.y(c.vertices.front()) - 5.0,
                           "curve " + std::to_string(ci), 11.0, colour));
    }
  }
  return svg.finish(frame.width() + 2 * kMargin, top + frame.height() + 2 * kMargin);
}

std::string format_complex_svg(const Complex2& c2, const SvgOptions& options) {
  const CellComplex<2>& complex = c2.complex;
  std::vector<const std::vector<Point>*> lines;
  for (const Curve& c : c2.curves.curves) lines.push_back(&c.vertices);
  const double top = title_height(options);
  const Frame frame(lines, options.width, top);
  SvgDocument svg;
  add_title(svg, options);
  const int max_winding = complex.max_winding_number();

  // Regions shaded by winding number (region 0, the unbounded one, stays white).
  for (RegionId r : ids<RegionId>(complex.region_count())) {
    if (r == kOutsideRegion || c2.region_boundary[r].empty()) continue;
    svg.add("<path d=\"" + loops_path(frame, c2.region_boundary[r]) + "\" fill=\"" +
            winding_fill(complex.winding_number(r), max_winding) +
            "\" fill-rule=\"evenodd\" stroke=\"none\"/>");
  }
  // Patches in palette colours (as Fig. 9 draws them), with arrows.
  for (PatchId p : ids<PatchId>(complex.patch_count())) {
    const std::vector<Point>& line = c2.patch_polyline[p];
    const char* colour = kPalette[p.index() % kPaletteSize];
    svg.add("<polyline points=\"" + polyline_points(frame, line) + "\" fill=\"none\" stroke=\"" +
            colour + "\" stroke-width=\"2\" stroke-linejoin=\"round\"/>");
  }
  for (const Curve& c : c2.curves.curves) add_arrows(svg, frame, c.vertices, 24, "#333");
  for (ArcId a : ids<ArcId>(complex.arc_count())) {
    const Point& p = c2.arc_point[a];
    svg.add("<circle cx=\"" + num(frame.x(p)) + "\" cy=\"" + num(frame.y(p)) +
            "\" r=\"3.5\" fill=\"#c00\"/>");
  }
  for (const ArcMark& mark : options.arc_marks) {
    const Point& p = c2.arc_point[mark.arc];
    constexpr double kMarkRadius = 11.0;
    const std::string style = "\" fill=\"none\" stroke=\"" + mark.colour + "\" stroke-width=\"2.5\"/>";
    if (mark.shape == ArcMark::Shape::Circle)
      svg.add("<circle cx=\"" + num(frame.x(p)) + "\" cy=\"" + num(frame.y(p)) + "\" r=\"" + num(kMarkRadius) + style);
    else
      svg.add("<rect x=\"" + num(frame.x(p) - kMarkRadius) + "\" y=\"" + num(frame.y(p) - kMarkRadius) +
              "\" width=\"" + num(2 * kMarkRadius) + "\" height=\"" + num(2 * kMarkRadius) + style);
  }
  if (options.labels) {
    for (PatchId p : ids<PatchId>(complex.patch_count())) {
      const Point at = point_along(c2.patch_polyline[p], 0.5);
      svg.add(text_element(frame.x(at) + 4.0, frame.y(at) - 4.0, "P" + std::to_string(p.value()),
                           10.0, kPalette[p.index() % kPaletteSize]));
    }
    for (ArcId a : ids<ArcId>(complex.arc_count())) {
      const Point& p = c2.arc_point[a];
      svg.add(text_element(frame.x(p) + 5.0, frame.y(p) + 12.0, "A" + std::to_string(a.value()),
                           10.0, "#c00"));
    }
    for (CellId c : ids<CellId>(complex.cell_count())) {
      const Point& p = c2.region_sample[complex.region_of(c)];
      svg.add(text_element(frame.x(p), frame.y(p), "C" + std::to_string(c.value()), 12.0, "#000",
                           "middle"));
    }
  }
  // Legend: cells with winding numbers.
  const double legend_x = frame.width() + 2 * kMargin;
  double y = top + kMargin + 4.0;
  svg.add(text_element(legend_x, y, "cell  winding  B-patches (* disagrees)", 11.0));
  std::size_t rows = 0;
  for (CellId c : ids<CellId>(complex.cell_count())) {
    y += kLegendLine;
    if (++rows > kMaxLegendRows) {
      svg.add(text_element(
          legend_x, y, "... and " + std::to_string(complex.cell_count() - kMaxLegendRows) + " more",
          11.0));
      break;
    }
    const int w = complex.winding_number(c);
    svg.add("<rect x=\"" + num(legend_x) + "\" y=\"" + num(y - 10.0) +
            "\" width=\"12\" height=\"12\" fill=\"" + winding_fill(w, max_winding) +
            "\" stroke=\"#888\"/>");
    std::string patches;
    for (const BPatch& b : complex.b_patches(c)) {
      if (patches.size() > 28) {
        patches += " ...";
        break;
      }
      if (!patches.empty()) patches += ' ';
      patches += 'P';
      patches += std::to_string(b.patch.value());
      if (!b.agrees) patches += '*';
    }
    svg.add(text_element(
        legend_x + 18.0, y,
        "C" + std::to_string(c.value()) + "   w=" + std::to_string(w) + "   " + patches, 11.0));
  }
  const double height = std::max(top + frame.height() + 2 * kMargin, y + kMargin);
  return svg.finish(legend_x + kLegendWidth, height);
}

std::string format_immersion_svg(const Complex2& c2, const Immersion& immersion,
                                 const SvgOptions& options) {
  const CellComplex<2>& complex = c2.complex;
  const NodeLayout& layout = immersion.layout;
  IMM_ASSERT(layout.node_count() >= complex.cell_count() || complex.cell_count() == 0,
             "immersion does not belong to this complex");
  std::vector<const std::vector<Point>*> lines;
  for (const Curve& c : c2.curves.curves) lines.push_back(&c.vertices);
  const double top = title_height(options);
  const double shift = 7.0;  // SVG units between consecutive copies of one cell
  int max_copies = 1;
  for (CellId c : ids<CellId>(complex.cell_count()))
    max_copies = std::max(max_copies, complex.winding_number(c));
  const Frame frame(lines, options.width - shift * (max_copies - 1), top);
  SvgDocument svg;
  add_title(svg, options);

  auto offset = [&](NodeId n) { return shift * layout.copy(n); };
  auto colour = [&](NodeId n) { return kPalette[n.index() % kPaletteSize]; };
  auto anchor = [&](NodeId n) {
    const Point& p = c2.region_sample[complex.region_of(layout.cell(n))];
    return std::pair<double, double>{frame.x(p) + offset(n), frame.y(p) + offset(n)};
  };

  // The curves, faintly, as the reference.
  for (const Curve& c : c2.curves.curves) {
    svg.add("<polygon points=\"" + polyline_points(frame, c.vertices) +
            "\" fill=\"none\" stroke=\"#bbb\" stroke-width=\"0.8\"/>");
  }
  // Nodes: the cell's region, filled in the node's colour; copies shifted diagonally.
  for (NodeId n : ids<NodeId>(layout.node_count())) {
    const RegionId r = complex.region_of(layout.cell(n));
    svg.add("<path d=\"" + loops_path(frame, c2.region_boundary[r], offset(n), offset(n)) +
            "\" fill=\"" + colour(n) +
            "\" fill-opacity=\"0.30\" fill-rule=\"evenodd\" stroke=\"none\"/>");
  }
  // B-patches per node: owned solid, declined dashed.
  for (NodeId n : ids<NodeId>(layout.node_count())) {
    for (const BPatch& b : complex.b_patches(layout.cell(n))) {
      const bool owned = immersion.owner[b.patch] == n;
      svg.add("<polyline points=\"" +
              polyline_points(frame, c2.patch_polyline[b.patch], offset(n), offset(n)) +
              "\" fill=\"none\" stroke=\"" + colour(n) + "\" stroke-width=\"" +
              (owned ? "2.4" : "1.2") + "\"" + (owned ? "" : " stroke-dasharray=\"5 4\"") +
              " stroke-linejoin=\"round\"/>");
    }
  }
  // Graph edges: a short stitch across the middle of the patch, from the inner node's copy (on
  // the patch's left, the inner side) to the outer node's copy (on its right), with a dot at
  // each end in the node's colour. Several edges across one patch fan out along it.
  std::vector<int> edges_on_patch(complex.patch_count(), 0);
  for (const ImmersionEdge& e : immersion.edges) {
    const std::vector<Point>& line = c2.patch_polyline[e.patch];
    const int rank = edges_on_patch[e.patch.index()]++;
    const double t = 0.5 + 0.08 * ((rank + 1) / 2) * (rank % 2 == 0 ? 1.0 : -1.0);
    const Point at = point_along(line, std::clamp(t, 0.1, 0.9));
    const Point ahead = point_along(line, std::clamp(t + 0.01, 0.0, 1.0));
    const Point behind = point_along(line, std::clamp(t - 0.01, 0.0, 1.0));
    double tx = frame.x(ahead) - frame.x(behind), ty = frame.y(ahead) - frame.y(behind);
    const double length = std::hypot(tx, ty);
    if (length > 0.0) {
      tx /= length;
      ty /= length;
    }
    // The curve's left in world coordinates is (-ty, tx) there; SVG flips y, so it is (ty, -tx).
    const double lx = ty, ly = -tx, reach = 9.0;
    const double ax = frame.x(at) + lx * reach + offset(e.inner),
                 ay = frame.y(at) + ly * reach + offset(e.inner);
    const double bx = frame.x(at) - lx * reach + offset(e.outer),
                 by = frame.y(at) - ly * reach + offset(e.outer);
    svg.add("<line x1=\"" + num(ax) + "\" y1=\"" + num(ay) + "\" x2=\"" + num(bx) + "\" y2=\"" +
            num(by) + "\" stroke=\"#222\" stroke-width=\"1\"/>");
    svg.add("<circle cx=\"" + num(ax) + "\" cy=\"" + num(ay) + "\" r=\"2\" fill=\"" +
            colour(e.inner) + "\"/>");
    svg.add("<circle cx=\"" + num(bx) + "\" cy=\"" + num(by) + "\" r=\"2\" fill=\"" +
            colour(e.outer) + "\"/>");
  }
  for (NodeId n : ids<NodeId>(layout.node_count())) {
    const auto [x, y] = anchor(n);
    svg.add("<circle cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"3\" fill=\"" + colour(n) +
            "\" stroke=\"#222\" stroke-width=\"0.6\"/>");
    if (options.labels) {
      svg.add(text_element(
          x + 4.0, y - 4.0,
          "C" + std::to_string(layout.cell(n).value()) + "." + std::to_string(layout.copy(n)),
          10.0));
    }
  }

  // Legend: nodes (cell, copy, winding) with their colour, then the graph's components.
  const double legend_x = frame.width() + shift * (max_copies - 1) + 2 * kMargin;
  double y = top + kMargin + 4.0;
  svg.add(text_element(legend_x, y, "node = cell.copy (winding); solid: owned, dashed: declined",
                       10.0));
  std::size_t rows = 0;
  for (NodeId n : ids<NodeId>(layout.node_count())) {
    y += kLegendLine;
    if (++rows > kMaxLegendRows) {
      svg.add(text_element(
          legend_x, y, "... and " + std::to_string(layout.node_count() - kMaxLegendRows) + " more",
          11.0));
      break;
    }
    const CellId c = layout.cell(n);
    std::string owned;
    for (const BPatch& b : complex.b_patches(c)) {
      if (immersion.owner[b.patch] != n) continue;
      if (owned.size() > 24) {
        owned += " ...";
        break;
      }
      if (!owned.empty()) owned += ' ';
      owned += 'P';
      owned += std::to_string(b.patch.value());
    }
    svg.add("<rect x=\"" + num(legend_x) + "\" y=\"" + num(y - 10.0) +
            "\" width=\"12\" height=\"12\" fill=\"" + colour(n) +
            "\" fill-opacity=\"0.6\" stroke=\"#444\"/>");
    svg.add(text_element(legend_x + 18.0, y,
                         "node " + std::to_string(n.value()) + ": C" + std::to_string(c.value()) +
                             "." + std::to_string(layout.copy(n)) +
                             " (w=" + std::to_string(complex.winding_number(c)) + ")" +
                             (owned.empty() ? "" : "  owns " + owned),
                         11.0));
  }
  const auto components = immersion.components();
  y += kLegendLine * 1.5;
  svg.add(text_element(legend_x, y,
                       std::to_string(components.size()) + " connected component" +
                           (components.size() == 1 ? "" : "s") + ", " +
                           std::to_string(immersion.edges.size()) + " edges",
                       11.0));
  const double height =
      std::max(top + frame.height() + shift * (max_copies - 1) + 2 * kMargin, y + kMargin);
  return svg.finish(legend_x + kLegendWidth + 60.0, height);
}

}  // namespace imm::dim2
