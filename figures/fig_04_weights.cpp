// Paper Fig. 4: topology-aware weights. Bounded biharmonic weights (Jacobson et al. 2011) of two
// handles on Sacht's test model (the torus with columns through its tube, Fig. 24; here the
// generated `sacht_torus`), computed on our unglued mesh and on the naive glued mesh of the
// same background tets. Handle A is the top of one column; handle B holds the bottom of that
// column and one cap of every other solid (each solid is its own part of the unglued mesh, and
// a part without a handle has no weights). The heat-method geodesic distance from A (Crane et
// al. 2013) is computed on both meshes too.
//
// The check (a comparison, on the torus's sheet where the column passes through it): for every
// vertex of the unglued mesh's torus copies within twice the column's radius of the column's
// axis, the weight of A there is strictly below the glued mesh's weight of A at the same vertex
// position, and the glued weight there is substantial (>= 0.1 on average: the column glued to
// the torus carries A's weight across); A's distance there is infinite on the unglued mesh
// (no path through the material) and finite on the glued one. A wrongly glued unglued mesh
// gives the same weights as the glued one and fails the strict comparison.
// Pictures: the weight of A and the distance from A on both meshes, with labelled colour bars.
#include <cmath>
#include <limits>
#include <map>

#include "deform/convert.h"
#include "deform/vtu.h"
#include "deform/weights.h"
#include "dim3/generators3.h"
#include "dim3/self_connecting.h"
#include "figures/deform_common.h"
#include "figures/figure_common.h"
#include "render/mesh_scenes.h"

using namespace imm;

