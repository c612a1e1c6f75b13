// The 3D input layer: OBJ/OFF/PLY/STL readers, the exact-precision writers and validate_surface.
// Every defect class is checked on a small hand-written mesh for its kind and for a message that
// names the triangle and vertex ids involved; the third-party files of ../shared/data/real/3d load
// with the triangle counts listed in SOURCES.md.
#include "dim3/surface.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>

namespace imm::dim3 {
namespace {

std::string temp_dir() {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "imm_surface_test";
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::string write_temp(const std::string& name, const std::string& contents) {
  const std::string path = temp_dir() + "/" + name;
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

Surface with_identity_faces(Surface s) {
  s.source_face.resize(s.triangles.size());
  std::iota(s.source_face.begin(), s.source_face.end(), 0u);
  return s;
}

/// The box [lo, hi] with 8 vertices (bit k of the id picks hi along axis k) and 12 outward
/// triangles.
Surface box(Point3 lo = {0, 0, 0}, Point3 hi = {1, 1, 1}) {
  Surface s;
  for (int i = 0; i < 8; ++i) {
    s.vertices.push_back({i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]});
  }
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({q[0], q[1], q[2]});
    s.triangles.push_back({q[0], q[2], q[3]});
  }
  return with_identity_faces(s);
}

/// A tetrahedron with outward triangles: apex 3 above the triangle 0, 1, 2.
Surface tetrahedron(Point3 a, Point3 b, Point3 c, Point3 apex) {
  Surface s;
  s.vertices = {a, b, c, apex};
  s.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  return with_identity_faces(s);
}

/// A torus around the z axis with n x m quads split in two (outward).
Surface torus(int n, int m) {
  Surface s;
  const double pi = std::acos(-1.0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double u = 2 * pi * i / n, v = 2 * pi * j / m;
      s.vertices.push_back(
          {(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>((i % n) * m + j % m); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return with_identity_faces(s);
}

std::vector<const Defect*> of_kind(const ValidationReport& report, DefectKind kind) {
  std::vector<const Defect*> out;
  for (const Defect& d : report.defects) {
    if (d.kind == kind) out.push_back(&d);
  }
  return out;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

bool has_id(const std::vector<long>& ids, long id) {
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

/// The single defect of a report (failing the test otherwise), by value: reports are often
/// temporaries.
Defect only_defect(const ValidationReport& report) {
  EXPECT_EQ(report.defects.size(), 1u) << report.summary();
  if (report.defects.empty()) return Defect{DefectKind::Empty, "", "<no defect>", {}, {}, {}};
  return report.defects.front();
}

// ---- OBJ -------------------------------------------------------------------------------------

TEST(SurfaceObj, RoundTripsFullPrecision) {
  Surface s = box();
  s.vertices[0] = {0.1, 1.0 / 3.0, -2.5e17};
  s.vertices[5] = {1e-300, std::nextafter(1.0, 2.0), -0.0};
  s.vertices[6] = {std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::max(),
                   123456.789};
  for (const bool obj : {true, false}) {
    const std::string path =
        write_temp(obj ? "round.obj" : "round.off", obj ? format_obj(s) : format_off(s));
    const SurfaceReadResult r = read_surface(path);
    ASSERT_TRUE(r.report.ok()) << r.report.summary();
    EXPECT_EQ(r.surface.vertices, s.vertices) << path;
    EXPECT_EQ(r.surface.triangles, s.triangles) << path;
    EXPECT_EQ(r.surface.source_face, s.source_face) << path;
  }
}

TEST(SurfaceObj, FanTriangulatesPolygonsAndRecordsTheFileFace) {
  const SurfaceReadResult r =
      read_surface(write_temp("polygons.obj",
                              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\n"
                              "f 1 2 3\n"
                              "f 1 2 3 4\n"
                              "f 1 2 3 5 4\n"));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  const std::vector<Triangle> expected = {{0, 1, 2}, {0, 1, 2}, {0, 2, 3},
                                          {0, 1, 2}, {0, 2, 4}, {0, 4, 3}};
  EXPECT_EQ(r.surface.triangles, expected);
  EXPECT_EQ(r.surface.source_face, (std::vector<std::uint32_t>{0, 1, 1, 2, 2, 2}));
}

TEST(SurfaceObj, IgnoresMaterialsTexturesGroupsAndPolylinesAndTakesNegativeIndices) {
  // The referenced .mtl does not exist: harmless. 'f' with v/vt/vn and v//vn, relative indices.
  const std::string text =
      "# comment\n"
      "mtllib no_such_file.mtl\n"
      "o box\ng side\ns 1\nusemtl red\n"
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1   # trailing comment\n"
      "vt 0 0\nvt 1 0\nvt 0 1\n"
      "vn 0 0 1\n"
      "f 1/1/1 3/3/1 2/2/1\n"
      "f -4//1 -3//1 -1//1\n"
      "f 2/2 3/3 4/1\n"
      "f -2 -4 -1\n"
      "l 1 2\n";
  const SurfaceReadResult r = read_surface(write_temp("decorated.obj", text));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.surface.vertex_count(), 4u);
  const std::vector<Triangle> expected = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  EXPECT_EQ(r.surface.triangles, expected);
  EXPECT_TRUE(validate_surface(r.surface).ok()) << validate_surface(r.surface).summary();
  EXPECT_GT(signed_volume(r.surface), 0.0);
}

TEST(SurfaceObj, IndexOutOfRangeNamesFileLineAndIndex) {
  const std::string path = write_temp("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
  const SurfaceReadResult r = read_surface(path);
  const Defect d = only_defect(r.report);
  EXPECT_EQ(d.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(d.message, path + ":5:")) << d.message;
  EXPECT_TRUE(contains(d.message, "face 1")) << d.message;
  EXPECT_TRUE(contains(d.message, "vertex 9")) << d.message;
  EXPECT_TRUE(contains(d.message, "3 vertices")) << d.message;
  EXPECT_EQ(r.surface.triangle_count(), 1u);  // the bad face is dropped, the good one kept
}

TEST(SurfaceObj, ParseErrorsNameTheLine) {
  const std::string path =
      write_temp("bad.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\nf 1 0 2\nf -5 1 2\n");
  const SurfaceReadResult r = read_surface(path);
  const auto unreadable = of_kind(r.report, DefectKind::Unreadable);
  ASSERT_EQ(unreadable.size(), 3u) << r.report.summary();
  EXPECT_TRUE(contains(unreadable[0]->message, path + ":2:")) << unreadable[0]->message;
  EXPECT_TRUE(contains(unreadable[1]->message, path + ":5:")) << unreadable[1]->message;
  EXPECT_TRUE(contains(unreadable[1]->message, "'0'")) << unreadable[1]->message;
  EXPECT_TRUE(contains(unreadable[2]->message, path + ":6:")) << unreadable[2]->message;
  EXPECT_TRUE(contains(unreadable[2]->message, "-5")) << unreadable[2]->message;
}

TEST(SurfaceObj, NonFiniteCoordinateNamesVertexAndLine) {
  const std::string path =
      write_temp("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1e999\nf 1 2 3\nf 1 2 4\n");
  const SurfaceReadResult r = read_surface(path);
  const auto bad = of_kind(r.report, DefectKind::NonFinite);
  ASSERT_EQ(bad.size(), 2u) << r.report.summary();
  EXPECT_TRUE(contains(bad[0]->message, path + ":3:")) << bad[0]->message;
  EXPECT_TRUE(contains(bad[0]->message, "vertex 2 ")) << bad[0]->message;
  EXPECT_TRUE(contains(bad[0]->message, "(0, nan, 0)")) << bad[0]->message;
  EXPECT_EQ(bad[0]->vertices, std::vector<long>{2});
  EXPECT_TRUE(contains(bad[1]->message, "(0, 0, inf)")) << bad[1]->message;
}

TEST(SurfaceObj, EmptyAndPolylineOnlyFiles) {
  const Defect empty =
      only_defect(read_surface(write_temp("empty.obj", "# nothing\nv 0 0 0\n")).report);
  EXPECT_EQ(empty.kind, DefectKind::Empty);
  EXPECT_TRUE(contains(empty.message, "no face")) << empty.message;
  const Defect curve = only_defect(
      read_surface(write_temp("curve.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3 1\n")).report);
  EXPECT_EQ(curve.kind, DefectKind::Empty);
  EXPECT_TRUE(contains(curve.message, "2D")) << curve.message;
}

TEST(SurfaceRead, MissingFileDirectoryAndUnknownExtension) {
  const Defect missing = only_defect(read_surface(temp_dir() + "/does_not_exist.obj").report);
  EXPECT_EQ(missing.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(missing.message, "does_not_exist.obj")) << missing.message;
  std::filesystem::create_directories(temp_dir() + "/folder.off");
  EXPECT_EQ(only_defect(read_surface(temp_dir() + "/folder.off").report).kind,
            DefectKind::Unreadable);
  const Defect ext = only_defect(read_surface(write_temp("mesh.txt", "v 0 0 0\n")).report);
  EXPECT_EQ(ext.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(ext.message, ".txt")) << ext.message;
}

TEST(SurfaceRead, ExtensionsAnyCase) {
  for (const char* p : {"a.obj", "b.OFF", "dir.x/c.Ply", "d.stl"})
    EXPECT_TRUE(is_surface_extension(p)) << p;
  for (const char* p : {"a.txt", "b.svg", "obj", "c.obj.gz", "stl"})
    EXPECT_FALSE(is_surface_extension(p)) << p;
}

// ---- OFF -------------------------------------------------------------------------------------

TEST(SurfaceOff, HeaderVariantsCommentsColorsAndQuads) {
  const std::string text =
      "COFF 5 2 0  # counts on the header line\n"
      "# a comment line\n"
      "0 0 0 255 0 0 255\n1 0 0 255 0 0 255\n1 1 0 0 0 0 0\n0 1 0 0 0 0 0\n\n0.5 2 0 1 1 1 1\n"
      "4 0 1 2 3 0.5 0.5 0.5\n"
      "3 3 2 4\n";
  const SurfaceReadResult r = read_surface(write_temp("variants.off", text));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.surface.vertex_count(), 5u);
  EXPECT_EQ(r.surface.triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}, {3, 2, 4}}));
  EXPECT_EQ(r.surface.source_face, (std::vector<std::uint32_t>{0, 0, 1}));
  EXPECT_EQ(r.surface.vertices[4], (Point3{0.5, 2, 0}));
}

TEST(SurfaceOff, TruncatedAndMalformedFiles) {
  const std::string truncated =
      write_temp("truncated.off", "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n");
  const Defect t = only_defect(read_surface(truncated).report);
  EXPECT_EQ(t.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(t.message, "2 of the 4 faces")) << t.message;
  const std::string short_vertex =
      write_temp("short.off", "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n");
  const Defect s = only_defect(read_surface(short_vertex).report);
  EXPECT_TRUE(contains(s.message, short_vertex + ":4:")) << s.message;
  const Defect h = only_defect(read_surface(write_temp("header.off", "PLY\n3 1 0\n")).report);
  EXPECT_TRUE(contains(h.message, "OFF header")) << h.message;
  const Defect range = only_defect(
      read_surface(write_temp("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n")).report);
  EXPECT_TRUE(contains(range.message, "vertex 3, but the file has 3 vertices")) << range.message;
}

// ---- PLY -------------------------------------------------------------------------------------

/// Appends the bytes of `value` in the requested byte order.
template <class T>
void put(std::string& out, T value, bool big_endian) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (big_endian != (std::endian::native == std::endian::big))
    std::reverse(bytes, bytes + sizeof(T));
  out.append(bytes, sizeof(T));
}

/// The box as a binary PLY: coordinates as T, list counts as C, plus properties to skip
/// (a vertex colour, a face flag and an unrelated element after the faces).
template <class T, class C>
std::string box_ply(bool big_endian, const char* coordinate_type, const char* count_type) {
  const Surface s = box({-1, 0.1, 0}, {2, 0.7, 1.0 / 3.0});
  std::string out =
      std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
      " 1.0\ncomment written by surface_test\n"
      "element vertex 8\nproperty " +
      coordinate_type + " x\nproperty " + coordinate_type + " y\n" +
      "property uchar red\nproperty " + coordinate_type + " z\n" +
      "element face 6\nproperty list " + count_type + " int vertex_indices\nproperty short flag\n" +
      "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  for (const Point3& p : s.vertices) {
    put(out, static_cast<T>(p[0]), big_endian);
    put(out, static_cast<T>(p[1]), big_endian);
    put(out, static_cast<std::uint8_t>(200), big_endian);
    put(out, static_cast<T>(p[2]), big_endian);
  }
  for (std::size_t q = 0; q < 6;
       ++q) {  // the box's quads: triangles 2q and 2q+1 share corners 0, 2
    const Triangle& a = s.triangles[2 * q];
    const Triangle& b = s.triangles[2 * q + 1];
    put(out, static_cast<C>(4), big_endian);
    for (std::uint32_t v : {a[0], a[1], a[2], b[2]})
      put(out, static_cast<std::int32_t>(v), big_endian);
    put(out, static_cast<std::int16_t>(-7), big_endian);
  }
  put(out, static_cast<std::int32_t>(0), big_endian);
  put(out, static_cast<std::int32_t>(1), big_endian);
  return out;
}

void expect_box_like(const SurfaceReadResult& r, bool exact_doubles) {
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  const Surface s = box({-1, 0.1, 0}, {2, 0.7, 1.0 / 3.0});
  EXPECT_EQ(r.surface.triangles, s.triangles);
  EXPECT_EQ(r.surface.source_face,
            (std::vector<std::uint32_t>{0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5}));
  ASSERT_EQ(r.surface.vertex_count(), 8u);
  for (std::size_t v = 0; v < 8; ++v) {
    for (int k = 0; k < 3; ++k) {
      const double expected = exact_doubles
                                  ? s.vertices[v][k]
                                  : static_cast<double>(static_cast<float>(s.vertices[v][k]));
      EXPECT_EQ(r.surface.vertices[v][k], expected) << "vertex " << v;
    }
  }
  EXPECT_TRUE(validate_surface(r.surface).ok()) << validate_surface(r.surface).summary();
}

TEST(SurfacePly, BinaryLittleAndBigEndianFloatAndDouble) {
  expect_box_like(read_surface(write_temp("le_double.ply",
                                          box_ply<double, std::uint8_t>(false, "double", "uchar"))),
                  true);
  expect_box_like(read_surface(write_temp("be_double.ply",
                                          box_ply<double, std::int32_t>(true, "float64", "int"))),
                  true);
  expect_box_like(
      read_surface(write_temp("le_float.ply", box_ply<float, std::int32_t>(false, "float", "int"))),
      false);
  expect_box_like(read_surface(write_temp("be_float.ply",
                                          box_ply<float, std::uint8_t>(true, "float32", "uint8"))),
                  false);
}

TEST(SurfacePly, Ascii) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n";
  const SurfaceReadResult r = read_surface(write_temp("ascii.ply", text));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.surface.triangles, tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}).triangles);
  EXPECT_TRUE(validate_surface(r.surface).ok());
}

