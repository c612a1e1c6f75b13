#include "core/atomic_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace imm {
namespace {

// Temporaries of writes in progress, readable from a signal handler: a fixed table of slots whose
// state is a lock-free atomic (0 free, 1 being filled, 2 holds a live path).
constexpr int kSlots = 1024;  // a command stages all its outputs before renaming them (Session)
constexpr std::size_t kPathBytes = 4096;
struct Slot {
  std::atomic<int> state{0};
  char path[kPathBytes];
};
Slot g_slots[kSlots];
static_assert(std::atomic<int>::is_always_lock_free, "signal handler needs lock-free atomics");

/// Registers `tmp` before the file is created (so a signal right after creation removes it).
/// @return the slot, or -1 when the table is full or the path too long (then it is simply not
///         removed on a signal; the write itself is unaffected).
int register_temporary(const std::string& tmp) {
  if (tmp.size() + 1 > kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!g_slots[i].state.compare_exchange_strong(expected, 1, std::memory_order_acquire)) continue;
    std::memcpy(g_slots[i].path, tmp.c_str(), tmp.size() + 1);
    g_slots[i].state.store(2, std::memory_order_release);
    return i;
  }
  return -1;
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_slots[slot].state.store(0, std::memory_order_release);
}

extern "C" void remove_temporaries_and_reraise(int signal_number) {
  for (Slot& s : g_slots)
    if (s.state.load(std::memory_order_acquire) == 2) ::unlink(s.path);
  struct sigaction action {};
  action.sa_handler = SIG_DFL;
  sigemptyset(&action.sa_mask);
  ::sigaction(signal_number, &action, nullptr);
  ::raise(signal_number);
}

std::string errno_text() { return errno ? std::strerror(errno) : "stream error"; }

/// Why a fill that returned false stopped: the stream's OS error when the stream failed (a full
/// disk: "No space left on device"), else that the producer abandoned it.
std::string abandoned_reason(const std::string& path, const std::ostream& out, int saved_errno) {
  if (!out.good() && saved_errno != 0) return "cannot write '" + path + "': " + std::strerror(saved_errno);
  if (!out.good()) return "cannot write '" + path + "': stream error";
  return "writing '" + path + "' was abandoned";
}

/// Writes a FIFO or device in place: no temporary, no rename (neither exists for them).
WriteStatus write_through(const std::string& path, const std::function<bool(std::ostream&)>& fill) {
  errno = 0;
  std::ofstream out(path, std::ios::binary);
  if (!out) return {"cannot open '" + path + "' for writing: " + errno_text()};
  errno = 0;
  if (!fill(out)) return {abandoned_reason(path, out, errno)};
  out.flush();
  const bool ok = static_cast<bool>(out);
  const std::string reason = errno_text();
  out.close();
  if (!ok || out.fail()) return {"cannot write '" + path + "': " + reason};
  return {};
}

/// Writes the temporary of a regular file (existing or not) into `staged`.
WriteStatus stage_replacing(const std::string& target, const std::function<bool(std::ostream&)>& fill,
                            StagedWrite& staged) {
  const std::string tmp = temporary_path(target);
  const int slot = register_temporary(tmp);
  auto discard = [&]() {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    unregister_temporary(slot);
  };
  errno = 0;
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) {
    const std::string reason = errno_text();
    unregister_temporary(slot);
    return {"cannot create '" + tmp + "': " + reason};
  }
  bool filled = false;
  errno = 0;
  try {
    filled = fill(out);
  } catch (...) {
    out.close();
    discard();
    throw;
  }
  if (!filled) {
    const int saved = errno;
    const std::string reason = abandoned_reason(target, out, saved);
    out.close();
    discard();
    return {reason};
  }
  out.flush();
  const bool stream_ok = static_cast<bool>(out);
  out.close();
  if (!stream_ok || out.fail()) {
    const std::string reason = errno_text();
    discard();
    return {"cannot write '" + tmp + "': " + reason};
  }
  staged.target = target;
  staged.temporary = tmp;
  staged.slot = slot;
  return {};
}

/// `path` with its symbolic links followed to what they name (a dangling link names the file to
/// create); `st_mode` 0 when that does not exist. @return an error message, or empty.
std::string follow_links(const std::string& path, std::string& target, mode_t& mode) {
  target = path;
  mode = 0;
  for (int hops = 0;; ++hops) {
    struct stat st {};
    if (::lstat(target.c_str(), &st) != 0) {
      if (errno == ENOENT) return {};
      return "cannot write '" + path + "': " + std::strerror(errno);
    }
    if (!S_ISLNK(st.st_mode)) {
      mode = st.st_mode;
      return {};
    }
    if (hops >= 40) return "cannot write '" + path + "': too many levels of symbolic links";
    std::error_code ec;
    std::filesystem::path link = std::filesystem::read_symlink(target, ec);
    if (ec) return "cannot read the symbolic link '" + target + "': " + ec.message();
    if (link.is_relative()) link = std::filesystem::path(target).parent_path() / link;
    target = link.string();
  }
}

}  // namespace

