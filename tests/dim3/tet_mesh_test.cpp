// The tet-mesh layer: readers of Vega .veg, Medit .mesh and TetGen .node/.ele on small
// hand-written files, every defect class with its kind and message, large files read on several
// threads as on one (decorated text, line numbers, defects, CRLF), reorientation, round trips of
// the three writers (the .vtu one through a small XML reader written here, since read_tet_mesh
// does not take .vtu), the Kuhn grid background (exact orientation, conformity, exact volume,
// coverage) and the Vega background meshes of ../shared/data/real/tet with the counts of
// SOURCES.md.
#include "dim3/tet_mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>

namespace imm::dim3 {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

std::string temp_dir() {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "imm_tet_mesh_test";
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::string write_temp(const std::string& name, const std::string& contents) {
  const std::string path = temp_dir() + "/" + name;
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

Kernel::Point_3 point(const Point3& p) { return {p[0], p[1], p[2]}; }

CGAL::Orientation orientation(const TetMesh& mesh, const Tet& t) {
  return CGAL::orientation(point(mesh.vertices[t[0]]), point(mesh.vertices[t[1]]),
                           point(mesh.vertices[t[2]]), point(mesh.vertices[t[3]]));
}

/// Exact 6 x signed volume of a tet.
mpq_class six_volume(const TetMesh& mesh, const Tet& t) {
  auto q = [&](int k, int c) { return mpq_class(mesh.vertices[t[k]][c]); };
  mpq_class m[3][3];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[r][c] = q(r + 1, c) - q(0, c);
  }
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

void expect_all_positive(const TetMesh& mesh, const std::string& what) {
  std::size_t bad = 0;
  for (const Tet& t : mesh.tets) bad += orientation(mesh, t) != CGAL::POSITIVE;
  EXPECT_EQ(bad, 0u) << what << ": tets not positively oriented";
}

Defect only_defect(const ValidationReport& report) {
  EXPECT_EQ(report.defects.size(), 1u) << report.summary();
  EXPECT_EQ(report.unlisted, 0u);
  if (report.defects.empty()) return Defect{DefectKind::Empty, "", "(no defect)", {}, {}, {}};
  return report.defects.front();
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// ---- orientation convention
// ----------------------------------------------------------------------

TEST(TetOrientation, CgalPositiveIsPositiveDeterminant) {
  // det(e_x, e_y, e_z) = +1: the header's "positively oriented" is CGAL's POSITIVE.
  EXPECT_EQ(CGAL::orientation(Kernel::Point_3(0, 0, 0), Kernel::Point_3(1, 0, 0),
                              Kernel::Point_3(0, 1, 0), Kernel::Point_3(0, 0, 1)),
            CGAL::POSITIVE);
  TetMesh unit;
  unit.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_EQ(six_volume(unit, {0, 1, 2, 3}), 1);
}

// ---- Vega
// ----------------------------------------------------------------------------------------

// Vertices 1..5: the unit tet's corners and a fifth point below; two positive tets.
const char* kVeg = R"(# Vega mesh file.
# 5 vertices, 2 elements

*VERTICES
5 3 0 0
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5, 0.5, 0.5, -1   # commas separate, as Vega allows

*ELEMENTS
TET
2 4 0
1 1 2 3 4
2 1 3 2 5

*MATERIAL defaultMaterial
ENU, 1000, 1000000, 0.45

*SET someSet
1, 2

*REGION
allElements, defaultMaterial
)";

TEST(TetVeg, ReadsVerticesAndTetsAndSkipsMaterialSetRegion) {
  const TetReadResult r = read_tet_mesh(write_temp("two.veg", kVeg));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  ASSERT_EQ(r.mesh.vertices.size(), 5u);
  EXPECT_EQ(r.mesh.vertices[4], (Point3{0.5, 0.5, -1}));
  // (0, 2, 1, 4): det(e_y, e_x, (.5, .5, -1)) = +1 > 0, so tet 2 is positive as written.
  ASSERT_EQ(r.mesh.tets.size(), 2u);
  EXPECT_EQ(r.mesh.tets[0], (Tet{0, 1, 2, 3}));
  EXPECT_EQ(r.mesh.tets[1], (Tet{0, 2, 1, 4}));
  EXPECT_EQ(r.reoriented, 0u);
  EXPECT_EQ(r.mesh.reference, (std::vector<int>{0, 0}));
  expect_all_positive(r.mesh, "veg");
}

TEST(TetVeg, NegativeTetsAreTurnedBySwappingTheLastTwo) {
  const char* text = R"(*VERTICES
4 3 0 0
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
*ELEMENTS
TET
2 4 0
1 1 3 2 4
2 2 1 3 4
)";
  const TetReadResult r = read_tet_mesh(write_temp("negative.veg", text));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.reoriented, 2u);
  ASSERT_EQ(r.mesh.tets.size(), 2u);
  EXPECT_EQ(r.mesh.tets[0], (Tet{0, 2, 3, 1}));
  EXPECT_EQ(r.mesh.tets[1], (Tet{1, 0, 3, 2}));
  expect_all_positive(r.mesh, "turned");
}

TEST(TetVeg, IncludeAndOtherElementTypesAreUnreadable) {
  const TetReadResult include =
      read_tet_mesh(write_temp("include.veg", "*INCLUDE other.veg\n*VERTICES\n0 3 0 0\n"));
  const Defect& d = only_defect(include.report);
  EXPECT_EQ(d.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(d.message, "include.veg:1:")) << d.message;
  const TetReadResult cubic = read_tet_mesh(write_temp(
      "cubic.veg", "*VERTICES\n1 3 0 0\n1 0 0 0\n*ELEMENTS\nCUBIC\n1 8 0\n1 1 1 1 1 1 1 1 1\n"));
  const Defect& c = only_defect(cubic.report);
  EXPECT_EQ(c.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(c.message, ":5:") && contains(c.message, "'CUBIC'")) << c.message;
}

// ---- Medit
// ---------------------------------------------------------------------------------------

TEST(TetMedit, ReadsTetsAndReferencesAndSkipsOtherSections) {
  const char* text = R"(MeshVersionFormatted 2
# a comment
Dimension
3
Vertices
5
0 0 0 1
1 0 0 1
0 1 0 2
0 0 1 2
1 1 1 0
Corners
2
1 2
Edges
1
1 2 5
Triangles
2
1 2 3 4
1 3 4 4
Tetrahedra
2
1 2 3 4 7
2 4 3 5 9
RequiredVertices 1 1
Normals
1
0 0 1
End
)";
  const TetReadResult r = read_tet_mesh(write_temp("sections.mesh", text));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  ASSERT_EQ(r.mesh.vertices.size(), 5u);
  EXPECT_EQ(r.mesh.vertices[4], (Point3{1, 1, 1}));
  ASSERT_EQ(r.mesh.tets.size(), 2u);
  EXPECT_EQ(r.mesh.tets[0], (Tet{0, 1, 2, 3}));
  // (1, 3, 2, 4): det((-1, 0, 1), (-1, 1, 0), (0, 1, 1)) = -2 < 0: turned.
  EXPECT_EQ(r.mesh.tets[1], (Tet{1, 3, 4, 2}));
  EXPECT_EQ(r.reoriented, 1u);
  EXPECT_EQ(r.mesh.reference, (std::vector<int>{7, 9}));
  expect_all_positive(r.mesh, "medit");
}

