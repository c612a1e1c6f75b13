// Issue 13, 2D: bad and unusual inputs end with exit 2 (what and where) or a verdict, never a
// signal, a hang or a half-written output. Each reproducer of the issue is one test here; the
// large-coordinate metamorphic tests check that scaling by 2^k and translating by 1e15 leave the
// answer unchanged (or give a documented exit 2).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/run_immerse.h"

namespace {

namespace fs = std::filesystem;
using imm::test::RunOutcome;

#define EXPECT_CONTAINS(text, piece) \
  EXPECT_NE((text).find(piece), std::string::npos) << "expected '" << (piece) << "' in:\n" << (text)

class Reliability2 : public testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(IMM_IMMERSE_EXE)) GTEST_SKIP() << "no immerse binary at " << IMM_IMMERSE_EXE;
    dir_ = imm::test::fresh_test_directory("imm_rel2", testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void TearDown() override {
    if (dir_.empty()) return;
    for (const auto& entry : fs::recursive_directory_iterator(dir_))
      EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << "temporary left: " << entry.path();
    if (!HasFailure()) fs::remove_all(dir_);
  }
  RunOutcome run(const std::string& args) const {
    RunOutcome r = imm::test::run_immerse(dir_, args);
    EXPECT_EQ(r.signal, 0) << "immerse " << args << " was killed by signal " << r.signal << "\n" << r.output;
    return r;
  }
  void write(const std::string& name, const std::string& text) const { imm::test::write_file(dir_ / name, text); }
  [[nodiscard]] std::string read(const std::string& name) const { return imm::test::read_file(dir_ / name); }

  /// The curve of `name` with every coordinate multiplied by `scale` and shifted by `shift`,
  /// written as `out` (exact when scale is a power of two and shift is 0).
  void transform_curve(const std::string& name, double scale, double shift, const std::string& out) const {
    std::istringstream in(read(name));
    std::ostringstream os;
    os.precision(17);
    for (std::string line; std::getline(in, line);) {
      std::istringstream fields(line);
      double x = 0, y = 0;
      if (fields >> x >> y) {
        os << (x * scale + shift) << ' ' << (y * scale + shift) << '\n';
      } else {
        os << line << '\n';
      }
    }
    write(out, os.str());
  }

  /// "N cells, M patches, ..." (the first line of `immerse cells`), for comparisons.
  [[nodiscard]] std::string counts(const std::string& input) const {
    const RunOutcome r = run("cells " + input);
    EXPECT_EQ(r.code, 0) << r.output;
    return r.output.substr(0, r.output.find('\n'));
  }
  fs::path dir_;
};

// Defect 1: SIGSEGV inside the arrangement sweep at large coordinates.
TEST_F(Reliability2, LargeCoordinatesAreExact) {
  write("a.txt", "0 0\n1e155 0\n0 1e155\n");
  for (const char* command : {"check", "cells", "immersions"}) {
    const RunOutcome r = run(std::string(command) + " a.txt");
    EXPECT_EQ(r.code, 0) << command << "\n" << r.output;
  }
  // Two crossing squares at 1e110: the same complex as at unit scale.
  write("two.txt", "0 0\n4 0\n4 2\n0 2\n\n1 -1\n3 -1\n3 3\n1 3\n");
  transform_curve("two.txt", 1e110, 0, "two_big.txt");
  EXPECT_EQ(counts("two_big.txt"), counts("two.txt"));
  // The same near the top of the double range.
  transform_curve("two.txt", 1e300, 0, "two_huge.txt");
  EXPECT_EQ(counts("two_huge.txt"), counts("two.txt"));
}

TEST_F(Reliability2, ScaledAndTranslatedFig6KeepsItsImmersions) {
  ASSERT_EQ(run("generate fig6 -o fig6.txt").code, 0);
  const std::string reference = counts("fig6.txt");
  const RunOutcome base = run("immersions fig6.txt --all");
  ASSERT_EQ(base.code, 0) << base.output;
  EXPECT_CONTAINS(base.output, "2 immersions");
  // Scale by 2^k (exact) up to the exponent limits, by 1e120 (issue 13), translate by 1e15.
  std::vector<std::pair<double, double>> motions;
  for (int k : {-1000, -700, -300, -60, 60, 300, 700, 1000}) motions.push_back({std::ldexp(1.0, k), 0.0});
  motions.push_back({1e120, 0.0});
  motions.push_back({1.0, 1e15});
  for (const auto& [scale, shift] : motions) {
    SCOPED_TRACE(testing::Message() << "scale " << scale << " shift " << shift);
    transform_curve("fig6.txt", scale, shift, "moved.txt");
    EXPECT_EQ(counts("moved.txt"), reference);
    const RunOutcome r = run("immersions moved.txt --all");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_CONTAINS(r.output, "2 immersions");
  }
}

