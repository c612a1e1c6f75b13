// What a picture shows, independent of the renderer: triangle parts (each with a colour, or a
// colour per triangle, or a scalar field through a colour map), tubes along polylines, element
// edges, a view direction and the camera fitted to the scene's bounding box, a ground plane for
// a soft shadow, and an optional colour bar. render/povray.h turns a Scene into a POV-Ray scene
// and runs the renderer; render/mesh_scenes.h builds scenes from the project's surfaces and tet
// meshes. CGAL-free; coordinates in doubles (display only, never used for a decision).
//
// Paper: the figures (Figs. 1-7, 9, 12, 15-17, 21, 22, 24) draw inputs with their intersecting
// triangles in red, tet meshes as boundaries with element edges, cut-aways that expose the
// duplicated tets, copies coloured by immersion-graph node, and scalar fields with a colour bar.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace imm::render {

using Vec3 = std::array<double, 3>;

/// Linear RGB in [0, 1] (written as sRGB-ish values: POV-Ray runs with assumed_gamma 1).
struct Color {
  double r = 0, g = 0, b = 0;
  friend bool operator==(const Color&, const Color&) = default;
};

/// Colours with a meaning, shared by the scenes, the figures and the picture checks.
namespace colors {
inline constexpr Color kSurface{0.78, 0.80, 0.84};       ///< input surface (low saturation)
inline constexpr Color kIntersecting{0.85, 0.08, 0.06};  ///< intersecting input triangles
inline constexpr Color kEdge{0.12, 0.12, 0.14};          ///< element edges
inline constexpr Color kBackground{1.0, 1.0, 1.0};
inline constexpr Color kGround{0.97, 0.97, 0.97};
inline constexpr Color kHelper{0.55, 0.55, 0.58};        ///< helper boxes (paper §6.2, Fig. 17)
}  // namespace colors

/// The k-th colour of a qualitative palette of well separated, saturated hues (none of them red,
/// which is reserved for intersecting triangles); cycles after palette_size().
Color palette(std::size_t k);
std::size_t palette_size();
/// Hue in degrees [0, 360) of the palette's k-th colour (what a picture check looks for).
double palette_hue(std::size_t k);

/// A perceptual sequential colour map (viridis-like), t in [0, 1] (clamped). A scalar part's
/// vertex without a value (NaN or infinite, e.g. a distance to an unreachable source) is drawn
/// in colors::kSurface instead.
Color colormap(double t);

/// One drawable triangle set. Exactly one colouring applies, in this order of precedence:
/// `vertex_scalar` (through `colormap`, normalised by the scene's scalar range), then
/// `triangle_colors`, then `color`.
struct Part {
  std::string name;  ///< written as a comment into the scene (for people reading it)
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  Color color = colors::kSurface;
  std::vector<Color> triangle_colors;  ///< per triangle, or empty
  std::vector<double> vertex_scalar;   ///< per vertex, or empty
  bool smooth = false;                 ///< area-weighted vertex normals (smooth surfaces)
  double transmit = 0.0;               ///< 0 opaque .. 1 invisible (see-through helper boxes)
  /// Draw every edge of the part as a thin dark tube (element edges of a mesh boundary).
  bool edges = false;
};

/// A tube along a polyline (e.g. an intersection curve).
struct Polyline {
  std::vector<Vec3> points;
  bool closed = false;
  Color color = colors::kIntersecting;
  double radius = 0.0;  ///< 0: a default relative to the scene's size
};

/// Where the camera looks from: a direction on the sphere around the scene (degrees), with
/// `up` the world axis that points up in the picture (0 = x, 1 = y, 2 = z).
struct View {
  double azimuth = 35.0;
  double elevation = 25.0;
  int up = 1;
  double field_of_view = 30.0;  ///< horizontal, degrees
  double margin = 0.06;         ///< free border, as a fraction of the picture
};

/// A scalar range for the colour bar and the parts' `vertex_scalar` (t = (s - lo) / (hi - lo)).
/// The colour bar has a dark tick and a label (the value, written with up to 3 significant
/// digits in a seven-segment font drawn by the scene itself: no font file needed) at each of
/// `ticks`; empty: at lo, the middle and hi (0, 0.5, 1 for weights).
struct ScalarRange {
  double lo = 0.0;
  double hi = 1.0;
  std::vector<double> ticks;
};

/// The values a colour bar labels: `range.ticks`, or lo, the middle and hi; values outside
/// [lo, hi] are left out.
std::vector<double> colour_bar_ticks(const ScalarRange& range);

/// Where the colour bar sits in the picture (fractions of the width from the left edge, of the
/// height from the top): the bar [bar_left, bar_right] x [top, bottom], its ticks to
/// tick_right, the labels from label_left to the right edge. Pictures checks look for the
/// labels there.
struct ColourBarLayout {
  double bar_left = 0.82, bar_right = 0.86, tick_right = 0.875, label_left = 0.895;
  double top = 0.125, bottom = 0.875;
  /// Label glyph height, as a fraction of the picture height.
  double glyph_height = 0.05;
  /// The picture row (fraction of the height from the top) of value `s`.
  [[nodiscard]] double row_of(const ScalarRange& range, double s) const {
    const double t = range.hi > range.lo ? (s - range.lo) / (range.hi - range.lo) : 0.0;
    return bottom + (top - bottom) * t;
  }
};
inline constexpr ColourBarLayout kColourBar{};

struct Scene {
  std::vector<Part> parts;
  std::vector<Polyline> polylines;
  View view;
  bool ground = true;  ///< a plane under the scene catching a soft shadow
  Color background = colors::kBackground;
  /// Set: scalar parts are normalised with this range and a colour bar is drawn at the right.
  std::optional<ScalarRange> scalar_range;
};

/// Axis-aligned bounds of every vertex and polyline point. @pre the scene has a point.
struct Bounds {
  Vec3 lo{0, 0, 0};
  Vec3 hi{0, 0, 0};
  [[nodiscard]] double diagonal() const;
  [[nodiscard]] Vec3 center() const;
};
Bounds scene_bounds(const Scene& scene);
bool scene_is_empty(const Scene& scene);

/// A pinhole camera: location, unit forward, and the picture plane's right and up vectors
/// (unit, right-handed world: right = forward x up).
struct Camera {
  Vec3 location{0, 0, 0};
  Vec3 forward{0, 0, 1};
  Vec3 right{1, 0, 0};
  Vec3 up{0, 1, 0};
  double tan_half_width = 0.27;   ///< tan(horizontal half field of view)
  double tan_half_height = 0.20;  ///< tan(vertical half field of view) = width one * H / W
  /// Horizontal shift of the picture window (tan units; > 0 moves the content left), to leave
  /// room for a colour bar at the right.
  double window_shift = 0.0;
};

/// The camera of `view` fitted to `bounds` for a width x height picture: it looks along the
/// view direction, is centred on the box's projection and moved back until every corner of the
/// box lies inside the picture with the view's margin.
/// @pre width, height >= 1.
Camera fit_camera(const Bounds& bounds, const View& view, int width, int height);

/// The camera a scene is rendered with: fit_camera, and with a colour bar (scalar_range set)
/// the content fitted into the left 80% of the picture.
Camera scene_camera(const Scene& scene, int width, int height);

/// Projects a world point with `camera` to picture coordinates (x right, y down, in pixels;
/// the picture is width x height). Points behind the camera give nullopt.
std::optional<std::array<double, 2>> project(const Camera& camera, const Vec3& p, int width, int height);

}  // namespace imm::render