TEST(TetMedit, TwoDimensionalMeshIsUnreadable) {
  const TetReadResult r = read_tet_mesh(
      write_temp("flat.mesh", "MeshVersionFormatted 1\nDimension 2\nVertices\n0\nEnd\n"));
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(d.message, "flat.mesh:2:") && contains(d.message, "Dimension 3"))
      << d.message;
}

// ---- TetGen
// --------------------------------------------------------------------------------------

TEST(TetTetGen, ZeroBasedWithAttributesBoundaryMarkersAndRegions) {
  write_temp("zero.node",
             "# TetGen\n5 3 1 1\n0 0 0 0 7.5 1\n1 1 0 0 7.5 1\n2 0 1 0 7.5 0\n3 0 0 1 7.5 1\n"
             "4 1 1 1 7.5 1\n");
  write_temp("zero.ele", "2 4 1\n0 0 1 2 3 3\n1 1 3 2 4 5\n");
  for (const char* name : {"zero.node", "zero.ele"}) {
    SCOPED_TRACE(name);
    const TetReadResult r = read_tet_mesh(temp_dir() + "/" + name);
    ASSERT_TRUE(r.report.ok()) << r.report.summary();
    ASSERT_EQ(r.mesh.vertices.size(), 5u);
    EXPECT_EQ(r.mesh.vertices[3], (Point3{0, 0, 1}));
    ASSERT_EQ(r.mesh.tets.size(), 2u);
    EXPECT_EQ(r.mesh.tets[0], (Tet{0, 1, 2, 3}));
    EXPECT_EQ(r.mesh.tets[1], (Tet{1, 3, 4, 2}));
    EXPECT_EQ(r.reoriented, 1u);
    EXPECT_EQ(r.mesh.reference, (std::vector<int>{3, 5}));
  }
}

