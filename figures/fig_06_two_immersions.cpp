// Paper Fig. 6: a self-overlapping curve with two distinct immersions, the decomposition of each
// (middle of the figure) and an unglued triangle mesh of each (right). Also the family of
// DESIGN §6: rotationally symmetric doodles with K = 2, 3, 4 lobes have 2, 5, 14 immersions.
// Right of the figure: each immersion's unglued mesh pulled out with 2D ARAP by two handles (the
// paper's green dots): the deformed curve is simple (0 crossings, counted exactly by
// dim2::check_generic) with no inverted triangle, for both immersions; the naive glued mesh of
// the same background triangles under the same handles keeps the input's crossings. Pictures of
// the pulled meshes (POV-Ray, seen from above) with the deformed curve and the green handles.
#include <set>

#include "deform/convert.h"
#include "figures/figure_common.h"
#include "figures/pull_2d.h"

using namespace imm;

namespace {

/// A handle chosen by hand, as the paper's: the vertices of the sheet under `at` (the graph node
/// whose triangles contain it) within `radius` of it, moved by `move`. Both points lie where the
/// curve's winding number is 1, in the outer band (the generator's units: radii 4, 7, 10 times
/// 100), so the sheet is unique and the glued baseline gets the same vertices.
struct HandleSpec {
  dim2::Point at;
  double radius;
  Eigen::RowVector2d move;
};
// Upper-left of the outer band fixed; lower-right of it pulled 2 diameters of the curve away:
// the three stacked turns of the immersed disk slide apart like a chain.
const HandleSpec kHandles[] = {{{-600, 600}, 200, {0, 0}}, {{600, -600}, 200, {3000, -3000}}};

/// The graph nodes whose output triangles contain `p` (the sheets over p).
std::set<int> sheets_at(const dim2::TriangleMesh& mesh, const dim2::Point& p) {
  std::set<int> nodes;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    bool inside = true;
    for (int i = 0; i < 3; ++i) {
      const dim2::Point& a = mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][static_cast<std::size_t>(i)])];
      const dim2::Point& b = mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][static_cast<std::size_t>((i + 1) % 3)])];
      inside = inside && (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x) >= 0;  // counter-clockwise
    }
    if (inside) nodes.insert(mesh.reference[t]);
  }
  return nodes;
}