TEST(SurfacePly, TruncatedBinaryAndBadHeader) {
  std::string data = box_ply<double, std::uint8_t>(false, "double", "uchar");
  data.resize(data.size() - 40);  // inside the faces
  const Defect t = only_defect(read_surface(write_temp("truncated.ply", data)).report);
  EXPECT_EQ(t.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(t.message, "ends inside 'face'")) << t.message;
  const std::string path =
      write_temp("header.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n");
  const Defect h = only_defect(read_surface(path).report);
  EXPECT_TRUE(contains(h.message, path + ":4:")) << h.message;
}

// ---- STL -------------------------------------------------------------------------------------

std::string box_stl_binary(const Surface& s, const std::string& header_start) {
  std::string out = header_start;
  out.resize(80, ' ');
  put(out, static_cast<std::uint32_t>(s.triangles.size()), false);
  for (const Triangle& t : s.triangles) {
    for (int k = 0; k < 3; ++k) put(out, 0.0f, false);  // normal: ignored
    for (std::uint32_t v : t) {
      for (double c : s.vertices[v]) put(out, static_cast<float>(c), false);
    }
    put(out, static_cast<std::uint16_t>(0), false);
  }
  return out;
}

std::string box_stl_ascii(const Surface& s) {
  std::string out = "solid box\n";
  for (const Triangle& t : s.triangles) {
    out += "  facet normal 0 0 0\n    outer loop\n";
    for (std::uint32_t v : t) {
      out += "      vertex " + std::to_string(s.vertices[v][0]) + " " +
             std::to_string(s.vertices[v][1]) + " " + std::to_string(s.vertices[v][2]) + "\n";
    }
    out += "    endloop\n  endfacet\n";
  }
  return out + "endsolid box\n";
}

