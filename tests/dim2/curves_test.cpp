// Readers (text, SVG, OBJ), the text writer and arrangement-free validation of 2D curve sets.
// Every bad-input class of issue 2 is checked for its defect kind and for a message that names
// the ids and coordinates involved (DESIGN §3: exit 2 "with a message naming the defect").
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "dim2/curves.h"

namespace imm::dim2 {
namespace {

std::string write_temp(const std::string& name, const std::string& contents) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "imm_curves_test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path path = dir / name;
  std::ofstream(path, std::ios::binary) << contents;
  return path.string();
}

std::vector<Point> pts(std::initializer_list<Point> list) { return list; }

/// The single defect of a report, with a readable failure otherwise.
const Defect& only_defect(const ValidationReport& report) {
  EXPECT_EQ(report.defects.size(), 1u) << report.summary();
  static const Defect kNone{DefectKind::Empty, "", "<no defect>", {}, {}, {}};
  return report.defects.empty() ? kNone : report.defects.front();
}

bool has_kind(const ValidationReport& report, DefectKind kind) {
  for (const Defect& d : report.defects) {
    if (d.kind == kind) return true;
  }
  return false;
}

// ---- text format --------------------------------------------------------------------------

TEST(CurvesText, ParsesCurvesCommentsAndBlankLines) {
  const ReadResult r = parse_curves_text(
      "# two squares\n"
      "0 0\n"
      "4 0   # a comment after a vertex\n"
      "4 4\n"
      "# a comment line does not end the curve\n"
      "0 4\n"
      "\n"
      "\n"
      "10 10\n"
      "12 10\n"
      "12 12\n");
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  ASSERT_EQ(r.curves.curves.size(), 2u);
  EXPECT_EQ(r.curves.curves[0].vertices, pts({{0, 0}, {4, 0}, {4, 4}, {0, 4}}));
  EXPECT_EQ(r.curves.curves[1].vertices, pts({{10, 10}, {12, 10}, {12, 12}}));
  EXPECT_EQ(r.curves.vertex_count(), 7u);
}

TEST(CurvesText, ExplicitlyClosedCurveDropsRepeatedLastVertex) {
  const ReadResult r = parse_curves_text("0 0\n1 0\n1 1\n0 0\n");
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.curves.curves.at(0).vertices, pts({{0, 0}, {1, 0}, {1, 1}}));
}

TEST(CurvesText, RoundTripsExactly) {
  CurveSet set;
  set.curves.push_back({pts({{0.1, -0.2}, {1e-300, 3.0}, {123456.789, 1.0 / 3.0}, {-5e20, 2.5}})});
  set.curves.push_back({pts({{std::nextafter(1.0, 2.0), 0}, {7, 7}, {0, 9}})});
  const std::string text = format_curves_text(set);
  const ReadResult back = parse_curves_text(text);
  ASSERT_TRUE(back.report.ok()) << back.report.summary();
  ASSERT_EQ(back.curves.curves.size(), set.curves.size());
  for (std::size_t c = 0; c < set.curves.size(); ++c) {
    EXPECT_EQ(back.curves.curves[c].vertices, set.curves[c].vertices) << text;
  }
  EXPECT_EQ(format_curves_text(back.curves), text);
}

TEST(CurvesText, ParseErrorNamesTheLine) {
  const ReadResult r = parse_curves_text("0 0\n1 0\n1 one\n0 1\n");
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::Unreadable);
  EXPECT_NE(d.message.find("line 3"), std::string::npos) << d.message;
}

TEST(CurvesText, ThreeNumbersOnALineIsAnError) {
  const ReadResult r = parse_curves_text("0 0 0\n1 0\n0 1\n");
  EXPECT_EQ(only_defect(r.report).kind, DefectKind::Unreadable);
}

TEST(CurvesFile, MissingFileIsUnreadable) {
  const ReadResult r = read_curves("/nonexistent/dir/curve.txt");
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::Unreadable);
  EXPECT_NE(d.message.find("/nonexistent/dir/curve.txt"), std::string::npos) << d.message;
}

TEST(CurvesFile, DirectoryIsUnreadable) {
  const ReadResult r = read_curves(testing::TempDir());
  ASSERT_FALSE(r.report.ok());
  EXPECT_EQ(r.report.defects.front().kind, DefectKind::Unreadable);
}

