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

#include "support/immerse_fixture.h"

namespace {

namespace fs = std::filesystem;
using imm::test::RunOutcome;

#define EXPECT_CONTAINS(text, piece) \
  EXPECT_NE((text).find(piece), std::string::npos) << "expected '" << (piece) << "' in:\n" << (text)

class Reliability2 : public imm::test::ImmerseTest {
 protected:
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

  /// "8 regions, 7 cells, 12 patches, 6 arcs ..." (the second line of `immerse cells`) and the
  /// winding column of the cell table, for comparisons.
  [[nodiscard]] std::string counts(const std::string& input) const {
    const RunOutcome r = run("cells " + input);
    EXPECT_EQ(r.code, 0) << r.output;
    std::istringstream lines(r.output);
    std::string line, out;
    std::getline(lines, line);  // names the file
    std::getline(lines, out);
    std::getline(lines, line);  // the table's header
    while (std::getline(lines, line)) {
      std::istringstream fields(line);
      std::string cell, region, winding;
      if (fields >> cell >> region >> winding) out += " " + winding;
    }
    return out;
  }
};

// Defect 1: SIGSEGV inside the arrangement sweep at large coordinates (CGAL's interval filters
// overflow beyond about 1e102). Now: exact up to the documented range 1e75, exit 2 beyond it.
TEST_F(Reliability2, LargeCoordinatesAreExactOrRefusedWithTheRange) {
  write("a.txt", "0 0\n1e155 0\n0 1e155\n");
  for (const char* command : {"check", "cells", "immersions", "mesh"}) {
    const RunOutcome r = run(std::string(command) + " a.txt" + (command[0] == 'm' ? " -o a.mesh" : ""));
    EXPECT_EQ(r.code, 2) << command << "\n" << r.output;
    EXPECT_CONTAINS(r.output, "vertex 1 (1e+155, 0) lies beyond the coordinate range of 2D inputs, |x|, |y| <= 1e75");
  }
  EXPECT_FALSE(fs::exists(dir_ / "a.mesh"));
  // Two crossing squares near the limit: the same complex as at unit scale.
  write("two.txt", "0 0\n4 0\n4 2\n0 2\n\n1 -1\n3 -1\n3 3\n1 3\n");
  transform_curve("two.txt", 1e74, 0, "two_big.txt");
  EXPECT_EQ(counts("two_big.txt"), counts("two.txt"));
  for (double scale : {1e110, 1e300}) {
    transform_curve("two.txt", scale, 0, "two_huge.txt");
    const RunOutcome r = run("cells two_huge.txt");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_CONTAINS(r.output, "|x|, |y| <= 1e75");
  }
  // Many vertices beyond: ten listed, then one count.
  std::string many;
  for (int i = 0; i < 30; ++i) many += std::to_string(i) + "e80 " + std::to_string(i % 2) + "\n";
  write("many.txt", many);
  const RunOutcome r = run("check many.txt");
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.output, "and 19 more vertices beyond 1e75");
}

TEST_F(Reliability2, ScaledAndTranslatedFig6KeepsItsImmersions) {
  ASSERT_EQ(run("generate fig6 -o fig6.txt").code, 0);
  const std::string reference = counts("fig6.txt");
  const RunOutcome base = run("immersions fig6.txt --all");
  ASSERT_EQ(base.code, 0) << base.output;
  EXPECT_CONTAINS(base.output, "2 immersions");
  // Scale by 2^k (exact) up to the exponent limits, by 1e120 (issue 13), translate by 1e15.
  std::vector<std::pair<double, double>> motions;
  // Down to the bottom of the exponent range: no limit (intervals that underflow stay
  // conservative); up to the documented range 1e75 (fig6 reaches about 1e3; 2^230 ~ 1.7e69).
  for (int k : {-1000, -700, -300, -60, 60, 230}) motions.push_back({std::ldexp(1.0, k), 0.0});
  motions.push_back({1.0, 1e15});
  motions.push_back({1.0, -1e15});
  for (const auto& [scale, shift] : motions) {
    SCOPED_TRACE(testing::Message() << "scale " << scale << " shift " << shift);
    transform_curve("fig6.txt", scale, shift, "moved.txt");
    EXPECT_EQ(counts("moved.txt"), reference);
    const RunOutcome r = run("immersions moved.txt --all");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_CONTAINS(r.output, "2 immersions");
  }
  // Beyond the range (1e120 crashed, issue 13): a clear exit 2.
  for (double scale : {std::ldexp(1.0, 300), 1e120, std::ldexp(1.0, 1000)}) {
    transform_curve("fig6.txt", scale, 0, "moved.txt");
    const RunOutcome r = run("immersions moved.txt --all");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_CONTAINS(r.output, "beyond the coordinate range");
  }
}

