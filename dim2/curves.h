// 2D input: closed polygonal curves, as read from a file, before any exact processing.
// CGAL-free: included by the CLI, the tests and the generators.
#pragma once

#include <string>
#include <vector>

#include "core/diagnostics.h"

namespace imm::dim2 {

struct Point {
  double x = 0.0;
  double y = 0.0;
  auto operator<=>(const Point&) const = default;
};

/// One closed curve: segment i joins vertices i and i+1 (mod n). Orientation = vertex order; a
/// counter-clockwise outer curve encloses winding number +1.
struct Curve {
  std::vector<Point> vertices;
};

/// Several closed curves (several components are valid input, paper §6.2).
struct CurveSet {
  std::vector<Curve> curves;

  [[nodiscard]] std::size_t vertex_count() const;
  [[nodiscard]] std::size_t segment_count() const { return vertex_count(); }
};

/// Input vertex / segment ids are global and 0-based in file order: curve 0's vertices first.
/// `segment i` joins global vertex i to the next vertex of the same curve.
struct CurveIndex {
  std::size_t curve;
  std::size_t local;
};

struct ReadResult {
  CurveSet curves;
  ValidationReport report;  ///< read errors (unreadable, non-finite, empty, ...)
};

/// Reads the 2D text format (DESIGN §3: `x y` per line, `#` comments, blank line ends a curve),
/// SVG (<polygon>, <polyline>, <path> with straight segments) or OBJ (`v`, `l`), chosen by the
/// file extension (.txt/.poly/.xy/other = text, .svg, .obj).
ReadResult read_curves(const std::string& path);

/// Parses the text format from a string (for tests and generators).
ReadResult parse_curves_text(const std::string& text);

/// Writes the text format, full double precision (round-trips exactly).
std::string format_curves_text(const CurveSet& curves);

/// Shortest decimal text that reads back as exactly `value` ("1", "0.1", "nan", "inf"); -0 is
/// written "0".
std::string format_number(double value);

/// "(x, y)" with format_number, for messages.
std::string format_point(const Point& p);

/// The checks that need no arrangement: empty input, fewer than 3 vertices, non-finite
/// coordinates, repeated consecutive vertices (zero-length segments), all-collinear curves.
/// Every defect names curve, vertex indices and coordinates.
ValidationReport validate_curves(const CurveSet& curves);

/// The largest absolute coordinate of a 2D input (validate_curves refuses larger ones with an
/// OutOfRange defect, exit 2). The decisions are exact at any size, but CGAL's interval filters
/// compute products of three coordinates in doubles: beyond about 5.6e102 they overflow to
/// infinite bounds and the arrangement sweep crashed (issue 13, at 1e102 on the fig6 curve). 1e75
/// keeps four-fold products finite, and is also the range of a generated background mesh.
/// Tiny coordinates have no such limit (an interval that underflows stays conservative).
inline constexpr double kMaxCoordinate2 = 1e75;

}  // namespace imm::dim2
