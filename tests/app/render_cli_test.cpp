// `immerse render` (app/cli_render.cpp) through the real executable: its options come from the
// same CLI11 table as the other commands', so malformed values, repeated or unknown options and
// missing arguments exit 64 with the command's usage, before anything is read or drawn.
#include <gtest/gtest.h>

#include <string>

#include "support/immerse_fixture.h"

namespace {

using imm::test::Outcome;

class RenderCli : public imm::test::ImmerseTest {};

TEST_F(RenderCli, BadCommandLinesExit64WithTheUsage) {
  const auto refused = [&](const std::string& args, const std::string& message) {
    const Outcome r = run("render " + args);
    EXPECT_EQ(r.code, 64) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("usage: immerse render"), std::string::npos) << r.output;
  };
  refused("", "missing input file");
  refused("a.obj", "no output picture");
  refused("a.obj -o x.png --size 10x10", "--size expects WxH");
  refused("a.obj -o x.png --size 100", "--size expects WxH");
  refused("a.mesh -o x.png --cut w=0.5", "--cut expects AXIS=F");
  refused("a.mesh -o x.png --cut x=2", "--cut expects AXIS=F");
  refused("a.obj -o x.png --view 10", "--view expects AZ,EL");
  refused("a.obj -o x.png --view inf,0", "AZ a finite number");
  refused("a.obj -o x.png --view 10,90", "EL in [-89, 89]");
  refused("a.obj -o x.png --view 10,20 --view 30,20", "--view");
  refused("a.obj -o x.png --up w", "--up expects x, y or z");
  refused("a.obj -o x.png --explode -1", "--explode expects");
  refused("a.obj -o x.png --color red", "--color expects node or single");
  refused("a.obj -o x.png --timeout 0", "--timeout");
  refused("a.obj -o x.png --bogus", "--bogus");
  refused("a.obj b.obj -o x.png", "unexpected argument");
  refused("a.obj -o x.jpg", "must be a .png");
  EXPECT_FALSE(exists("x.png"));
}

TEST_F(RenderCli, HelpListsTheOptions) {
  for (const std::string& args : {"render --help", "help render"}) {
    const Outcome r = run(args);
    EXPECT_EQ(r.code, 0) << r.output;
    for (const char* option : {"--cut", "--explode", "--view", "--no-ground", "OUT.png"})
      EXPECT_NE(r.output.find(option), std::string::npos) << args << ": " << option << "\n" << r.output;
  }
}

TEST_F(RenderCli, AnUnreadableInputExits2) {
  const Outcome r = run("render missing.obj -o x.png");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_FALSE(exists("x.png"));
}

}  // namespace
