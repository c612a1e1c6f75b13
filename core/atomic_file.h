// Outputs that are never half-written (DESIGN §3: "never a silent partial file").
//
// The content goes to "<path>.tmp.<pid>" in the same directory, is flushed and closed, and is then
// renamed over `path` (rename(2) is atomic within one file system). On any error the temporary
// file is removed and `path` is left as it was.
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

/// Writes `content` to `path` atomically (temporary file + rename).
/// @param[in] path destination; its directory must exist (see ensure_directory).
/// @return the status; on failure nothing is left behind and `path` is unchanged.
WriteStatus write_file_atomic(const std::string& path, std::string_view content);

/// Streams into `path` atomically: `fill` writes to a stream opened on the temporary file; it
/// returns false (or throws) to abandon the write, which then removes the temporary file.
/// Exceptions from `fill` are rethrown after the clean-up.
WriteStatus write_file_atomic(const std::string& path,
                              const std::function<bool(std::ostream&)>& fill);

/// Creates a directory and its parents when missing. @return the status (error when the path
/// exists and is not a directory, or cannot be created).
WriteStatus ensure_directory(const std::string& path);

}  // namespace imm
