// Shared plumbing of the figure programs: `--out DIR` and `--quick`, the 2D pipeline on a named
// generator, atomic output files and a self-check that fails the program (exit 1) when the
// reproduced fact differs from the paper's. Each fig_NN_<slug>.cpp states its paper item.
#pragma once

#include <algorithm>
#include <cstdio>
#include <optional>
#include <utility>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/graph_search.h"
#include "dim2/complex2.h"
#include "dim2/generators.h"
#include "dim2/mesh2.h"
#include "dim2/svg.h"
#include "render/png_image.h"
#include "render/povray.h"
#include "render/svg_png.h"

namespace imm::figures {

struct FigureArgs {
  std::string out;     ///< output directory
  bool quick = false;  ///< small sizes, for the CTest label "figures"
  int picture_width = 0;   ///< --size WxH (0: by mode)
  int picture_height = 0;
};

/// What the gallery shows for a figure program (figures/make_gallery.sh collects every
/// program's `gallery.md`): the paper item, the caption's claim, the facts the program checked
/// (every passing `expect`) and its pictures.
struct FigureRecord {
  std::string program;
  std::string out;
  bool quick = false;
  std::string item;   ///< "Fig. 21"
  std::string claim;  ///< the caption's claim, in a sentence
  std::vector<std::string> facts;
  std::vector<std::pair<std::string, std::string>> pictures;  ///< file (PNG), label
  std::vector<std::string> skipped;                           ///< pictures not made, and why
};
inline FigureRecord& record() {
  static FigureRecord r;
  return r;
}

/// Names the paper item and the caption's claim a program reproduces (for the gallery).
inline void describe(const std::string& item, const std::string& claim) {
  record().item = item;
  record().claim = claim;
}

inline FigureArgs parse_args(int argc, char** argv, const std::string& name) {
  FigureArgs args{"out/figures/" + name, false};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      args.quick = true;
    } else if (a == "--out" && i + 1 < argc) {
      args.out = argv[++i];
    } else if (a == "--size" && i + 1 < argc &&
               std::sscanf(argv[i + 1], "%dx%d", &args.picture_width, &args.picture_height) == 2 &&
               args.picture_width > 0 && args.picture_height > 0 && args.picture_width <= 8192 &&
               args.picture_height <= 8192) {
      ++i;
    } else {
      std::cerr << "usage: " << name << " [--out DIR] [--quick] [--size WxH]\n";
      std::exit(64);
    }
  }
  const WriteStatus dir = ensure_directory(args.out);
  if (!dir.ok()) throw std::runtime_error(dir.error);
  record().program = name;
  record().out = args.out;
  record().quick = args.quick;
  return args;
}

/// Picture sizes: small in --quick (CI renders every figure), full size otherwise.
inline int picture_width(const FigureArgs& args) {
  return args.picture_width > 0 ? args.picture_width : args.quick ? 320 : 1024;
}
inline int picture_height(const FigureArgs& args) {
  return args.picture_height > 0 ? args.picture_height : args.quick ? 240 : 768;
}

/// Pixels of a picture that are not background: a picture must show something.
inline void expect_not_blank(const render::Image& image, const std::string& file) {
  const std::size_t shown = render::count_non_background(image, render::colors::kBackground);
  if (shown * 50 < static_cast<std::size_t>(image.width) * image.height)
    throw std::runtime_error("figure check failed: picture " + file + " is (nearly) blank: " +
                             std::to_string(shown) + " pixels drawn");
}

inline void svg_preview(const FigureArgs& args, const std::string& svg_file);

/// Writes `<out>/<file>` atomically; an SVG also gets its PNG preview beside it.
inline void write(const FigureArgs& args, const std::string& file, const std::string& content) {
  const WriteStatus status = write_file_atomic(args.out + "/" + file, content);
  if (!status.ok()) throw std::runtime_error(status.error);
  std::cout << "wrote " << args.out << "/" << file << '\n';
  if (file.size() > 4 && file.compare(file.size() - 4, 4, ".svg") == 0) svg_preview(args, file);
}

/// Fails the figure program when a reproduced fact differs from the paper's; a fact that holds
/// is listed in the gallery.
inline void expect(bool ok, const std::string& what) {
  if (!ok) throw std::runtime_error("figure check failed: " + what);
  auto& facts = record().facts;
  if (!what.empty() && std::find(facts.begin(), facts.end(), what) == facts.end()) facts.push_back(what);
}

