#include "render/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace imm::render {

namespace {

// Hues at least 30 degrees apart and at least 30 degrees from red (intersecting triangles).
constexpr std::array<double, 7> kPaletteHues{212, 36, 120, 275, 178, 62, 318};

Color from_hsv(double hue, double saturation, double value) {
  const double h = std::fmod(hue, 360.0) / 60.0;
  const double c = value * saturation;
  const double x = c * (1.0 - std::abs(std::fmod(h, 2.0) - 1.0));
  const double m = value - c;
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(h)) {
    case 0: r = c; g = x; break;
    case 1: r = x; g = c; break;
    case 2: g = c; b = x; break;
    case 3: g = x; b = c; break;
    case 4: r = x; b = c; break;
    default: r = c; b = x; break;
  }
  return {r + m, g + m, b + m};
}

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 normalized(const Vec3& a) {
  const double n = std::sqrt(dot(a, a));
  return n > 0 ? scale(a, 1.0 / n) : a;
}

}  // namespace

std::size_t palette_size() { return kPaletteHues.size(); }
double palette_hue(std::size_t k) { return kPaletteHues[k % kPaletteHues.size()]; }
Color palette(std::size_t k) { return from_hsv(palette_hue(k), 0.78, 0.88); }

Color colormap(double t) {
  // Viridis sampled at quarters, linearly interpolated between them.
  static constexpr std::array<Color, 5> kStops{{{0.267, 0.005, 0.329},
                                                {0.229, 0.322, 0.546},
                                                {0.128, 0.567, 0.551},
                                                {0.369, 0.789, 0.383},
                                                {0.993, 0.906, 0.144}}};
  if (!(t > 0.0)) t = 0.0;  // NaN goes to the bottom
  t = std::min(t, 1.0) * 4.0;
  const int k = std::min(static_cast<int>(t), 3);
  const double f = t - k;
  const Color& a = kStops[k];
  const Color& b = kStops[k + 1];
  return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}

std::vector<double> colour_bar_ticks(const ScalarRange& range) {
  std::vector<double> ticks = range.ticks;
  if (ticks.empty()) ticks = {range.lo, 0.5 * (range.lo + range.hi), range.hi};
  std::vector<double> out;
  for (double t : ticks)
    if (std::isfinite(t) && t >= std::min(range.lo, range.hi) && t <= std::max(range.lo, range.hi)) out.push_back(t);
  return out;
}

double Bounds::diagonal() const { return std::sqrt(dot(sub(hi, lo), sub(hi, lo))); }
Vec3 Bounds::center() const { return scale(add(lo, hi), 0.5); }

bool scene_is_empty(const Scene& scene) {
  for (const Part& p : scene.parts)
    if (!p.triangles.empty()) return false;
  for (const Polyline& l : scene.polylines)
    if (!l.points.empty()) return false;
  return true;
}

Bounds scene_bounds(const Scene& scene) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Bounds b{{inf, inf, inf}, {-inf, -inf, -inf}};
  auto take = [&](const Vec3& p) {
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = std::min(b.lo[d], p[d]);
      b.hi[d] = std::max(b.hi[d], p[d]);
    }
  };
  for (const Part& part : scene.parts)
    for (const auto& t : part.triangles)
      for (std::uint32_t v : t) take(part.vertices[v]);
  for (const Polyline& l : scene.polylines)
    for (const Vec3& p : l.points) take(p);
  if (b.lo[0] > b.hi[0]) return Bounds{};
  return b;
}

