#include "render/povray.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "render/png_image.h"
#include "render/process.h"

namespace imm::render {

namespace {

// Coordinates with 9 significant digits: sub-pixel for any picture size, and a scene file of
// reasonable size for 100k triangles.
struct Num {
  double v;
};
std::ostream& operator<<(std::ostream& os, Num n) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", std::isfinite(n.v) ? n.v : 0.0);
  return os << buffer;
}
std::ostream& operator<<(std::ostream& os, const Vec3& p) {
  return os << '<' << Num{p[0]} << ',' << Num{p[1]} << ',' << Num{p[2]} << '>';
}
// Colours are given as they should look (sRGB); POV-Ray computes in linear light
// (assumed_gamma 1) and encodes the picture as sRGB, so they are linearised here.
double linear(double v) { return std::pow(std::clamp(v, 0.0, 1.0), 2.2); }
std::ostream& operator<<(std::ostream& os, const Color& c) {
  return os << "rgb <" << Num{linear(c.r)} << ',' << Num{linear(c.g)} << ',' << Num{linear(c.b)} << '>';
}

Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 normalized(const Vec3& a) {
  const double n = std::sqrt(dot(a, a));
  return n > 0 ? scale(a, 1.0 / n) : a;
}

constexpr const char* kFinish = "finish { ambient 0.16 diffuse 0.72 specular 0.12 roughness 0.04 }";
constexpr int kScalarLevels = 64;

void write_texture(std::ostream& os, const Color& c, double transmit = 0.0) {
  os << "texture { pigment { color " << c;
  if (transmit > 0) os << " transmit " << Num{std::min(transmit, 1.0)};
  os << " } " << kFinish << " }";
}

/// The texture of a scalar value: its colour level, or kScalarLevels (colors::kSurface: no
/// value) for NaN and infinities.
int scalar_level(double s, const ScalarRange& range) {
  if (!std::isfinite(s)) return kScalarLevels;
  const double span = range.hi - range.lo;
  double t = span > 0 ? (s - range.lo) / span : 0.0;
  if (!(t > 0)) t = 0;
  return std::min(kScalarLevels - 1, static_cast<int>(std::lround(std::min(t, 1.0) * (kScalarLevels - 1))));
}

void write_part(std::ostream& os, const Part& part, const std::optional<ScalarRange>& range, double edge_radius) {
  if (part.triangles.empty()) return;
  os << "// part: " << part.name << " (" << part.vertices.size() << " vertices, " << part.triangles.size()
     << " triangles)\n";
  os << "mesh2 {\n  vertex_vectors { " << part.vertices.size();
  for (const Vec3& v : part.vertices) os << ",\n    " << v;
  os << " }\n";
  if (part.smooth) {
    std::vector<Vec3> normals(part.vertices.size(), Vec3{0, 0, 0});
    for (const auto& t : part.triangles) {
      const Vec3 n = cross(sub(part.vertices[t[1]], part.vertices[t[0]]), sub(part.vertices[t[2]], part.vertices[t[0]]));
      for (std::uint32_t v : t) normals[v] = add(normals[v], n);
    }
    os << "  normal_vectors { " << normals.size();
    for (Vec3& n : normals) {
      n = normalized(n);
      if (dot(n, n) == 0) n = {0, 0, 1};
      os << ",\n    " << n;
    }
    os << " }\n";
  }
  const bool scalar = !part.vertex_scalar.empty() && part.vertex_scalar.size() == part.vertices.size();
  const bool per_triangle = !scalar && part.triangle_colors.size() == part.triangles.size();
  std::vector<int> triangle_texture;
  if (scalar) {
    ScalarRange r{0.0, 0.0};
    if (range) {
      r = *range;
    } else {
      bool first = true;
      for (double v : part.vertex_scalar)
        if (std::isfinite(v)) r = first ? ScalarRange{v, v} : ScalarRange{std::min(r.lo, v), std::max(r.hi, v)}, first = false;
    }
    os << "  texture_list { " << kScalarLevels + 1;
    for (int k = 0; k < kScalarLevels; ++k) {
      os << ",\n    ";
      write_texture(os, colormap(static_cast<double>(k) / (kScalarLevels - 1)));
    }
    os << ",\n    ";
    write_texture(os, colors::kSurface);
    os << " }\n  face_indices { " << part.triangles.size();
    for (const auto& t : part.triangles)
      os << ",\n    <" << t[0] << ',' << t[1] << ',' << t[2] << ">, " << scalar_level(part.vertex_scalar[t[0]], r)
         << ',' << scalar_level(part.vertex_scalar[t[1]], r) << ',' << scalar_level(part.vertex_scalar[t[2]], r);
    os << " }\n";
  } else if (per_triangle) {
    std::map<std::array<double, 3>, int> index;
    std::vector<Color> list;
    for (const Color& c : part.triangle_colors) {
      const auto [it, inserted] = index.emplace(std::array<double, 3>{c.r, c.g, c.b}, static_cast<int>(list.size()));
      if (inserted) list.push_back(c);
      triangle_texture.push_back(it->second);
    }
    os << "  texture_list { " << list.size();
    for (const Color& c : list) {
      os << ",\n    ";
      write_texture(os, c, part.transmit);
    }
    os << " }\n  face_indices { " << part.triangles.size();
    for (std::size_t i = 0; i < part.triangles.size(); ++i) {
      const auto& t = part.triangles[i];
      os << ",\n    <" << t[0] << ',' << t[1] << ',' << t[2] << ">, " << triangle_texture[i];
    }
    os << " }\n";
  } else {
    os << "  face_indices { " << part.triangles.size();
    for (const auto& t : part.triangles) os << ",\n    <" << t[0] << ',' << t[1] << ',' << t[2] << '>';
    os << " }\n";
  }
  os << "  ";
  write_texture(os, part.color, part.transmit);
  os << "\n}\n";
  if (part.edges) {
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const auto& t : part.triangles)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = t[k], b = t[(k + 1) % 3];
        edges.emplace(std::min(a, b), std::max(a, b));
      }
    os << "// edges of " << part.name << "\nunion {\n";
    for (const auto& [a, b] : edges) {
      if (part.vertices[a] == part.vertices[b]) continue;
      os << "  cylinder { " << part.vertices[a] << ", " << part.vertices[b] << ", " << Num{edge_radius} << " }\n";
    }
    os << "  pigment { color " << colors::kEdge << " } finish { ambient 0.3 diffuse 0.4 }\n  no_shadow\n}\n";
  }
}

