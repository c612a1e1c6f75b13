#include "render/png_image.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace imm::render {

ImageReadResult read_png(const std::string& path) {
  ImageReadResult result;
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) {
    result.error = path + ": not a readable PNG (" + png.message + ")";
    return result;
  }
  png.format = PNG_FORMAT_RGB;
  result.image.width = static_cast<int>(png.width);
  result.image.height = static_cast<int>(png.height);
  result.image.rgb.resize(PNG_IMAGE_SIZE(png));
  png_color white{255, 255, 255};
  if (!png_image_finish_read(&png, &white, result.image.rgb.data(), 0, nullptr)) {
    result.error = path + ": PNG decoding failed (" + png.message + ")";
    result.image = Image{};
  }
  png_image_free(&png);
  return result;
}

double pixel_hue(std::uint8_t r8, std::uint8_t g8, std::uint8_t b8) {
  const double r = r8 / 255.0, g = g8 / 255.0, b = b8 / 255.0;
  const double mx = std::max({r, g, b}), mn = std::min({r, g, b});
  const double c = mx - mn;
  if (c <= 0) return 0.0;
  double h = 0;
  if (mx == r) h = std::fmod((g - b) / c, 6.0);
  else if (mx == g) h = (b - r) / c + 2.0;
  else h = (r - g) / c + 4.0;
  h *= 60.0;
  return h < 0 ? h + 360.0 : h;
}

double pixel_saturation(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  const int mx = std::max({r, g, b}), mn = std::min({r, g, b});
  return mx == 0 ? 0.0 : static_cast<double>(mx - mn) / mx;
}

double color_hue(const Color& c) {
  auto q = [](double v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); };
  return pixel_hue(q(c.r), q(c.g), q(c.b));
}

HueQuery query_for(const Color& c) {
  auto q = [](double v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); };
  return HueQuery{color_hue(c), 12.0, 0.6 * pixel_saturation(q(c.r), q(c.g), q(c.b)), 0.15};
}

std::size_t count_non_background(const Image& image, const Color& background, int tolerance) {
  const int br = static_cast<int>(std::lround(background.r * 255));
  const int bg = static_cast<int>(std::lround(background.g * 255));
  const int bb = static_cast<int>(std::lround(background.b * 255));
  std::size_t n = 0;
  for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3)
    if (std::abs(image.rgb[i] - br) > tolerance || std::abs(image.rgb[i + 1] - bg) > tolerance ||
        std::abs(image.rgb[i + 2] - bb) > tolerance)
      ++n;
  return n;
}

std::size_t count_hue(const Image& image, const HueQuery& query) {
  return count_hue(image, query, 0, 0, image.width, image.height);
}

std::size_t count_hue(const Image& image, const HueQuery& query, int x0, int y0, int x1, int y1) {
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, image.width);
  y1 = std::min(y1, image.height);
  std::size_t n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const auto [r, g, b] = image.at(x, y);
      if (std::max({r, g, b}) < query.min_value * 255) continue;
      if (pixel_saturation(r, g, b) < query.min_saturation) continue;
      double d = std::abs(pixel_hue(r, g, b) - query.hue);
      d = std::min(d, 360.0 - d);
      if (d <= query.tolerance) ++n;
    }
  return n;
}

long count_differing_pixels(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) return -1;
  long n = 0;
  for (std::size_t i = 0; i + 2 < a.rgb.size(); i += 3)
    if (a.rgb[i] != b.rgb[i] || a.rgb[i + 1] != b.rgb[i + 1] || a.rgb[i + 2] != b.rgb[i + 2]) ++n;
  return n;
}

std::size_t count_dark(const Image& image, int x0, int y0, int x1, int y1, int max_value, int max_spread) {
  std::size_t n = 0;
  for (int y = std::max(0, y0); y < std::min(image.height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(image.width, x1); ++x) {
      const auto p = image.at(x, y);
      const int hi = std::max({p[0], p[1], p[2]}), lo = std::min({p[0], p[1], p[2]});
      n += hi < max_value && hi - lo <= max_spread ? 1 : 0;
    }
  return n;
}

}  // namespace imm::render