Camera fit_camera(const Bounds& bounds, const View& view, int width, int height) {
  constexpr double deg = std::numbers::pi / 180.0;
  const int u = ((view.up % 3) + 3) % 3;
  const int a = (u + 1) % 3;
  const int s = (u + 2) % 3;
  Vec3 e_up{0, 0, 0}, e_front{0, 0, 0}, e_side{0, 0, 0};
  e_up[u] = 1;
  e_front[a] = 1;
  e_side[s] = 1;
  const double az = view.azimuth * deg;
  const double el = std::clamp(view.elevation, -89.0, 89.0) * deg;
  // Direction from the scene to the camera.
  const Vec3 towards = add(scale(add(scale(e_front, std::cos(az)), scale(e_side, std::sin(az))), std::cos(el)),
                           scale(e_up, std::sin(el)));
  Camera cam;
  cam.forward = normalized(scale(towards, -1.0));
  cam.right = normalized(cross(cam.forward, e_up));
  cam.up = cross(cam.right, cam.forward);
  cam.tan_half_width = std::tan(std::clamp(view.field_of_view, 1.0, 170.0) * deg / 2.0);
  cam.tan_half_height = cam.tan_half_width * height / std::max(width, 1);

  std::vector<Vec3> corners;
  for (int k = 0; k < 8; ++k)
    corners.push_back({(k & 1) ? bounds.hi[0] : bounds.lo[0], (k & 2) ? bounds.hi[1] : bounds.lo[1],
                       (k & 4) ? bounds.hi[2] : bounds.lo[2]});
  // Centre the box's parallel projection in the picture, then back off until every corner fits.
  Vec3 target = bounds.center();
  double xlo = std::numeric_limits<double>::infinity(), xhi = -xlo, ylo = xlo, yhi = -xlo;
  for (const Vec3& c : corners) {
    const Vec3 rel = sub(c, target);
    xlo = std::min(xlo, dot(rel, cam.right));
    xhi = std::max(xhi, dot(rel, cam.right));
    ylo = std::min(ylo, dot(rel, cam.up));
    yhi = std::max(yhi, dot(rel, cam.up));
  }
  target = add(target, add(scale(cam.right, (xlo + xhi) / 2), scale(cam.up, (ylo + yhi) / 2)));
  const double keep = std::clamp(1.0 - 2.0 * view.margin, 0.1, 1.0);
  const double tw = cam.tan_half_width * keep;
  const double th = cam.tan_half_height * keep;
  // Back off until every corner fits; then re-centre on the perspective projection (which is
  // not symmetric like the parallel one) and back off again, a few times.
  double distance = 0.0;
  for (int round = 0; round < 4; ++round) {
    distance = 0.0;
    for (const Vec3& c : corners) {
      const Vec3 rel = sub(c, target);
      const double x = std::abs(dot(rel, cam.right));
      const double y = std::abs(dot(rel, cam.up));
      const double z = dot(rel, cam.forward);
      distance = std::max(distance, std::max(x / tw, y / th) - z);
    }
    if (round == 3) break;
    const Vec3 eye = sub(target, scale(cam.forward, distance));
    double lo_x = std::numeric_limits<double>::infinity(), hi_x = -lo_x, lo_y = lo_x, hi_y = -lo_x;
    for (const Vec3& c : corners) {
      const Vec3 rel = sub(c, eye);
      const double depth = std::max(dot(rel, cam.forward), 1e-300);
      lo_x = std::min(lo_x, dot(rel, cam.right) / depth);
      hi_x = std::max(hi_x, dot(rel, cam.right) / depth);
      lo_y = std::min(lo_y, dot(rel, cam.up) / depth);
      hi_y = std::max(hi_y, dot(rel, cam.up) / depth);
    }
    target = add(target, add(scale(cam.right, (lo_x + hi_x) / 2 * distance), scale(cam.up, (lo_y + hi_y) / 2 * distance)));
  }
  distance = std::max(distance, 1e-3 * std::max(bounds.diagonal(), 1e-300));
  cam.location = sub(target, scale(cam.forward, distance));
  return cam;
}

Camera scene_camera(const Scene& scene, int width, int height) {
  const Bounds bounds = scene_bounds(scene);
  if (!scene.scalar_range) return fit_camera(bounds, scene.view, width, height);
  // Fit into a window 80% as wide, then widen the window to the right (off-axis).
  constexpr double kContent = 0.8;
  constexpr double deg = std::numbers::pi / 180.0;
  View narrow = scene.view;
  const double tw = std::tan(std::clamp(scene.view.field_of_view, 1.0, 170.0) * deg / 2.0);
  narrow.field_of_view = 2.0 * std::atan(tw * kContent) / deg;
  const int narrow_width = std::max(1, static_cast<int>(std::lround(width * kContent)));
  Camera cam = fit_camera(bounds, narrow, narrow_width, height);
  cam.tan_half_width = cam.tan_half_width / kContent;
  cam.tan_half_height = cam.tan_half_width * height / std::max(width, 1);
  cam.window_shift = (1.0 - kContent) * cam.tan_half_width;
  return cam;
}

std::optional<std::array<double, 2>> project(const Camera& camera, const Vec3& p, int width, int height) {
  const Vec3 rel = sub(p, camera.location);
  const double depth = dot(rel, camera.forward);
  if (!(depth > 0)) return std::nullopt;
  const double xs = (dot(rel, camera.right) / depth - camera.window_shift) / camera.tan_half_width;
  const double ys = dot(rel, camera.up) / (depth * camera.tan_half_height);
  return std::array<double, 2>{(xs + 1.0) / 2.0 * width, (1.0 - ys) / 2.0 * height};
}

}  // namespace imm::render
