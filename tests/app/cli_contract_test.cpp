// The command-line contract (README, DESIGN §3) on the inputs and command lines a tester found
// breaking it: an OBJ with faces and 'l' lines, two outputs on one file, a 2D mesh under a 3D
// extension, devices and endless streams as inputs, a failed write leaving half of the outputs,
// and the smaller help and listing defects. Each test runs the real `immerse` in a fresh
// directory (support/immerse_fixture.h).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <sys/wait.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "support/immerse_fixture.h"

namespace {

namespace fs = std::filesystem;

using imm::test::Outcome;

class CliContract : public imm::test::ImmerseTest {
 protected:
  /// `immerse ARGS` under a memory and time bound (2 GB, 60 s, then SIGKILL): an input read
  /// without end must fail this test, not the machine.
  /// `before`: shell commands run first (a writer started in the background).
  [[nodiscard]] Outcome run_bounded(const std::string& args, const std::string& before = "") const {
    // timeout's SIGKILL shows as 137, a signal (run_shell).
    const Outcome r = imm::test::run_shell("cd '" + dir_.string() + "' && ulimit -v 2000000 && " + before +
                                           "exec timeout -s KILL 60 '" + IMM_IMMERSE_EXE + "' " + args + " 2>&1");
    EXPECT_EQ(r.signal, 0) << "immerse " << args << " was killed (no bound on the read?)\n" << r.output.substr(0, 2000);
    return r;
  }
  /// A closed tetrahedron (OBJ), outward faces.
  void write_tetra(const std::string& name, const std::string& extra = "") const {
    write(name, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n" + extra);
  }
  void write_square(const std::string& name) const { write(name, "0 0\n4 0\n4 4\n0 4\n"); }
};

#define EXPECT_CONTAINS(text, piece) \
  EXPECT_NE((text).find(piece), std::string::npos) << "expected '" << (piece) << "' in:\n" << (text)

// 1. Faces and 'l' lines in one OBJ: read as a 2D curve ("2D input, 1 curve") and every face
// dropped. Faces make a surface now; the loose edges are ignored with a note.
TEST_F(CliContract, ObjWithFacesAndLinesIsASurfaceWithANote) {
  write_tetra("t.obj", "l 1 2 3 1\nl 2 4\n");
  for (const char* command : {"check", "cells", "immersions"}) {
    const Outcome r = run(std::string(command) + " t.obj");
    EXPECT_EQ(r.code, 0) << command << "\n" << r.output;
    EXPECT_CONTAINS(r.output, "3D input, 4 triangles");
    EXPECT_CONTAINS(r.output, "2 'l' lines (loose edges) ignored");
  }
  const Outcome m = run("mesh t.obj --resolution 3 -o t.mesh");
  EXPECT_EQ(m.code, 0) << m.output;
  EXPECT_CONTAINS(read("t.mesh"), "Tetrahedra");
  // Lines alone are still a 2D curve.
  write("c.obj", "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nl 1 2 3 4 1\n");
  const Outcome c = run("check c.obj");
  EXPECT_EQ(c.code, 0) << c.output;
  EXPECT_CONTAINS(c.output, "2D input, 1 curve");
}

// 2. Two outputs on one file: the second silently replaced the first (exit 0).
TEST_F(CliContract, TwoOutputsOnOneFileAreAUsageError) {
  write_tetra("t.obj");
  write_square("s.txt");
  struct Case {
    const char* args;
    const char* message;
  };
  fs::create_symlink("a.mesh", dir_ / "link.mesh");
  for (const Case& c : {
           Case{"mesh t.obj -o a.mesh --embedding a.mesh", "-o 'a.mesh' and --embedding 'a.mesh' name the same file"},
           Case{"mesh t.obj -o a.mesh --json a.mesh", "-o 'a.mesh' and --json 'a.mesh' name the same file"},
           Case{"mesh t.obj -o a.mesh --json ./sub/../a.mesh", "-o 'a.mesh' and --json './sub/../a.mesh'"},
           Case{"mesh t.obj -o a.mesh --json link.mesh", "-o 'a.mesh' and --json 'link.mesh' name the same file"},
           Case{"mesh t.obj -o f.node --embedding f.ele", "the .ele of -o 'f.node': 'f.ele' and --embedding 'f.ele'"},
           Case{"mesh t.obj --all -o m.mesh --json m_1.mesh", "-o 'm.mesh' (numbered by --all) and --json 'm_1.mesh'"},
           Case{"mesh t.obj --all -o m.mesh --embedding m.mesh", "name the same file"},
           Case{"mesh s.txt -o a.mesh --svg a.mesh", "-o 'a.mesh' and --svg 'a.mesh' name the same file"},
           Case{"cells t.obj --json a.obj --cut-mesh a.obj", "--json 'a.obj' and --cut-mesh 'a.obj'"},
       }) {
    const Outcome r = run(c.args);
    EXPECT_EQ(r.code, 64) << c.args << "\n" << r.output;
    EXPECT_CONTAINS(r.output, c.message);
    EXPECT_FALSE(exists("a.mesh")) << c.args;
  }
  // Different files are fine, and --all numbers both.
  const Outcome ok = run("mesh t.obj --resolution 3 -o f.node --embedding f.emb --json f.json");
  EXPECT_EQ(ok.code, 0) << ok.output;
  for (const char* name : {"f.node", "f.ele", "f.emb", "f.json"}) EXPECT_TRUE(exists(name)) << name;
}

// 3. `mesh curve -o x.vtu` wrote Medit text under a VTU name (3D exits 64 there).
TEST_F(CliContract, TwoDimensionalMeshRefusesExtensionsItCannotWrite) {
  write_square("s.txt");
  for (const char* name : {"x.vtu", "x.veg", "x.msh", "x.node", "x.obj"}) {
    const Outcome r = run(std::string("mesh s.txt -o ") + name);
    EXPECT_EQ(r.code, 64) << name << "\n" << r.output;
    EXPECT_CONTAINS(r.output, "a 2D triangle mesh is written as .mesh (Medit)");
    EXPECT_FALSE(exists(name));
  }
  const Outcome r = run("mesh s.txt -o x.mesh");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_CONTAINS(read("x.mesh"), "Triangles");
}

// 4. Devices and streams as inputs: /dev/zero and /dev/urandom grew to GBs and never ended.
TEST_F(CliContract, DevicesAreRefusedAndBinaryStreamsStopAtOnce) {
  fs::create_symlink("/dev/zero", dir_ / "z.obj");
  fs::create_symlink("/dev/urandom", dir_ / "r.txt");
  fs::create_symlink("/dev/zero", dir_ / "z.stl");
  for (const char* name : {"z.obj", "r.txt", "z.stl"}) {
    const Outcome r = run_bounded(std::string("check ") + name);
    EXPECT_EQ(r.code, 2) << name << "\n" << r.output;
    EXPECT_CONTAINS(r.output, "it is a character device, not a regular file");
  }
  // A NUL byte ends the read of a 2D input: no text, SVG or OBJ file holds one.
  write("nul.txt", std::string("0 0\n4 0\n4 4\0\n0 4\n", 17));
  Outcome r = run("check nul.txt");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "a NUL byte at byte 11 (line 3): not a text file");
  // A FIFO fed an endless binary stream (the tester's /dev/urandom through a pipe).
  ASSERT_EQ(::mkfifo((dir_ / "stream.txt").c_str(), 0600), 0);
  r = run_bounded("check stream.txt", "(head -c 3000000000 /dev/urandom >stream.txt 2>/dev/null &) ; ");
  EXPECT_EQ(r.code, 2) << r.output.substr(0, 2000);
  EXPECT_CONTAINS(r.output, "not a text file");
}

// FIFOs stay inputs (2D text reads them as before).
TEST_F(CliContract, FifoInputStillWorks) {
  const fs::path fifo = dir_ / "in.txt";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] { std::ofstream(fifo) << "0 0\n4 0\n4 4\n0 4\n"; });
  const Outcome r = run("check in.txt");
  // Unblock the writer when the program did not open the FIFO.
  const int fd = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  writer.join();
  if (fd >= 0) ::close(fd);
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_CONTAINS(r.output, "2D input, 1 curve, 4 vertices: valid");
}