TEST(TetTetGen, OneBasedWithoutAttributes) {
  write_temp("one.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
  write_temp("one.ele", "1 4 0\n1 1 2 3 4\n");
  const TetReadResult r = read_tet_mesh(temp_dir() + "/one.ele");
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  ASSERT_EQ(r.mesh.tets.size(), 1u);
  EXPECT_EQ(r.mesh.tets[0], (Tet{0, 1, 2, 3}));
  EXPECT_EQ(r.mesh.reference, (std::vector<int>{0}));
}

TEST(TetTetGen, QuadraticTetsKeepTheirCorners) {
  write_temp("quadratic.node", "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 0.5 0 0\n");
  write_temp("quadratic.ele", "1 10 0\n1 1 2 3 4 5 5 5 5 5 5\n");
  const TetReadResult r = read_tet_mesh(temp_dir() + "/quadratic.ele");
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  ASSERT_EQ(r.mesh.tets.size(), 1u);
  EXPECT_EQ(r.mesh.tets[0], (Tet{0, 1, 2, 3}));
}

// Face pairing numbers faces 4 t + f in 32 bits: a background of 2^30 tets or more would
// overflow it, so its file is refused at the header, before any record is read (no memory).
TEST(TetTetGen, MoreTetsThanTheMesherTakesAreRefusedAtTheHeader) {
  write_temp("huge.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
  write_temp("huge.ele", "1073741824 4 0\n1 1 2 3 4\n");
  const TetReadResult r = read_tet_mesh(temp_dir() + "/huge.ele");
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(d.message, "1073741824 tets, more than the 1073741823")) << d.message;
  // One tet fewer passes the header: the file is then only truncated.
  write_temp("huge.ele", "1073741823 4 0\n1 1 2 3 4\n");
  const TetReadResult at_limit = read_tet_mesh(temp_dir() + "/huge.ele");
  const Defect& truncated = only_defect(at_limit.report);
  EXPECT_FALSE(contains(truncated.message, "more than")) << truncated.message;
}

TEST(TetTetGen, MissingSiblingIsUnreadableAndNamed) {
  write_temp("alone.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
  const TetReadResult r = read_tet_mesh(temp_dir() + "/alone.node");
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(d.message, "alone.ele")) << d.message;
}

// ---- defects
// -------------------------------------------------------------------------------------

std::string veg(const std::string& vertices, int n, const std::string& tets, int m) {
  return "*VERTICES\n" + std::to_string(n) + " 3 0 0\n" + vertices + "*ELEMENTS\nTET\n" +
         std::to_string(m) + " 4 0\n" + tets;
}

const std::string kUnitVertices = "1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";

TEST(TetDefects, NonFiniteCoordinateNamesVertexLineAndValue) {
  const TetReadResult r = read_tet_mesh(
      write_temp("nan.veg", veg("1 0 0 0\n2 1 0 0\n3 0 nan 0\n4 0 0 inf\n", 4, "1 1 2 3 4\n", 1)));
  ASSERT_EQ(r.report.defects.size(), 2u) << r.report.summary();
  const Defect& d = r.report.defects[0];
  EXPECT_EQ(d.kind, DefectKind::NonFinite);
  EXPECT_EQ(d.stage, "background");
  EXPECT_EQ(d.vertices, (std::vector<long>{2}));
  EXPECT_TRUE(contains(d.message, "nan.veg:5:") && contains(d.message, "vertex 2") &&
              contains(d.message, "nan"))
      << d.message;
  EXPECT_TRUE(contains(r.report.defects[1].message, "inf")) << r.report.defects[1].message;
  EXPECT_TRUE(r.mesh.tets.empty());  // the tet using them is left out, not oriented
}

TEST(TetDefects, IndexOutOfRangeNamesTetAndFileNumber) {
  const TetReadResult r =
      read_tet_mesh(write_temp("range.veg", veg(kUnitVertices, 4, "1 1 2 3 4\n2 1 2 3 9\n", 2)));
  const Defect& d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::OutOfRange);
  EXPECT_EQ(d.facets, (std::vector<long>{1}));
  EXPECT_TRUE(contains(d.message, "range.veg:11:") && contains(d.message, "tet 1") &&
              contains(d.message, "vertex 9") && contains(d.message, "1..4"))
      << d.message;
  EXPECT_EQ(r.mesh.tets.size(), 1u);
}

TEST(TetDefects, ZeroVolumeTetsNameTetVerticesAndCoordinates) {
  const TetReadResult r = read_tet_mesh(write_temp(
      "flat.veg", veg(kUnitVertices + "5 1 1 0\n", 5, "1 1 2 3 5\n2 1 2 2 4\n3 1 2 3 4\n", 3)));
  ASSERT_EQ(r.report.defects.size(), 2u) << r.report.summary();
  const Defect& coplanar = r.report.defects[0];
  EXPECT_EQ(coplanar.kind, DefectKind::DegenerateFacet);
  EXPECT_EQ(coplanar.facets, (std::vector<long>{0}));
  EXPECT_EQ(coplanar.vertices, (std::vector<long>{0, 1, 2, 4}));
  ASSERT_EQ(coplanar.points.size(), 4u);
  EXPECT_EQ(coplanar.points[3], (std::vector<double>{1, 1, 0}));
  EXPECT_TRUE(contains(coplanar.message, "tet 0") && contains(coplanar.message, "coplanar") &&
              contains(coplanar.message, "4 (1, 1, 0)"))
      << coplanar.message;
  const Defect& repeated = r.report.defects[1];
  EXPECT_EQ(repeated.kind, DefectKind::DegenerateFacet);
  EXPECT_TRUE(contains(repeated.message, "tet 1") && contains(repeated.message, "repeated"))
      << repeated.message;
  ASSERT_EQ(r.mesh.tets.size(), 1u);
  EXPECT_EQ(r.mesh.tets[0], (Tet{0, 1, 2, 3}));
}

TEST(TetDefects, ZeroVolumeOnlyExactly) {
  // The fourth corner 1e-300 above the plane: positive for the exact predicate.
  const TetReadResult r = read_tet_mesh(write_temp(
      "thin.veg", veg("1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0.3 0.3 1e-300\n", 4, "1 1 2 3 4\n", 1)));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.mesh.tets.size(), 1u);
  expect_all_positive(r.mesh, "thin");
}

