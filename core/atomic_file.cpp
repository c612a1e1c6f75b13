#include "core/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace imm {

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
  const std::string tmp = temporary_path(path);
  auto discard = [&]() {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
  };
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) return {"cannot create '" + tmp + "': " + std::strerror(errno)};
  bool filled = false;
  try {
    filled = fill(out);
  } catch (...) {
    out.close();
    discard();
    throw;
  }
  if (!filled) {
    out.close();
    discard();
    return {"writing '" + path + "' was abandoned"};
  }
  out.flush();
  const bool stream_ok = static_cast<bool>(out);
  out.close();
  if (!stream_ok || out.fail()) {
    const std::string reason = errno ? std::strerror(errno) : "stream error";
    discard();
    return {"cannot write '" + tmp + "': " + reason};
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    discard();
    return {"cannot rename '" + tmp + "' to '" + path + "': " + reason};
  }
  return {};
}

WriteStatus ensure_directory(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return {};
  if (std::filesystem::exists(path, ec)) return {"'" + path + "' exists and is not a directory"};
  std::filesystem::create_directories(path, ec);
  if (ec) return {"cannot create directory '" + path + "': " + ec.message()};
  return {};
}

}  // namespace imm