void write_polyline(std::ostream& os, const Polyline& line, double default_radius) {
  if (line.points.size() < 2) return;
  const double r = line.radius > 0 ? line.radius : default_radius;
  os << "union {\n";
  const std::size_t n = line.points.size();
  const std::size_t segments = line.closed ? n : n - 1;
  for (std::size_t i = 0; i < segments; ++i) {
    const Vec3& a = line.points[i];
    const Vec3& b = line.points[(i + 1) % n];
    if (a != b) os << "  cylinder { " << a << ", " << b << ", " << Num{r} << " }\n";
  }
  for (const Vec3& p : line.points) os << "  sphere { " << p << ", " << Num{r} << " }\n";
  os << "  pigment { color " << line.color << " } " << kFinish << "\n}\n";
}

/// Rectangles in picture coordinates (fractions of the width from the left, of the height from
/// the top), collected into one self-lit mesh2 in camera space.
struct FlatQuads {
  std::vector<std::array<double, 4>> rects;  ///< x0, y0, x1, y1
  std::vector<int> texture;
  void add(double x0, double y0, double x1, double y1, int t) {
    rects.push_back({x0, y0, x1, y1});
    texture.push_back(t);
  }
};

/// The seven segments a (top), b (top right), c (bottom right), d (bottom), e (bottom left),
/// f (top left), g (middle) of a character, as a bit mask (bit 0 = a); 0 for a character the
/// font does not have.
int seven_segments(char c) {
  switch (c) {
    case '0': return 0b0111111;
    case '1': return 0b0000110;
    case '2': return 0b1011011;
    case '3': return 0b1001111;
    case '4': return 0b1100110;
    case '5': return 0b1101101;
    case '6': return 0b1111101;
    case '7': return 0b0000111;
    case '8': return 0b1111111;
    case '9': return 0b1101111;
    case '-': return 0b1000000;
    case 'e': return 0b1111001;  // E
    default: return 0;
  }
}

