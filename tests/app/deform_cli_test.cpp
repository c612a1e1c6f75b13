// `immerse deform` and `immerse weights` (app/cli_deform.cpp) through the real executable: the
// pull-apart of Fig. 7 on the unglued mesh leaves no crossing, on the glued baseline it keeps them;
// bad handle files exit 2 with a message; outputs are written per frame.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "support/immerse_fixture.h"

namespace {

namespace fs = std::filesystem;

using imm::test::Outcome;

class DeformCli : public imm::test::ImmerseTest {};

constexpr const char* kPullApart = R"({"handles": [
  {"box": {"min": [-10000, -10000], "max": [-650, 10000]}, "displacement": [-800, 0]},
  {"box": {"min": [680, -10000], "max": [10000, 10000]}, "displacement": [800, 0]}]})";

/// The crossings reported for the last frame ("frame N: I inverted elements, C self-intersecting ...").
int last_crossings(const std::string& output) {
  const std::regex line(R"(frame \d+: (\d+) inverted elements, (\d+) self-intersecting)");
  int crossings = -1;
  for (auto it = std::sregex_iterator(output.begin(), output.end(), line); it != std::sregex_iterator(); ++it)
    crossings = std::stoi((*it)[2]);
  return crossings;
}

TEST_F(DeformCli, Fig7PullsApartUngluedButNotGlued) {
  ASSERT_EQ(run("generate fig7 -o fig7.txt").code, 0);
  write("h.json", kPullApart);
  const Outcome unglued = run("deform fig7.txt --handles h.json -o out --frames 2 --resolution 20 --json out/r.json");
  ASSERT_EQ(unglued.code, 0) << unglued.output;
  EXPECT_EQ(last_crossings(unglued.output), 0) << unglued.output;
  EXPECT_NE(unglued.output.find("frame 2: 0 inverted elements"), std::string::npos) << unglued.output;
  EXPECT_TRUE(exists("out/mesh_001.vtu"));
  EXPECT_TRUE(exists("out/input_002.txt"));
  EXPECT_NE(read("out/r.json").find("\"input_self_intersections\""), std::string::npos);
  const Outcome glued = run("deform fig7.txt --handles h.json -o glued --frames 1 --resolution 20 --glued");
  ASSERT_EQ(glued.code, 0) << glued.output;
  EXPECT_GT(last_crossings(glued.output), 0) << glued.output;
}

TEST_F(DeformCli, FemAndWeightsRun) {
  ASSERT_EQ(run("generate fig7 -o fig7.txt").code, 0);
  write("h.json", kPullApart);
  const Outcome fem = run("deform fig7.txt --handles h.json -o fem --method fem-static --frames 1 --resolution 16");
  ASSERT_EQ(fem.code, 0) << fem.output;
  EXPECT_EQ(last_crossings(fem.output), 0) << fem.output;
  const Outcome weights = run("weights fig7.txt --handles h.json -o w.vtu --resolution 16");
  ASSERT_EQ(weights.code, 0) << weights.output;
  EXPECT_NE(read("w.vtu").find("Name=\"weight_1\""), std::string::npos);
}

// The README's dynamic example: Fig. 7 (1,600 units across) pulled 800 units in ten frames of
// 1/60 s follows its handles only with a material stiff for that scale; with the default modulus
// the far side lags and the curves stay crossed (inertia, not a defect of the unglued mesh).
TEST_F(DeformCli, DynamicFemFollowsTheHandlesWithAMaterialForTheScale) {
  ASSERT_EQ(run("generate fig7 -o fig7.txt").code, 0);
  std::string stiff = kPullApart;
  stiff.insert(stiff.rfind('}'), R"(, "material": {"youngs_modulus": 1e8})");
  write("stiff.json", stiff);
  write("soft.json", kPullApart);
  const Outcome follows = run("deform fig7.txt --handles stiff.json -o stiff --method fem");
  ASSERT_EQ(follows.code, 0) << follows.output;
  EXPECT_EQ(last_crossings(follows.output), 0) << follows.output;
  EXPECT_NE(follows.output.find("frame 10: 0 inverted elements"), std::string::npos) << follows.output;
  const Outcome lags = run("deform fig7.txt --handles soft.json -o soft --method fem");
  ASSERT_EQ(lags.code, 0) << lags.output;
  EXPECT_GT(last_crossings(lags.output), 0) << lags.output;
}

