// `immerse render IN -o OUT.png [options]`: the options' table and their values (sizes, angles,
// cut planes) turned into a render::RenderRequest; the drawing is render/render_command.cpp's.
#include "app/cli_render.h"

#include <charconv>
#include <cmath>
#include <optional>

#include "render/render_command.h"

namespace imm::cli {

namespace {

std::optional<double> parse_number(const std::string& s) {
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<int> parse_int(const std::string& s) {
  int v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

int axis_of(const std::string& s) {
  if (s == "x") return 0;
  if (s == "y") return 1;
  if (s == "z") return 2;
  return -1;
}

/// Fills `request` from the command line; returns what is wrong with a value, or "".
std::string parse_render_request(const CommandLine& cl, render::RenderRequest& request) {
  request.input = cl.positional.at(0);
  request.output = *cl.value("-o");
  if (extension_of(request.output) != ".png") return "the output must be a .png file, got '" + request.output + "'";
  if (auto v = cl.value("--size")) {
    const std::size_t x = v->find('x');
    const auto w = x == std::string::npos ? std::nullopt : parse_int(v->substr(0, x));
    const auto h = x == std::string::npos ? std::nullopt : parse_int(v->substr(x + 1));
    if (!w || !h || *w < 16 || *h < 16 || *w > 8192 || *h > 8192)
      return "--size expects WxH between 16x16 and 8192x8192, got '" + *v + "'";
    request.options.width = *w;
    request.options.height = *h;
  }
  if (auto v = cl.value("--view")) {
    const std::size_t comma = v->find(',');
    if (comma == std::string::npos) return "--view expects AZ,EL in degrees, got '" + *v + "'";
    const auto az = parse_number(v->substr(0, comma));
    const auto el = parse_number(v->substr(comma + 1));
    if (!az) return "--view expects AZ,EL with AZ a finite number of degrees, got '" + *v + "'";
    if (!el || *el < -89 || *el > 89) return "--view expects AZ,EL with EL in [-89, 89], got '" + *v + "'";
    request.view.azimuth = *az;
    request.view.elevation = *el;
    request.view_given = true;
  }
  if (auto v = cl.value("--up")) {
    const int axis = axis_of(*v);
    if (axis < 0) return "--up expects x, y or z, got '" + *v + "'";
    request.view.up = axis;
  }
  if (auto v = cl.value("--cut")) {
    std::string spec = *v;
    render::CutRequest cut;
    cut.keep_upper = spec[0] == '-';
    if (cut.keep_upper) spec.erase(0, 1);
    const std::size_t eq = spec.find('=');
    cut.axis = eq == std::string::npos ? -1 : axis_of(spec.substr(0, eq));
    const auto f = eq == std::string::npos ? std::nullopt : parse_number(spec.substr(eq + 1));
    if (cut.axis < 0 || !f || *f < 0 || *f > 1) return "--cut expects AXIS=F (AXIS x, y or z; F in [0, 1]), got '" + *v + "'";
    cut.fraction = *f;
    request.cut = cut;
  }
  if (auto v = cl.value("--explode")) {
    const auto f = parse_number(*v);
    if (!f || *f < 0 || *f > 10) return "--explode expects a number in [0, 10], got '" + *v + "'";
    request.explode = *f;
  }
  if (auto v = cl.value("--color")) {
    if (*v != "node" && *v != "single") return "--color expects node or single, got '" + *v + "'";
    request.color_by_node = *v == "node";
  }
  request.edges = !cl.has("--no-edges");
  request.intersections = !cl.has("--no-intersections");
  request.ground = !cl.has("--no-ground");
  if (cl.has("--fast")) {
    request.options.antialias = false;
    request.options.soft_shadows = false;
  }
  request.options.keep_scene = cl.has("--keep-scene");
  if (auto t = cl.real("--timeout")) request.options.timeout_seconds = *t;
  return {};
}

}  // namespace

CommandSpec render_command_spec() {
  CommandSpec spec;
  spec.name = "render";
  spec.usage = "render IN -o OUT.png [--size WxH] [--view AZ,EL] [--up x|y|z] [--cut AXIS=F] [--explode F] [options]";
  spec.positional_help =
      "a surface (.obj .off .ply .stl: intersecting triangles red, intersection curves as tubes), a tet mesh "
      "(.mesh .veg .node .ele: boundary with element edges, copies coloured by reference, the graph node of "
      "'immerse mesh' outputs) or curves (.txt, 2D .svg: drawn as SVG, converted to PNG)";
  spec.description =
      "A picture of a surface, a tet mesh or 2D curves (POV-Ray for 3D, rsvg-convert for 2D), written\n"
      "atomically.\n";
  spec.options = {
      {"-o", ValueKind::Text, "OUT.png", "the picture (required)"},
      {"--size", ValueKind::Text, "WxH", "picture size in pixels (default 800x600)"},
      {"--view", ValueKind::Text, "AZ,EL", "camera azimuth and elevation in degrees (default 35,25; with --cut, a view facing the cut)"},
      {"--up", ValueKind::Text, "x|y|z", "the world axis that points up in the picture (default y)"},
      {"--cut", ValueKind::Text, "AXIS=F",
       "cut-away (tet meshes): keep the tets whose centroid lies below the plane across AXIS at fraction F of the "
       "box (e.g. z=0.5); -AXIS=F keeps the upper side"},
      {"--explode", ValueKind::Text, "F", "pull each graph node's copies apart by F times their offset from the mesh centre (tet meshes; default 0)"},
      {"--color", ValueKind::Text, "node|single", "tet colours: by reference (default) or one colour"},
      {"--no-edges", ValueKind::Flag, "", "no element edges"},
      {"--no-intersections", ValueKind::Flag, "", "do not compute the intersecting triangles (surfaces)"},
      {"--no-ground", ValueKind::Flag, "", "no ground plane (and no shadow)"},
      {"--fast", ValueKind::Flag, "", "no antialiasing, hard shadows"},
      {"--keep-scene", ValueKind::Flag, "", "keep the POV-Ray scene beside the picture (OUT.pov)"},
      {"--timeout", ValueKind::Real, "S", "stop the renderer after S seconds (default 300)"},
  };
  spec.footer =
      "Exit codes: 0 written, 2 unreadable or invalid input, 1 the renderer is missing or failed or the picture\n"
      "cannot be written, 64 bad command line (or a cut that leaves no tet).\n";
  return spec;
}

int command_render(Session& s, const CommandLine& cl) {
  if (!cl.has("-o")) return usage_error(s.env(), "render", "no output picture (-o OUT.png)");
  render::RenderRequest request;
  if (std::string error = parse_render_request(cl, request); !error.empty()) return usage_error(s.env(), "render", error);
  return render::render_picture(request, s.env().out, s.env().err);
}

}  // namespace imm::cli
