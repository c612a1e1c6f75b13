// Runs the `immerse` binary in a directory and reports how it ended: exit code, or the signal
// that killed it (a crash is never mistaken for an exit code). For the end-to-end tests of
// issue 13 (bad and unusual inputs).
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace imm::test {

struct RunOutcome {
  int code = -1;    ///< exit code, or -1 when killed by a signal
  int signal = 0;   ///< the signal that ended the process, or 0
  std::string output;  ///< stdout and stderr together
};

/// `sh -c COMMAND`, its stdout (add `2>&1` for stderr too) and how it ended.
inline RunOutcome run_shell(const std::string& command) {
  RunOutcome r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return r;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
  const int status = ::pclose(pipe);
  if (WIFEXITED(status)) {
    r.code = WEXITSTATUS(status);
    // `sh` reports a signal of its (exec'd) child as 128 + signal.
    if (r.code > 128 && r.code < 128 + 65) r.signal = r.code - 128;
  } else if (WIFSIGNALED(status)) {
    r.signal = WTERMSIG(status);
  }
  return r;
}

/// `cd dir && immerse ARGS 2>&1`, with the binary IMM_IMMERSE_EXE.
inline RunOutcome run_immerse(const std::filesystem::path& dir, const std::string& args) {
  return run_shell("cd '" + dir.string() + "' && exec '" IMM_IMMERSE_EXE "' " + args + " 2>&1");
}

inline void write_file(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A fresh directory under the system temporary directory, named after the running test.
inline std::filesystem::path fresh_test_directory(const std::string& prefix, const std::string& test_name) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()) + "_" + test_name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace imm::test

#include <fcntl.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace imm::test {

/// Reads a FIFO on a thread while something else writes it; `finish()` returns what was read,
/// never hanging when the writer did not open the FIFO at all (it then opens it itself, so that
/// the reader's open returns, and the read gives what little there was).
class FifoReader {
 public:
  explicit FifoReader(std::filesystem::path fifo)
      : fifo_(std::move(fifo)), thread_([this] {
          text_ = read_file(fifo_);
          done_ = true;
        }) {}
  std::string finish() {
    while (!done_) {
      const int fd = ::open(fifo_.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd >= 0) ::close(fd);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    thread_.join();
    return text_;
  }
  ~FifoReader() {
    if (thread_.joinable()) finish();
  }

 private:
  std::filesystem::path fifo_;
  std::string text_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

}  // namespace imm::test
