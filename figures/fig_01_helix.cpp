// Paper Fig. 1: a helix-shaped tube whose consecutive turns pass through each other. Left: the
// input with its intersecting triangles in red. Right: the output tet mesh, duplicated and
// connected so the turns are not glued (the paper pulls it apart with ARAP; here each graph
// node's copies are drawn in their own colour and pulled apart in an exploded view, and a
// cut-away shows the duplicated tets inside the overlap).
// Checks: the intersecting triangles are red in the picture (and only then), the helix has one
// immersion with max winding 2, the winding-2 cell has two copies (two node colours in the
// picture), every output tet positively oriented.
#include <map>

#include "dim3/generators3.h"
#include "dim3/mesh3.h"
#include "dim3/self_connecting.h"
#include "figures/figure_common.h"
#include "render/mesh_scenes.h"

using namespace imm;

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_01_helix");
    figures::describe("Fig. 1",
                      "the tets are duplicated and connected to account for the helix's self-intersections "
                      "(input: intersecting triangles red); the output can be pulled apart.");
    const int loops = args.quick ? 2 : 4;
    const dim3::Surface helix = dim3::helix(loops, args.quick ? 12 : 20);
    dim3::ImmerseOptions options;
    options.build.exact_volumes = false;
    const dim3::Immersed im = dim3::immerse_surface(helix, options);
    figures::expect(im.build.complex && im.search.status == ImmersionStatus::Immersible &&
                        im.search.immersions.size() == 1,
                    "the helix has exactly one immersion");
    const dim3::Complex& complex = *im.build.complex;
    const int max_winding = complex.complex.max_winding_number();
    figures::expect(max_winding == 2, "consecutive turns overlap: max winding number 2");
    const std::vector<bool> crossing = render::intersecting_triangles(complex);
    const auto red_triangles = std::count(crossing.begin(), crossing.end(), true);
    figures::expect(red_triangles > 0, "the turns intersect: some input triangles cross");

    dim3::MeshOptions mesh_options;
    mesh_options.resolution = args.quick ? 14 : 36;
    const dim3::MeshResult mesh = dim3::mesh_immersion(complex, im.search.immersions.front(), mesh_options);
    figures::expect(mesh.report.ok(), "the helix meshes");
    std::map<int, std::size_t> copies;
    for (int t : mesh.background_tet) ++copies[t];
    std::size_t duplicated = 0;
    for (const auto& [tet, n] : copies) duplicated += n > 1 ? 1 : 0;
    figures::expect(duplicated > 0, "background tets in the overlap are duplicated");
    figures::write(args, "fig1_helix.obj", dim3::format_obj(helix));
    figures::write(args, "fig1_helix_tets.vtu", dim3::format_vtu(mesh.mesh));

    render::Scene input = render::surface_scene(helix, &complex, true);
    input.view = render::View{30, 25, 2};
    if (const auto image = figures::picture(args, input, "fig1_input.png", "input, intersecting triangles red"))
      figures::expect(figures::hue_pixels(*image, render::colors::kIntersecting) > 0,
                      "the picture of the input shows red (intersecting) triangles");

    render::TetStyle style;
    style.edges = !args.quick;
    style.explode = 0.6;
    render::Scene tets = render::tet_mesh_scene(mesh.mesh, style);
    tets.view = render::View{30, 25, 2};
    if (const auto image = figures::picture(args, tets, "fig1_tets_by_node.png",
                                            "output tets, coloured by graph node, pulled apart")) {
      std::size_t colours = 0;
      for (std::size_t k = 0; k < render::palette_size(); ++k)
        colours += figures::hue_pixels(*image, render::palette(k)) > 20 ? 1 : 0;
      figures::expect(colours >= 2, "the picture shows the copies of at least two graph nodes");
      figures::expect(figures::hue_pixels(*image, render::colors::kIntersecting) == 0,
                      "no red in the output picture (red means intersecting input triangles)");
    }
    style.explode = 0.0;
    style.color_by = render::TetStyle::ColorBy::Flag;
    style.flag.assign(mesh.mesh.tets.size(), 0);
    for (std::size_t t = 0; t < mesh.mesh.tets.size(); ++t) style.flag[t] = copies[mesh.background_tet[t]] > 1;
    style.cut = render::cut_across(render::tet_mesh_bounds(mesh.mesh), 1, 0.5);
    render::Scene cut = render::tet_mesh_scene(mesh.mesh, style);
    cut.view = render::view_facing_cut(1, false, 2);
    if (const auto image = figures::picture(args, cut, "fig1_cutaway.png",
                                            "cut-away: duplicated background tets highlighted"))
      figures::expect(figures::hue_pixels(*image, style.highlight) > 0,
                      "the cut-away shows duplicated tets (highlighted)");

    std::ostringstream md;
    md << "# Fig. 1: the helix\n\n- input: " << helix.triangle_count() << " triangles, " << loops << " turns, "
       << red_triangles << " intersecting triangles\n- cells: " << complex.complex.cell_count()
       << ", max winding " << max_winding << ", 1 immersion\n- output: " << mesh.mesh.tets.size() << " tets from "
       << mesh.stats.background_tets << " background tets; " << duplicated << " background tets duplicated\n";
    figures::write(args, "fig1.md", md.str());
  });
}
