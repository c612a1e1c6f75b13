// Running an external program (the renderer, the SVG converter) without a shell, with a time
// limit: the picture tools are separate Debian programs, and a scene that takes too long must
// fail with a message instead of hanging a figure program or a test.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace imm::render {

/// The full path of `program` found on PATH (or `program` itself when it contains a '/' and is
/// executable), or nullopt.
std::optional<std::string> find_program(const std::string& program);

struct ProcessResult {
  bool started = false;     ///< false: could not be executed (see error)
  bool timed_out = false;   ///< killed after the time limit
  int exit_code = -1;       ///< when it exited normally
  int signal = 0;           ///< when a signal ended it
  std::string output;       ///< stdout and stderr, last 4 KB
  std::string error;        ///< why it could not start
  double seconds = 0.0;     ///< wall time
  [[nodiscard]] bool ok() const { return started && !timed_out && signal == 0 && exit_code == 0; }
};

/// Runs `argv[0]` (a path) with `argv` in `working_directory` (empty: the current one), stdin
/// from /dev/null, stdout and stderr captured; kills it after `timeout_seconds` (> 0).
ProcessResult run_process(const std::vector<std::string>& argv, const std::string& working_directory,
                          double timeout_seconds);

}  // namespace imm::render