// 5. A failed write (exit 1) left the outputs written before it: c.mesh without its .emb.
TEST_F(CliContract, AFailedWriteLeavesNoneOfTheOutputs) {
  write_tetra("t.obj");
  write_square("s.txt");
  if (fs::is_character_file("/dev/full")) {
    for (const char* input : {"t.obj --resolution 3", "s.txt"}) {
      const Outcome r = run(std::string("mesh ") + input + " -o c.mesh --embedding /dev/full --json c.json");
      EXPECT_EQ(r.code, 1) << r.output;
      EXPECT_CONTAINS(r.output, std::string("cannot write '/dev/full': ") + std::strerror(ENOSPC));
      EXPECT_CONTAINS(r.output, "not written either");
      EXPECT_FALSE(exists("c.mesh")) << input;
      EXPECT_FALSE(exists("c.json")) << input;
      EXPECT_EQ(r.output.find("wrote c.mesh"), std::string::npos) << r.output;
    }
  }
  // The output budget refuses the embedding after the mesh fitted; an older c.mesh is kept as it was.
  write("c.mesh", "older\n");
  const Outcome full = run("mesh t.obj --resolution 3 -o c.mesh --embedding c.emb");
  ASSERT_EQ(full.code, 0) << full.output;
  const std::size_t mesh_bytes = fs::file_size(dir_ / "c.mesh");
  write("c.mesh", "older\n");
  const Outcome r = run("mesh t.obj --resolution 3 -o c.mesh --embedding c2.emb --max-output " +
                        std::to_string(mesh_bytes + 1));
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_CONTAINS(r.output, "--max-output");
  EXPECT_EQ(read("c.mesh"), "older\n");
  EXPECT_FALSE(exists("c2.emb"));
}

