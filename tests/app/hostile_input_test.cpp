// A new user's and a hostile input's tour of the newer commands (mesh --conforming, deform,
// weights, render): every run ends with a verdict (exit 0, 2, 3 or 64) and a message saying what
// is wrong, in seconds, never a signal, a hang or a half-written output.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>

#include "support/immerse_fixture.h"

namespace {

namespace fs = std::filesystem;
using imm::test::Outcome;

#define EXPECT_CONTAINS(text, piece) \
  EXPECT_NE((text).find(piece), std::string::npos) << "expected '" << (piece) << "' in:\n" << (text)

class HostileInput : public imm::test::ImmerseTest {};

// TetGen's quality refinement did not end with a dihedral bound of 25 degrees or more on
// tube-overlap (the preserved cut triangles cannot be improved; its memory grew by ~16 MB/s), and
// a tiny --edge-length asked for ~1e900 tets: both ran until memory ran out, silently. Now the
// Steiner points are capped (TetGen -S) and the edge length's tet count is estimated first.
TEST_F(HostileInput, ConformingRefinementIsBounded) {
  ASSERT_EQ(run("generate tube-overlap -o tube.obj").code, 0);
  Outcome r = run("mesh tube.obj --conforming --min-dihedral 28 -o q.vtu --embedding q.emb");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "stopped refining after");
  EXPECT_CONTAINS(r.output, "minimum dihedral 28 degrees");
  EXPECT_FALSE(exists("q.vtu"));
  EXPECT_FALSE(exists("q.emb"));
  r = run("mesh tube.obj --conforming --edge-length 1e-300 -o e.vtu");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "edge length 1e-300 would fill the input");
  EXPECT_FALSE(exists("e.vtu"));
  // The bounds leave reachable requests alone.
  r = run("mesh tube.obj --conforming --min-dihedral 15 -o ok.vtu");
  EXPECT_EQ(r.code, 0) << r.output;
}

// `weights tori.obj -o tori.obj` replaced the user's surface by the weights' VTU (and `--json`
// could replace any input): an output naming an input file, by any path, is a usage error now,
// before any work, and the input is untouched.
TEST_F(HostileInput, OutputsNeverReplaceAnInput) {
  ASSERT_EQ(run("generate two-tori 10 -o tori.obj").code, 0);
  write("h.json", R"({"handles": [{"box": {"min": [-10, -10, -10], "max": [-1, 10, 10]}, "displacement": [-1, 0, 0]},
                                 {"box": {"min": [2, -10, -10], "max": [10, 10, 10]}}]})");
  const std::string surface = read("tori.obj");
  for (const char* command :
       {"weights tori.obj --handles h.json -o tori.obj --resolution 6", "weights tori.obj --handles h.json -o ./h.json",
        "mesh tori.obj --resolution 6 -o m.mesh --json ../" /* below: the same file by another path */,
        "cells tori.obj --cut-mesh tori.obj", "mesh tori.obj --resolution 6 -o m.mesh --embedding tori.obj"}) {
    std::string args = command;
    if (args.find("../") != std::string::npos) args += dir_.filename().string() + "/tori.obj";
    SCOPED_TRACE(args);
    const Outcome r = run(args);
    EXPECT_EQ(r.code, 64) << r.output;
    EXPECT_CONTAINS(r.output, "it would be replaced");
    EXPECT_FALSE(exists("m.mesh"));
  }
  EXPECT_EQ(read("tori.obj"), surface);
  EXPECT_EQ(read("h.json").find("VTKFile"), std::string::npos);
  EXPECT_EQ(run("weights tori.obj --handles h.json -o w.vtu --resolution 6").code, 0);
}

