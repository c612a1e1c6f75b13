// Reading PNG pictures back (libpng, Debian libpng-dev) and the content checks the figures and
// tests apply to them: a picture is checked for what it shows, not only for existing.
//  - not blank: pixels that differ from the background colour;
//  - colours that carry meaning: pixels whose hue is near a given hue with enough saturation
//    (shading changes brightness, not hue, so a red triangle stays red under any light).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "render/scene.h"

namespace imm::render {

/// 8-bit RGB pixels, row-major from the top-left.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< 3 * width * height
  [[nodiscard]] std::array<std::uint8_t, 3> at(int x, int y) const {
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * width + x);
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

struct ImageReadResult {
  Image image;
  std::string error;  ///< empty when read
  [[nodiscard]] bool ok() const { return error.empty(); }
};

/// Decodes a PNG file of any colour type / bit depth into 8-bit RGB (alpha composed on white).
ImageReadResult read_png(const std::string& path);

/// Hue (degrees, [0, 360)) and saturation ([0, 1], HSV) of an 8-bit pixel.
double pixel_hue(std::uint8_t r, std::uint8_t g, std::uint8_t b);
double pixel_saturation(std::uint8_t r, std::uint8_t g, std::uint8_t b);
/// Hue of a colour (degrees).
double color_hue(const Color& c);

/// Pixels that differ from `background` by more than `tolerance` in some channel (0-255).
std::size_t count_non_background(const Image& image, const Color& background, int tolerance = 12);

/// Pixels with saturation >= `min_saturation` and value >= `min_value` whose hue lies within
/// `tolerance` degrees of `hue`. Restrict to the rectangle [x0, x1) x [y0, y1) when given.
struct HueQuery {
  double hue = 0.0;
  double tolerance = 12.0;
  double min_saturation = 0.35;
  double min_value = 0.12;
};
/// The query for pixels showing `color` lit in any way: its hue within 12 degrees, saturation at
/// least 60% of the colour's own (antialiased mixtures of two colours, and dark shades whose
/// rounding moves the hue, fall below it).
HueQuery query_for(const Color& color);
std::size_t count_hue(const Image& image, const HueQuery& query);
std::size_t count_hue(const Image& image, const HueQuery& query, int x0, int y0, int x1, int y1);

/// Dark grey pixels in [x0, x1) x [y0, y1) (clipped to the picture): every channel below
/// `max_value` and the channels within `max_spread` of each other (the colour bar's ticks and
/// labels; saturated colours do not count).
std::size_t count_dark(const Image& image, int x0, int y0, int x1, int y1, int max_value = 170, int max_spread = 40);

/// Number of pixels that differ between two pictures of the same size (-1 if sizes differ).
long count_differing_pixels(const Image& a, const Image& b);

}  // namespace imm::render