/// Writes `text` (digits, '.', '-', 'e') with its left edge at x and its middle at y; glyphs
/// `h` high (fraction of the picture height), strokes of the same width in pixels both ways.
void add_label(FlatQuads& quads, const std::string& text, double x, double y, double h, int width, int height, int t) {
  const double aspect = static_cast<double>(height) / std::max(width, 1);  // x fraction per y fraction, same pixels
  const double w = 0.55 * h * aspect;
  const double ty = 0.18 * h, tx = ty * aspect;
  const double top = y - h / 2;
  for (char c : text) {
    if (c == '.') {
      quads.add(x, top + h - ty, x + tx, top + h, t);
      x += tx + 0.22 * h * aspect;
      continue;
    }
    const int mask = seven_segments(c);
    auto horizontal = [&](double v) { quads.add(x - tx / 2, top + v * h - ty / 2, x + w + tx / 2, top + v * h + ty / 2, t); };
    auto vertical = [&](double u, double v0, double v1) {
      quads.add(x + u * w - tx / 2, top + v0 * h - ty / 2, x + u * w + tx / 2, top + v1 * h + ty / 2, t);
    };
    if (mask & 1) horizontal(0);
    if (mask & 2) vertical(1, 0, 0.5);
    if (mask & 4) vertical(1, 0.5, 1);
    if (mask & 8) horizontal(1);
    if (mask & 16) vertical(0, 0.5, 1);
    if (mask & 32) vertical(0, 0, 0.5);
    if (mask & 64) horizontal(0.5);
    x += w + 0.22 * h * aspect;
  }
}

/// A colour bar in camera space at the right of the picture (render/scene.h kColourBar): one
/// self-lit quad per colour level, and a dark tick and label per value of colour_bar_ticks, at
/// half the depth of the nearest corner of the scene's box (in front of everything).
void write_colour_bar(std::ostream& os, const ScalarRange& range, const Bounds& bounds, const Camera& cam, int width,
                      int height) {
  const double diag = std::max(bounds.diagonal(), 1e-300);
  double near = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 8; ++k) {
    const Vec3 c{(k & 1) ? bounds.hi[0] : bounds.lo[0], (k & 2) ? bounds.hi[1] : bounds.lo[1],
                 (k & 4) ? bounds.hi[2] : bounds.lo[2]};
    near = std::min(near, dot(sub(c, cam.location), cam.forward));
  }
  const double depth = std::max(near * 0.5, 1e-6 * diag);
  // Picture fractions (x from the left, y from the top) to a point at `depth` on the ray.
  auto at = [&](double fx, double fy) {
    const double tx = cam.window_shift + (2 * fx - 1) * cam.tan_half_width;
    const double ty = (1 - 2 * fy) * cam.tan_half_height;
    return add(cam.location, scale(add(cam.forward, add(scale(cam.right, tx), scale(cam.up, ty))), depth));
  };
  const ColourBarLayout& l = kColourBar;
  FlatQuads quads;
  for (int k = 0; k < kScalarLevels; ++k) {
    const double y0 = l.bottom + (l.top - l.bottom) * (k + 1) / kScalarLevels;
    const double y1 = l.bottom + (l.top - l.bottom) * k / kScalarLevels;
    quads.add(l.bar_left, y0, l.bar_right, y1, k);
  }
  const double line = 0.005;  // tick thickness, fraction of the height
  const double aspect = static_cast<double>(height) / std::max(width, 1);
  os << "// colour bar: " << Num{range.lo} << " (bottom) to " << Num{range.hi} << " (top); ticks:";
  for (double v : colour_bar_ticks(range)) {
    const double y = l.row_of(range, v);
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    os << ' ' << text;
    quads.add(l.bar_left - line * aspect, y - line / 2, l.tick_right, y + line / 2, kScalarLevels);
    add_label(quads, text, l.label_left, y, l.glyph_height, width, height, kScalarLevels);
  }
  os << "\nmesh2 {\n  vertex_vectors { " << 4 * quads.rects.size();
  for (const auto& r : quads.rects)
    os << ",\n    " << at(r[0], r[1]) << ", " << at(r[2], r[1]) << ", " << at(r[2], r[3]) << ", " << at(r[0], r[3]);
  os << " }\n  texture_list { " << kScalarLevels + 1;
  for (int k = 0; k < kScalarLevels; ++k)
    os << ",\n    texture { pigment { color " << colormap((k + 0.5) / kScalarLevels)
       << " } finish { ambient 0 diffuse 0 emission 1 } }";
  os << ",\n    texture { pigment { color " << colors::kEdge << " } finish { ambient 0 diffuse 0 emission 1 } }";
  os << " }\n  face_indices { " << 2 * quads.rects.size();
  for (std::size_t q = 0; q < quads.rects.size(); ++q) {
    const std::size_t a = 4 * q;
    os << ",\n    <" << a << ',' << a + 1 << ',' << a + 2 << ">, " << quads.texture[q] << ",\n    <" << a << ','
       << a + 2 << ',' << a + 3 << ">, " << quads.texture[q];
  }
  os << " }\n  no_shadow\n}\n";
}

}  // namespace