std::string temporary_path(const std::string& path) {
  return path + ".tmp." + std::to_string(static_cast<long>(::getpid()));
}

WriteStatus write_file_atomic(const std::string& path, std::string_view content) {
  return write_file_atomic(path, [&](std::ostream& out) {
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    return static_cast<bool>(out);
  });
}

WriteStatus write_file_atomic(const std::string& path,
                              const std::function<bool(std::ostream&)>& fill) {
  StagedWrite staged;
  if (WriteStatus status = stage_write(path, fill, staged); !status.ok()) return status;
  return commit_write(staged);
}

WriteStatus stage_write(const std::string& path, const std::function<bool(std::ostream&)>& fill,
                        StagedWrite& staged) {
  staged = StagedWrite{};
  staged.path = path;
  // Follow symbolic links to what they name, so that the rename replaces the target, never
  // the link.
  std::string target;
  mode_t mode = 0;
  if (std::string error = follow_links(path, target, mode); !error.empty()) return {std::move(error)};
  if (mode == 0 || S_ISREG(mode)) return stage_replacing(target, fill, staged);
  if (S_ISFIFO(mode) || S_ISCHR(mode) || S_ISBLK(mode)) {
    staged.target = target;
    return write_through(target, fill);
  }
  if (S_ISDIR(mode)) return {"cannot write '" + path + "': it is a directory"};
  return {"cannot write '" + path + "': not a regular file, FIFO or device"};
}

WriteStatus commit_write(StagedWrite& staged) {
  if (staged.temporary.empty()) return {};
  if (std::rename(staged.temporary.c_str(), staged.target.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    const std::string message = "cannot rename '" + staged.temporary + "' to '" + staged.target + "': " + reason;
    discard_write(staged);
    return {message};
  }
  unregister_temporary(staged.slot);
  staged.temporary.clear();
  staged.slot = -1;
  return {};
}

void discard_write(StagedWrite& staged) {
  if (staged.temporary.empty()) return;
  std::error_code ignored;
  std::filesystem::remove(staged.temporary, ignored);
  unregister_temporary(staged.slot);
  staged.temporary.clear();
  staged.slot = -1;
}

std::string output_identity(const std::string& path) {
  std::string target;
  mode_t mode = 0;
  if (!follow_links(path, target, mode).empty()) target = path;
  struct stat st {};
  if (mode != 0 && ::stat(target.c_str(), &st) == 0)
    return "inode:" + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(std::filesystem::absolute(target, ec), ec);
  return "path:" + (ec ? target : canonical.lexically_normal().string());
}

WriteStatus ensure_directory(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return {};
  if (std::filesystem::exists(path, ec)) return {"'" + path + "' exists and is not a directory"};
  std::filesystem::create_directories(path, ec);
  if (ec) return {"cannot create directory '" + path + "': " + ec.message()};
  return {};
}

WriteStatus ensure_parent_directory(const std::string& file) {
  const std::filesystem::path parent = std::filesystem::path(file).parent_path();
  return parent.empty() ? WriteStatus{} : ensure_directory(parent.string());
}

std::string unreadable_file_kind(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return {};
  if (S_ISCHR(st.st_mode)) return "a character device";
  if (S_ISBLK(st.st_mode)) return "a block device";
  if (S_ISSOCK(st.st_mode)) return "a socket";
  return {};
}

void remove_temporaries_on_signals() {
  // Every signal whose default action ends the process without a core dump of interest: a
  // command stages all its outputs until it ends (app/cli_common.h, Session), so a reader that
  // closes its pipe (SIGPIPE), a file-size or CPU limit, or an alarm would leave them all.
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGXCPU, SIGXFSZ, SIGALRM, SIGVTALRM, SIGPROF,
                            SIGUSR1, SIGUSR2}) {
    struct sigaction current {};
    if (::sigaction(signal_number, nullptr, &current) != 0) continue;
    if (current.sa_handler != SIG_DFL) continue;  // ignored or handled by the program: keep it
    struct sigaction action {};
    action.sa_handler = remove_temporaries_and_reraise;
    sigemptyset(&action.sa_mask);
    ::sigaction(signal_number, &action, nullptr);
  }
}

int temporaries_in_progress() {
  int n = 0;
  for (const Slot& s : g_slots) n += s.state.load(std::memory_order_acquire) == 2 ? 1 : 0;
  return n;
}

}  // namespace imm