TEST(SurfaceStl, BinaryAndAsciiAreWelded) {
  const Surface s = box({-1, 0.5, 0}, {2, 0.75, 4});  // floats: exact in both encodings
  // A binary STL whose header starts with "solid" (as some writers do) is still binary: its size
  // decides.
  for (const std::string& header : {std::string("binary box"), std::string("solid but binary")}) {
    const SurfaceReadResult r = read_surface(write_temp("box.stl", box_stl_binary(s, header)));
    ASSERT_TRUE(r.report.ok()) << r.report.summary();
    EXPECT_EQ(r.surface.vertex_count(), 8u) << header;
    EXPECT_EQ(r.surface.triangle_count(), 12u) << header;
    EXPECT_TRUE(validate_surface(r.surface).ok()) << validate_surface(r.surface).summary();
    EXPECT_DOUBLE_EQ(signed_volume(r.surface), 3 * 0.25 * 4);
  }
  const SurfaceReadResult r = read_surface(write_temp("box_ascii.STL", box_stl_ascii(s)));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.surface.vertex_count(), 8u);
  EXPECT_EQ(r.surface.triangle_count(), 12u);
  EXPECT_TRUE(validate_surface(r.surface).ok()) << validate_surface(r.surface).summary();
}

TEST(SurfaceStl, WeldingTreatsSignedZerosAsOnePoint) {
  Surface s = tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  // Triangle 1 writes the origin as (-0, -0, -0): still the same vertex.
  std::string data = box_stl_binary(s, "signed zeros");
  const std::size_t origin_of_triangle_1 = 84 + 50 + 12;
  for (int c = 0; c < 3; ++c) {
    const float minus_zero = -0.0f;
    std::memcpy(data.data() + origin_of_triangle_1 + 4 * c, &minus_zero, 4);
  }
  const SurfaceReadResult r = read_surface(write_temp("zeros.stl", data));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.surface.vertex_count(), 4u);
  EXPECT_TRUE(validate_surface(r.surface).ok()) << validate_surface(r.surface).summary();
}