TEST(CurvesFile, EmptyFileIsEmpty) {
  EXPECT_EQ(only_defect(read_curves(write_temp("empty.txt", "")).report).kind, DefectKind::Empty);
  EXPECT_EQ(only_defect(read_curves(write_temp("comments.txt", "# nothing\n\n# here\n")).report).kind,
            DefectKind::Empty);
  EXPECT_EQ(only_defect(read_curves(write_temp("empty.svg", "<svg></svg>")).report).kind, DefectKind::Empty);
  EXPECT_EQ(only_defect(read_curves(write_temp("empty.obj", "v 0 0 0\n")).report).kind, DefectKind::Empty);
}

TEST(CurvesFile, TextFileRoundTrip) {
  CurveSet set;
  set.curves.push_back({pts({{0, 0}, {3, 0}, {0, 3}})});
  const ReadResult r = read_curves(write_temp("tri.txt", format_curves_text(set)));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.curves.curves.at(0).vertices, set.curves[0].vertices);
}

// ---- SVG ------------------------------------------------------------------------------------

TEST(CurvesSvg, ReadsPolygonPolylineAndPath) {
  const std::string svg = R"(<?xml version="1.0"?>
<!-- <polygon points="9 9 9 9"/> inside a comment is ignored -->
<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
  <polygon points="0,0 10,0 10,10 0,10" fill="none"/>
  <polyline points="20 0, 30 0, 30 10, 20 0"/>
  <g><path id="p" d="M 40 0 L 50 0 50 10 Z m 20 0 h 10 v 10 h -10 z M1e1-5L.5.5 8 8"/></g>
  <svg:path d='m 100 100 l 5 0 l 0 5'/>
</svg>)";
  const ReadResult r = read_curves(write_temp("shapes.svg", svg));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  ASSERT_EQ(r.curves.curves.size(), 6u);
  EXPECT_EQ(r.curves.curves[0].vertices, pts({{0, 0}, {10, 0}, {10, 10}, {0, 10}}));
  // The polyline is closed; its explicit closing vertex is dropped.
  EXPECT_EQ(r.curves.curves[1].vertices, pts({{20, 0}, {30, 0}, {30, 10}}));
  EXPECT_EQ(r.curves.curves[2].vertices, pts({{40, 0}, {50, 0}, {50, 10}}));
  // Relative moveto after Z starts from the closed subpath's start (40, 0).
  EXPECT_EQ(r.curves.curves[3].vertices, pts({{60, 0}, {70, 0}, {70, 10}, {60, 10}}));
  // Compact number syntax: "1e1-5" is (10, -5), ".5.5" is (0.5, 0.5).
  EXPECT_EQ(r.curves.curves[4].vertices, pts({{10, -5}, {0.5, 0.5}, {8, 8}}));
  EXPECT_EQ(r.curves.curves[5].vertices, pts({{100, 100}, {105, 100}, {105, 105}}));
}