/// Renders a 3D scene into `<out>/<file>` (PNG) with POV-Ray and checks it is not blank.
/// Renderer missing: the picture is skipped with a message (the facts are still checked) and
/// nullopt returned; any other rendering failure fails the figure.
inline std::optional<render::Image> picture(const FigureArgs& args, const render::Scene& scene,
                                            const std::string& file, const std::string& label) {
  render::RenderOptions options;
  options.width = picture_width(args);
  options.height = picture_height(args);
  options.soft_shadows = !args.quick;
  const std::string path = args.out + "/" + file;
  const render::RenderStatus status = render::render_png(scene, path, options);
  if (status.renderer_missing) {
    std::cout << "skipped picture " << path << ": " << status.error << '\n';
    record().skipped.push_back(file + ": " + status.error);
    return std::nullopt;
  }
  if (!status.ok()) throw std::runtime_error(status.error);
  const render::ImageReadResult read = render::read_png(path);
  if (!read.ok()) throw std::runtime_error(read.error);
  expect_not_blank(read.image, file);
  record().pictures.emplace_back(file, label);
  std::cout << "wrote " << path << " (" << options.width << "x" << options.height << ", "
            << static_cast<int>(status.seconds * 1000) << " ms)\n";
  return read.image;
}

/// A PNG preview of an SVG the program wrote (rsvg-convert); skipped with a message when the
/// converter is missing.
inline void svg_preview(const FigureArgs& args, const std::string& svg_file) {
  const std::string png_file = svg_file.substr(0, svg_file.size() - 4) + ".png";
  const render::ConvertStatus status =
      render::svg_to_png(args.out + "/" + svg_file, args.out + "/" + png_file, picture_width(args));
  if (status.converter_missing) {
    std::cout << "skipped picture " << args.out << "/" << png_file << ": " << status.error << '\n';
    record().skipped.push_back(png_file + ": " + status.error);
    return;
  }
  if (!status.ok()) throw std::runtime_error(status.error);
  const render::ImageReadResult read = render::read_png(args.out + "/" + png_file);
  if (!read.ok()) throw std::runtime_error(read.error);
  expect_not_blank(read.image, png_file);
  record().pictures.emplace_back(png_file, svg_file);
  std::cout << "wrote " << args.out << "/" << png_file << '\n';
}

/// Counts pixels of a meaningful colour (palette hue or red) in a picture.
inline std::size_t hue_pixels(const render::Image& image, const render::Color& color) {
  return render::count_hue(image, render::query_for(color));
}

/// A named generator through the exact complex and the search (all immersions).
struct CurveRun {
  dim2::CurveSet curves;
  dim2::BuildResult built;
  SearchResult search;
};

inline CurveRun run_curve(const std::string& generator, const std::vector<std::string>& params = {}) {
  CurveRun run;
  const dim2::GenerateResult generated = dim2::generate(generator, params);
  if (!generated.ok()) throw std::runtime_error(generated.error);
  run.curves = generated.curves;
  run.built = dim2::build_complex(run.curves);
  if (!run.built.report.ok()) throw std::runtime_error(run.built.report.summary());
  if (run.built.complex && !run.built.inversion) {
    SearchOptions options;
    options.max_immersions = 0;
    run.search = find_immersions(run.built.complex->complex, options);
  }
  return run;
}

/// Meshes one immersion at `resolution` (fails the figure on any defect) and writes the mesh
/// pulled apart as `<stem>.svg` and the Medit file `<stem>.mesh`.
inline dim2::MeshResult mesh_and_write(const FigureArgs& args, const dim2::Complex2& complex,
                                       const Immersion& immersion, int resolution,
                                       const std::string& stem) {
  dim2::MeshOptions options;
  options.resolution = resolution;
  dim2::MeshResult mesh = dim2::mesh_immersion(complex, immersion, options);
  expect(mesh.report.ok(), mesh.report.summary());
  write(args, stem + ".svg", dim2::format_mesh_svg(complex, immersion, mesh));
  write(args, stem + ".mesh", dim2::format_medit_2d(mesh.mesh));
  return mesh;
}

/// Runs a figure's body, mapping failures to exit code 1 with the reason.
/// `<out>/gallery.md`: this program's section of the gallery (figures/make_gallery.sh).
inline void write_gallery() {
  const FigureRecord& r = record();
  if (r.out.empty()) return;
  std::ostringstream md;
  md << "## " << (r.item.empty() ? r.program : r.item) << " — `" << r.program << "`\n\n";
  if (!r.claim.empty()) md << "*Paper:* " << r.claim << "\n\n";
  if (!r.facts.empty()) {
    md << "*Checked by the program:*\n";
    for (const std::string& f : r.facts) md << "- " << f << "\n";
    md << "\n";
  }
  for (const auto& [file, label] : r.pictures) md << "![" << label << "](" << file << ")\n";
  for (const std::string& s : r.skipped) md << "\n(picture skipped: " << s << ")\n";
  md << "\n";
  const WriteStatus status = write_file_atomic(r.out + "/gallery.md", md.str());
  if (!status.ok()) throw std::runtime_error(status.error);
}

template <class Body>
int main_guard(Body&& body) {
  try {
    body();
    write_gallery();
    return 0;
  } catch (const std::exception& e) {
    std::cerr << e.what() << '\n';
    return 1;
  }
}

}  // namespace imm::figures