TEST(SurfaceStl, TruncatedBinaryAndBrokenAscii) {
  std::string data = box_stl_binary(box(), "short");
  data.resize(data.size() - 60);
  const Defect t = only_defect(read_surface(write_temp("truncated.stl", data)).report);
  EXPECT_EQ(t.kind, DefectKind::Unreadable);
  EXPECT_TRUE(contains(t.message, "announces 12 facets")) << t.message;
  const std::string path =
      write_temp("broken.stl",
                 "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\nvertex 1 0 0\n"
                 "vertex 0 1 0\nendloop\nendfacet\nendsolid x\n");
  const SurfaceReadResult r = read_surface(path);
  ASSERT_FALSE(r.report.ok());
  EXPECT_TRUE(contains(r.report.defects.front().message, path + ":4:")) << r.report.summary();
}

// ---- writers and helpers ----------------------------------------------------------------------

TEST(SurfaceFormat, PointsVolumeAndMerge) {
  EXPECT_EQ(format_point({0.1, -2, 1e300}), "(0.1, -2, 1e+300)");
  EXPECT_EQ(format_point({-0.0, 1.0 / 3.0, 5e-324}), "(0, 0.3333333333333333, 5e-324)");
  EXPECT_DOUBLE_EQ(signed_volume(box({0, 0, 0}, {2, 3, 4})), 24.0);
  Surface inverted = box();
  for (Triangle& t : inverted.triangles) std::swap(t[1], t[2]);
  EXPECT_DOUBLE_EQ(signed_volume(inverted), -1.0);

  const Surface a = box();
  Surface b = tetrahedron({5, 0, 0}, {6, 0, 0}, {5, 1, 0}, {5, 0, 1});
  b.source_face = {0, 0, 1, 2};  // as if its first face had been a quad
  const Surface m = merge(a, b);
  ASSERT_EQ(m.vertex_count(), 12u);
  ASSERT_EQ(m.triangle_count(), 16u);
  EXPECT_EQ(m.triangles[12], (Triangle{8, 10, 9}));
  EXPECT_EQ(m.source_face[11], 11u);
  EXPECT_EQ(m.source_face[12], 12u);
  EXPECT_EQ(m.source_face[15], 14u);
  EXPECT_DOUBLE_EQ(signed_volume(m), 1.0 + 1.0 / 6.0);
  EXPECT_TRUE(validate_surface(m).ok()) << "several components are one valid input";
}

