// Rendering a Scene with POV-Ray (Debian package `povray`), headless: the project writes the
// scene (meshes as mesh2 with per-triangle or per-vertex textures, edge and polyline tubes, a
// camera fitted to the bounding box, an area key light for soft shadows, a fill light, a ground
// plane, a colour bar in camera space), runs `povray +FN -D` with a time limit in the output's
// directory, checks the PNG it wrote and renames it into place (never a half-written picture).
// Rendering is deterministic: no jitter, no radiosity, so the same scene and size give the same
// pixels.
#pragma once

#include <string>

#include "render/scene.h"

namespace imm::render {

struct RenderOptions {
  int width = 800;
  int height = 600;
  bool antialias = true;
  bool soft_shadows = true;     ///< area key light (costs time on big pictures)
  double timeout_seconds = 300;
  unsigned threads = 0;         ///< POV-Ray render threads (0 = its default: all cores)
  /// The renderer: a path, or a program name looked up on PATH. Empty: $IMM_POVRAY if set,
  /// else "povray".
  std::string povray;
  /// Keep the scene beside the picture as <png without .png>.pov (to re-render it by hand).
  bool keep_scene = false;
};

struct RenderStatus {
  std::string error;              ///< empty on success: what failed and why
  bool renderer_missing = false;  ///< POV-Ray is not installed (or not where it was said to be)
  double seconds = 0.0;           ///< wall time of the renderer
  [[nodiscard]] bool ok() const { return error.empty(); }
};

/// The POV-Ray 3.7 scene text for `scene` at width x height (the camera depends on the aspect).
/// @pre the scene has at least one triangle or polyline point (scene_is_empty is false).
std::string format_povray(const Scene& scene, int width, int height, bool soft_shadows = true);

/// The renderer that render_png would run, or an error naming what is missing and how to
/// install it.
struct RendererLookup {
  std::string path;
  std::string error;
};
RendererLookup find_povray(const std::string& requested = {});

/// Renders `scene` into the PNG `png_path` (its directory must exist). On any failure (renderer
/// missing, time limit, renderer error, unreadable output) `png_path` is left as it was and no
/// temporary file remains.
RenderStatus render_png(const Scene& scene, const std::string& png_path, const RenderOptions& options = {});

}  // namespace imm::render