// Handle files: a misspelt key ("displacment") left its handle fixed without a word, a vertex id
// of 2^64 - 1 was reported as vertex -1, and the file was read only after meshing.
TEST_F(HostileInput, HandleFilesSayWhatIsWrongBeforeMeshing) {
  ASSERT_EQ(run("generate fig7 -o fig7.txt").code, 0);
  const std::pair<const char*, const char*> cases[] = {
      {R"({"handles": [{"vertices": [0], "displacment": [1, 1]}]})", R"(handle 0: unknown key "displacment")"},
      {R"({"handles": [{"vertices": [0]}], "materal": {}})", R"(unknown key "materal")"},
      {R"({"handles": [{"vertices": [0]}], "material": {"young": 3}})", R"(material: unknown key "young")"},
      {R"({"handles": [{"vertices": [0]}], "ground": {"normal": [0, 1], "ofset": 1}})", R"(ground: unknown key "ofset")"},
      {R"({"handles": [{"vertices": [0]}], "ground": {"normal": [0, 0], "offset": 1}})", "ground: the normal is the zero vector"},
      {R"({"handles": [{"vertices": [0], "fixed": true, "displacement": [1, 0]}]})", "a fixed handle has no displacement"},
      {R"({"handles": [{"vertices": [18446744073709551615]}]})", "vertex 18446744073709551615 is not a mesh vertex"},
  };
  for (const auto& [json, message] : cases) {
    SCOPED_TRACE(json);
    write("h.json", json);
    for (const char* command : {"deform", "weights"}) {
      const Outcome r = run(std::string(command) + " fig7.txt --handles h.json -o out/w.vtu --resolution 8");
      EXPECT_EQ(r.code, 2) << r.output;
      EXPECT_CONTAINS(r.output, message);
      EXPECT_FALSE(exists("out"));
    }
  }
  // Read first: a bad handle file is the verdict even before the input is opened.
  write("bad.json", "{\"handles\": [");
  const Outcome r = run("deform missing.obj --handles bad.json -o out");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "not valid JSON");
  // The documented keys still pass.
  write("ok.json", R"({"handles": [{"vertices": [0], "fixed": true}, {"vertices": [5], "displacement": [1, 0]}],
                       "material": {"youngs_modulus": 1000, "poisson_ratio": 0.3, "density": 1}, "time_step": 0.1,
                       "gravity": [0, -1], "ground": {"normal": [0, 1], "offset": -1000}})");
  EXPECT_EQ(run("deform fig7.txt --handles ok.json -o ok --resolution 8 --frames 1 --method fem").code, 0);
}

// `deform --immersion 5` on an input with one immersion said "'fig7.txt' has no immersion to mesh
// (immersible)" with exit 3; `mesh` calls it a usage error naming the count. And a 3D
// --resolution past 150 is a usage error before the handle file is judged.
TEST_F(HostileInput, DeformChecksItsOptionsLikeMesh) {
  ASSERT_EQ(run("generate fig7 -o fig7.txt").code, 0);
  write("h.json", R"({"handles": [{"vertices": [0]}]})");
  for (const char* command : {"deform fig7.txt --handles h.json -o out", "weights fig7.txt --handles h.json -o out/w.vtu"}) {
    SCOPED_TRACE(command);
    const Outcome r = run(std::string(command) + " --resolution 8 --immersion 5");
    EXPECT_EQ(r.code, 64) << r.output;
    EXPECT_CONTAINS(r.output, "has only 1 immersion");
  }
  ASSERT_EQ(run("generate two-spheres 6 -o ts.obj").code, 0);
  const Outcome r = run("deform ts.obj --handles h.json -o out --resolution 200");
  EXPECT_EQ(r.code, 64) << r.output;
  EXPECT_CONTAINS(r.output, "at most 150");
  EXPECT_FALSE(exists("out"));
}

// Displacements and forces beyond the range of doubles: ARAP moved the input to 1e300 and counted
// self-intersections of coordinates past the input range; FEM under a gravity of 1e308 reported a
// converged step and moved nothing. Both are now invalid handle data (exit 2) naming the frame.
TEST_F(HostileInput, DeformationsOutOfRangeAreRefused) {
  ASSERT_EQ(run("generate fig7 -o fig7.txt").code, 0);
  write("far.json", R"({"handles": [{"vertices": [0], "fixed": true}, {"vertices": [5], "displacement": [1e300, 0]}]})");
  Outcome r = run("deform fig7.txt --handles far.json -o far --resolution 8 --frames 1");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "frame 1: the deformed input leaves the coordinate range");
  write("heavy.json", R"({"handles": [{"vertices": [0], "fixed": true}], "gravity": [1e308, 1e308]})");
  r = run("deform fig7.txt --handles heavy.json -o heavy --resolution 8 --frames 1 --method fem");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "not finite");
  // In range, the same handles deform.
  write("near.json", R"({"handles": [{"vertices": [0], "fixed": true}, {"vertices": [5], "displacement": [100, 0]}]})");
  EXPECT_EQ(run("deform fig7.txt --handles near.json -o near --resolution 8 --frames 1").code, 0);
}

}  // namespace
