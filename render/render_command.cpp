#include "render/render_command.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>

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

constexpr const char* kHelp = R"(usage: immerse render IN -o OUT.png [options]

A picture of a surface, a tet mesh or 2D curves (POV-Ray for 3D, rsvg-convert for 2D).
  IN: surface (.obj .off .ply .stl): intersecting triangles red, intersection curves as tubes
      tet mesh (.mesh .veg .node .ele): boundary with element edges, copies coloured by
      reference (the graph node of `immerse mesh` outputs)
      curves (.txt, 2D .svg): drawn as SVG, converted to PNG

options:
  -o, --output OUT.png   the picture (written atomically)
  --size WxH             picture size in pixels (default 800x600)
  --view AZ,EL           camera azimuth and elevation in degrees (default 35,25; with --cut,
                         a view facing the cut)
  --up x|y|z             the world axis that points up in the picture (default y)
  --cut AXIS=F           cut-away (tet meshes): keep the tets whose centroid lies below the plane
                         across AXIS at fraction F of the box (e.g. z=0.5); -AXIS=F keeps the
                         upper side
  --explode F            pull each graph node's copies apart by F times their offset from the
                         mesh centre (tet meshes; default 0)
  --color node|single    tet colours: by reference (default) or one colour
  --no-edges             no element edges
  --no-intersections     do not compute the intersecting triangles (surfaces)
  --no-ground            no ground plane (and no shadow)
  --fast                 no antialiasing, hard shadows
  --keep-scene           keep the POV-Ray scene beside the picture (OUT.pov)
  --timeout S            stop the renderer after S seconds (default 300)
)";

bool ends_with(std::string s, const std::string& suffix) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::optional<double> parse_double(const std::string& s) {
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

int axis_of(const std::string& s) {
  if (s == "x") return 0;
  if (s == "y") return 1;
  if (s == "z") return 2;
  return -1;
}

/// A 2D input: text curves, or an SVG/OBJ that holds curves rather than a surface.
bool is_curve_input(const std::string& path) {
  if (ends_with(path, ".txt") || ends_with(path, ".svg")) return true;
  return false;
}

}  // namespace

const char* render_command_help() { return kHelp; }

int run_render_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  auto usage = [&](const std::string& message) {
    err << "immerse render: " << message << "\n(see immerse render --help)\n";
    return 64;
  };
  std::string input, output;
  RenderOptions options;
  View view;
  bool view_given = false;
  std::optional<std::pair<int, double>> cut;
  bool keep_upper = false;
  double explode = 0.0;
  bool by_node = true, edges = true, intersections = true, ground = true;
  std::set<std::string> seen;  // an option given twice is a usage error, as in the other commands
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (!a.empty() && a[0] == '-' && !seen.insert(a == "-o" ? "--output" : a).second)
      return usage(a + " given twice");
    auto value = [&]() -> std::optional<std::string> {
      if (i + 1 >= args.size()) return std::nullopt;
      return args[++i];
    };
    if (a == "--help" || a == "-h") {
      out << kHelp;
      return 0;
    } else if (a == "-o" || a == "--output") {
      const auto v = value();
      if (!v) return usage(a + " needs a file name");
      output = *v;
    } else if (a == "--size") {
      const auto v = value();
      int w = 0, h = 0;
      if (!v || std::sscanf(v->c_str(), "%dx%d", &w, &h) != 2 || w < 16 || h < 16 || w > 8192 || h > 8192)
        return usage("--size expects WxH between 16x16 and 8192x8192");
      options.width = w;
      options.height = h;
    } else if (a == "--view") {
      const auto v = value();
      const std::size_t comma = v ? v->find(',') : std::string::npos;
      if (comma == std::string::npos) return usage("--view expects AZ,EL in degrees");
      const auto az = parse_double(v->substr(0, comma));
      const auto el = parse_double(v->substr(comma + 1));
      if (!az) return usage("--view expects AZ,EL with AZ a finite number of degrees");
      if (!el || *el < -89 || *el > 89) return usage("--view expects AZ,EL with EL in [-89, 89]");
      view.azimuth = *az;
      view.elevation = *el;
      view_given = true;
    } else if (a == "--up") {
      const auto v = value();
      const int axis = v ? axis_of(*v) : -1;
      if (axis < 0) return usage("--up expects x, y or z");
      view.up = axis;
    } else if (a == "--cut") {
      const auto v = value();
      std::string spec = v.value_or("");
      keep_upper = !spec.empty() && spec[0] == '-';
      if (keep_upper) spec.erase(0, 1);
      const std::size_t eq = spec.find('=');
      const int axis = eq == std::string::npos ? -1 : axis_of(spec.substr(0, eq));
      const auto f = eq == std::string::npos ? std::nullopt : parse_double(spec.substr(eq + 1));
      if (axis < 0 || !f || *f < 0 || *f > 1) return usage("--cut expects AXIS=F (AXIS x, y or z; F in [0, 1])");
      cut = std::pair{axis, *f};
    } else if (a == "--explode") {
      const auto v = value();
      const auto f = v ? parse_double(*v) : std::nullopt;
      if (!f || *f < 0 || *f > 10) return usage("--explode expects a number in [0, 10]");
      explode = *f;
    } else if (a == "--color") {
      const auto v = value();
      if (!v || (*v != "node" && *v != "single")) return usage("--color expects node or single");
      by_node = *v == "node";
    } else if (a == "--no-edges") {
      edges = false;
    } else if (a == "--no-intersections") {
      intersections = false;
    } else if (a == "--no-ground") {
      ground = false;
    } else if (a == "--fast") {
      options.antialias = false;
      options.soft_shadows = false;
    } else if (a == "--keep-scene") {
      options.keep_scene = true;
    } else if (a == "--timeout") {
      const auto v = value();
      const auto t = v ? parse_double(*v) : std::nullopt;
      if (!t || *t <= 0) return usage("--timeout expects a positive number of seconds");
      options.timeout_seconds = *t;
    } else if (!a.empty() && a[0] == '-') {
      return usage("unknown option " + a);
    } else if (input.empty()) {
      input = a;
    } else {
      return usage("one input only (got " + input + " and " + a + ")");
    }
  }
  if (input.empty()) return usage("no input file");
  if (output.empty()) return usage("no output picture (-o OUT.png)");
  if (!ends_with(output, ".png")) return usage("the output must be a .png file");
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
    if (intersections) {
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
    style.color_by = by_node ? TetStyle::ColorBy::Reference : TetStyle::ColorBy::Single;
    style.edges = edges;
    style.explode = explode;
    if (cut) style.cut = cut_across(tet_mesh_bounds(read.mesh), cut->first, cut->second, keep_upper);
    scene = tet_mesh_scene(read.mesh, style);
    if (scene_is_empty(scene)) {
      err << "immerse render: the cut leaves no tet to draw\n";
      return 64;
    }
    what = std::to_string(read.mesh.tets.size()) + " tets";
  } else {
    return usage(input + ": unknown input type (surface .obj/.off/.ply/.stl, tet mesh .mesh/.veg/.node/.ele, "
                         "curves .txt/.svg)");
  }
  scene.ground = ground;
  scene.view = view;
  if (cut && !view_given) scene.view = view_facing_cut(cut->first, keep_upper, view.up);
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