TEST(CurvesSvg, CurvedPathCommandIsADefectNamingTheElement) {
  const std::string svg = R"(<svg>
<polygon points="0 0 1 0 1 1"/>
<path id="blob" d="M 0 0 C 1 1 2 2 3 0 Z"/>
</svg>)";
  const ReadResult r = read_curves(write_temp("curved.svg", svg));
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::Unreadable);
  EXPECT_NE(d.message.find("<path> element 1"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("blob"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("line 3"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("'C'"), std::string::npos) << d.message;
}

TEST(CurvesSvg, CircleIsADefect) {
  const ReadResult r = read_curves(write_temp("circle.svg", "<svg><circle cx='1' cy='1' r='2'/></svg>"));
  EXPECT_EQ(only_defect(r.report).kind, DefectKind::Unreadable);
}

TEST(CurvesSvg, ZeroLengthPathSegmentIsADefect) {
  const ReadResult r = read_curves(write_temp("zero.svg", "<svg><path d='M 0 0 l 4 0 l 0 0 l 0 4 z'/></svg>"));
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::DuplicateVertex);
  EXPECT_NE(d.message.find("vertices 1 and 2"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("(4, 0)"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("zero length"), std::string::npos) << d.message;
}

TEST(CurvesSvg, OddNumberOfCoordinatesIsUnreadable) {
  const ReadResult r = read_curves(write_temp("odd.svg", "<svg><polygon points='0 0 1 0 1'/></svg>"));
  EXPECT_EQ(only_defect(r.report).kind, DefectKind::Unreadable);
}

// ---- OBJ ------------------------------------------------------------------------------------

TEST(CurvesObj, ReadsLoopsWithNegativeIndicesAndIgnoresZ) {
  const std::string obj =
      "# a square and a triangle\n"
      "o curves\n"
      "v 0 0 5\n"
      "v 4 0 5\n"
      "v 4 4 5\n"
      "v 0 4\n"
      "l 1 2 3\n"
      "l 3 4 1\n"
      "v 10 10 0\n"
      "v 12 10 0\n"
      "v 12 12 0\n"
      "l -3 -2 -1 -3\n";
  const ReadResult r = read_curves(write_temp("loops.obj", obj));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  ASSERT_EQ(r.curves.curves.size(), 2u);
  EXPECT_EQ(r.curves.curves[0].vertices, pts({{0, 0}, {4, 0}, {4, 4}, {0, 4}}));
  EXPECT_EQ(r.curves.curves[1].vertices, pts({{10, 10}, {12, 10}, {12, 12}}));
}

TEST(CurvesObj, SegmentPairsChainIntoALoop) {
  const ReadResult r = read_curves(write_temp("pairs.obj", "v 0 0\nv 1 0\nv 1 1\nl 2 3\nl 1 2\nl 3 1\n"));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  ASSERT_EQ(r.curves.curves.size(), 1u);
  EXPECT_EQ(r.curves.curves[0].vertices, pts({{1, 0}, {1, 1}, {0, 0}}));
}

TEST(CurvesObj, OpenCurveIsNotClosed) {
  const ReadResult r = read_curves(write_temp("open.obj", "v 0 0\nv 1 0\nv 1 1\nv 7 8\nl 1 2 3 4\n"));
  ASSERT_EQ(r.report.defects.size(), 2u) << r.report.summary();
  for (const Defect& d : r.report.defects) EXPECT_EQ(d.kind, DefectKind::NotClosed);
  EXPECT_NE(r.report.defects[0].message.find("vertex 1 (0, 0)"), std::string::npos) << r.report.summary();
  EXPECT_NE(r.report.defects[1].message.find("vertex 4 (7, 8)"), std::string::npos) << r.report.summary();
}

TEST(CurvesObj, BadIndexIsUnreadable) {
  const ReadResult r = read_curves(write_temp("bad.obj", "v 0 0\nv 1 0\nl 1 2 9\n"));
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::Unreadable);
  EXPECT_NE(d.message.find("line 3"), std::string::npos) << d.message;
}

TEST(CurvesObj, RepeatedIndexIsAZeroLengthSegment) {
  const ReadResult r = read_curves(write_temp("rep.obj", "v 0 0\nv 1 0\nv 1 1\nl 1 2 2 3 1\n"));
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::DuplicateVertex);
  EXPECT_NE(d.message.find("vertex 2 (1, 0)"), std::string::npos) << d.message;
}

// ---- round trips through every format ---------------------------------------------------------

CurveSet awkward_curves() {
  CurveSet set;
  set.curves.push_back({pts({{0.1, -0.2}, {1e-300, 3.0}, {123456.789, 1.0 / 3.0}, {-5e20, 2.5}})});
  set.curves.push_back({pts({{std::nextafter(1.0, 2.0), 0}, {7, 7}, {-0.5, 9e-7}})});
  return set;
}

TEST(CurvesRoundTrip, SvgPolygonsAndPaths) {
  const CurveSet set = awkward_curves();
  std::string polygons = "<svg xmlns=\"http://www.w3.org/2000/svg\">\n";
  std::string paths = polygons;
  for (const Curve& c : set.curves) {
    polygons += "<polygon points=\"";
    paths += "<path d=\"M";
    for (const Point& p : c.vertices) {
      polygons += format_number(p.x) + "," + format_number(p.y) + " ";
      paths.append(" ").append(format_number(p.x)).append(" ").append(format_number(p.y));
    }
    polygons += "\"/>\n";
    paths += " Z\"/>\n";
  }
  polygons += "</svg>\n";
  paths += "</svg>\n";
  for (const std::string& svg : {polygons, paths}) {
    const ReadResult r = read_curves(write_temp("round.svg", svg));
    ASSERT_TRUE(r.report.ok()) << r.report.summary() << svg;
    ASSERT_EQ(r.curves.curves.size(), set.curves.size());
    for (std::size_t c = 0; c < set.curves.size(); ++c) EXPECT_EQ(r.curves.curves[c].vertices, set.curves[c].vertices);
  }
}

TEST(CurvesRoundTrip, Obj) {
  const CurveSet set = awkward_curves();
  std::string obj;
  std::size_t base = 1;
  for (const Curve& c : set.curves) {
    for (const Point& p : c.vertices) obj += "v " + format_number(p.x) + " " + format_number(p.y) + " 0\n";
    obj += "l";
    for (std::size_t i = 0; i <= c.vertices.size(); ++i) obj.append(" ").append(std::to_string(base + i % c.vertices.size()));
    obj += "\n";
    base += c.vertices.size();
  }
  const ReadResult r = read_curves(write_temp("round.obj", obj));
  ASSERT_TRUE(r.report.ok()) << r.report.summary() << obj;
  ASSERT_EQ(r.curves.curves.size(), set.curves.size());
  for (std::size_t c = 0; c < set.curves.size(); ++c) EXPECT_EQ(r.curves.curves[c].vertices, set.curves[c].vertices);
}

// ---- validation -------------------------------------------------------------------------------

TEST(ValidateCurves, TooShortCurveNamesItsVertices) {
  const ReadResult r = parse_curves_text("0 0\n1 0\n1 1\n\n5 5\n6 7\n");
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::TooShort);
  EXPECT_NE(d.message.find("curve 1"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("3 (5, 5)"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("4 (6, 7)"), std::string::npos) << d.message;
  EXPECT_EQ(d.vertices, (std::vector<long>{3, 4}));
}

TEST(ValidateCurves, RepeatedConsecutiveVertex) {
  const ReadResult r = parse_curves_text("9 9\n8 9\n8 8\n\n0 0\n1 0\n1 0\n1 1\n");
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::DuplicateVertex);
  EXPECT_NE(d.message.find("curve 1"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("vertices 4 and 5"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("(1, 0)"), std::string::npos) << d.message;
  EXPECT_EQ(d.vertices, (std::vector<long>{4, 5}));
}

TEST(ValidateCurves, ClosingZeroLengthSegmentOfAProgrammaticCurve) {
  CurveSet set;
  set.curves.push_back({pts({{0, 0}, {1, 0}, {1, 1}, {0, 0}})});
  const ValidationReport report = validate_curves(set);
  const Defect& d = only_defect(report);
  EXPECT_EQ(d.kind, DefectKind::DuplicateVertex);
  EXPECT_NE(d.message.find("vertices 3 and 0"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("segment 3 has zero length"), std::string::npos) << d.message;
}

TEST(ValidateCurves, NonFiniteCoordinates) {
  const ReadResult r = parse_curves_text("0 0\nnan 1\n1 1\ninf 2\n1e999 3\n");
  ASSERT_EQ(r.report.defects.size(), 3u) << r.report.summary();
  for (const Defect& d : r.report.defects) EXPECT_EQ(d.kind, DefectKind::NonFinite);
  EXPECT_NE(r.report.defects[0].message.find("vertex 1 has a non-finite coordinate (nan, 1)"), std::string::npos)
      << r.report.summary();
  EXPECT_NE(r.report.defects[1].message.find("vertex 3"), std::string::npos) << r.report.summary();
  EXPECT_NE(r.report.defects[2].message.find("(inf, 3)"), std::string::npos) << r.report.summary();
}

TEST(ValidateCurves, AllCollinearCurveIsDegenerate) {
  const ReadResult r = parse_curves_text("0 0\n1 1\n3 3\n2 2\n");
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::DegenerateFacet);
  EXPECT_NE(d.message.find("curve 0"), std::string::npos) << d.message;
  EXPECT_NE(d.message.find("collinear"), std::string::npos) << d.message;
}

TEST(ValidateCurves, EmptySet) {
  EXPECT_EQ(only_defect(validate_curves(CurveSet{})).kind, DefectKind::Empty);
}

TEST(ValidateCurves, ReportsEveryDefect) {
  const ReadResult r = parse_curves_text("0 0\n0 0\n1 1\n\n2 2\n\n0 0\n1 0\nnan 2\n");
  EXPECT_TRUE(has_kind(r.report, DefectKind::DuplicateVertex)) << r.report.summary();
  EXPECT_TRUE(has_kind(r.report, DefectKind::TooShort)) << r.report.summary();
  EXPECT_TRUE(has_kind(r.report, DefectKind::NonFinite)) << r.report.summary();
}

TEST(ValidateCurves, ValidTriangle) {
  CurveSet set;
  set.curves.push_back({pts({{0, 0}, {1, 0}, {0, 1}})});
  EXPECT_TRUE(validate_curves(set).ok());
}

TEST(FormatNumber, ShortestRoundTrip) {
  EXPECT_EQ(format_number(1.0), "1");
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(-2.5), "-2.5");
  EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(format_point({381, 269}), "(381, 269)");
}

}  // namespace
}  // namespace imm::dim2