// README: "a FIFO or a device (/dev/null, /dev/full) is written through"; `mesh -o /dev/null`
// exited 64 on the extension check.
// A long deform run commits its frames in batches (the signal handler's table of temporaries is
// finite): a later output naming a file of an earlier batch is still a clash (it replaced frame 1
// with the report, exit 0), and the message says which outputs are in place rather than claiming
// that none are.
TEST_F(CliContract, AClashWithAnEarlierBatchIsStillAClash) {
  ASSERT_EQ(run("generate fig7 -o fig7.txt").code, 0);
  write("h.json", R"({"handles": [
  {"box": {"min": [-10000, -10000], "max": [-650, 10000]}, "displacement": [-800, 0]},
  {"box": {"min": [680, -10000], "max": [10000, 10000]}, "displacement": [800, 0]}]})");
  const Outcome r = run("deform fig7.txt --handles h.json -o out --frames 970 --resolution 6 --json out/mesh_001.vtu");
  EXPECT_EQ(r.code, 64) << r.output.substr(r.output.size() > 3000 ? r.output.size() - 3000 : 0);
  EXPECT_CONTAINS(r.output, "is the file 'out/mesh_001.vtu' (deformed mesh) already written by this command");
  EXPECT_CONTAINS(r.output, "already in place and stay");
  EXPECT_EQ(read("out/mesh_001.vtu").rfind("<?xml", 0), 0u) << "frame 1 was replaced";
  for (const auto& entry : fs::directory_iterator(dir_ / "out"))
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << entry.path();
}

