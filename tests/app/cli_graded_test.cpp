// `immerse mesh --surface-resolution M [--gap-resolution G]` (graded backgrounds, issue 17): the
// program's options, refusals and report, run as the real executable.
// Keys are read with .at(): a missing key throws json::out_of_range and fails the test.
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include "support/immerse_fixture.h"

namespace {

class CliGradedTest : public imm::test::ImmerseTest {};

TEST_F(CliGradedTest, GradedMeshReportsSizesAndQuality) {
  ASSERT_EQ(run("generate comb 3 -o comb.obj").code, 0);
  const auto r = run("mesh comb.obj --resolution 4 --surface-resolution 16 --gap-resolution 32 -o comb.mesh --json c.json");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("graded: cubes"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("min dihedral 45 deg"), std::string::npos) << r.output;
  const auto j = nlohmann::json::parse(read("c.json"));
  EXPECT_EQ(j.at("options").at("surface_resolution").get<int>(), 16);
  EXPECT_EQ(j.at("options").at("gap_resolution").get<int>(), 32);
  const auto& g = j.at("meshes")[0].at("graded_background");
  EXPECT_EQ(g.at("tets").get<long>(), j.at("meshes")[0].at("counts").at("background_tets").get<long>());
  EXPECT_GE(g.at("min_dihedral_deg").get<double>(), g.at("min_dihedral_bound_deg").get<double>() - 1e-9);
  EXPECT_GT(g.at("gap_tets").get<long>(), 0);
  EXPECT_LT(g.at("gap_size").get<double>(), g.at("surface_size").get<double>());
  // The same command writes the same mesh (threads included).
  ASSERT_EQ(run("mesh comb.obj --resolution 4 --surface-resolution 16 --gap-resolution 32 --threads 1 -o again.mesh").code, 0);
  EXPECT_EQ(read("comb.mesh"), read("again.mesh"));
}

TEST_F(CliGradedTest, ConflictingOptionsAreUsageErrors) {
  ASSERT_EQ(run("generate comb 2 -o comb.obj").code, 0);
  write("bg.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n0\nTetrahedra\n0\nEnd\n");
  for (const std::string args : {"--surface-resolution 16 --background bg.mesh", "--gap-resolution 32",
                                 "--surface-resolution 16 --conforming", "--resolution 16 --surface-resolution 8",
                                 "--surface-resolution 16 --gap-resolution 8"}) {
    const auto r = run("mesh comb.obj " + args + " -o out.mesh");
    EXPECT_EQ(r.code, 64) << args << "\n" << r.output;
    EXPECT_FALSE(exists("out.mesh")) << args;
  }
  ASSERT_EQ(run("generate figure-eight -o f.txt").code, 0);
  EXPECT_EQ(run("mesh f.txt --surface-resolution 16").code, 64);
}

}  // namespace
