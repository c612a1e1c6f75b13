// Paper Fig. 7: an input of two components forming an egg-shaped hole. One immersion (two
// overlapping disks); the unglued mesh separates the overlapping ends (pulled-apart SVG). Then
// both components are pulled apart sideways with 2D ARAP (the handles of the README's
// `immerse deform` example), on the unglued mesh and on the naive glued mesh of the same
// background triangles: the deformed curves have 0 crossings on the unglued mesh (counted
// exactly, dim2::check_generic) and keep crossings on the glued one. Pictures of both deformed
// meshes with the deformed curves drawn on them (POV-Ray, seen from above).
#include "deform/convert.h"
#include "figures/figure_common.h"
#include "figures/pull_2d.h"

using namespace imm;

namespace {

/// The README's handles: mesh vertices with x <= -650 move by (-800, 0), with x >= 680 by
/// (+800, 0); ARAP in 4 warm-started steps.
figures::Pulled2 pull(const deform::SimplexMesh<2>& mesh, const std::vector<deform::EmbeddedPoint>& embedding,
                      const dim2::CurveSet& curves) {
  figures::Handle2 left, right;
  left.move << -800, 0;
  right.move << 800, 0;
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) {
    if (mesh.vertices(v, 0) <= -650) left.vertices.push_back(v);
    else if (mesh.vertices(v, 0) >= 680) right.vertices.push_back(v);
  }
  return figures::pull_2d(mesh, embedding, curves, {left, right}, 4);
}

}  // namespace

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_07_two_components");
    figures::describe("Fig. 7", "an input of two components forming an egg-shaped hole has one immersion, meshed unglued; "
                                "the unglued mesh pulls apart (ARAP), the glued one does not.");
    const auto run = figures::run_curve("fig7");
    const dim2::Complex2& complex = *run.built.complex;
    figures::expect(run.search.complete && run.search.immersions.size() == 1, "Fig. 7 has one immersion");
    const Immersion& im = run.search.immersions.front();
    figures::expect(im.components().size() == 2, "the immersion is two overlapping disks");
    figures::write(args, "fig7_input.svg", dim2::format_complex_svg(complex, {.title = "Fig. 7: input and cells"}));
    figures::write(args, "fig7_immersion.svg", dim2::format_immersion_svg(complex, im, {.title = "Fig. 7: immersion"}));
    const dim2::MeshResult mesh = figures::mesh_and_write(args, complex, im, args.quick ? 16 : 64, "fig7_mesh");
    figures::write(args, "fig7_mesh.emb", dim2::format_embedding(mesh.embedding));
    std::ostringstream md;
    md << "# Fig. 7\n\ncells " << complex.complex.cell_count() << ", patches " << complex.complex.patch_count()
       << ", arcs " << complex.complex.arc_count() << ", immersions " << run.search.immersions.size()
       << ", graph components " << im.components().size() << ", background triangles "
       << mesh.stats.background_triangles << ", cut " << mesh.stats.cut_triangles << ", output triangles "
       << mesh.mesh.triangles.size() << "\n";
    figures::write(args, "fig7.md", md.str());

    // Pulled apart with ARAP, unglued against glued.
    const deform::DeformableInput<2> in = deform::deformable(mesh);
    const std::size_t before = dim2::check_generic(run.curves).crossings;
    const figures::Pulled2 unglued = pull(in.unglued, in.unglued_embedding, run.curves);
    const figures::Pulled2 glued = pull(in.glued.mesh, in.glued_embedding, run.curves);
    std::cout << "deformed curves, crossings (exact): input " << before << ", unglued " << unglued.crossings() << ", glued "
              << glued.crossings() << "; inverted triangles: unglued " << unglued.inverted << ", glued " << glued.inverted << '\n';
    figures::expect(before > 0, "the two components cross each other");
    figures::expect(unglued.crossings() == 0, "Fig. 7: pulled apart on the unglued mesh, the curves no longer cross (0 crossings)");
    figures::expect(unglued.inverted == 0, "no inverted triangle in the pulled unglued mesh");
    figures::expect(glued.crossings() > 0, "on the glued mesh the same pull keeps crossings (" + std::to_string(glued.crossings()) + ")");
    figures::write(args, "fig7_unglued_pulled.txt", dim2::format_curves_text(unglued.curves));
    figures::write(args, "fig7_glued_pulled.txt", dim2::format_curves_text(glued.curves));
    if (const auto image = figures::picture(args, figures::pulled_scene(in.unglued, unglued.positions, mesh.mesh.reference, unglued.curves),
                                            "fig7_unglued_pulled.png",
                                            "unglued mesh pulled apart (ARAP), by graph node: " + std::to_string(unglued.crossings()) +
                                                " crossings")) {
      std::size_t colours = 0;
      for (std::size_t k = 0; k < render::palette_size(); ++k) colours += figures::hue_pixels(*image, render::palette(k)) > 20 ? 1 : 0;
      figures::expect(colours >= 2, "the pulled unglued mesh shows the copies of at least two graph nodes");
    }
    figures::picture(args, figures::pulled_scene(in.glued.mesh, glued.positions, {}, glued.curves), "fig7_glued_pulled.png",
                     "glued baseline, same pull: " + std::to_string(glued.crossings()) + " crossings");
  });
}
