// The fixture of the end-to-end tests of `immerse` (tests/app): a fresh directory per test, the
// binary run in it (run_immerse.h: a signal is never mistaken for an exit code), files written
// and read there, and the DESIGN §3 check on teardown that no temporary file was left behind.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/run_immerse.h"

namespace imm::test {

using Outcome = RunOutcome;

class ImmerseTest : public testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(IMM_IMMERSE_EXE)) GTEST_SKIP() << "no immerse binary at " << IMM_IMMERSE_EXE;
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fresh_test_directory(std::string("imm_") + info->test_suite_name(), info->name());
  }
  void TearDown() override {
    if (dir_.empty()) return;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir_)) {
      EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos)
          << "temporary file left behind: " << entry.path();
    }
    if (!HasFailure()) std::filesystem::remove_all(dir_);
  }

  /// Runs `immerse ARGS` in the test directory (stdout and stderr together); a signal is a
  /// failure of its own (a crash is never an expected verdict).
  [[nodiscard]] Outcome run(const std::string& args) const {
    Outcome r = run_immerse(dir_, args);
    EXPECT_EQ(r.signal, 0) << "immerse " << args << " was killed by signal " << r.signal << "\n" << r.output;
    return r;
  }
  void write(const std::string& name, const std::string& text) const { write_file(dir_ / name, text); }
  [[nodiscard]] std::string read(const std::string& name) const { return read_file(dir_ / name); }
  [[nodiscard]] bool exists(const std::string& name) const { return std::filesystem::exists(dir_ / name); }

  std::filesystem::path dir_;
};

}  // namespace imm::test