TEST_F(Reliability2, MeshingFarFromUnitScaleIsDoneOrRefusedWithTheLimit) {
  ASSERT_EQ(run("generate fig6 -o fig6.txt").code, 0);
  for (int k : {-1000, -300, 300, 1000}) {
    SCOPED_TRACE(testing::Message() << "scale 2^" << k);
    transform_curve("fig6.txt", std::ldexp(1.0, k), 0, "moved.txt");
    const RunOutcome r = run("mesh moved.txt --resolution 8 -o m.mesh --embedding m.emb");
    if (std::abs(k) <= 200) {
      EXPECT_EQ(r.code, 0) << r.output;
    } else {
      EXPECT_EQ(r.code, 2) << r.output;  // README: generating a background has coordinate limits
      EXPECT_CONTAINS(r.output, "cannot generate a background mesh");
      EXPECT_FALSE(fs::exists(dir_ / "m.mesh"));
    }
  }
}

// Defect 5: SVG transforms were ignored (a false overlap, or silently wrong geometry).
TEST_F(Reliability2, SvgTransformsAreApplied) {
  // Two unit squares drawn at the same place, one moved away by a transform: no overlap.
  write("t.svg",
        "<svg xmlns='http://www.w3.org/2000/svg'>\n"
        "<polygon points='0,0 10,0 10,10 0,10'/>\n"
        "<g transform='translate(100 0)'><g transform='scale(2)'>\n"
        "  <polygon points='0,0 10,0 10,10 0,10'/>\n"
        "</g></g>\n"
        "<rect x='0' y='0' width='10' height='10' transform='matrix(1 0 0 1 0 50)'/>\n"
        "</svg>\n");
  const RunOutcome r = run("cells t.svg --json c.json");
  EXPECT_EQ(r.code, 0) << r.output;
  // Areas: 100 + 400 (scaled by 2) + 100 = 600, in three cells of winding 1.
  const std::string json = read("c.json");
  EXPECT_CONTAINS(json, "\"400\"");
  // A transform applies to its element only: the square after </g> is not moved.
  write("u.svg",
        "<svg><g transform='translate(5 3)'><polygon points='0,0 10,0 10,10 0,10'/></g>"
        "<polygon points='0,0 10,0 10,10 0,10'/></svg>");
  const RunOutcome overlap = run("check u.svg");
  EXPECT_EQ(overlap.code, 0) << overlap.output;  // two squares crossing generically (untransformed: equal)
  // Shapes inside <defs> are not drawn: only one square here.
  write("d.svg", "<svg><defs><polygon id='p' points='0,0 1,0 1,1'/></defs><polygon points='0,0 4,0 4,4 0,4'/></svg>");
  const RunOutcome defs = run("cells d.svg");
  EXPECT_EQ(defs.code, 0) << defs.output;
  EXPECT_CONTAINS(defs.output, "1 cell");
}

TEST_F(Reliability2, SvgPercentagesUnitsAndClonesAreRefused) {
  write("p.svg", "<svg><rect x='0' y='0' width='10%' height='10'/></svg>");
  RunOutcome r = run("check p.svg");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "width='10%'");
  write("mm.svg", "<svg><rect x='0' y='0' width='10mm' height='10'/></svg>");
  r = run("check mm.svg");
  EXPECT_EQ(r.code, 2) << r.output;
  write("px.svg", "<svg><rect x='0' y='0' width='10px' height='10'/></svg>");
  EXPECT_EQ(run("check px.svg").code, 0);
  write("use.svg", "<svg><defs><polygon id='p' points='0,0 4,0 4,4'/></defs><use href='#p'/></svg>");
  r = run("check use.svg");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "<use>");
  write("bad.svg", "<svg><polygon transform='shear(3)' points='0,0 4,0 4,4'/></svg>");
  r = run("check bad.svg");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "shear");
  write("inf.svg", "<svg><polygon transform='scale(1e300) scale(1e300)' points='0,0 4,0 4,4'/></svg>");
  r = run("check inf.svg");
  EXPECT_EQ(r.code, 2) << r.output;
}

// Defect 8: --resolution 10,000 ended in std::bad_alloc (exit 1); now refused before allocating.
TEST_F(Reliability2, HugeResolutionIsRefusedWithTheCap) {
  ASSERT_EQ(run("generate fig6 -o fig6.txt").code, 0);
  for (const char* n : {"10000", "100000"}) {
    const RunOutcome r = run(std::string("mesh fig6.txt --resolution ") + n + " -o m.mesh");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_CONTAINS(r.output, "background triangles; at most 4000000");
    EXPECT_FALSE(fs::exists(dir_ / "m.mesh"));
  }
  EXPECT_EQ(run("mesh fig6.txt --resolution 300 -o m.mesh").code, 0);
}

// Defect 11 (2D reader): a binary file printed its raw bytes (183 KB) on stderr.
TEST_F(Reliability2, BinaryInputGivesAShortPrintableMessage) {
  std::string junk;
  std::uint32_t state = 12345;
  for (int i = 0; i < 200000; ++i) {
    state = state * 1664525u + 1013904223u;
    junk.push_back(static_cast<char>(state >> 24));
  }
  write("junk.txt", junk);
  const RunOutcome r = run("check junk.txt");
  EXPECT_EQ(r.code, 2);
  EXPECT_LT(r.output.size(), 8000u) << r.output.substr(0, 2000);
  for (char c : r.output)
    EXPECT_TRUE(c == '\n' || std::isprint(static_cast<unsigned char>(c))) << "byte " << int(static_cast<unsigned char>(c));
  EXPECT_CONTAINS(r.output, "more unreadable lines");
}

}  // namespace
