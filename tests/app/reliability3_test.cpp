// Issue 13, 3D: bad and unusual inputs end with exit 2 (what and where) or a verdict, never a
// signal, a hang or a half-written output; outputs respect what their path names.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/immerse_fixture.h"

namespace {

namespace fs = std::filesystem;
using imm::test::RunOutcome;

#define EXPECT_CONTAINS(text, piece) \
  EXPECT_NE((text).find(piece), std::string::npos) << "expected '" << (piece) << "' in:\n" << (text)

/// A positively oriented tetrahedron as OBJ (outward normals).
std::string tetra_obj(const std::array<std::array<double, 3>, 4>& v) {
  std::ostringstream os;
  os.precision(17);
  for (const auto& p : v) os << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  os << "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  return os.str();
}

class Reliability3 : public imm::test::ImmerseTest {};

// Defect 2: SIGFPE beyond about 5.6e102 (a double volume overflowed and became a rational).
TEST_F(Reliability3, LargeCoordinatesDoNotOverflowTheVolumes) {
  for (double s : {1e110, 1e200, 1e300}) {
    SCOPED_TRACE(testing::Message() << "scale " << s);
    write("big.obj", tetra_obj({{{0, 0, 0}, {s, 0, 0}, {0, s, 0}, {0, 0, s}}}));
    for (const char* command : {"check", "cells", "immersions"}) {
      const RunOutcome r = run(std::string(command) + " big.obj");
      EXPECT_EQ(r.code, 0) << command << "\n" << r.output;
    }
    const RunOutcome m = run("mesh big.obj --resolution 3 -o big.mesh --embedding big.emb --json big.json");
    EXPECT_TRUE(m.code == 0 || m.code == 2) << m.output;
    if (m.code == 0) {  // the embedding's precision is measured, not lost to an overflow
      EXPECT_CONTAINS(read("big.json"), "\"embedding_error\": ");
      EXPECT_EQ(read("big.json").find("\"embedding_error\": null"), std::string::npos) << read("big.json");
    }
    if (m.code == 2) {
      EXPECT_CONTAINS(m.output, "coordinate");
      EXPECT_FALSE(fs::exists(dir_ / "big.mesh"));
    }
  }
  // Beyond the documented range (the fuzzer's -1e308 stopped the program with SIGFPE): exit 2.
  write("beyond.obj", tetra_obj({{{0, 0, 0}, {1, 0, 0}, {0, -1e308, 0}, {0, 0, 1}}}));
  for (const char* command : {"check", "immersions", "mesh"}) {
    const RunOutcome r = run(std::string(command) + " beyond.obj" + (command[0] == 'm' ? " -o b.mesh" : ""));
    EXPECT_EQ(r.code, 2) << command << "\n" << r.output;
    EXPECT_CONTAINS(r.output, "|x|, |y|, |z| <= 1e300");
  }
  // Tiny coordinates: the same.
  const double t = 1e-300;
  write("tiny.obj", tetra_obj({{{0, 0, 0}, {t, 0, 0}, {0, t, 0}, {0, 0, t}}}));
  EXPECT_EQ(run("immersions tiny.obj").code, 0);
}

// Defect 3: the unit tetrahedron failed to mesh (every grid retry met the same input edge).
TEST_F(Reliability3, UnitTetrahedronMeshesAtEveryResolution) {
  write("unit.obj", tetra_obj({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}));
  for (const char* resolution : {"", " --resolution 4", " --resolution 8", " --resolution 17"}) {
    const RunOutcome r = run(std::string("mesh unit.obj -o unit.mesh") + resolution);
    EXPECT_EQ(r.code, 0) << resolution << "\n" << r.output;
  }
}

TEST_F(Reliability3, RandomIntegerTetrahedraMesh) {
  std::mt19937 random(13);
  std::uniform_int_distribution<int> coordinate(-4, 4);
  const int resolutions[] = {4, 5, 7, 8, 11, 16};
  int meshed = 0;
  for (int k = 0; k < 48; ++k) {
    std::array<std::array<double, 3>, 4> v{};
    double volume = 0;
    do {
      for (auto& p : v)
        for (double& x : p) x = coordinate(random);
      const auto d = [&](int i, int c) { return v[i][c] - v[0][c]; };
      volume = d(1, 0) * (d(2, 1) * d(3, 2) - d(2, 2) * d(3, 1)) - d(1, 1) * (d(2, 0) * d(3, 2) - d(2, 2) * d(3, 0)) +
               d(1, 2) * (d(2, 0) * d(3, 1) - d(2, 1) * d(3, 0));
    } while (volume == 0);
    if (volume < 0) std::swap(v[2], v[3]);
    write("t.obj", tetra_obj(v));
    const int resolution = resolutions[k % 6];
    const RunOutcome r = run("mesh t.obj --resolution " + std::to_string(resolution) + " -o t.mesh");
    EXPECT_EQ(r.code, 0) << "tetrahedron " << k << " at resolution " << resolution << ":\n"
                         << read("t.obj") << r.output;
    meshed += r.code == 0 ? 1 : 0;
  }
  EXPECT_EQ(meshed, 48);
}

// Defect 6: an unused vertex passed `check` but broke `mesh`.
TEST_F(Reliability3, UnusedVertexIsLeftOutOfTheEmbedding) {
  write("extra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 5 5 5\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  EXPECT_EQ(run("check extra.obj").code, 0);
  const RunOutcome r = run("mesh extra.obj --resolution 4 -o e.mesh --embedding e.emb");
  ASSERT_EQ(r.code, 0) << r.output;
  std::istringstream emb(read("e.emb"));
  std::string count;
  std::getline(emb, count);
  EXPECT_EQ(count, "5");
  std::vector<std::string> lines;
  for (std::string line; std::getline(emb, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[4], "-1 0 0 0 0");
  for (int v = 0; v < 4; ++v) EXPECT_NE(lines[static_cast<std::size_t>(v)].rfind("-1 ", 0), 0u) << lines[v];
}

// Defect 11: empty faces were skipped silently; 'f 1/x/1' was accepted.
TEST_F(Reliability3, EmptyFacesAndMalformedReferencesAreDefects) {
  const std::string tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  write("empty_face.obj", tetra + "f\n");
  RunOutcome r = run("check empty_face.obj");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "face 4 has 0 vertices");
  write("bad_ref.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1/x/1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  r = run("check bad_ref.obj");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "'1/x/1'");
  write("ok_ref.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvn 0 0 1\n"
                      "f 1/1/1 3//1 2/1\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  r = run("check ok_ref.obj");
  EXPECT_EQ(r.code, 0) << r.output;
  write("empty.off", "OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n0\n");
  r = run("check empty.off");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "face 4 has 0 vertices");
  write("empty.ply",
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
        "element face 5\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n0\n");
  r = run("check empty.ply");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "face 4 has 0 vertices");
  // Binary PLY with an empty face.
  std::string binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 5\nproperty list uchar int vertex_indices\nend_header\n";
  const float coords[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  binary.append(reinterpret_cast<const char*>(coords), sizeof coords);
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& f : faces) {
    binary.push_back(3);
    binary.append(reinterpret_cast<const char*>(f), sizeof f);
  }
  binary.push_back(0);
  write("empty_binary.ply", binary);
  r = run("check empty_binary.ply");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "face 4 has 0 vertices");
}

TEST_F(Reliability3, BinaryJunkGivesAShortPrintableMessage) {
  std::string junk;
  std::uint32_t state = 99;
  for (int i = 0; i < 200000; ++i) {
    state = state * 1664525u + 1013904223u;
    junk.push_back(static_cast<char>(state >> 24));
  }
  for (const char* name : {"junk.obj", "junk.off", "junk.ply", "junk.stl"}) {
    write(name, junk);
    const RunOutcome r = run(std::string("check ") + name);
    EXPECT_EQ(r.code, 2) << name;
    EXPECT_LT(r.output.size(), 8000u) << name << "\n" << r.output.substr(0, 2000);
    for (char c : r.output)
      EXPECT_TRUE(c == '\n' || std::isprint(static_cast<unsigned char>(c))) << name << ": byte "
                                                                             << int(static_cast<unsigned char>(c));
  }
}

// Found by scripts/fuzz.py (seed 1): a PLY element name with a byte that is not UTF-8 made the
// JSON report impossible to write (exit 1 from the JSON library).
TEST_F(Reliability3, NonTextBytesInMessagesAreEscaped) {
  std::string ply = imm::test::read_file(fs::path(IMM_TEST_DATA_DIR).parent_path() / "fuzz" / "corpus" / "tetra_binary.ply");
  ASSERT_FALSE(ply.empty());
  ply[ply.find("vertex") + 1] = static_cast<char>(0xe9);  // "v\xe9rtex"
  ply.resize(ply.find("end_header\n") + 11 + 20);          // and the file ends in its records
  write("bad.ply", ply);
  const RunOutcome r = run("mesh bad.ply -o bad.mesh --json bad.json");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "'v?rtex'");
  EXPECT_CONTAINS(read("bad.json"), "invalid-input");
  EXPECT_FALSE(fs::exists(dir_ / "bad.mesh"));
}

// Defect 4: `-o FIFO` turned the FIFO into a file; `-o link.mesh` replaced the link.
TEST_F(Reliability3, OutputsRespectLinksAndFifos) {
  write("unit.obj", tetra_obj({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}));
  fs::create_directories(dir_ / "real");
  fs::create_symlink("real/target.mesh", dir_ / "link.mesh");
  RunOutcome r = run("mesh unit.obj --resolution 3 -o link.mesh");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.mesh"));
  EXPECT_CONTAINS(read("real/target.mesh"), "Tetrahedra");

  ASSERT_EQ(::mkfifo((dir_ / "out.fifo").c_str(), 0600), 0);
  imm::test::FifoReader reader(dir_ / "out.fifo");
  r = run("cells unit.obj --json out.fifo");
  const std::string received = reader.finish();
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::is_fifo(dir_ / "out.fifo"));
  EXPECT_CONTAINS(received, "\"regions\"");
}

}  // namespace