TEST_F(DeformCli, ConformingMeshesPullApartToo) {
  // The conforming meshes (2D: the curve as constraints; 3D: TetGen's tets bounded by the cut
  // mesh) deform like the background ones: the unglued mesh pulls the overlapping parts apart.
  ASSERT_EQ(run("generate fig7 -o fig7.txt").code, 0);
  write("h.json", kPullApart);
  const Outcome flat = run("deform fig7.txt --handles h.json -o flat --frames 2 --resolution 20 --conforming");
  ASSERT_EQ(flat.code, 0) << flat.output;
  EXPECT_EQ(last_crossings(flat.output), 0) << flat.output;
  ASSERT_EQ(run("generate two-tori 10 -o tori.obj").code, 0);
  write("t.json", R"({"handles": [
    {"box": {"min": [-10, -10, -10], "max": [-1.0, 10, 10]}, "displacement": [-3, 0, 0]},
    {"box": {"min": [2.0, -10, -10], "max": [10, 10, 10]}, "displacement": [3, 0, 0]}]})");
  const Outcome solid = run("deform tori.obj --handles t.json -o solid --frames 2 --conforming --edge-length 0.3");
  ASSERT_EQ(solid.code, 0) << solid.output;
  EXPECT_EQ(last_crossings(solid.output), 0) << solid.output;
  EXPECT_TRUE(exists("solid/mesh_002.vtu"));
  const Outcome glued = run("deform tori.obj --handles t.json -o glued --frames 2 --conforming --edge-length 0.3 --glued");
  ASSERT_EQ(glued.code, 0) << glued.output;
  EXPECT_GT(last_crossings(glued.output), 0) << glued.output;
  const Outcome weights = run("weights tori.obj --handles t.json -o w.vtu --conforming --edge-length 0.3");
  ASSERT_EQ(weights.code, 0) << weights.output;
  EXPECT_EQ(run("deform tori.obj --handles t.json -o x --conforming --background b.veg").code, 64);
  EXPECT_EQ(run("deform tori.obj --handles t.json -o x --edge-length 0.3").code, 64);
}

TEST_F(DeformCli, BadHandleFilesExit2WithAMessage) {
  ASSERT_EQ(run("generate fig7 -o fig7.txt").code, 0);
  write("bad.json", "{\"handles\": [");
  Outcome r = run("deform fig7.txt --handles bad.json -o out --resolution 12");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("not valid JSON"), std::string::npos) << r.output;
  write("empty.json", R"({"handles": [{"box": {"min": [5000, 5000], "max": [6000, 6000]}}]})");
  r = run("deform fig7.txt --handles empty.json -o out --resolution 12");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("handle 0 selects no mesh vertex"), std::string::npos) << r.output;
  write("twice.json", R"({"handles": [{"vertices": [0]}, {"vertices": [0]}]})");
  r = run("deform fig7.txt --handles twice.json -o out --resolution 12");
  EXPECT_EQ(r.code, 2) << r.output;
  write("dim.json", R"({"handles": [{"vertices": [0], "displacement": [1, 2, 3]}]})");
  r = run("deform fig7.txt --handles dim.json -o out --resolution 12");
  EXPECT_EQ(r.code, 2) << r.output;
  r = run("deform fig7.txt -o out");
  EXPECT_EQ(r.code, 64) << r.output;
  r = run("deform fig7.txt --handles missing.json -o out --resolution 12");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_FALSE(exists("out"));
}

