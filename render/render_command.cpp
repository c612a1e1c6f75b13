#include "render/render_command.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "core/atomic_file.h"
#include "dim2/curves.h"
#include "dim2/svg.h"
#include "dim3/complex3.h"
#include "dim3/surface.h"
#include "dim3/tet_mesh.h"
#include "render/mesh_scenes.h"
#include "render/povray.h"
#include "render/svg_png.h"

namespace imm::render {

namespace {

bool ends_with(std::string s, const std::string& suffix) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// A 2D input: text curves, or an SVG/OBJ that holds curves rather than a surface.
bool is_curve_input(const std::string& path) {
  if (ends_with(path, ".txt") || ends_with(path, ".svg")) return true;
  return false;
}

}  // namespace

int render_picture(const RenderRequest& request, std::ostream& out, std::ostream& err) {
  const std::string& input = request.input;
  const std::string& output = request.output;
  const RenderOptions& options = request.options;
  if (!ends_with(output, ".png")) {
    err << "immerse render: the output must be a .png file\n";
    return 64;
  }
  if (const WriteStatus dir = ensure_parent_directory(output); !dir.ok()) {
    err << "immerse render: " << dir.error << '\n';
    return 1;
  }

  Scene scene;
  std::string what;
  if (is_curve_input(input)) {
    // 2D: the curves as SVG, converted.
    const dim2::ReadResult read = dim2::read_curves(input);
    if (!read.report.ok()) {
      err << "immerse render: " << input << ": " << read.report.summary() << '\n';
      return 2;
    }
    const std::string svg = output.substr(0, output.size() - 4) + ".tmp." + std::to_string(::getpid()) + ".svg";
    if (const WriteStatus w = write_file_atomic(svg, dim2::format_curves_svg(read.curves)); !w.ok()) {
      err << "immerse render: " << w.error << '\n';
      return 1;
    }
    const ConvertStatus converted = svg_to_png(svg, output, options.width, options.timeout_seconds);
    std::error_code ec;
    std::filesystem::remove(svg, ec);
    if (!converted.ok()) {
      err << "immerse render: " << converted.error << '\n';
      return 1;
    }
    out << "wrote " << output << " (curves, " << options.width << " px wide)\n";
    return 0;
  }
  if (dim3::is_surface_extension(input)) {
    const dim3::SurfaceReadResult read = dim3::read_surface(input);
    if (!read.report.ok()) {
      err << "immerse render: " << input << ": " << read.report.summary() << '\n';
      return 2;
    }
    std::shared_ptr<dim3::Complex> complex;
    if (request.intersections) {
      dim3::BuildOptions build_options;
      build_options.exact_volumes = false;
      const dim3::BuildResult built = dim3::build_complex(read.surface, build_options);
      if (built.complex) {
        complex = built.complex;
      } else {
        std::string first = built.report.summary();
        first = first.substr(0, first.find('\n'));
        err << "note: intersections not shown (" << (first.empty() ? "not valid input" : first) << ")\n";
      }
    }
    scene = surface_scene(read.surface, complex.get(), true);
    std::size_t red = 0;
    if (complex)
      for (bool b : intersecting_triangles(*complex)) red += b ? 1 : 0;
    what = std::to_string(read.surface.triangle_count()) + " triangles" +
           (complex ? ", " + std::to_string(red) + " intersecting (red)" : std::string{});
  } else if (dim3::is_tet_mesh_extension(input)) {
    const dim3::TetReadResult read = dim3::read_tet_mesh(input);
    if (!read.report.ok()) {
      err << "immerse render: " << input << ": " << read.report.summary() << '\n';
      return 2;
    }
    TetStyle style;
    style.color_by = request.color_by_node ? TetStyle::ColorBy::Reference : TetStyle::ColorBy::Single;
    style.edges = request.edges;
    style.explode = request.explode;
    if (request.cut)
      style.cut = cut_across(tet_mesh_bounds(read.mesh), request.cut->axis, request.cut->fraction, request.cut->keep_upper);
    scene = tet_mesh_scene(read.mesh, style);
    if (scene_is_empty(scene)) {
      err << "immerse render: the cut leaves no tet to draw\n";
      return 64;
    }
    what = std::to_string(read.mesh.tets.size()) + " tets";
  } else {
    err << "immerse render: " << input
        << ": unknown input type (surface .obj/.off/.ply/.stl, tet mesh .mesh/.veg/.node/.ele, curves .txt/.svg)\n";
    return 64;
  }
  scene.ground = request.ground;
  scene.view = request.view;
  if (request.cut && !request.view_given) scene.view = view_facing_cut(request.cut->axis, request.cut->keep_upper, request.view.up);
  const RenderStatus status = render_png(scene, output, options);
  if (!status.ok()) {
    err << "immerse render: " << status.error << '\n';
    return 1;
  }
  out << "wrote " << output << " (" << what << ", " << options.width << "x" << options.height << ", "
      << static_cast<int>(status.seconds * 1000) << " ms)\n";
  return 0;
}

}  // namespace imm::render