/// The handles of kHandles on the unglued mesh and, through the copies' glued elements (same
/// corner order), on the glued baseline.
void select_handles(const dim2::MeshResult& mesh, const deform::DeformableInput<2>& in,
                    std::vector<figures::Handle2>& unglued, std::vector<figures::Handle2>& glued) {
  for (const HandleSpec& spec : kHandles) {
    const std::set<int> nodes = sheets_at(mesh.mesh, spec.at);
    figures::expect(nodes.size() == 1, "each handle point lies on exactly one sheet (one graph node)");
    const int node = *nodes.begin();
    figures::Handle2 u{{}, spec.move}, g{{}, spec.move};
    for (Eigen::Index t = 0; t < in.unglued.element_count(); ++t) {
      if (mesh.mesh.reference[static_cast<std::size_t>(t)] != node) continue;
      for (int i = 0; i < 3; ++i) {
        const Eigen::Index v = in.unglued.elements(t, i);
        if ((in.unglued.vertices.row(v) - Eigen::RowVector2d(spec.at.x, spec.at.y)).norm() > spec.radius) continue;
        u.vertices.push_back(v);
        g.vertices.push_back(in.glued.mesh.elements(in.glued.element_of_copy[static_cast<std::size_t>(t)], i));
      }
    }
    for (figures::Handle2* h : {&u, &g}) {
      std::sort(h->vertices.begin(), h->vertices.end());
      h->vertices.erase(std::unique(h->vertices.begin(), h->vertices.end()), h->vertices.end());
    }
    figures::expect(!u.vertices.empty(), "every handle selects mesh vertices");
    unglued.push_back(std::move(u));
    glued.push_back(std::move(g));
  }
}

}  // namespace

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_06_two_immersions");
    figures::describe("Fig. 6", "a self-overlapping curve with two distinct immersions; both are found and meshed, and "
                                "each mesh is pulled out with ARAP (green dots: handles).");
    const auto run = figures::run_curve("fig6");
    const dim2::Complex2& complex = *run.built.complex;
    figures::expect(run.search.complete && run.search.immersions.size() == 2,
                    "Fig. 6 has exactly two immersions");
    figures::write(args, "fig6_input.svg", dim2::format_complex_svg(complex, {.title = "Fig. 6: input and cells"}));
    const std::size_t input_crossings = dim2::check_generic(run.curves).crossings;
    figures::expect(input_crossings > 0, "the input curve crosses itself (" + std::to_string(input_crossings) + " crossings)");
    std::ostringstream md, pulls;
    md << "# Fig. 6: two immersions\n\n| immersion | nodes | edges | components | output triangles |\n"
       << "|---|---|---|---|---|\n";
    pulls << "\n## Pulled out with ARAP (Fig. 6 right)\n\nHandles (green dots): the sheet under (-600, 600) within 200 "
          << "fixed, the sheet under (600, -600) within 200 moved by (3000, -3000); 4 warm-started ARAP steps. Input: "
          << input_crossings << " crossings.\n\n"
          << "| immersion | mesh | handle vertices | crossings after (exact) | inverted triangles | ARAP iterations |\n"
          << "|---|---|---|---|---|---|\n";
    std::optional<deform::DeformableInput<2>> first_input;
    std::optional<figures::Pulled2> first_glued;
    for (std::size_t k = 0; k < run.search.immersions.size(); ++k) {
      const Immersion& im = run.search.immersions[k];
      const std::string title = "Fig. 6: immersion " + std::to_string(k);
      figures::write(args, "fig6_immersion_" + std::to_string(k) + ".svg",
                     dim2::format_immersion_svg(complex, im, {.title = title}));
      const dim2::MeshResult mesh =
          figures::mesh_and_write(args, complex, im, args.quick ? 16 : 48, "fig6_mesh_" + std::to_string(k));
      figures::write(args, "fig6_mesh_" + std::to_string(k) + ".emb", dim2::format_embedding(mesh.embedding));
      md << "| " << k << " | " << im.layout.node_count() << " | " << im.edges.size() << " | "
         << im.components().size() << " | " << mesh.mesh.triangles.size() << " |\n";

      // Pulled out with ARAP, unglued against glued, under the same handles.
      deform::DeformableInput<2> in = deform::deformable(mesh);
      std::vector<figures::Handle2> unglued_handles, glued_handles;
      select_handles(mesh, in, unglued_handles, glued_handles);
      const figures::Pulled2 unglued = figures::pull_2d(in.unglued, in.unglued_embedding, run.curves, unglued_handles);
      const figures::Pulled2 glued = figures::pull_2d(in.glued.mesh, in.glued_embedding, run.curves, glued_handles);
      const std::string which = "immersion " + std::to_string(k);
      std::cout << which << " pulled, crossings (exact): unglued " << unglued.crossings() << ", glued " << glued.crossings()
                << "; inverted triangles: unglued " << unglued.inverted << ", glued " << glued.inverted << '\n';
      pulls << "| " << k << " | unglued | " << unglued.handle_vertices << " | " << unglued.crossings() << " | " << unglued.inverted
            << " | " << unglued.iterations << " |\n| " << k << " | glued | " << glued.handle_vertices << " | "
            << glued.crossings() << " | " << glued.inverted << " | " << glued.iterations << " |\n";
      figures::expect(unglued.crossings() == 0 && unglued.genericity.generic,
                      "Fig. 6 right: each immersion pulled out with ARAP gives a simple curve (0 crossings, exact)");
      figures::expect(unglued.inverted == 0, "no inverted triangle in either pulled unglued mesh");
      figures::expect(glued.handle_vertices == unglued.handle_vertices,
                      "the glued baseline gets as many handle vertices (the handle points are on one sheet)");
      figures::expect(glued.crossings() > 0 || glued.inverted > 0,
                      "the glued baseline under the same handles keeps crossings (" + std::to_string(glued.crossings()) +
                          ") or inverts triangles (" + std::to_string(glued.inverted) + ")");
      figures::write(args, "fig6_unglued_pulled_" + std::to_string(k) + ".txt", dim2::format_curves_text(unglued.curves));
      if (const auto image = figures::picture(
              args, figures::pulled_scene(in.unglued, unglued.positions, mesh.mesh.reference, unglued.curves, unglued.handle_points),
              "fig6_unglued_pulled_" + std::to_string(k) + ".png",
              which + ", unglued mesh pulled out (ARAP), by graph node, handles green: " +
                  std::to_string(unglued.crossings()) + " crossings")) {
        std::size_t colours = 0;
        for (std::size_t n = 0; n + 1 < render::palette_size(); ++n)
          colours += figures::hue_pixels(*image, figures::node_color(n, true)) > 20 ? 1 : 0;
        figures::expect(colours >= 3, "the pulled unglued meshes show the copies of at least three graph nodes");
        figures::expect(figures::hue_pixels(*image, figures::handle_color()) > 0, "the pictures show the green handle dots");
        figures::expect(render::count_dark(*image, 0, 0, image->width, image->height) > 0,
                        "the pictures show the deformed curve (dark)");
      }
      // The glued baseline forgets the immersion: both immersions give the same glued mesh.
      if (!first_input) {
        first_input = std::move(in);
        first_glued = glued;
      } else {
        figures::expect(first_input->glued.mesh.vertices == in.glued.mesh.vertices &&
                            first_input->glued.mesh.elements == in.glued.mesh.elements &&
                            first_glued->positions == glued.positions,
                        "the glued baseline is the same mesh, pulled the same way, for both immersions");
      }
    }
    if (first_input) {
      // Where the handles are: the input curve on the (glued) mesh at rest, the dots at the
      // handles' rest centres.
      std::vector<Eigen::RowVector2d> rest_points;
      for (const HandleSpec& spec : kHandles) rest_points.emplace_back(spec.at.x, spec.at.y);
      if (const auto image = figures::picture(
              args, figures::pulled_scene(first_input->glued.mesh, first_input->glued.mesh.vertices, {}, run.curves, rest_points),
              "fig6_handles.png", "the input curve at rest and the handle points (green): left fixed, right pulled"))
        figures::expect(figures::hue_pixels(*image, figures::handle_color()) > 0, "the pictures show the green handle dots");
      figures::write(args, "fig6_glued_pulled.txt", dim2::format_curves_text(first_glued->curves));
      if (const auto image = figures::picture(
              args, figures::pulled_scene(first_input->glued.mesh, first_glued->positions, {}, first_glued->curves,
                                          first_glued->handle_points),
              "fig6_glued_pulled.png",
              "glued baseline (either immersion), same handles: " + std::to_string(first_glued->crossings()) +
                  " crossings, " + std::to_string(first_glued->inverted) + " inverted triangles")) {
        figures::expect(figures::hue_pixels(*image, figures::handle_color()) > 0, "the pictures show the green handle dots");
        std::size_t node_pixels = 0;
        for (std::size_t n = 0; n + 1 < render::palette_size(); ++n) node_pixels += figures::hue_pixels(*image, figures::node_color(n, true));
        figures::expect(node_pixels == 0, "the glued picture is one colour (no graph nodes) besides the green handles");
      }
    }
    if (!args.quick) {
      // The handles are not tuned to one mesh: the same pull at other resolutions.
      pulls << "\nThe same handles at other resolutions (unglued crossings / inverted triangles):\n\n"
            << "| resolution | immersion 0 | immersion 1 |\n|---|---|---|\n";
      for (const int resolution : {16, 24, 32, 64}) {
        pulls << "| " << resolution;
        for (const Immersion& im : run.search.immersions) {
          dim2::MeshOptions options;
          options.resolution = resolution;
          const dim2::MeshResult mesh = dim2::mesh_immersion(complex, im, options);
          figures::expect(mesh.report.ok(), mesh.report.summary());
          const deform::DeformableInput<2> in = deform::deformable(mesh);
          std::vector<figures::Handle2> unglued_handles, glued_handles;
          select_handles(mesh, in, unglued_handles, glued_handles);
          const figures::Pulled2 p = figures::pull_2d(in.unglued, in.unglued_embedding, run.curves, unglued_handles);
          pulls << " | " << p.crossings() << " / " << p.inverted;
          figures::expect(p.crossings() == 0 && p.genericity.generic && p.inverted == 0,
                          "the same handles give a simple curve and no inverted triangle at resolutions 16, 24, 32, 64 too");
        }
        pulls << " |\n";
      }
    }
    md << pulls.str();
    md << "\n## Symmetric doodles (DESIGN §6)\n\n| lobes K | immersions | expected (Catalan) |\n|---|---|---|\n";
    const int catalan[] = {1, 1, 2, 5, 14};
    for (int lobes = 2; lobes <= (args.quick ? 3 : 4); ++lobes) {
      const auto doodle = figures::run_curve("doodle", {std::to_string(lobes)});
      md << "| " << lobes << " | " << doodle.search.immersions.size() << " | " << catalan[lobes] << " |\n";
      figures::expect(doodle.search.immersions.size() == static_cast<std::size_t>(catalan[lobes]),
                      "doodle " + std::to_string(lobes) + " has Catalan(K) immersions");
    }
    figures::write(args, "fig6.md", md.str());
  });
}