// ---- validate_surface: one small mesh per defect class ------------------------------------------

TEST(SurfaceValidate, ClosedManifoldsPass) {
  EXPECT_TRUE(validate_surface(box()).ok());
  EXPECT_TRUE(validate_surface(torus(12, 8)).ok());
  // A genuinely flat-looking but non-degenerate bottom face: double arithmetic computes its cross
  // product as exactly 0 ((1.1 * 0.39) - (1.3 * 0.33) rounds to 0), the exact test does not.
  const Surface flat = tetrahedron({0, 0, 0}, {1.1, 1.3, 0}, {0.33, 0.39, 0}, {0, 0, 1});
  EXPECT_EQ(1.1 * 0.39 - 1.3 * 0.33, 0.0) << "the example no longer fools double arithmetic";
  EXPECT_TRUE(validate_surface(flat).ok()) << validate_surface(flat).summary();
}

TEST(SurfaceValidate, Empty) {
  Surface s;
  s.vertices = {{0, 0, 0}};
  EXPECT_EQ(only_defect(validate_surface(s)).kind, DefectKind::Empty);
}

TEST(SurfaceValidate, NonFiniteVertex) {
  Surface s = box();
  s.vertices[6][1] = std::numeric_limits<double>::infinity();
  const Defect d = only_defect(validate_surface(s));
  EXPECT_EQ(d.kind, DefectKind::NonFinite);
  EXPECT_EQ(d.vertices, std::vector<long>{6});
  EXPECT_TRUE(contains(d.message, "vertex 6 (0, inf, 1)")) << d.message;
}

TEST(SurfaceValidate, IndexOutOfRange) {
  Surface s = box();
  s.triangles[4][2] = 8;
  const ValidationReport report = validate_surface(s);
  const auto range = of_kind(report, DefectKind::OutOfRange);
  ASSERT_EQ(range.size(), 1u) << report.summary();
  EXPECT_EQ(range[0]->facets, std::vector<long>{4});
  EXPECT_TRUE(contains(range[0]->message, "triangle 4")) << range[0]->message;
  EXPECT_TRUE(contains(range[0]->message, "vertex 8")) << range[0]->message;
  EXPECT_FALSE(of_kind(report, DefectKind::NotClosed).empty()) << "the rest is checked without it";
}

TEST(SurfaceValidate, RepeatedVertexIsDegenerate) {
  Surface s = box();
  s.triangles.push_back({3, 5, 3});
  const Defect d = only_defect(validate_surface(s));
  EXPECT_EQ(d.kind, DefectKind::DegenerateFacet);
  EXPECT_EQ(d.facets, std::vector<long>{12});
  EXPECT_TRUE(contains(d.message, "triangle 12 (vertices 3, 5, 3)")) << d.message;
}

