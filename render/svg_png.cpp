#include "render/svg_png.h"

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>

#include "render/png_image.h"
#include "render/process.h"

namespace imm::render {

ConvertStatus svg_to_png(const std::string& svg_path, const std::string& png_path, int width,
                         double timeout_seconds) {
  namespace fs = std::filesystem;
  static std::atomic<unsigned> counter{0};
  ConvertStatus status;
  const char* env = std::getenv("IMM_RSVG_CONVERT");
  const std::string name = env && *env ? env : "rsvg-convert";
  const auto program = find_program(name);
  if (!program) {
    status.error = "rsvg-convert not found (looked for '" + name +
                   "'); install the Debian package librsvg2-bin (scripts/install_deps.sh does)";
    status.converter_missing = true;
    return status;
  }
  if (width < 1 || width > 16384) {
    status.error = "picture width " + std::to_string(width) + " out of range (1..16384)";
    return status;
  }
  if (!fs::is_regular_file(svg_path)) {
    status.error = svg_path + ": no such SVG file";
    return status;
  }
  const fs::path target = fs::absolute(png_path);
  const fs::path temp = target.parent_path() / ("." + target.stem().string() + ".tmp." +
                                                std::to_string(::getpid()) + "." + std::to_string(counter++) + ".png");
  const ProcessResult run = run_process(
      {*program, "--width", std::to_string(width), "--keep-aspect-ratio", "--background-color", "white",
       "--format", "png", "--output", temp.string(), fs::absolute(svg_path).string()},
      {}, timeout_seconds);
  std::error_code ec;
  if (!run.ok()) {
    fs::remove(temp, ec);
    status.error = svg_path + ": rsvg-convert failed" + (run.timed_out ? std::string(" (time limit)") : "") + ": " +
                   (run.started ? run.output : run.error);
    return status;
  }
  const ImageReadResult check = read_png(temp.string());
  if (!check.ok()) {
    fs::remove(temp, ec);
    status.error = check.error;
    return status;
  }
  fs::rename(temp, target, ec);
  if (ec) {
    fs::remove(temp, ec);
    status.error = png_path + ": cannot rename the picture into place";
  }
  return status;
}

}  // namespace imm::render
