// Outputs that are never half-written (DESIGN §3: "never a silent partial file").
//
// A regular file (or a path that does not exist yet) is written to "<path>.tmp.<pid>" in the same
// directory, flushed and closed, and then renamed over `path` (rename(2) is atomic within one file
// system). On any error the temporary file is removed and `path` is left as it was.
//
// What the path names is respected, never replaced: a symbolic link is followed (its target is
// written atomically, the link stays a link); a FIFO or a character/block device is written
// through (opened for writing, no temporary, no rename: such a stream cannot be made atomic, and
// whatever was written before an error has already gone to its reader); a directory or a socket
// is refused with an error.
//
// Signals: remove_temporaries_on_signals() makes SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE,
// SIGXCPU, SIGXFSZ, SIGALRM, SIGVTALRM, SIGPROF, SIGUSR1 and SIGUSR2 remove every
// temporary this process has open before the signal's default action ends the process. Programs
// call it once at start-up; a library never installs handlers on its own.
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <string_view>

namespace imm {

/// The result of a write: empty `error` on success.
struct WriteStatus {
  std::string error;  ///< human-readable: which path and why (errno text)
  [[nodiscard]] bool ok() const { return error.empty(); }
};

/// The temporary name used for `path` by this process: "<path>.tmp.<pid>".
std::string temporary_path(const std::string& path);

/// Writes `content` to `path` atomically (temporary file + rename) when `path` is, or will be, a
/// regular file; see the file comment for links, FIFOs and devices.
/// @param[in] path destination; its directory must exist (see ensure_directory).
/// @return the status; on failure nothing is left behind and `path` is unchanged.
WriteStatus write_file_atomic(const std::string& path, std::string_view content);

/// Streams into `path` atomically: `fill` writes to a stream opened on the temporary file; it
/// returns false (or throws) to abandon the write, which then removes the temporary file.
/// Exceptions from `fill` are rethrown after the clean-up.
WriteStatus write_file_atomic(const std::string& path,
                              const std::function<bool(std::ostream&)>& fill);

/// A write prepared but not yet visible (for a set of outputs that must land together): the
/// content sits in `temporary` until commit_write renames it over `target`. An empty `temporary`
/// after a successful stage_write: the path was a FIFO or device, written through already.
struct StagedWrite {
  std::string path;       ///< as given
  std::string target;     ///< the file it replaces (symbolic links followed)
  std::string temporary;  ///< "<target>.tmp.<pid>", removed on a signal until committed
  int slot = -1;          ///< internal: the temporary's slot for the signal handler
};

/// The first half of write_file_atomic: fills the temporary (a FIFO or device is written through
/// at once). On failure nothing is left behind. @return the status.
WriteStatus stage_write(const std::string& path, const std::function<bool(std::ostream&)>& fill,
                        StagedWrite& staged);
/// Renames a staged temporary over its target (nothing for a written-through one).
/// @return the status; on failure the temporary is removed.
WriteStatus commit_write(StagedWrite& staged);
/// Removes a staged temporary; the target stays as it was.
void discard_write(StagedWrite& staged);

/// What file writing `path` would replace, as a string equal for two paths exactly when they name
/// the same file: the device and inode of an existing target (symbolic links followed, so a link
/// and its target, or two hard links, are the same), else its canonical absolute path.
std::string output_identity(const std::string& path);

/// Creates a directory and its parents when missing. @return the status (error when the path
/// exists and is not a directory, or cannot be created).
WriteStatus ensure_directory(const std::string& path);

/// ensure_directory of the directory `file` is to be written in (nothing for a bare file name).
WriteStatus ensure_parent_directory(const std::string& file);

/// Why `path` must not be read as an input file: "a character device", "a block device", "a
/// socket" (reading /dev/zero or /dev/urandom never ends); empty for a regular file, a FIFO, a
/// directory (the readers say so themselves) or a path that cannot be examined (the open then
/// reports why). Symbolic links are followed.
std::string unreadable_file_kind(const std::string& path);

/// Installs handlers for SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGXCPU, SIGXFSZ, SIGALRM,
/// SIGVTALRM, SIGPROF, SIGUSR1 and SIGUSR2 (those whose disposition is still the default) that unlink the temporaries of writes in progress, then re-raise the signal with
/// its default action (so the exit status still says which signal ended the process).
/// Idempotent. Async-signal-safe inside the handler (unlink, sigaction, raise only).
void remove_temporaries_on_signals();

/// The number of temporaries of writes in progress in this process (for tests).
int temporaries_in_progress();

}  // namespace imm
