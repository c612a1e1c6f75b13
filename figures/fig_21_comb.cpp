// Paper Fig. 21 (and Fig. 18): nearly self-intersecting shapes with no intersection at all — the
// teeth of a comb, lips that almost touch. A background tet that spans a narrow gap meets the
// solid in two local regions; the virtual tets (§7.1) give it one copy per region, so the teeth
// are not welded across the gap although the whole comb stays one connected mesh.
// Checks: duplicated background tets exist exactly where a tet spans a gap (more copies than the
// winding number of the cell), the output is one face-connected solid, and every tet is
// positively oriented. Writes the meshes for ParaView (.vtu, reference = graph node) and a
// Markdown summary; with ../shared/data present (full mode), also the real comb on Vega's tets.
#include <algorithm>
#include <filesystem>
#include <map>

#include "dim3/generators3.h"
#include "dim3/mesh3.h"
#include "dim3/self_connecting.h"
#include "figures/figure_common.h"
#include "render/mesh_scenes.h"

using namespace imm;

namespace {

struct CombRun {
  std::string name;
  dim3::Surface surface;
  std::size_t triangles = 0;
  dim3::MeshResult mesh;
  std::size_t duplicated = 0;  ///< background tets with more copies than their cell's winding number
  std::size_t components = 0;  ///< face-connected components of the output
};

CombRun run(const std::string& name, const dim3::Surface& surface, const dim3::MeshOptions& options) {
  dim3::ImmerseOptions immerse;
  immerse.build.exact_volumes = false;
  const dim3::Immersed im = dim3::immerse_surface(surface, immerse);
  figures::expect(im.build.complex && im.search.status == ImmersionStatus::Immersible,
                  name + " is immersible");
  const CellComplex<3>& c = im.build.complex->complex;
  figures::expect(c.cell_count() == 1 && c.arc_count() == 0, name + " has no self-intersection: one cell");
  CombRun r{name, surface, surface.triangle_count(),
            dim3::mesh_immersion(*im.build.complex, im.search.immersions.front(), options, im.input_vertices,
                                  im.input_triangles)};
  figures::expect(r.mesh.report.ok(), name + " meshes: " + r.mesh.report.summary());
  std::map<int, std::size_t> copies;
  for (int t : r.mesh.background_tet) ++copies[t];
  for (const auto& [tet, n] : copies) r.duplicated += n > 1 ? 1 : 0;  // winding number 1 everywhere
  r.components = dim3::face_connected_components(r.mesh.mesh);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_21_comb");
    figures::describe("Fig. 21 (and Fig. 18)",
                      "tet vertices are duplicated to embed a comb: a tet spanning the gap between two teeth "
                      "is copied once per tooth, so nearly touching parts are not welded.");
    std::vector<CombRun> runs;
    dim3::MeshOptions grid;
    grid.resolution = args.quick ? 16 : 40;
    runs.push_back(run("comb (generated, 8 teeth)", dim3::comb(8), grid));
    runs.push_back(run("mouth (generated)", dim3::mouth(args.quick ? 24 : 48), grid));
    const std::filesystem::path real = std::filesystem::path(IMM_SHARED_DATA_DIR) / "3d" / "comb.obj";
    const std::filesystem::path veg = std::filesystem::path(IMM_SHARED_DATA_DIR) / "tet" / "comb.tet.veg";
    if (!args.quick && std::filesystem::exists(real) && std::filesystem::exists(veg)) {
      const dim3::SurfaceReadResult read = dim3::read_surface(real.string());
      figures::expect(read.report.ok(), "comb.obj reads");
      dim3::MeshOptions vega;
      vega.background_path = veg.string();
      runs.push_back(run("comb.obj on comb.tet.veg (Vega)", read.surface, vega));
    }
    std::ostringstream md;
    md << "# Fig. 21: the comb's teeth are not welded\n\n"
       << "| input | triangles | background tets | output tets | background tets duplicated | components |\n"
       << "|---|---:|---:|---:|---:|---:|\n";
    for (const CombRun& r : runs) {
      figures::expect(r.duplicated > 0, r.name + ": some background tet spans a gap and is duplicated");
      figures::expect(r.components == 1, r.name + ": the output is one connected solid");
      md << "| " << r.name << " | " << r.triangles << " | " << r.mesh.stats.background_tets << " | "
         << r.mesh.stats.output_tets << " | " << r.duplicated << " | " << r.components << " |\n";
      std::string file = r.name.substr(0, r.name.find(' '));
      std::replace(file.begin(), file.end(), '.', '_');
      figures::write(args, "fig21_" + file + ".vtu", dim3::format_vtu(r.mesh.mesh));
      // Picture: the output's boundary with the copies of duplicated background tets highlighted
      // (orange) and the input surface beside it.
      std::map<int, std::size_t> copies;
      for (int t : r.mesh.background_tet) ++copies[t];
      render::TetStyle style;
      style.color_by = render::TetStyle::ColorBy::Flag;
      style.edges = !args.quick;
      style.flag.resize(r.mesh.mesh.tets.size());
      for (std::size_t t = 0; t < style.flag.size(); ++t) style.flag[t] = copies[r.mesh.background_tet[t]] > 1;
      // Cut-away across the axis that exposes the most duplicated tets (the lips of the mouth
      // are inside the head), at the duplicated tets' middle.
      const dim3::Box3 box = render::tet_mesh_bounds(r.mesh.mesh);
      render::Scene scene;
      std::size_t best = 0;
      for (int axis = 0; axis < 3; ++axis) {
        std::vector<double> along;
        for (std::size_t t = 0; t < style.flag.size(); ++t)
          if (style.flag[t]) along.push_back(r.mesh.mesh.vertices[r.mesh.mesh.tets[t][0]][axis]);
        if (along.empty()) break;
        std::nth_element(along.begin(), along.begin() + along.size() / 2, along.end());
        const double fraction = (along[along.size() / 2] - box.lo[axis]) / (box.hi[axis] - box.lo[axis]);
        render::TetStyle cut_style = style;
        cut_style.cut = render::cut_across(box, axis, fraction);
        render::Scene candidate = render::tet_mesh_scene(r.mesh.mesh, cut_style);
        std::size_t shown = 0;
        for (const render::Part& part : candidate.parts)
          if (part.color == style.highlight) shown += part.triangles.size();
        if (shown > best) {
          best = shown;
          scene = std::move(candidate);
          scene.view = render::view_facing_cut(axis, false, 1);
        }
      }
      figures::expect(best > 0, r.name + ": a cut-away exposes duplicated tets");
      if (const auto image = figures::picture(args, scene, "fig21_" + file + "_tets.png",
                                              r.name + ": cut-away, copies of duplicated background tets orange"))
        figures::expect(figures::hue_pixels(*image, style.highlight) > 0,
                        r.name + ": the picture shows duplicated tets");
      render::Scene input = render::surface_scene(r.surface);
      input.view = render::View{25, 30, 1};
      if (const auto image = figures::picture(args, input, "fig21_" + file + "_input.png", r.name + ": input"))
        figures::expect(figures::hue_pixels(*image, render::colors::kIntersecting) == 0,
                        r.name + ": no red in the input picture (it does not intersect itself)");
    }
    md << "\nA duplicated background tet holds two local regions of the one cell (two teeth, or two\n"
          "lips, on either side of a gap narrower than the tet): without virtual tets it would weld\n"
          "them. Open the .vtu files in ParaView and colour by `reference`, or shrink the cells, to\n"
          "see the gaps stay open.\n";
    figures::write(args, "fig21.md", md.str());
  });
}