TEST(TetDefects, ListsTwentyPerKindAndCountsTheRest) {
  std::string tets;
  for (int t = 1; t <= 25; ++t) tets += std::to_string(t) + " 1 1 2 3\n";
  const TetReadResult r = read_tet_mesh(write_temp("many.veg", veg(kUnitVertices, 4, tets, 25)));
  EXPECT_EQ(r.report.defects.size(), 20u);
  EXPECT_EQ(r.report.unlisted, 5u);
  EXPECT_EQ(r.report.total(), 25u);
  for (const Defect& d : r.report.defects) EXPECT_EQ(d.kind, DefectKind::DegenerateFacet);
  EXPECT_TRUE(contains(r.report.summary(), "5 more")) << r.report.summary();
}

TEST(TetDefects, EmptyMeshes) {
  const Defect& no_tets =
      only_defect(read_tet_mesh(write_temp("notets.veg", veg(kUnitVertices, 4, "", 0))).report);
  EXPECT_EQ(no_tets.kind, DefectKind::Empty);
  EXPECT_TRUE(contains(no_tets.message, "4 vertices, 0 tets")) << no_tets.message;
  const Defect& no_section = only_defect(
      read_tet_mesh(write_temp("nosection.veg", "*VERTICES\n1 3 0 0\n1 0 0 0\n")).report);
  EXPECT_EQ(no_section.kind, DefectKind::Empty);
  EXPECT_TRUE(contains(no_section.message, "*ELEMENTS")) << no_section.message;
  EXPECT_EQ(only_defect(read_tet_mesh(write_temp("empty.mesh", "")).report).kind,
            DefectKind::Empty);
}

TEST(TetDefects, UnreadableFilesNameFileAndLine) {
  EXPECT_EQ(only_defect(read_tet_mesh(temp_dir() + "/absent.veg").report).kind,
            DefectKind::Unreadable);
  const Defect& extension = only_defect(read_tet_mesh(write_temp("mesh.obj", "")).report);
  EXPECT_EQ(extension.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(extension.message, ".obj")) << extension.message;
  // A non-number in a vertex line.
  const Defect& garbage = only_defect(
      read_tet_mesh(write_temp("garbage.veg", veg("1 0 0 0\n2 1 x 0\n", 2, "", 0))).report);
  EXPECT_EQ(garbage.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(garbage.message, "garbage.veg:4:")) << garbage.message;
  // Fewer tets than announced.
  const Defect& short_file = only_defect(
      read_tet_mesh(write_temp("short.mesh",
                               "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n"
                               "1 0 0 0\n0 1 0 0\n0 0 1 0\nTetrahedra\n3\n1 2 3 4 0\n"))
          .report);
  EXPECT_EQ(short_file.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(short_file.message, "after 1 of the 3 tets")) << short_file.message;
  // TetGen numbering that is not consecutive.
  write_temp("gap.node", "2 3 0 0\n0 0 0 0\n2 1 0 0\n");
  write_temp("gap.ele", "0 4 0\n");
  const Defect& gap = only_defect(read_tet_mesh(temp_dir() + "/gap.node").report);
  EXPECT_EQ(gap.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(gap.message, "gap.node:3:")) << gap.message;
}

// ---- large files, read on several threads
// -------------------------------------------------------------------------

/// A Vega text of `mesh` decorated the ways a file may be: comment lines, blank lines, lines of
/// separators only, commas, trailing comments; `line_of_tet[t]` is the line (1-based) of tet t's record,
/// counted here as the text is written, independently of the reader.
std::string decorated_veg(const TetMesh& mesh, std::vector<std::size_t>& line_of_tet, unsigned seed) {
  std::mt19937 random(seed);
  std::string text;
  std::size_t line = 1;
  const auto put = [&](const std::string& s) {
    text += s;
    line += static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
  };
  const auto noise = [&] {
    switch (random() % 16) {
      case 0: put("# a comment line, 1 2 3 4\n"); break;
      case 1: put("\n"); break;
      case 2: put(" \t , \n"); break;
      case 3: put("   # indented comment\n"); break;
      default: break;
    }
  };
  const auto number = [](double x) {
    char buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof buffer, x).ptr;
    return std::string(buffer, end);
  };
  put("# Vega mesh file.\n*VERTICES\n" + std::to_string(mesh.vertices.size()) + " 3 0 0\n");
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    noise();
    const Point3& p = mesh.vertices[v];
    const char* separator = random() % 2 ? ", " : " \t";
    put(std::to_string(v + 1) + separator + number(p[0]) + separator + number(p[1]) + separator + number(p[2]) +
        (random() % 3 == 0 ? "#c\n" : "\n"));
  }
  put("\n*ELEMENTS\nTET\n" + std::to_string(mesh.tets.size()) + " 4 0\n");
  line_of_tet.assign(mesh.tets.size(), 0);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    noise();
    line_of_tet[t] = line;
    std::string record = std::to_string(t + 1);
    for (int k = 0; k < 4; ++k) record += (random() % 2 ? "," : " ") + std::to_string(mesh.tets[t][k] + 1);
    put(record + (random() % 4 == 0 ? "  # trailing\n" : "\n"));
  }
  put("*MATERIAL defaultMaterial\nENU, 1000, 1000000, 0.45\n");
  return text;
}