TEST(SurfaceValidate, CollinearCornersAreDegenerate) {
  // Split edge 0-2 of the box's first triangle (0, 2, 3) at its midpoint m = 8 on one side only and
  // close the slit with the zero-area triangle (2, 8, 0): closed, consistently oriented,
  // degenerate.
  Surface s = box();
  ASSERT_EQ(s.triangles[0], (Triangle{0, 2, 3}));
  s.vertices.push_back({0, 0.5, 0});
  s.triangles[0] = {0, 8, 3};
  s.triangles.push_back({8, 2, 3});
  s.triangles.push_back({2, 8, 0});
  s.source_face.assign(s.triangles.size(), 0);
  std::iota(s.source_face.begin(), s.source_face.end(), 0u);
  const Defect d = only_defect(validate_surface(s));
  EXPECT_EQ(d.kind, DefectKind::DegenerateFacet);
  EXPECT_EQ(d.facets, std::vector<long>{13});
  EXPECT_EQ(d.vertices, (std::vector<long>{2, 8, 0}));
  EXPECT_TRUE(contains(d.message, "triangle 13")) << d.message;
  EXPECT_TRUE(contains(d.message, "(0, 0.5, 0)")) << d.message;
  EXPECT_TRUE(contains(d.message, "collinear")) << d.message;
}

TEST(SurfaceValidate, DuplicateVertexPositionUsedTwice) {
  // Two tetrahedra touching at one point, each with its own vertex id there.
  const Surface s = merge(tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}),
                          tetrahedron({0, 0, 1}, {1, 0, 2}, {0, 1, 2}, {0, 0, 3}));
  const Defect d = only_defect(validate_surface(s));
  EXPECT_EQ(d.kind, DefectKind::DuplicateVertex);
  EXPECT_EQ(d.vertices, (std::vector<long>{3, 4}));
  EXPECT_TRUE(contains(d.message, "vertices 3, 4")) << d.message;
  EXPECT_TRUE(contains(d.message, "(0, 0, 1)")) << d.message;
  // An unused vertex at the same position is no defect.
  Surface unused = box();
  unused.vertices.push_back(unused.vertices[7]);
  EXPECT_TRUE(validate_surface(unused).ok());
}

TEST(SurfaceValidate, DuplicateFacetInEitherOrientation) {
  Surface s = box();
  s.triangles.push_back(s.triangles[5]);
  s.triangles.push_back({s.triangles[7][0], s.triangles[7][2], s.triangles[7][1]});
  const ValidationReport report = validate_surface(s);
  ASSERT_EQ(report.defects.size(), 2u)
      << report.summary();  // the copies are left out of the topology
  for (const Defect& d : report.defects) EXPECT_EQ(d.kind, DefectKind::DuplicateFacet);
  EXPECT_EQ(report.defects[0].facets, (std::vector<long>{5, 12}));
  EXPECT_TRUE(contains(report.defects[0].message, "triangles 5, 12")) << report.defects[0].message;
  EXPECT_FALSE(contains(report.defects[0].message, "opposite"));
  EXPECT_EQ(report.defects[1].facets, (std::vector<long>{7, 13}));
  EXPECT_TRUE(contains(report.defects[1].message, "opposite orientations"))
      << report.defects[1].message;
}

TEST(SurfaceValidate, OpenBoundary) {
  Surface s = box();
  const Triangle removed = s.triangles[3];
  s.triangles.erase(s.triangles.begin() + 3);
  const ValidationReport report = validate_surface(s);
  ASSERT_EQ(report.defects.size(), 3u) << report.summary();
  for (const Defect& d : report.defects) {
    EXPECT_EQ(d.kind, DefectKind::NotClosed);
    ASSERT_EQ(d.vertices.size(), 2u);
    ASSERT_EQ(d.facets.size(), 1u);
    for (long v : d.vertices)
      EXPECT_TRUE(std::count(removed.begin(), removed.end(), v) == 1) << d.message;
    EXPECT_TRUE(contains(d.message, "triangle " + std::to_string(d.facets[0]))) << d.message;
    EXPECT_TRUE(contains(d.message, "vertex " + std::to_string(d.vertices[0]))) << d.message;
  }
}

TEST(SurfaceValidate, NonManifoldEdge) {
  // Two tetrahedra sharing the edge 0-1 (the same vertex ids): the edge has four triangles.
  Surface s = tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  s.vertices.push_back({0.5, -1, 0});
  s.vertices.push_back({0.5, -0.5, -1});
  const std::vector<Triangle> second = {
      {0, 1, 4}, {0, 5, 1}, {1, 5, 4}, {4, 5, 0}};  // tetra 0, 1, 4, 5
  s.triangles.insert(s.triangles.end(), second.begin(), second.end());
  s = with_identity_faces(s);
  const Defect d = only_defect(validate_surface(s));
  EXPECT_EQ(d.kind, DefectKind::NonManifoldEdge);
  EXPECT_EQ(d.vertices, (std::vector<long>{0, 1}));
  EXPECT_EQ(d.facets, (std::vector<long>{0, 1, 4, 5}));
  EXPECT_TRUE(contains(d.message, "4 triangles (0, 1, 4, 5)")) << d.message;
}

