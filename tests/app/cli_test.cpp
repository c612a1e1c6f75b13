// End-to-end tests of the `immerse` binary (DESIGN §3): exit codes 0/1/2/3/64, the messages of
// every bad-input class, the report files and their agreement with the mesh files, the default
// job, and that no temporary "*.tmp.*" file is ever left behind.
//
// Each test runs the real executable (IMM_IMMERSE_EXE) with popen in a fresh temporary directory.
#include <algorithm>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/immerse_fixture.h"

namespace {

namespace fs = std::filesystem;

using imm::test::Outcome;

class CliTest : public imm::test::ImmerseTest {};

#define EXPECT_CONTAINS(text, piece) \
  EXPECT_NE((text).find(piece), std::string::npos) << "expected '" << (piece) << "' in:\n" << (text)

/// Points of a parametric curve, sampled off t = 0 and rounded to integers, as text.
template <class F>
std::string sampled_curve(int n, F f) {
  std::ostringstream os;
  os.precision(17);
  for (int k = 0; k < n; ++k) {
    const double t = 2.0 * M_PI * (k + 0.5) / n;
    const auto [x, y] = f(t);
    os << std::round(x) << ' ' << std::round(y) << '\n';
  }
  return os.str();
}

/// z(t) = e^{it} + 1.3 e^{3it} + 0.6 e^{-5it}: 10 crossings, winding numbers up to 3 and
/// exactly two immersions (the situation of the paper's Fig. 6).
std::string two_immersion_curve() {
  return sampled_curve(120, [](double t) {
    return std::pair{1000.0 * (std::cos(t) + 1.3 * std::cos(3 * t) + 0.6 * std::cos(-5 * t)),
                     1000.0 * (std::sin(t) + 1.3 * std::sin(3 * t) + 0.6 * std::sin(-5 * t))};
  });
}

/// r = 100 (1 + 2 cos t): a limaçon with an inner loop (turning number 2), not immersible.
std::string limacon_curve() {
  return sampled_curve(24, [](double t) {
    const double r = 100.0 * (1.0 + 2.0 * std::cos(t));
    return std::pair{r * std::cos(t), r * std::sin(t)};
  });
}

/// The first integer member named `key` of the JSON text, depth-first in document order, or -1.
long json_integer(const std::string& json, const std::string& key) {
  std::function<std::optional<long>(const nlohmann::ordered_json&)> find =
      [&](const nlohmann::ordered_json& v) -> std::optional<long> {
    if (v.is_object()) {
      for (const auto& [k, x] : v.items()) {
        if (k == key && x.is_number_integer()) return x.get<long>();
        if (auto found = find(x)) return found;
      }
    } else if (v.is_array()) {
      for (const auto& x : v) {
        if (auto found = find(x)) return found;
      }
    }
    return std::nullopt;
  };
  return find(nlohmann::ordered_json::parse(json)).value_or(-1);
}

/// The count following a Medit keyword line ("Vertices\n146").
long medit_count(const std::string& mesh, const std::string& keyword) {
  std::smatch m;
  if (!std::regex_search(mesh, m, std::regex("(^|\\n)" + keyword + "\\s+([0-9]+)"))) return -1;
  return std::stol(m[2]);
}

// ---- invalid input: exit 2, every defect named ---------------------------------------------

TEST_F(CliTest, EveryBadInputClassExitsWithTwoAndNamesTheDefect) {
  struct Case {
    const char* file;
    std::string content;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases = {
      {"open.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\n", {"not-closed", "open curve"}},
      {"short.txt", "0 0\n1 0\n", {"too-short", "at least 3"}},
      {"repeat.txt", "0 0\n1 0\n1 0\n0 1\n", {"duplicate-vertex", "vertices 1 and 2 are the same point (1, 0)"}},
      {"nan.txt", "0 0\nnan 0\n1 1\n", {"non-finite", "vertex 1"}},
      {"overlap.txt", "0 0\n10 0\n10 10\n0 10\n\n2 0\n8 0\n5 -5\n",
       {"collinear-overlap", "segments 0 and 4 overlap collinearly from (2, 0) to (8, 0)"}},
      {"touch.txt", "0 0\n10 0\n10 10\n0 10\n\n5 0\n7 -5\n3 -5\n",
       {"touching", "vertex 4 at (5, 0) lies on segment 0"}},
      {"triple.txt", "-10 -1\n10 1\n10 5\n\n-1 -10\n1 10\n-5 10\n\n-10 10\n10 -10\n10 -15\n",
       {"triple-point", "segments 0, 3 and 6 all pass through (0, 0)"}},
      {"empty.txt", "", {"empty", "no curve"}},
      {"surface.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       {"not-closed", "open boundary"}},
      {"surface.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", {"not-closed", "open boundary"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    write(c.file, c.content);
    for (const char* command : {"check", "immersions"}) {
      // --strict: exact contacts are defects too (by default they are resolved, see below).
      const Outcome r = run(std::string(command) + " " + c.file + " --strict");
      EXPECT_EQ(r.code, 2) << r.output;
      EXPECT_CONTAINS(r.output, "invalid input");
      for (const std::string& piece : c.expected) EXPECT_CONTAINS(r.output, piece);
    }
  }
  const Outcome missing = run("check missing.txt");
  EXPECT_EQ(missing.code, 2);
  EXPECT_CONTAINS(missing.output, "cannot open 'missing.txt'");
}

TEST_F(CliTest, EveryDefectIsListedAndTheJsonSaysSo) {
  // Two triangles hanging from the square at vertices on its bottom and top sides: two defects.
  write("two.txt", "0 0\n10 0\n10 10\n0 10\n\n5 0\n7 -5\n3 -5\n\n5 10\n3 15\n7 15\n");
  const Outcome r = run("cells two.txt --json two.json --strict");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "2 defects");
  EXPECT_CONTAINS(r.output, "vertex 4 at (5, 0) lies on segment 0");
  EXPECT_CONTAINS(r.output, "vertex 7 at (5, 10) lies on segment 2");
  const auto json = nlohmann::json::parse(read("two.json"));
  EXPECT_EQ(json["status"], "invalid-input");
  ASSERT_EQ(json["defects"].size(), 2u);
  for (const auto& defect : json["defects"]) EXPECT_EQ(defect["kind"], "touching") << defect;
}

// By default the same contacts are resolved by a tiny perturbation: a note, the counts per kind
// in the JSON, the two triangles kept apart from the square (3 cells: none of them merged).
TEST_F(CliTest, ExactContactsAreResolvedWithANote) {
  write("two.txt", "0 0\n10 0\n10 10\n0 10\n\n5 0\n3 -5\n7 -5\n\n5 10\n7 15\n3 15\n");
  const Outcome r = run("cells two.txt --json two.json");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_CONTAINS(r.output, "2 exact contacts (2 touching), resolved by perturbing the input by at most");
  const std::string json = read("two.json");
  EXPECT_CONTAINS(json, "\"resolved\": true");
  EXPECT_CONTAINS(json, "\"touching\": 2");
  const Outcome c = run("check two.txt");
  ASSERT_EQ(c.code, 0) << c.output;
  EXPECT_CONTAINS(c.output, "vertex 4 at (5, 0) lies on segment 0");
  EXPECT_CONTAINS(c.output, "3 cells");
  EXPECT_EQ(run("mesh two.txt -o two.mesh --embedding two.emb").code, 0);
}

// ---- verdicts: exit 3 ----------------------------------------------------------------------------

TEST_F(CliTest, LimaconIsNotImmersibleAndTheRuleIsNamed) {
  write("limacon.txt", limacon_curve());
  EXPECT_EQ(run("check limacon.txt").code, 0);
  const Outcome r = run("immersions limacon.txt --all --json limacon.json");
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_CONTAINS(r.output, "not immersible");
  EXPECT_TRUE(std::regex_search(r.output, std::regex("Rule [1-7]"))) << r.output;
  const std::string json = read("limacon.json");
  EXPECT_EQ(nlohmann::json::parse(json)["status"], "not-immersible");
  EXPECT_EQ(json_integer(json, "count"), 0);
  EXPECT_GE(json_integer(json, "rule"), 1);
  EXPECT_EQ(run("mesh limacon.txt -o limacon.mesh").code, 3);
  EXPECT_FALSE(exists("limacon.mesh"));
}

/// Coordinates the exact steps take but the double-precision background mesher cannot: a clear
/// exit 2, never a crash (it used to end in a segmentation fault inside the mesher).
TEST_F(CliTest, HugeAndTinyCoordinatesAreRefusedByTheMesherNotCrashed) {
  write("beyond.txt", "0 0\n1e300 0\n1e300 1e300\n0 1e300\n");
  write("tiny.txt", "0 0\n1e-70 0\n1e-70 1e-70\n0 1e-70\n");
  // Beyond the 2D coordinate range (README, Limits): exit 2 for every command (issue 13).
  const Outcome beyond = run("immersions beyond.txt");
  EXPECT_EQ(beyond.code, 2) << beyond.output;
  EXPECT_CONTAINS(beyond.output, "|x|, |y| <= 1e75");
  for (const char* file : {"tiny.txt"}) {
    SCOPED_TRACE(file);
    EXPECT_EQ(run(std::string("immersions ") + file).code, 0);  // exact steps are fine
    const Outcome r = run(std::string("mesh ") + file + " -o out.mesh");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_CONTAINS(r.output, "out-of-range");
    EXPECT_CONTAINS(r.output, "--background");
    EXPECT_FALSE(exists("out.mesh"));
  }
}

TEST_F(CliTest, InvertedRegionExitsWithThree) {
  // A figure-eight: winding numbers +1 and -1 (paper §3, Fig. 8).
  write("eight.txt", sampled_curve(48, [](double t) {
          return std::pair{1000.0 * std::sin(t), 500.0 * std::sin(2 * t)};
        }));
  const Outcome r = run("immersions eight.txt");
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_CONTAINS(r.output, "winding number -1");
  EXPECT_CONTAINS(r.output, "invert");
}

TEST_F(CliTest, SearchBudgetExhaustionExitsWithThree) {
  write("doodle.txt", two_immersion_curve());
  const Outcome r = run("immersions doodle.txt --all --max-states 1");
  EXPECT_EQ(r.code, 3) << r.output;
  EXPECT_CONTAINS(r.output, "search budget exhausted after 1 states");
}

// ---- results --------------------------------------------------------------------------------------

TEST_F(CliTest, TwoImmersionsWithSvgAndJson) {
  write("doodle.txt", two_immersion_curve());
  const Outcome r = run("immersions doodle.txt --all --svg pictures --json doodle.json");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_CONTAINS(r.output, "2 immersions");
  std::vector<std::string> svgs;
  for (const auto& entry : fs::directory_iterator(dir_ / "pictures")) svgs.push_back(entry.path().filename().string());
  std::sort(svgs.begin(), svgs.end());
  EXPECT_EQ(svgs, (std::vector<std::string>{"immersion_0.svg", "immersion_1.svg"}));
  EXPECT_CONTAINS(read("pictures/immersion_1.svg"), "</svg>");
  const std::string json = read("doodle.json");
  EXPECT_EQ(json_integer(json, "count"), 2);
  EXPECT_EQ(nlohmann::json::parse(json)["status"], "immersible");
  EXPECT_EQ(nlohmann::json::parse(json)["complete"], true);
  // Without --all the search stops at one and says so.
  const Outcome one = run("immersions doodle.txt");
  EXPECT_EQ(one.code, 0) << one.output;
  EXPECT_CONTAINS(one.output, "1 immersion");
  EXPECT_CONTAINS(one.output, "use --all");
}

TEST_F(CliTest, CellsJsonHasExactAreasAndCcwJunctions) {
  write("doodle.txt", two_immersion_curve());
  const Outcome r = run("cells doodle.txt --json cells.json");
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string json = read("cells.json");
  EXPECT_EQ(json_integer(json, "arcs"), 10);
  EXPECT_EQ(json_integer(json, "max_winding"), 3);
  const auto cells = nlohmann::json::parse(json);
  ASSERT_FALSE(cells["regions"].empty());
  for (const auto& region : cells["regions"]) {
    EXPECT_TRUE(std::regex_match(region["area"].get<std::string>(), std::regex("-?[0-9]+(/[0-9]+)?"))) << region;
  }
  ASSERT_EQ(cells["arcs"].size(), 10u);
  EXPECT_EQ(cells["arcs"][0]["junction_patches_ccw"].size(), 4u);
  EXPECT_FALSE(cells["input"]["reversed"].get<bool>());
}

TEST_F(CliTest, ClockwiseInputIsReversedAndSaysSo) {
  write("cw.txt", "0 0\n0 10\n10 10\n10 0\n");
  const Outcome r = run("cells cw.txt --json cw.json");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_CONTAINS(r.output, "reversed");
  EXPECT_EQ(nlohmann::json::parse(read("cw.json"))["input"]["reversed"], true);
}

TEST_F(CliTest, MeshFilesMatchTheJsonCounts) {
  write("doodle.txt", two_immersion_curve());
  const Outcome r = run(
      "mesh doodle.txt --resolution 12 --immersion 1 -o m/doodle.mesh --embedding m/doodle.emb "
      "--svg m/doodle.svg --json m/doodle.json");
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string json = read("m/doodle.json");
  const std::string mesh = read("m/doodle.mesh");
  EXPECT_EQ(json_integer(json, "immersion"), 1);
  const long triangles = json_integer(json, "output_triangles");
  const long vertices = json_integer(json, "output_vertices");
  EXPECT_GT(triangles, 0);
  EXPECT_EQ(medit_count(mesh, "Triangles"), triangles);
  EXPECT_EQ(medit_count(mesh, "Vertices"), vertices);
  EXPECT_CONTAINS(mesh, "Dimension 2");
  // .emb: the number of input vertices, then one line per input vertex.
  std::istringstream emb(read("m/doodle.emb"));
  long count = 0;
  emb >> count;
  EXPECT_EQ(count, 120);
  EXPECT_EQ(json_integer(json, "input_vertices"), 120);
  std::string line;
  long lines = 0;
  std::getline(emb, line);
  while (std::getline(emb, line)) lines += line.empty() ? 0 : 1;
  EXPECT_EQ(lines, 120);
  EXPECT_CONTAINS(read("m/doodle.svg"), "</svg>");
  // The CSG baseline (exact polygon booleans per triangle) gives the same duplication: the same
  // vertex copies and triangle copies with the same references, numbered in another order when
  // it lists a triangle's local regions in another order.
  const Outcome csg = run("mesh doodle.txt --resolution 12 --immersion 1 --method csg -o m/csg.mesh "
                          "--embedding m/csg.emb --json m/csg.json");
  ASSERT_EQ(csg.code, 0) << csg.output;
  const std::string csg_mesh = read("m/csg.mesh");
  EXPECT_EQ(medit_count(csg_mesh, "Triangles"), triangles);
  EXPECT_EQ(medit_count(csg_mesh, "Vertices"), vertices);
  const auto sorted_lines = [](const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    std::sort(lines.begin(), lines.end());
    return lines;
  };
  // Vertex positions (as a multiset) and the references of the triangles agree.
  const auto references = [](const std::string& text) {
    std::istringstream in(text.substr(text.find("Triangles")));
    std::string word;
    long n = 0;
    in >> word >> n;
    std::vector<long> refs;
    for (long i = 0; i < n; ++i) {
      long a = 0, b = 0, c = 0, ref = 0;
      in >> a >> b >> c >> ref;
      refs.push_back(ref);
    }
    std::sort(refs.begin(), refs.end());
    return refs;
  };
  EXPECT_EQ(sorted_lines(csg_mesh.substr(0, csg_mesh.find("Triangles"))),
            sorted_lines(mesh.substr(0, mesh.find("Triangles"))));
  EXPECT_EQ(references(csg_mesh), references(mesh));
  EXPECT_EQ(nlohmann::json::parse(read("m/csg.json"))["options"]["method"], "csg");
  // The one-line timing summary, always on stderr.
  EXPECT_TRUE(std::regex_search(r.output, std::regex("immerse: .*\\| read [0-9.]+ ms, complex .*search .*mesh ")))
      << r.output;
}

// ---- command line ---------------------------------------------------------------------------------

TEST_F(CliTest, UsageErrorsExitWith64) {
  write("doodle.txt", two_immersion_curve());
  const std::vector<std::string> bad = {
      "frobnicate",
      "--frobnicate",
      "check",
      "check a.txt b.txt",
      "cells doodle.txt --frob",
      "cells doodle.txt --json",
      "immersions doodle.txt --max 0",
      "immersions doodle.txt --max two",
      "immersions doodle.txt --all --max 2",
      "immersions doodle.txt --time-limit -1",
      "mesh doodle.txt --resolution 0",
      "mesh doodle.txt --resolution 10 --background b.mesh",
      "mesh doodle.txt --immersion -1",
      "mesh doodle.txt --immersion 2",  // the curve has immersions 0 and 1 only
      "mesh doodle.txt --method sketch",
      "generate",
      "generate no-such-curve",
  };
  for (const std::string& args : bad) {
    const Outcome r = run(args);
    EXPECT_EQ(r.code, 64) << args << "\n" << r.output;
    EXPECT_CONTAINS(r.output, "--help");
  }
  const Outcome help = run("--help");
  EXPECT_EQ(help.code, 0);
  EXPECT_CONTAINS(help.output, "exit codes");
  EXPECT_CONTAINS(help.output, "64");
  for (const char* command : {"check", "cells", "immersions", "mesh", "generate"}) {
    const Outcome r = run(std::string(command) + " --help");
    EXPECT_EQ(r.code, 0) << command;
    EXPECT_CONTAINS(r.output, std::string("usage: immerse ") + command);
  }
}

TEST_F(CliTest, GenerateListsAndWritesCurves) {
  const Outcome list = run("generate --list");
  ASSERT_EQ(list.code, 0) << list.output;
  EXPECT_CONTAINS(list.output, "convex");
  const Outcome convex = run("generate convex -o shapes/convex.txt");
  ASSERT_EQ(convex.code, 0) << convex.output;
  const Outcome check = run("check shapes/convex.txt");
  EXPECT_EQ(check.code, 0) << check.output;
  EXPECT_CONTAINS(check.output, "valid");
}

/// Issue 19: a generated pile of overlapping circles is immersible with either search order,
/// and the old order (--classic-search) explores more states for the same first immersion.
TEST_F(CliTest, CirclesPileWithBothSearchOrders) {
  const Outcome g = run("generate circles-pile k=10 seed=2 n=16 -o pile.txt");
  ASSERT_EQ(g.code, 0) << g.output;
  const Outcome fast = run("immersions pile.txt --json fast.json");
  ASSERT_EQ(fast.code, 0) << fast.output;
  const Outcome slow = run("immersions pile.txt --classic-search --json slow.json");
  ASSERT_EQ(slow.code, 0) << slow.output;
  const auto states = [&](const std::string& file) {
    return nlohmann::json::parse(read(file))["stats"]["states"].get<long>();
  };
  EXPECT_LT(states("fast.json"), states("slow.json"));
  const Outcome all = run("immersions pile.txt --all --classic-search");
  EXPECT_EQ(all.code, 0) << all.output;
  EXPECT_CONTAINS(all.output, "1 immersion");
}

TEST_F(CliTest, GeneratedFiguresGiveTheirKnownVerdicts) {
  // `immerse generate` then `immerse immersions --all` on the paper's figure curves
  // (dim2/generators.h): the counts the generators are designed for, through the binary.
  struct Case {
    const char* name;
    int code;
    const char* expected;
  };
  const std::vector<Case> cases = {
      {"fig5", 0, "1 immersion"},        {"fig6", 0, "2 immersions"},
      {"fig7", 0, "1 immersion"},        {"fig8", 3, "not immersible"},
      {"fig9", 0, "1 immersion"},        {"fig12-simple", 0, "1 immersion"},
      {"fig12-ring", 3, "self-connecting"}, {"fig15", 0, "1 immersion"},
      {"figure-eight", 3, "winding number -1"}, {"doodle 3", 0, "5 immersions"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string file = std::string("gen/") + std::regex_replace(c.name, std::regex(" "), "_") + ".txt";
    const Outcome g = run(std::string("generate ") + c.name + " -o " + file);
    ASSERT_EQ(g.code, 0) << g.output;
    EXPECT_EQ(run("check " + file).code, 0);
    const Outcome r = run("immersions " + file + " --all");
    EXPECT_EQ(r.code, c.code) << r.output;
    EXPECT_CONTAINS(r.output, c.expected);
  }
  // fig6 with pictures: one SVG per immersion, and the JSON agrees.
  const Outcome r = run("immersions gen/fig6.txt --all --svg fig6_svg --json fig6.json");
  ASSERT_EQ(r.code, 0) << r.output;
  std::vector<std::string> svgs;
  for (const auto& entry : fs::directory_iterator(dir_ / "fig6_svg")) svgs.push_back(entry.path().filename().string());
  std::sort(svgs.begin(), svgs.end());
  EXPECT_EQ(svgs, (std::vector<std::string>{"immersion_0.svg", "immersion_1.svg"}));
  EXPECT_EQ(json_integer(read("fig6.json"), "count"), 2);
  // Parameters and the OBJ output format.
  const Outcome obj = run("generate doodle-chain 2 -o gen/chain.obj");
  ASSERT_EQ(obj.code, 0) << obj.output;
  const Outcome chain = run("immersions gen/chain.obj --all");
  EXPECT_EQ(chain.code, 0) << chain.output;
  EXPECT_CONTAINS(chain.output, "4 immersions");
  // SVG output reads back to the same complex.
  ASSERT_EQ(run("generate fig9 -o gen/fig9.svg").code, 0);
  const Outcome svg = run("cells gen/fig9.svg --json fig9_svg.json");
  ASSERT_EQ(svg.code, 0) << svg.output;
  const Outcome txt = run("cells gen/fig9.txt --json fig9_txt.json");
  ASSERT_EQ(txt.code, 0) << txt.output;
  for (const char* key : {"cells", "patches", "arcs", "max_winding"}) {
    EXPECT_EQ(json_integer(read("fig9_svg.json"), key), json_integer(read("fig9_txt.json"), key)) << key;
  }
  EXPECT_EQ(json_integer(read("fig9_txt.json"), "cells"), 4);
  EXPECT_EQ(run("generate doodle 0").code, 64);
}

TEST_F(CliTest, UnwritableOutputExitsWithOneAndLeavesNothing) {
  write("doodle.txt", two_immersion_curve());
  write("blocker", "a file where a directory is expected\n");
  fs::create_directories(dir_ / "a_directory");
  const Outcome into_file = run("cells doodle.txt --json blocker/cells.json");
  EXPECT_EQ(into_file.code, 1) << into_file.output;
  const Outcome onto_directory = run("cells doodle.txt --json a_directory");
  EXPECT_EQ(onto_directory.code, 1) << onto_directory.output;
  EXPECT_TRUE(fs::is_directory(dir_ / "a_directory"));
  // TearDown checks that no "*.tmp.*" file was left.
}

TEST_F(CliTest, DefaultJobWritesTheOutDirectory) {
  const Outcome r = run("");
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* name : {"input.txt", "input.svg", "cells.json", "immersions.json", "immersion_0.svg",
                           "mesh.mesh", "mesh.emb", "mesh.svg", "mesh.json"}) {
    SCOPED_TRACE(name);
    EXPECT_TRUE(exists(std::string("out/") + name));
    EXPECT_CONTAINS(r.output, std::string("out/") + name);
  }
  // The bundled curve has several immersions, each drawn.
  const std::string json = read("out/immersions.json");
  const long count = json_integer(json, "count");
  EXPECT_GE(count, 2);
  for (long k = 0; k < count; ++k) EXPECT_TRUE(exists("out/immersion_" + std::to_string(k) + ".svg")) << k;
  EXPECT_EQ(medit_count(read("out/mesh.mesh"), "Triangles"), json_integer(read("out/mesh.json"), "output_triangles"));
  EXPECT_CONTAINS(r.output, "| generate ");
}

}  // namespace