void expect_same_read(const TetReadResult& a, const TetReadResult& b, const std::string& what) {
  EXPECT_EQ(a.mesh.vertices, b.mesh.vertices) << what;
  EXPECT_EQ(a.mesh.tets, b.mesh.tets) << what;
  EXPECT_EQ(a.mesh.reference, b.mesh.reference) << what;
  EXPECT_EQ(a.reoriented, b.reoriented) << what;
  EXPECT_EQ(a.report.summary(), b.report.summary()) << what;
  ASSERT_EQ(a.report.defects.size(), b.report.defects.size()) << what;
  for (std::size_t i = 0; i < a.report.defects.size(); ++i)
    EXPECT_EQ(a.report.defects[i].message, b.report.defects[i].message) << what;
}

// Files of more than a few thousand records are parsed on several threads, each chunk of the
// text from its own first line: the vertices, tets, line numbers in messages and every defect
// must be those of the one-thread reading (checked against the line numbers the writer counted).
TEST(TetLargeFiles, ReadOnSeveralThreadsAsOnOne) {
  const TetMesh grid = make_grid_background({{-1.0, 0.25, 0.0}, {2.0, 3.0 + 1.0 / 3, 2.9}}, 17);
  ASSERT_GT(grid.vertices.size(), 5000u);
  ASSERT_GT(grid.tets.size(), 20000u);
  for (const unsigned seed : {1u, 2u}) {
    std::vector<std::size_t> line_of_tet;
    const std::string text = decorated_veg(grid, line_of_tet, seed);
    const std::string path = write_temp("large" + std::to_string(seed) + ".veg", text);
    const TetReadResult one = read_tet_mesh(path, 1);
    ASSERT_TRUE(one.report.ok()) << one.report.summary();
    EXPECT_EQ(one.mesh.vertices, grid.vertices);
    EXPECT_EQ(one.mesh.tets, grid.tets);
    for (const unsigned threads : {2u, 3u, 8u}) expect_same_read(one, read_tet_mesh(path, threads), path);
    // The same file with Windows line ends.
    std::string crlf;
    for (const char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    const std::string crlf_path = write_temp("large_crlf" + std::to_string(seed) + ".veg", crlf);
    const TetReadResult crlf_one = read_tet_mesh(crlf_path, 1);
    ASSERT_TRUE(crlf_one.report.ok()) << crlf_one.report.summary();
    EXPECT_EQ(crlf_one.mesh.vertices, grid.vertices);
    expect_same_read(crlf_one, read_tet_mesh(crlf_path, 3), crlf_path);
  }

  // Defects late in the file: a zero-volume tet and one out of range, named at their lines.
  TetMesh broken = grid;
  const std::size_t flat = 17001, outside = 19999;
  broken.tets[flat][3] = broken.tets[flat][0];
  broken.tets[outside][2] = static_cast<int>(grid.vertices.size());
  std::vector<std::size_t> line_of_tet;
  const std::string path = write_temp("large_defects.veg", decorated_veg(broken, line_of_tet, 3));
  const TetReadResult one = read_tet_mesh(path, 1);
  ASSERT_EQ(one.report.defects.size(), 2u) << one.report.summary();
  EXPECT_TRUE(contains(one.report.defects[0].message,
                       "large_defects.veg:" + std::to_string(line_of_tet[flat]) + ": tet " + std::to_string(flat)))
      << one.report.defects[0].message;
  EXPECT_TRUE(contains(one.report.defects[1].message,
                       "large_defects.veg:" + std::to_string(line_of_tet[outside]) + ": tet " + std::to_string(outside)))
      << one.report.defects[1].message;
  for (const unsigned threads : {2u, 3u}) expect_same_read(one, read_tet_mesh(path, threads), path);
}

TEST(TetLargeFiles, UnreadableRecordsAreReportedAsOnOneThread) {
  const TetMesh grid = make_grid_background({{0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}}, 17);
  ASSERT_GT(grid.tets.size(), 20000u);
  std::vector<std::size_t> line_of_tet;
  const std::string text = decorated_veg(grid, line_of_tet, 4);
  const auto replace_line = [&](std::size_t line, const std::string& with) {
    std::size_t begin = 0;
    for (std::size_t l = 1; l < line; ++l) begin = text.find('\n', begin) + 1;
    return text.substr(0, begin) + with + text.substr(text.find('\n', begin));
  };
  struct Case {
    std::string name, text, expected;
  };
  const std::vector<Case> cases = {
      {"bad_tet.veg", replace_line(line_of_tet[15000], "15001 1 2 x 4"),
       "bad_tet.veg:" + std::to_string(line_of_tet[15000]) + ": expected tet 15000"},
      {"missing_corner.veg", replace_line(line_of_tet[20000], "20001 1 2 3"),
       "missing_corner.veg:" + std::to_string(line_of_tet[20000]) + ": expected tet 20000"},
      {"short.veg", text.substr(0, text.find('\n', text.find("*ELEMENTS")) + 1) + "TET\n30000 4 0\n1 1 2 3 4\n",
       "after 1 of the 30000 tets"},
      // One tet short: '*MATERIAL' is read where the last tet should be.
      {"missing_tet.veg", replace_line(line_of_tet.back(), ""), "expected tet " + std::to_string(grid.tets.size() - 1)},
  };
  for (const Case& c : cases) {
    const std::string path = write_temp(c.name, c.text);
    const TetReadResult one = read_tet_mesh(path, 1);
    const Defect& d = only_defect(one.report);
    EXPECT_EQ(d.kind, DefectKind::Unreadable) << c.name;
    EXPECT_TRUE(contains(d.message, c.expected)) << c.name << ": " << d.message;
    for (const unsigned threads : {2u, 3u}) expect_same_read(one, read_tet_mesh(path, threads), c.name);
  }
  // A vertex out of sequence in the middle of the vertex section (its record is the first line
  // starting with "4500" and a separator).
  std::string misnumbered = text;
  const std::size_t where = std::min(misnumbered.find("\n4500,"), misnumbered.find("\n4500 ")) + 1;
  ASSERT_LT(where, misnumbered.find("*ELEMENTS"));
  misnumbered[where + 3] = '1';  // 4500 -> 4501
  const std::size_t line = static_cast<std::size_t>(std::count(misnumbered.begin(), misnumbered.begin() + static_cast<long>(where), '\n')) + 1;
  const std::string path = write_temp("misnumbered.veg", misnumbered);
  const TetReadResult one = read_tet_mesh(path, 1);
  const Defect& d = only_defect(one.report);
  EXPECT_TRUE(contains(d.message, "misnumbered.veg:" + std::to_string(line) + ": expected vertex 4500")) << d.message;
  for (const unsigned threads : {2u, 3u}) expect_same_read(one, read_tet_mesh(path, threads), "misnumbered.veg");
}

TEST(TetLargeFiles, TetGenRegionsReadOnSeveralThreadsAsOnOne) {
  TetMesh grid = make_grid_background({{0.0, 0.0, 0.0}, {1.0, 1.1, 1.2}}, 17);
  ASSERT_GT(grid.vertices.size(), 5000u);
  ASSERT_GT(grid.tets.size(), 20000u);
  grid.reference.resize(grid.tets.size());
  for (std::size_t t = 0; t < grid.tets.size(); ++t) grid.reference[t] = static_cast<int>(t % 7) - 2;
  const TetGenTexts texts = format_tetgen(grid);
  write_temp("large.node", texts.node);
  const std::string ele = write_temp("large.ele", texts.ele);
  const TetReadResult one = read_tet_mesh(ele, 1);
  ASSERT_TRUE(one.report.ok()) << one.report.summary();
  EXPECT_EQ(one.mesh.reference, grid.reference);
  for (const unsigned threads : {2u, 3u}) expect_same_read(one, read_tet_mesh(ele, threads), ele);
}

// ---- writers
// -------------------------------------------------------------------------------------

/// A small mesh with coordinates that need all 17 digits, and references.
TetMesh sample_mesh() {
  TetMesh mesh = make_grid_background({{0.1, -1.0 / 3, 1e-7}, {1.7, 2.0 / 3, 0.9}}, 2);
  // Unused vertices (allowed) with hard numbers: 0.30000000000000004, a tiny and a subnormal one.
  mesh.vertices.push_back({0.1 + 0.2, -1e-300, 1.0 / 3});
  mesh.vertices.push_back({4.9406564584124654e-324, -0.0, 1.7976931348623157e308});
  mesh.reference.clear();
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    mesh.reference.push_back(static_cast<int>(t % 5) - 1);
  return mesh;
}

TEST(TetWriters, MeditRoundTripsExactly) {
  const TetMesh mesh = sample_mesh();
  const TetReadResult r = read_tet_mesh(write_temp("round.mesh", format_medit_3d(mesh)));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.mesh.vertices, mesh.vertices);
  EXPECT_EQ(r.mesh.tets, mesh.tets);
  EXPECT_EQ(r.mesh.reference, mesh.reference);
  EXPECT_EQ(r.reoriented, 0u);
}