TEST(SurfaceValidate, NonManifoldVertex) {
  // Two tetrahedra sharing vertex 3 (one id): two fans around it.
  Surface s = tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  s.vertices.push_back({1, 0, 2});
  s.vertices.push_back({0, 1, 2});
  s.vertices.push_back({0, 0, 3});
  const std::vector<Triangle> second = {{3, 5, 4}, {3, 4, 6}, {4, 5, 6}, {5, 3, 6}};
  s.triangles.insert(s.triangles.end(), second.begin(), second.end());
  s = with_identity_faces(s);
  ASSERT_GT(signed_volume(s), 0);
  const Defect d = only_defect(validate_surface(s));
  EXPECT_EQ(d.kind, DefectKind::NonManifoldVertex);
  EXPECT_EQ(d.vertices, std::vector<long>{3});
  EXPECT_EQ(d.facets, (std::vector<long>{1, 2, 3, 4, 5, 7}));
  EXPECT_TRUE(contains(d.message, "vertex 3 (0, 0, 1)")) << d.message;
  EXPECT_TRUE(contains(d.message, "2 separate fans (triangles 1, 2, 3 | 4, 5, 7)")) << d.message;
}

TEST(SurfaceValidate, InconsistentOrientation) {
  Surface s = box();
  std::swap(s.triangles[6][1], s.triangles[6][2]);
  const ValidationReport report = validate_surface(s);
  ASSERT_EQ(report.defects.size(), 3u) << report.summary();
  for (const Defect& d : report.defects) {
    EXPECT_EQ(d.kind, DefectKind::InconsistentOrientation);
    EXPECT_TRUE(has_id(d.facets, 6)) << d.message;
    EXPECT_EQ(d.facets.size(), 2u);
    EXPECT_TRUE(contains(d.message, "triangle 6")) << d.message;
  }
}

TEST(SurfaceValidate, NonOrientableClosedSurfaceIsInconsistent) {
  // A torus whose second ring is glued back with a flip (a Klein bottle): closed and manifold,
  // so the only defect class is orientation.
  const int n = 8, m = 6;
  Surface s;
  const double pi = std::acos(-1.0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j)
      s.vertices.push_back({double(i), std::cos(2 * pi * j / m), std::sin(2 * pi * j / m)});
  }
  auto id = [&](int i, int j) {
    if (i == n) return static_cast<std::uint32_t>((m - j) % m);  // glued back mirrored
    return static_cast<std::uint32_t>(i * m + (j % m));
  };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  const ValidationReport report = validate_surface(with_identity_faces(s));
  ASSERT_FALSE(report.ok());
  for (const Defect& d : report.defects)
    EXPECT_EQ(d.kind, DefectKind::InconsistentOrientation) << d.message;
}

TEST(SurfaceValidate, MessagesAreCappedPerKind) {
  Surface s = box();
  for (std::uint32_t k = 0; k < 1000; ++k) s.triangles.push_back({k % 8, k % 8, (k + 1) % 8});
  const ValidationReport report = validate_surface(s);
  ASSERT_EQ(report.defects.size(), 21u);
  EXPECT_EQ(report.defects.back().kind, DefectKind::DegenerateFacet);
  EXPECT_TRUE(contains(report.defects.back().message, "... and 980 more"))
      << report.defects.back().message;
}

// How long this takes is measured by BM_ValidateSurface_Torus (bench/bench_inputs3.cpp).
TEST(SurfaceValidate, LargeMeshIsValid) {
  const Surface s = torus(500, 300);  // 300k triangles
  ASSERT_EQ(s.triangle_count(), 300000u);
  const ValidationReport report = validate_surface(s);
  EXPECT_TRUE(report.ok()) << report.summary();
}

// ---- third-party files (../shared/data/real/3d, SOURCES.md)
// --------------------------------------

struct RealFile {
  const char* name;
  std::size_t triangles;
  bool valid;  ///< passes validate_surface
};

// Triangle counts after fan triangulation (SOURCES.md). All are closed 2-manifolds; the two with
// duplicated vertex positions touch themselves at a point (two vertex ids at one position, each
// with its own fan, in the same shell): DuplicateVertex, exit 2.
//  - cow.off: vertices 621 and 2761 are both (-0.416893, 0.220802, 0);
//  - Offset1.obj: vertices 1032/1034 and 1039/1040.
const RealFile kRealFiles[] = {
    {"quintupleTorus.obj", 30438, true},
    {"doubleLoopWithCube.obj", 4012, true},
    {"doubleLoopWithCube_tri.obj", 4012, true},
    {"doubleLoop_torusOnly_tri.obj", 4000, true},
    {"comb.obj", 9816, true},
    {"comb_tri.obj", 9816, true},
    {"self_intersectA.obj", 17160, true},
    {"two_spheres.stl", 1600, true},
    {"two_spheres_welded.obj", 1600, true},
    {"cow.off", 5520, false},
    {"cube_with_fold.ply", 48, true},
    {"yeahright_controlmesh_boolean_proxy.obj", 1146, true},
    {"Generic_Twin_7863.1.t0_left.obj", 212, true},
    {"Offset1.obj", 4418, false},
    {"TinyTorus.obj", 48, true},
    {"3holes.off", 7200, true},
    {"decimated-knight.off", 1000, true},
    {"spot.obj", 5856, true},
    {"armadillo.obj", 86482, true},
};