TEST_F(DeformCli, ResolutionAndBackgroundExcludeEachOtherAsInMesh) {
  ASSERT_EQ(run("generate two-spheres 6 -o ts.obj").code, 0);
  write("h.json", R"({"handles": [{"vertices": [0], "displacement": [1, 0, 0]}]})");
  const Outcome mesh = run("mesh ts.obj --resolution 8 --background bg.veg -o m.vtu");
  EXPECT_EQ(mesh.code, 64) << mesh.output;
  for (const char* command : {"deform ts.obj --handles h.json -o out", "weights ts.obj --handles h.json -o w.vtu"}) {
    SCOPED_TRACE(command);
    const Outcome r = run(std::string(command) + " --resolution 8 --background bg.veg");
    EXPECT_EQ(r.code, 64) << r.output;
    EXPECT_NE(r.output.find("--resolution and --background exclude each other"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(exists("out"));
}

/// The first line of a usage error: "immerse COMMAND: message".
std::string usage_message(const std::string& output, const std::string& command) {
  const std::string prefix = "immerse " + command + ": ";
  const std::size_t at = output.find(prefix);
  if (at == std::string::npos) return {};
  const std::size_t end = output.find('\n', at);
  return output.substr(at + prefix.size(), end - at - prefix.size());
}

// deform and weights parse the mesher options with mesh's own parser (parse_mesh_choice): every
// combination mesh refuses, they refuse with the same message, before any work.
TEST_F(DeformCli, MesherOptionsAreCheckedAsMeshChecksThem) {
  ASSERT_EQ(run("generate two-spheres 6 -o ts.obj").code, 0);
  ASSERT_EQ(run("generate fig7 -o fig7.txt").code, 0);
  write("h.json", R"({"handles": [{"vertices": [0], "displacement": [1, 0, 0]}]})");
  const char* bad[] = {
      "ts.obj --resolution 8 --background bg.veg",
      "ts.obj --surface-resolution 16 --background bg.veg",
      "ts.obj --gap-resolution 64",
      "ts.obj --resolution 16 --surface-resolution 8",
      "ts.obj --surface-resolution 16 --gap-resolution 8",
      "ts.obj --conforming --surface-resolution 16",
      "ts.obj --conforming --background bg.veg",
      "ts.obj --edge-length 0.1",
      "ts.obj --conforming --radius-edge 0.5",
      "ts.obj --resolution 151",
      "ts.obj --background bg.obj",
      "fig7.txt --surface-resolution 16",
      "fig7.txt --conforming --edge-length 0.1",
      "fig7.txt --conforming --background bg.mesh",
  };
  for (const char* args : bad) {
    SCOPED_TRACE(args);
    const Outcome mesh = run(std::string("mesh ") + args + " -o m.vtu");
    ASSERT_EQ(mesh.code, 64) << mesh.output;
    const std::string message = usage_message(mesh.output, "mesh");
    ASSERT_FALSE(message.empty()) << mesh.output;
    const Outcome deform = run(std::string("deform ") + args + " --handles h.json -o out");
    EXPECT_EQ(deform.code, 64) << deform.output;
    EXPECT_EQ(usage_message(deform.output, "deform"), message) << deform.output;
    const Outcome weights = run(std::string("weights ") + args + " --handles h.json -o w.vtu");
    EXPECT_EQ(weights.code, 64) << weights.output;
    EXPECT_EQ(usage_message(weights.output, "weights"), message) << weights.output;
  }
  EXPECT_FALSE(exists("out"));
  EXPECT_FALSE(exists("w.vtu"));
}

// A graded background (issue 17) reaches deform and weights: the mesh they deform is mesh's own
// (the element counts agree, and differ from the uniform grid's).
TEST_F(DeformCli, GradedBackgroundsAsInMesh) {
  ASSERT_EQ(run("generate two-spheres 6 -o ts.obj").code, 0);
  write("h.json", R"({"handles": [{"box": {"min": [-100, -100, -100], "max": [-0.5, 100, 100]}, "displacement": [-0.5, 0, 0]},
                                  {"box": {"min": [0.5, -100, -100], "max": [100, 100, 100]}}]})");
  const auto count = [&](const std::string& file, const std::string& key) {
    const std::regex pattern("\"" + key + "\": (\\d+)");
    std::smatch match;
    const std::string json = read(file);
    return std::regex_search(json, match, pattern) ? std::stol(match[1]) : -1L;
  };
  ASSERT_EQ(run("mesh ts.obj --resolution 4 --surface-resolution 8 -o m.vtu --json m.json").code, 0);
  ASSERT_EQ(run("mesh ts.obj --resolution 4 -o u.vtu --json u.json").code, 0);
  const long graded_tets = count("m.json", "output_tets");
  ASSERT_GT(graded_tets, 0);
  ASSERT_NE(graded_tets, count("u.json", "output_tets"));  // the grading changes the mesh
  const Outcome deform = run("deform ts.obj --handles h.json -o out --frames 1 --resolution 4 --surface-resolution 8 --json out/r.json");
  ASSERT_EQ(deform.code, 0) << deform.output;
  EXPECT_EQ(count("out/r.json", "elements"), graded_tets) << read("out/r.json");
  const Outcome weights = run("weights ts.obj --handles h.json -o w.vtu --resolution 4 --surface-resolution 8");
  ASSERT_EQ(weights.code, 0) << weights.output;
  EXPECT_TRUE(exists("w.vtu"));
}

}  // namespace