TEST(TetWriters, VegRoundTripsExactly) {
  const TetMesh mesh = sample_mesh();
  const TetReadResult r = read_tet_mesh(write_temp("round.veg", format_veg(mesh)));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.mesh.vertices, mesh.vertices);
  EXPECT_EQ(r.mesh.tets, mesh.tets);
  EXPECT_EQ(r.reoriented, 0u);
}

/// The contents of the ASCII DataArray named `name`, as tokens.
std::vector<std::string> vtu_array(const std::string& xml, const std::string& name) {
  const std::size_t tag = xml.find("Name=\"" + name + "\"");
  if (tag == std::string::npos) return {};
  const std::size_t start = xml.find('>', tag) + 1;
  const std::size_t end = xml.find("</DataArray>", start);
  std::vector<std::string> tokens;
  std::size_t i = start;
  while (i < end) {
    while (i < end && std::isspace(static_cast<unsigned char>(xml[i]))) ++i;
    const std::size_t s = i;
    while (i < end && !std::isspace(static_cast<unsigned char>(xml[i]))) ++i;
    if (i > s) tokens.push_back(xml.substr(s, i - s));
  }
  return tokens;
}

template <class T>
T number(const std::string& token) {
  T value{};
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  EXPECT_TRUE(ec == std::errc() && ptr == token.data() + token.size()) << token;
  return value;
}