std::string real_dir() { return std::string(IMM_SHARED_DATA_DIR) + "/3d"; }

TEST(SurfaceRealData, EveryFileLoadsWithTheDocumentedCounts) {
  if (!std::filesystem::is_directory(real_dir()))
    GTEST_SKIP() << "no shared data at " << real_dir();
  for (const RealFile& f : kRealFiles) {
    const std::string path = real_dir() + "/" + f.name;
    const SurfaceReadResult r = read_surface(path);
    ASSERT_TRUE(r.report.ok()) << f.name << ": " << r.report.summary();
    EXPECT_EQ(r.surface.triangle_count(), f.triangles) << f.name;
    EXPECT_EQ(r.surface.source_face.size(), f.triangles) << f.name;
    const ValidationReport report = validate_surface(r.surface);
    EXPECT_EQ(report.ok(), f.valid) << f.name << ": " << report.summary();
    if (f.valid) {
      EXPECT_GT(signed_volume(r.surface), 0.0) << f.name << " is oriented outward";
    }
  }
}

TEST(SurfaceRealData, PolygonFilesRecordTheirFaces) {
  if (!std::filesystem::is_directory(real_dir()))
    GTEST_SKIP() << "no shared data at " << real_dir();
  // doubleLoopWithCube.obj: 2006 quads (with mtllib naming an absent .mtl), each split in two.
  const SurfaceReadResult quads = read_surface(real_dir() + "/doubleLoopWithCube.obj");
  ASSERT_TRUE(quads.report.ok()) << quads.report.summary();
  EXPECT_EQ(quads.surface.source_face.back(), 2005u);
  // The derived file is the same fan triangulation, vertex for vertex.
  const SurfaceReadResult triangles = read_surface(real_dir() + "/doubleLoopWithCube_tri.obj");
  EXPECT_EQ(quads.surface.vertices, triangles.surface.vertices);
  EXPECT_EQ(quads.surface.triangles, triangles.surface.triangles);
  // two_spheres.stl welded = the derived OBJ.
  const SurfaceReadResult stl = read_surface(real_dir() + "/two_spheres.stl");
  const SurfaceReadResult welded = read_surface(real_dir() + "/two_spheres_welded.obj");
  EXPECT_EQ(stl.surface.vertex_count(), welded.surface.vertex_count());
  EXPECT_EQ(stl.surface.triangles, welded.surface.triangles);
}

TEST(SurfaceRealData, DuplicatedPositionsAreNamed) {
  if (!std::filesystem::is_directory(real_dir()))
    GTEST_SKIP() << "no shared data at " << real_dir();
  const ValidationReport cow = validate_surface(read_surface(real_dir() + "/cow.off").surface);
  const Defect d = only_defect(cow);
  EXPECT_EQ(d.kind, DefectKind::DuplicateVertex);
  EXPECT_EQ(d.vertices, (std::vector<long>{621, 2761}));
  const ValidationReport offset =
      validate_surface(read_surface(real_dir() + "/Offset1.obj").surface);
  ASSERT_EQ(offset.defects.size(), 2u) << offset.summary();
  EXPECT_EQ(offset.defects[0].vertices, (std::vector<long>{1032, 1034}));
  EXPECT_EQ(offset.defects[1].vertices, (std::vector<long>{1039, 1040}));
  for (const Defect& e : offset.defects) EXPECT_EQ(e.kind, DefectKind::DuplicateVertex);
}

TEST(SurfaceRealData, LargeFilesLoadAndValidate) {
  // Their read and validation times are benchmarks (BM_Surface3_ReadValidate), not assertions.
  if (!std::filesystem::is_directory(real_dir()))
    GTEST_SKIP() << "no shared data at " << real_dir();
  for (const char* name : {"quintupleTorus.obj", "armadillo.obj"}) {
    const SurfaceReadResult r = read_surface(real_dir() + "/" + name);
    EXPECT_TRUE(r.report.ok()) << name << ": " << r.report.summary();
    const ValidationReport report = validate_surface(r.surface);
    EXPECT_TRUE(report.ok()) << name << ": " << report.summary();
    EXPECT_GT(r.surface.triangle_count(), 10'000u) << name;
  }
}

}  // namespace
}  // namespace imm::dim3