std::string format_povray(const Scene& scene, int width, int height, bool soft_shadows) {
  const Bounds bounds = scene_bounds(scene);
  const Camera cam = scene_camera(scene, width, height);
  const double diag = std::max(bounds.diagonal(), 1e-300);
  const Vec3 center = bounds.center();
  const int up_axis = ((scene.view.up % 3) + 3) % 3;
  Vec3 world_up{0, 0, 0};
  world_up[up_axis] = 1;

  std::ostringstream os;
  os << "// Written by immersion (render/povray.cpp). Render: povray +I<this> +FN +W" << width << " +H" << height
     << " -D\n#version 3.7;\n"
     << "global_settings { assumed_gamma 1.0 max_trace_level 6 }\n"
     << "background { color " << scene.background << " }\n";
  os << "camera {\n  perspective\n  location " << cam.location << "\n  direction "
     << add(cam.forward, scale(cam.right, cam.window_shift)) << "\n  right " << scale(cam.right, 2 * cam.tan_half_width)
     << "\n  up " << scale(cam.up, 2 * cam.tan_half_height) << "\n}\n";
  // Key light above, behind the viewer's left shoulder; a soft area light when asked.
  const Vec3 key_dir = normalized(add(add(scale(world_up, 2.0), scale(cam.forward, -0.9)), scale(cam.right, -0.6)));
  const Vec3 key = add(center, scale(key_dir, 3.0 * diag));
  os << "light_source {\n  " << key << "\n  color rgb <0.78,0.78,0.76>\n";
  if (soft_shadows) {
    const Vec3 a1 = normalized(cross(key_dir, world_up[0] == 0 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
    const Vec3 a2 = normalized(cross(key_dir, a1));
    os << "  area_light " << scale(a1, 0.6 * diag) << ", " << scale(a2, 0.6 * diag)
       << ", 5, 5\n  adaptive 1\n  circular\n  orient\n";
  }
  os << "}\n";
  os << "light_source { " << add(cam.location, scale(cam.up, 0.2 * diag)) << " color rgb <0.42,0.42,0.44> shadowless }\n";
  if (scene.ground) {
    const double level = bounds.lo[up_axis] - 0.004 * diag;
    os << "plane { " << world_up << ", " << Num{level} << "\n  pigment { color " << colors::kGround
       << " }\n  finish { ambient 0.55 diffuse 0.45 }\n}\n";
  }
  const double edge_radius = 0.0011 * diag;
  for (const Part& part : scene.parts) write_part(os, part, scene.scalar_range, edge_radius);
  for (const Polyline& line : scene.polylines) write_polyline(os, line, 0.004 * diag);
  if (scene.scalar_range) write_colour_bar(os, *scene.scalar_range, bounds, cam, width, height);
  return os.str();
}

RendererLookup find_povray(const std::string& requested) {
  std::string name = requested;
  if (name.empty()) {
    const char* env = std::getenv("IMM_POVRAY");
    name = env && *env ? env : "povray";
  }
  RendererLookup lookup;
  if (const auto path = find_program(name)) {
    lookup.path = *path;
  } else {
    lookup.error = "POV-Ray not found (looked for '" + name +
                   "'); install the Debian package povray (scripts/install_deps.sh does) or set IMM_POVRAY";
  }
  return lookup;
}

RenderStatus render_png(const Scene& scene, const std::string& png_path, const RenderOptions& options) {
  namespace fs = std::filesystem;
  static std::atomic<unsigned> counter{0};
  RenderStatus status;
  if (options.width < 1 || options.height < 1 || options.width > 16384 || options.height > 16384) {
    status.error = "picture size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                   " out of range (1..16384)";
    return status;
  }
  if (scene_is_empty(scene)) {
    status.error = png_path + ": nothing to draw (the scene has no triangle)";
    return status;
  }
  const RendererLookup renderer = find_povray(options.povray);
  if (!renderer.error.empty()) {
    status.error = renderer.error;
    status.renderer_missing = true;
    return status;
  }
  const fs::path target = fs::absolute(png_path);
  const fs::path dir = target.parent_path();
  if (!fs::is_directory(dir)) {
    status.error = png_path + ": directory " + dir.string() + " does not exist";
    return status;
  }
  // POV-Ray may only write into its working directory (Debian's povray.conf), so it runs in the
  // picture's directory on names relative to it.
  const std::string stem = "." + target.stem().string() + ".tmp." + std::to_string(::getpid()) + "." +
                           std::to_string(counter++);
  const std::string scene_name = stem + ".pov";
  const std::string image_name = stem + ".png";
  const fs::path scene_file = dir / scene_name;
  const fs::path image_file = dir / image_name;
  auto clean = [&] {
    std::error_code ec;
    fs::remove(scene_file, ec);
    fs::remove(image_file, ec);
  };
  const WriteStatus written =
      write_file_atomic(scene_file.string(), format_povray(scene, options.width, options.height, options.soft_shadows));
  if (!written.ok()) {
    status.error = written.error;
    return status;
  }
  std::vector<std::string> argv{renderer.path, "+I" + scene_name, "+O" + image_name, "+FN8",
                                "+W" + std::to_string(options.width), "+H" + std::to_string(options.height),
                                "-D", "-V", "-P", "-J", "-GD", "-GR", "-GS", "-GW"};
  if (options.antialias) argv.insert(argv.end(), {"+A0.2", "+AM2", "+R2"});
  if (options.threads > 0) argv.push_back("+WT" + std::to_string(options.threads));
  // POV-Ray 3.7's front end gives up when its render threads take too long to start, which
  // happens on a loaded machine ("Timed out waiting for worker thread startup", exit 1, seen
  // about once in a few hundred pictures while others compiled); that one failure is retried.
  ProcessResult run = run_process(argv, dir.string(), options.timeout_seconds);
  status.seconds = run.seconds;
  for (int retry = 0; retry < 2 && !run.ok() && run.started && !run.timed_out &&
                      run.output.find("Timed out waiting for worker thread startup") != std::string::npos;
       ++retry) {
    run = run_process(argv, dir.string(), options.timeout_seconds);
    status.seconds += run.seconds;
  }
  if (!run.ok()) {
    clean();
    if (!run.started) {
      status.error = "POV-Ray (" + renderer.path + ") could not run: " + run.error;
    } else if (run.timed_out) {
      status.error = png_path + ": POV-Ray did not finish within " + std::to_string(options.timeout_seconds) +
                     " s (stopped)";
    } else {
      std::string tail = run.output;
      if (tail.size() > 1200) tail = tail.substr(tail.size() - 1200);
      status.error = png_path + ": POV-Ray failed (" +
                     (run.signal ? "signal " + std::to_string(run.signal) : "exit " + std::to_string(run.exit_code)) +
                     "): " + tail;
    }
    return status;
  }
  const ImageReadResult check = read_png(image_file.string());
  if (!check.ok() || check.image.width != options.width || check.image.height != options.height) {
    clean();
    status.error = png_path + ": POV-Ray wrote no usable picture" + (check.ok() ? std::string{} : ": " + check.error);
    return status;
  }
  std::error_code ec;
  fs::rename(image_file, target, ec);
  if (ec) {
    clean();
    status.error = png_path + ": cannot rename the picture into place: " + ec.message();
    return status;
  }
  if (options.keep_scene) {
    fs::path kept = target;
    kept.replace_extension(".pov");
    fs::rename(scene_file, kept, ec);
  }
  clean();
  return status;
}

}  // namespace imm::render