TEST(TetWriters, VtuHoldsPointsCellsAndReferencesExactly) {
  const TetMesh mesh = sample_mesh();
  const std::string xml = format_vtu(mesh);
  EXPECT_TRUE(contains(xml, "<VTKFile type=\"UnstructuredGrid\""));
  EXPECT_TRUE(contains(xml, "NumberOfPoints=\"" + std::to_string(mesh.vertices.size()) +
                                "\" NumberOfCells=\"" + std::to_string(mesh.tets.size()) + "\""));
  const auto points = vtu_array(xml, "Points");
  const auto connectivity = vtu_array(xml, "connectivity");
  const auto offsets = vtu_array(xml, "offsets");
  const auto types = vtu_array(xml, "types");
  const auto reference = vtu_array(xml, "reference");
  ASSERT_EQ(points.size(), 3 * mesh.vertices.size());
  ASSERT_EQ(connectivity.size(), 4 * mesh.tets.size());
  ASSERT_EQ(offsets.size(), mesh.tets.size());
  ASSERT_EQ(types.size(), mesh.tets.size());
  ASSERT_EQ(reference.size(), mesh.tets.size());
  TetMesh back;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    back.vertices.push_back({number<double>(points[3 * v]), number<double>(points[3 * v + 1]),
                             number<double>(points[3 * v + 2])});
  }
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    back.tets.push_back({number<int>(connectivity[4 * t]), number<int>(connectivity[4 * t + 1]),
                         number<int>(connectivity[4 * t + 2]),
                         number<int>(connectivity[4 * t + 3])});
    EXPECT_EQ(number<long>(offsets[t]), 4 * static_cast<long>(t + 1));
    EXPECT_EQ(types[t], "10");  // VTK_TETRA
    back.reference.push_back(number<int>(reference[t]));
  }
  EXPECT_EQ(back.vertices, mesh.vertices);
  EXPECT_EQ(back.tets, mesh.tets);
  EXPECT_EQ(back.reference, mesh.reference);
  // VTK's tetra has (v1 - v0) x (v2 - v0) pointing to v3: our positive orientation.
  expect_all_positive(back, "vtu");
}

TEST(TetWriters, MissingReferencesAreWrittenAsZero) {
  TetMesh mesh = sample_mesh();
  mesh.reference.clear();
  const TetReadResult r = read_tet_mesh(write_temp("noref.mesh", format_medit_3d(mesh)));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.mesh.reference, std::vector<int>(mesh.tets.size(), 0));
  for (const std::string& token : vtu_array(format_vtu(mesh), "reference")) EXPECT_EQ(token, "0");
}

TEST(TetIo, ExtensionsAnyCase) {
  for (const char* name : {"a.veg", "b.MESH", "c.node", "d.Ele"})
    EXPECT_TRUE(is_tet_mesh_extension(name)) << name;
  for (const char* name : {"a.vtu", "b.obj", "mesh", "c.meshb"})
    EXPECT_FALSE(is_tet_mesh_extension(name)) << name;
}

// ---- grid background
// -----------------------------------------------------------------------------

/// Sorted distinct coordinates of the mesh's vertices along `axis`.
std::vector<double> lattice(const TetMesh& mesh, int axis) {
  std::set<double> values;
  for (const Point3& p : mesh.vertices) values.insert(p[axis]);
  return {values.begin(), values.end()};
}

/// Checks everything the header promises about make_grid_background(box, resolution, attempt).
void check_grid(const Box3& box, int resolution, int attempt) {
  SCOPED_TRACE(testing::Message() << "resolution " << resolution << ", attempt " << attempt);
  const TetMesh mesh = make_grid_background(box, resolution, attempt);
  std::array<std::vector<double>, 3> axes;
  std::size_t cells = 1;
  for (int k = 0; k < 3; ++k) {
    axes[k] = lattice(mesh, k);
    ASSERT_GE(axes[k].size(), 2u);
    cells *= axes[k].size() - 1;
  }
  // One vertex per lattice point, 6 tets per cube.
  ASSERT_EQ(mesh.vertices.size(), axes[0].size() * axes[1].size() * axes[2].size());
  ASSERT_EQ(mesh.tets.size(), 6 * cells);
  std::set<Point3> distinct(mesh.vertices.begin(), mesh.vertices.end());
  EXPECT_EQ(distinct.size(), mesh.vertices.size());

  // Coverage with a margin of at least one cube of side h.
  double longest = 0;
  for (int k = 0; k < 3; ++k) longest = std::max(longest, box.hi[k] - box.lo[k]);
  const double h = longest / resolution;
  for (int k = 0; k < 3; ++k) {
    EXPECT_LE(axes[k].front(), box.lo[k] - h) << "axis " << k;
    EXPECT_GE(axes[k].back(), box.hi[k] + h) << "axis " << k;
    EXPECT_LT(axes[k].front(), box.lo[k] - h * 1.0001) << "the grid is shifted off the box";
    EXPECT_GT(axes[k].front(), box.lo[k] - 2 * h);  // the margin stays small
  }

  // Exact orientation and exact total volume = the grid box's volume.
  mpq_class total = 0;
  std::size_t not_positive = 0;
  for (const Tet& t : mesh.tets) {
    not_positive += orientation(mesh, t) != CGAL::POSITIVE;
    total += six_volume(mesh, t);
  }
  EXPECT_EQ(not_positive, 0u);
  mpq_class box_volume = 6;
  for (int k = 0; k < 3; ++k) box_volume *= mpq_class(axes[k].back()) - mpq_class(axes[k].front());
  EXPECT_EQ(total, box_volume);

  // Conformity: every face is shared by 2 tets with opposite orientations, or lies on the box.
  std::map<std::array<int, 3>, std::vector<std::array<int, 3>>> faces;
  for (const Tet& t : mesh.tets) {
    const std::array<std::array<int, 3>, 4> outward = {
        {{t[1], t[2], t[3]}, {t[0], t[3], t[2]}, {t[0], t[1], t[3]}, {t[0], t[2], t[1]}}};
    for (std::array<int, 3> f : outward) {
      std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
      std::array<int, 3> key = f;
      std::sort(key.begin(), key.end());
      faces[key].push_back(f);
    }
  }
  std::size_t boundary = 0, bad = 0;
  for (const auto& [key, sides] : faces) {
    if (sides.size() == 2) {
      const auto& a = sides[0];
      const auto& b = sides[1];
      bad += !(a[0] == b[0] && a[1] == b[2] && a[2] == b[1]);  // opposite cyclic order
    } else if (sides.size() == 1) {
      ++boundary;
      bool on_box = false;
      for (int k = 0; k < 3; ++k) {
        for (double side : {axes[k].front(), axes[k].back()}) {
          on_box = on_box || (mesh.vertices[key[0]][k] == side &&
                              mesh.vertices[key[1]][k] == side && mesh.vertices[key[2]][k] == side);
        }
      }
      bad += !on_box;
    } else {
      ++bad;
    }
  }
  EXPECT_EQ(bad, 0u);
  const std::size_t nx = axes[0].size() - 1, ny = axes[1].size() - 1, nz = axes[2].size() - 1;
  EXPECT_EQ(boundary, 4 * (nx * ny + ny * nz + nz * nx));  // 2 triangles per boundary square
}