TEST_F(CliContract, DevicesAreWrittenThroughWhateverTheirName) {
  write_tetra("t.obj");
  write_square("s.txt");
  for (const char* input : {"t.obj --resolution 3", "s.txt"}) {
    const Outcome r = run(std::string("mesh ") + input + " -o /dev/null --embedding /dev/null --json /dev/null");
    EXPECT_EQ(r.code, 0) << input << "\n" << r.output;
    EXPECT_CONTAINS(r.output, "wrote /dev/null");
  }
  // --all numbers its files (OUT_K.ext), but not a device's name: /dev/null_0 would be a new file.
  const Outcome all = run("mesh t.obj --resolution 3 --all -o /dev/null --embedding /dev/null");
  EXPECT_EQ(all.code, 0) << all.output;
  EXPECT_EQ(all.output.find("/dev/null_0"), std::string::npos) << all.output;
  EXPECT_FALSE(fs::exists("/dev/null_0"));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

// 6. Smaller: --repair-folds accepted silently in 2D; 2D check listed every contact (157 KB);
// a binary STL announcing fewer facets than it holds looked open.
TEST_F(CliContract, RepairFoldsIsThreeDimensionalOnly) {
  write_square("s.txt");
  for (const char* command : {"mesh", "cells", "immersions"}) {
    const Outcome r = run(std::string(command) + " s.txt --repair-folds 0.1");
    EXPECT_EQ(r.code, 64) << command << "\n" << r.output;
    EXPECT_CONTAINS(r.output, "--repair-folds");
    EXPECT_CONTAINS(r.output, "3D surfaces only");
  }
}

TEST_F(CliContract, CheckListsAtMostFiftyContacts) {
  // Two copies of a 200-gon: every segment overlaps its copy, hundreds of contacts.
  std::ostringstream os;
  for (int copy = 0; copy < 2; ++copy) {
    for (int k = 0; k < 200; ++k) {
      const double t = 2 * M_PI * k / 200;
      os << std::lround(1000 * std::cos(t)) << ' ' << std::lround(1000 * std::sin(t)) << '\n';
    }
    os << '\n';
  }
  write("dup.txt", os.str());
  const Outcome r = run("check dup.txt");
  EXPECT_EQ(r.code, 0) << r.output.substr(0, 4000);  // the copies are moved apart: two overlapping parts
  EXPECT_CONTAINS(r.output, "400 exact contacts");
  EXPECT_CONTAINS(r.output, "... and 350 more\n");  // the contacts: 50 listed
  std::size_t lines = 0;
  for (char c : r.output) lines += c == '\n' ? 1 : 0;
  EXPECT_LT(lines, 120u) << r.output.substr(0, 4000);  // was 400 contact lines, then the defects
}

TEST_F(CliContract, BinaryStlWithMoreFacetsThanItsCountSaysSo) {
  const std::array<std::array<float, 3>, 4> v{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  const std::array<std::array<int, 3>, 4> faces{{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
  const auto stl = [&](std::uint32_t count) {
    std::string data(80, ' ');
    data.append(reinterpret_cast<const char*>(&count), 4);
    for (const auto& f : faces) {
      data.append(12, '\0');  // normal
      for (int i : f) data.append(reinterpret_cast<const char*>(v[i].data()), 12);
      data.append(2, '\0');
    }
    return data;
  };
  write("ok.stl", stl(4));
  Outcome r = run("check ok.stl");
  EXPECT_EQ(r.code, 0) << r.output;
  write("short.stl", stl(3));
  r = run("check short.stl");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_CONTAINS(r.output, "announces 3 facets (234 bytes) but the file has 284 bytes, room for 4 facets");
  // A few bytes of padding after the last facet are not a facet.
  write("padded.stl", stl(4) + std::string(8, '\0'));
  r = run("check padded.stl");
  EXPECT_EQ(r.code, 0) << r.output;
}

// 7. Help and generators: `generate --list` prints N=12, the parser took only n=12; the
// immersions help promised the JSON "in every case"; the positional showed as "IN ...".
TEST_F(CliContract, GeneratorKeysInEitherCaseAndHonestHelp) {
  Outcome r = run("generate sphere N=5 -o a.obj");
  EXPECT_EQ(r.code, 0) << r.output;
  r = run("generate sphere n=5 -o b.obj");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(read("a.obj"), read("b.obj"));
  r = run("generate convex N=7");
  EXPECT_EQ(r.code, 0) << r.output;
  r = run("immersions --help");
  EXPECT_EQ(r.output.find("written in every case"), std::string::npos) << r.output;
  EXPECT_CONTAINS(r.output, "--time-limit");
  for (const char* command : {"check", "cells", "immersions", "mesh"}) {
    r = run(std::string(command) + " --help");
    EXPECT_EQ(r.output.find("IN ..."), std::string::npos) << command << "\n" << r.output;
  }
  r = run("generate --help");
  EXPECT_CONTAINS(r.output, "...");  // generate does take several
}

}  // namespace