namespace {

using Vec3d = Eigen::Vector3d;

Vec3d point(const dim3::Point3& p) { return {p[0], p[1], p[2]}; }

/// The handles on one mesh: A, then B (see the file comment), as mesh vertices.
std::vector<std::vector<Eigen::Index>> handles_on(const deform::SimplexMesh<3>& mesh,
                                                  const std::vector<deform::EmbeddedPoint>& embedding,
                                                  const std::vector<std::size_t>& a_inputs,
                                                  const std::vector<std::size_t>& b_inputs) {
  return {figures::carrying_vertices(mesh, embedding, a_inputs), figures::carrying_vertices(mesh, embedding, b_inputs)};
}

struct Field {
  deform::WeightsResult weights;
  Eigen::VectorXd distance;
};

Field compute(const deform::SimplexMesh<3>& mesh, const std::vector<std::vector<Eigen::Index>>& handles,
              const std::string& name) {
  Field f;
  f.weights = deform::bounded_biharmonic_weights<3>(mesh, handles);
  if (!f.weights.ok()) throw std::runtime_error("bounded biharmonic weights on the " + name + " mesh: " + f.weights.error);
  f.distance = deform::heat_geodesic<3>(mesh, handles[0]);
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_04_weights");
    figures::describe("Fig. 4",
                      "bounded biharmonic weights computed on our volumetric mesh reflect the topology of the "
                      "embedded surface; naive voxelization glues the cylinders together and the weights leak.");
    const int n = args.quick ? 24 : 36;
    const dim3::Surface input = dim3::sacht_torus(n, false);
    int parts = 0;
    const std::vector<int> part = figures::surface_parts(input, parts);
    figures::expect(parts == 5, "Sacht's model (small): a torus and 4 columns through its tube, 5 solids");

    dim3::MeshOptions options;
    options.resolution = args.quick ? 20 : 26;
    const auto [im, meshed, in] = figures::immerse_and_mesh(input, options, "the model");

    // Part 0 is the torus (the generator's first vertices), part 1 the column through which A's
    // weight could leak: its axis from the mean of its lowest to the mean of its highest cap.
    std::vector<std::vector<std::size_t>> vertices_of(static_cast<std::size_t>(parts));
    for (std::size_t v = 0; v < input.vertices.size(); ++v) vertices_of[static_cast<std::size_t>(part[v])].push_back(v);
    auto extreme = [&](int p, bool top) {
      std::size_t best = vertices_of[static_cast<std::size_t>(p)].front();
      for (std::size_t v : vertices_of[static_cast<std::size_t>(p)])
        if (top ? input.vertices[v][2] > input.vertices[best][2] : input.vertices[v][2] < input.vertices[best][2]) best = v;
      return best;
    };
    auto cap = [&](int p, bool top) {  // the input vertices within 0.1 of the part's top (bottom) vertex
      const Vec3d tip = point(input.vertices[extreme(p, top)]);
      std::vector<std::size_t> out;
      for (std::size_t v : vertices_of[static_cast<std::size_t>(p)])
        if ((point(input.vertices[v]) - tip).norm() < 0.1) out.push_back(v);
      return out;
    };
    const int column = 1;
    const Vec3d axis_lo = point(input.vertices[extreme(column, false)]);
    const Vec3d axis_hi = point(input.vertices[extreme(column, true)]);
    const Vec3d axis = (axis_hi - axis_lo).normalized();
    double column_radius = 0;
    for (std::size_t v : vertices_of[column]) {
      const Vec3d d = point(input.vertices[v]) - axis_lo;
      column_radius = std::max(column_radius, (d - d.dot(axis) * axis).norm());
    }
    const std::vector<std::size_t> a_inputs = cap(column, true);
    std::vector<std::size_t> b_inputs = cap(column, false);
    {  // the torus's far side, and the top of every other column
      std::size_t far = vertices_of[0].front();
      auto horizontal = [&](std::size_t v) { return std::hypot(input.vertices[v][0] - axis_lo[0], input.vertices[v][1] - axis_lo[1]); };
      for (std::size_t v : vertices_of[0])
        if (horizontal(v) > horizontal(far)) far = v;
      for (std::size_t v : vertices_of[0])
        if ((point(input.vertices[v]) - point(input.vertices[far])).norm() < 0.15) b_inputs.push_back(v);
      for (int p = 2; p < parts; ++p)
        for (std::size_t v : cap(p, true)) b_inputs.push_back(v);
    }

    const auto unglued_handles = handles_on(in.unglued, in.unglued_embedding, a_inputs, b_inputs);
    const auto glued_handles = handles_on(in.glued.mesh, in.glued_embedding, a_inputs, b_inputs);
    const Field unglued = compute(in.unglued, unglued_handles, "unglued");
    const Field glued = compute(in.glued.mesh, glued_handles, "glued");

    // The torus's sheet of the unglued mesh: the connected part holding the torus's input vertices.
    int mesh_parts = 0;
    const std::vector<int> mesh_part = deform::vertex_components(in.unglued.vertex_count(), in.unglued.elements, mesh_parts);
    const int torus_part = mesh_part[static_cast<std::size_t>(in.unglued.elements(in.unglued_embedding[vertices_of[0].front()].element, 0))];
    // Unglued vertex -> the glued vertex at the same place (copies keep the background corner order).
    std::vector<Eigen::Index> glued_vertex(static_cast<std::size_t>(in.unglued.vertex_count()), -1);
    for (Eigen::Index e = 0; e < in.unglued.element_count(); ++e)
      for (int i = 0; i < 4; ++i)
        glued_vertex[static_cast<std::size_t>(in.unglued.elements(e, i))] =
            in.glued.mesh.elements(in.glued.element_of_copy[static_cast<std::size_t>(e)], i);
    std::vector<Eigen::Index> overlap;  // unglued torus-sheet vertices near the column's axis
    for (Eigen::Index v = 0; v < in.unglued.vertex_count(); ++v) {
      if (mesh_part[static_cast<std::size_t>(v)] != torus_part) continue;
      const Vec3d d = in.unglued.vertices.row(v).transpose() - axis_lo;
      if ((d - d.dot(axis) * axis).norm() <= 2 * column_radius) overlap.push_back(v);
    }
    figures::expect(!overlap.empty(), "the torus's copies near the column exist");
    double unglued_max = 0, glued_sum = 0, glued_min = std::numeric_limits<double>::infinity();
    std::size_t below = 0, unreached = 0, reached_glued = 0;
    double glued_distance_sum = 0;
    for (Eigen::Index v : overlap) {
      const Eigen::Index g = glued_vertex[static_cast<std::size_t>(v)];
      const double wu = unglued.weights.weights(v, 0), wg = glued.weights.weights(g, 0);
      unglued_max = std::max(unglued_max, wu);
      glued_sum += wg;
      glued_min = std::min(glued_min, wg);
      below += wu < wg ? 1 : 0;
      unreached += std::isinf(unglued.distance[v]) ? 1 : 0;
      if (std::isfinite(glued.distance[g])) ++reached_glued, glued_distance_sum += glued.distance[g];
    }
    const double glued_mean = glued_sum / static_cast<double>(overlap.size());
    std::ostringstream numbers;
    numbers << "over " << overlap.size() << " torus-sheet vertices within " << 2 * column_radius
            << " of the column's axis: weight of A unglued max " << unglued_max << ", glued mean " << glued_mean
            << " (min " << glued_min << ")";
    std::cout << numbers.str() << '\n';
    figures::expect(below == overlap.size(),
                    "Fig. 4: at every torus-sheet vertex where the column passes through, A's weight on the unglued "
                    "mesh is below the glued mesh's (" + std::to_string(below) + " of " + std::to_string(overlap.size()) +
                        " vertices; unglued max " + std::to_string(unglued_max) + ", glued mean " +
                        std::to_string(glued_mean) + ")");
    figures::expect(glued_mean >= 0.1, "the glued mesh leaks A's weight into the torus (mean " + std::to_string(glued_mean) + " >= 0.1)");
    figures::expect(unreached == overlap.size() && reached_glued == overlap.size(),
                    "the torus near the column is unreachable from A through the unglued material, reached through "
                    "the glued mesh (mean distance " + std::to_string(glued_distance_sum / std::max<std::size_t>(1, reached_glued)) + ")");

    // Files: both meshes with their fields.
    auto fields = [](const Field& f) {
      deform::VtuFields out;
      out.point_scalars.emplace_back("weight_A", f.weights.weights.col(0));
      out.point_scalars.emplace_back("weight_B", f.weights.weights.col(1));
      out.point_scalars.emplace_back("distance_A", f.distance);
      return out;
    };
    figures::write(args, "fig4_unglued_weights.vtu", deform::format_vtu(in.unglued.vertices, in.unglued.elements, fields(unglued)));
    figures::write(args, "fig4_glued_weights.vtu", deform::format_vtu(in.glued.mesh.vertices, in.glued.mesh.elements, fields(glued)));

    // Pictures: A's weight and distance on both meshes, one colour bar range per field.
    double max_distance = 0;
    for (const Eigen::VectorXd* d : {&unglued.distance, &glued.distance})
      for (Eigen::Index v = 0; v < d->size(); ++v)
        if (std::isfinite((*d)[v])) max_distance = std::max(max_distance, (*d)[v]);
    auto draw = [&](const deform::SimplexMesh<3>& mesh, const Eigen::VectorXd& values, const render::ScalarRange& range,
                    const std::string& file, const std::string& label) {
      render::TetStyle style;
      style.color_by = render::TetStyle::ColorBy::Scalar;
      style.vertex_scalar.assign(values.data(), values.data() + values.size());
      style.edges = !args.quick;
      render::Scene scene = render::tet_mesh_scene(figures::to_tet_mesh(mesh, mesh.vertices), style);
      scene.scalar_range = range;
      scene.view = render::View{20, 28, 2};
      if (const auto image = figures::picture(args, scene, file, label)) {
        figures::expect_colour_bar_labels(*image, range, file);
        figures::expect(figures::hue_pixels(*image, render::colormap(1.0)) > 0, file + " shows the top of its scale (yellow)");
      }
    };
    const render::ScalarRange unit{0.0, 1.0, {0.0, 0.5, 1.0}};
    draw(in.unglued, unglued.weights.weights.col(0), unit, "fig4_weight_unglued.png",
         "weight of handle A, our unglued mesh (the torus stays at 0)");
    draw(in.glued.mesh, glued.weights.weights.col(0), unit, "fig4_weight_glued.png",
         "weight of handle A, glued baseline (leaks into the torus)");
    // Round ticks: the range's top is the largest distance rounded up to a half unit.
    const double top = std::ceil(2.0 * max_distance) / 2.0;
    const render::ScalarRange distance_range{0.0, top, {0.0, top / 2, top}};
    draw(in.unglued, unglued.distance, distance_range, "fig4_distance_unglued.png",
         "heat geodesic distance from A, unglued (grey: unreachable)");
    draw(in.glued.mesh, glued.distance, distance_range, "fig4_distance_glued.png", "heat geodesic distance from A, glued");

    std::ostringstream md;
    md << "# Fig. 4: bounded biharmonic weights, unglued against glued\n\n"
       << "- input: sacht_torus(" << n << ", small), " << input.triangle_count() << " triangles, " << parts << " solids\n"
       << "- unglued mesh: " << in.unglued.element_count() << " tets, " << in.unglued.vertex_count() << " vertices, "
       << mesh_parts << " connected parts; glued: " << in.glued.mesh.element_count() << " tets, "
       << in.glued.mesh.vertex_count() << " vertices\n"
       << "- handle A: " << unglued_handles[0].size() << " vertices (top of the column); B: " << unglued_handles[1].size()
       << " vertices (its bottom, the torus's far side, the other columns' tops)\n"
       << "- active-set iterations: unglued " << unglued.weights.active_set_iterations[0] << ", "
       << unglued.weights.active_set_iterations[1] << "; glued " << glued.weights.active_set_iterations[0] << ", "
       << glued.weights.active_set_iterations[1] << "\n- " << numbers.str() << "\n";
    figures::write(args, "fig4.md", md.str());
    std::cout << md.str();
  });
}