TEST(TetGrid, KuhnGridIsPositiveConformingAndFillsItsBox) {
  check_grid({{0, 0, 0}, {1, 1, 1}}, 4, 0);
  check_grid({{-1.5, 0.25, 3}, {2.5, 1.25, 3.5}}, 5, 0);
  check_grid({{-1.5, 0.25, 3}, {2.5, 1.25, 3.5}}, 5, 3);
  check_grid({{0, 0, 0}, {1e-3, 2e-3, 1e-3}}, 1, 1);
  check_grid({{1e6, 1e6, 1e6}, {1e6 + 1, 1e6 + 0.5, 1e6 + 0.1}}, 3, 2);
}

TEST(TetGrid, LatticePlanesMissRoundCoordinates) {
  const Box3 box{{0, 0, 0}, {1, 1, 1}};
  for (int attempt = 0; attempt < 6; ++attempt) {
    const TetMesh mesh = make_grid_background(box, 8, attempt);
    for (int k = 0; k < 3; ++k) {
      for (double c : lattice(mesh, k)) {
        EXPECT_NE(c * 16, std::round(c * 16))
            << "attempt " << attempt << ", axis " << k << ": " << c;
      }
    }
  }
}

TEST(TetGrid, DeterministicAndShiftedByAttempt) {
  const Box3 box{{-1, 0, 2}, {1, 3, 2.5}};
  const TetMesh a = make_grid_background(box, 6, 0);
  const TetMesh b = make_grid_background(box, 6, 0);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_TRUE(a.reference.empty());
  const TetMesh c = make_grid_background(box, 6, 1);
  EXPECT_NE(a.vertices.front(), c.vertices.front());
}

TEST(TetGrid, AbsurdSizesAndBadArgumentsAreRefused) {
  const Box3 box{{0, 0, 0}, {1, 1, 1}};
  EXPECT_THROW(make_grid_background(box, 1000), InvariantError);  // 6 x 1003^3 tets
  EXPECT_THROW(make_grid_background(box, 0), InvariantError);
  EXPECT_THROW(make_grid_background({{0, 0, 0}, {0, 0, 0}}, 4), InvariantError);
  EXPECT_NO_THROW(make_grid_background({{0, 0, 0}, {1, 1e-6, 1e-6}}, 2000));  // thin: few cubes
}

// ---- real Vega background meshes
// -----------------------------------------------------------------

struct RealTetFile {
  const char* name;
  std::size_t vertices;
  std::size_t tets;
};

constexpr RealTetFile kRealTetFiles[] = {
    {"quintupleTorus.veg", 15789, 71427},
    {"comb.tet.veg", 1623, 5844},
    {"doubleLoopWithCube.veg", 1181, 4650},
    {"helix.veg", 4532, 16226},
};

std::string real_tet_dir() { return std::string(IMM_SHARED_DATA_DIR) + "/tet"; }

TEST(TetRealData, VegaFilesLoadWithTheDocumentedCounts) {
  if (!std::filesystem::is_directory(real_tet_dir()))
    GTEST_SKIP() << "no shared data at " << real_tet_dir();
  for (const RealTetFile& f : kRealTetFiles) {
    const std::string path = real_tet_dir() + "/" + f.name;
    if (!std::filesystem::exists(path)) continue;
    const TetReadResult r = read_tet_mesh(path);
    ASSERT_TRUE(r.report.ok()) << f.name << ": " << r.report.summary();
    EXPECT_EQ(r.mesh.vertices.size(), f.vertices) << f.name;
    EXPECT_EQ(r.mesh.tets.size(), f.tets) << f.name;
    expect_all_positive(r.mesh, f.name);
    RecordProperty(std::string(f.name) + "_reoriented", std::to_string(r.reoriented));
  }
}

}  // namespace
}  // namespace imm::dim3
