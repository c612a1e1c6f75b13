// PNG previews of the 2D figures' SVG pictures, converted by rsvg-convert (Debian package
// librsvg2-bin): the SVG stays the figure's source, the PNG sits beside it for viewers and the
// gallery. Written atomically (temporary name in the same directory, then renamed).
#pragma once

#include <string>

namespace imm::render {

struct ConvertStatus {
  std::string error;               ///< empty on success
  bool converter_missing = false;  ///< rsvg-convert is not installed
  [[nodiscard]] bool ok() const { return error.empty(); }
};

/// Converts `svg_path` into `png_path`, `width` pixels wide (height from the SVG's aspect), on a
/// white background. The converter: $IMM_RSVG_CONVERT if set, else rsvg-convert on PATH.
ConvertStatus svg_to_png(const std::string& svg_path, const std::string& png_path, int width,
                         double timeout_seconds = 60);

}  // namespace imm::render