TEST_F(Reliability2, MeshingFarFromUnitScaleIsDoneOrRefusedWithTheLimit) {
  ASSERT_EQ(run("generate fig6 -o fig6.txt").code, 0);
  for (int k : {-1000, -100, 100, 230}) {
    SCOPED_TRACE(testing::Message() << "scale 2^" << k);
    transform_curve("fig6.txt", std::ldexp(1.0, k), 0, "moved.txt");
    const RunOutcome r = run("mesh moved.txt --resolution 8 -o m.mesh --embedding m.emb");
    if (k >= -100) {
      EXPECT_EQ(r.code, 0) << r.output;
    } else {
      EXPECT_EQ(r.code, 2) << r.output;  // README: a generated background needs a diagonal >= 1e-60
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
  // Random bytes hold a NUL early: the read stops there (an endless binary stream stops too).
  EXPECT_CONTAINS(r.output, "not a text file");
}

// Found by scripts/fuzz.py (seed 11): 21 stacked copies of two crossing squares printed 80 KB of
// defects (each names 21 curves); at most 50 lines now, the rest counted (all are in --json).
TEST_F(Reliability2, ManyDefectsPrintAShortListing) {
  std::string copies;
  for (int k = 0; k < 21; ++k) copies += "0 0\n4 0\n4 2\n0 2\n\n1 -1\n3 -1\n3 3\n1 3\n\n";
  write("stacked.txt", copies);
  // --strict: without it the identical copies are contacts a perturbation resolves (exit 0).
  const RunOutcome r = run("cells stacked.txt --strict --json defects.json");
  EXPECT_EQ(r.code, 2);
  EXPECT_LT(r.output.size(), 32000u);
  EXPECT_CONTAINS(r.output, "more");
  EXPECT_GT(read("defects.json").size(), r.output.size());  // the report has every defect
}

// Found by scripts/fuzz.py (seed 1): an SVG path command byte that is not UTF-8, quoted in the
// message, made the JSON report impossible to write (exit 1).
TEST_F(Reliability2, NonTextBytesInMessagesAreEscaped) {
  write("bad.svg", std::string("<svg><path d='M 0 0 L 4 0 \xc1 4 4 Z'/></svg>"));
  const RunOutcome r = run("immersions bad.svg --json bad.json");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "unknown path command '?'");
  EXPECT_CONTAINS(read("bad.json"), "invalid-input");
}

// Defect 7: --time-limit stopped the search, then SVGs were written for minutes (about 15 GB).
TEST_F(Reliability2, OutputsAreBoundedBeforeTheyAreBuilt) {
  ASSERT_EQ(run("generate fig6 -o fig6.txt").code, 0);
  // Two drawings of some 10 KB each do not fit 1,000 bytes: refused before the first one.
  RunOutcome r = run("immersions fig6.txt --all --svg drawings --max-output 1000");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_CONTAINS(r.output, "2 SVG drawings would take about");
  EXPECT_CONTAINS(r.output, "--max-output");
  EXPECT_FALSE(fs::exists(dir_ / "drawings" / "immersion_0.svg"));
  r = run("immersions fig6.txt --all --json all.json --max-output 1000");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "all.json"));
  // Within the budget: written.
  r = run("immersions fig6.txt --all --svg drawings --json all.json --max-output 100000000");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "drawings" / "immersion_1.svg"));
  // The time limit bounds the whole command: once it has passed, nothing more is written.
  r = run("immersions fig6.txt --all --time-limit 1e-9 --json late.json");
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_CONTAINS(r.output, "time limit");
  EXPECT_FALSE(fs::exists(dir_ / "late.json"));
}

TEST_F(Reliability2, ManyImmersionsAreRefusedNotWrittenForMinutes) {
  ASSERT_EQ(run("generate doodle-chain 16 -o chain.txt").code, 0);
  const RunOutcome r = run("immersions chain.txt --all --time-limit 2 --svg drawings");
  EXPECT_TRUE(r.code == 1 || r.code == 3) << r.output;
  EXPECT_CONTAINS(r.output, "not written");
  EXPECT_FALSE(fs::exists(dir_ / "drawings" / "immersion_0.svg"));
}

// Defect 9: a background far larger than the input lost the embedding's precision silently.
TEST_F(Reliability2, EmbeddingPrecisionIsMeasuredAndWarned) {
  write("square.txt", "0 0\n1 0\n1 1\n0 1\n");
  const auto background = [&](double size) {
    std::ostringstream os;
    os.precision(17);
    os << "MeshVersionFormatted 2\nDimension 2\nVertices\n3\n" << -size << ' ' << -size << " 0\n"
       << 3 * size << ' ' << -size << " 0\n" << -size << ' ' << 3 * size << " 0\nTriangles\n1\n1 2 3 0\nEnd\n";
    return os.str();
  };
  write("near.mesh", background(2));
  write("far.mesh", background(1e10));
  RunOutcome r = run("mesh square.txt --background near.mesh -o a.mesh --json a.json");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output.find("warning: the embedding"), std::string::npos) << r.output;
  r = run("mesh square.txt --background far.mesh -o b.mesh --json b.json");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_CONTAINS(r.output, "warning: the embedding reproduces the input vertices only within");
  EXPECT_CONTAINS(read("b.json"), "\"embedding_error\"");
}

}  // namespace
