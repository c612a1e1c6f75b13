// Plumbing shared by the figure programs of paper §8 (deformation and weights on the unglued
// mesh beside the glued baseline): a deform::SimplexMesh<3> at some positions as a dim3::TetMesh
// to draw, the input surface carried by an embedding, the connected parts of an input surface,
// handle vertices picked through the embedding, the colour-bar check of a scalar picture, the
// immerse-mesh-deformable preparation every figure starts with, and the dynamic FEM run with held or
// driven handles of Figs. 3 and 22.
#pragma once

#include <numeric>
#include <string>
#include <vector>

#include "core/parallel.h"
#include "deform/convert.h"
#include "deform/fem.h"
#include "deform/simplex_mesh.h"
#include "deform/vtu.h"
#include "dim3/self_connecting.h"
#include "dim3/surface.h"
#include "dim3/surface_genericity.h"
#include "dim3/tet_mesh.h"
#include "figures/figure_common.h"
#include "render/mesh_scenes.h"
#include "render/png_image.h"
#include "render/scene.h"

namespace imm::figures {

/// An input immersed, its first immersion meshed, and the unglued mesh beside its glued baseline.
struct Meshed {
  dim3::Immersed im;
  dim3::MeshResult mesh;
  deform::DeformableInput<3> in;
};

/// Immerses `input` (volumes in doubles: the figures need none exact), meshes its first immersion
/// with `options` and builds both deformable meshes; `what` names the input in the checks
/// ("the head" -> "the head is immersible").
inline Meshed immerse_and_mesh(const dim3::Surface& input, const dim3::MeshOptions& options, const std::string& what) {
  dim3::ImmerseOptions io;
  io.build.exact_volumes = false;
  Meshed m{dim3::immerse_surface(input, io), {}, {}};
  expect(m.im.build.complex && !m.im.search.immersions.empty(), what + " is immersible");
  m.mesh = dim3::mesh_immersion(*m.im.build.complex, m.im.search.immersions[0], options, m.im.input_vertices,
                                m.im.input_triangles);
  expect(m.mesh.report.ok(), m.mesh.report.summary());
  m.in = deform::deformable(m.mesh);
  return m;
}

/// `mesh`'s elements at `positions` (n x 3) as a tet mesh to draw; `reference` per element
/// (graph node, for colouring) or empty.
inline dim3::TetMesh to_tet_mesh(const deform::SimplexMesh<3>& mesh, const Eigen::MatrixXd& positions,
                                 const std::vector<int>& reference = {}) {
  dim3::TetMesh out;
  out.vertices.resize(static_cast<std::size_t>(positions.rows()));
  for (Eigen::Index v = 0; v < positions.rows(); ++v)
    for (int a = 0; a < 3; ++a) out.vertices[static_cast<std::size_t>(v)][static_cast<std::size_t>(a)] = positions(v, a);
  out.tets.resize(static_cast<std::size_t>(mesh.element_count()));
  for (Eigen::Index e = 0; e < mesh.element_count(); ++e)
    for (int i = 0; i < 4; ++i) out.tets[static_cast<std::size_t>(e)][static_cast<std::size_t>(i)] = mesh.elements(e, i);
  out.reference = reference;
  return out;
}

/// The input surface with its vertices moved to `points` (one row per vertex, from
/// deform::embedded_positions).
inline dim3::Surface moved_surface(const dim3::Surface& surface, const Eigen::MatrixXd& points) {
  dim3::Surface out = surface;
  for (std::size_t v = 0; v < out.vertices.size(); ++v)
    for (int a = 0; a < 3; ++a) out.vertices[v][static_cast<std::size_t>(a)] = points(static_cast<Eigen::Index>(v), a);
  return out;
}

/// Connected parts of a surface (triangles sharing a vertex): per vertex its part, numbered in
/// the order of their first vertex; `count` the number of parts.
inline std::vector<int> surface_parts(const dim3::Surface& surface, int& count) {
  std::vector<std::size_t> parent(surface.vertices.size());
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const auto& t : surface.triangles)
    for (int k = 1; k < 3; ++k) parent[find(t[static_cast<std::size_t>(k)])] = find(t[0]);
  std::vector<int> part(surface.vertices.size(), -1);
  std::vector<int> root_part(surface.vertices.size(), -1);
  count = 0;
  for (std::size_t v = 0; v < surface.vertices.size(); ++v) {
    int& p = root_part[find(v)];
    if (p < 0) p = count++;
    part[v] = p;
  }
  return part;
}

/// The mesh vertices that carry the input vertices `picked`: every corner of the elements the
/// embedding puts them in (sorted, unique). On the unglued mesh these are the copies of the
/// picked vertices' own sheet; on the glued mesh the one glued copy.
inline std::vector<Eigen::Index> carrying_vertices(const deform::SimplexMesh<3>& mesh,
                                                   const std::vector<deform::EmbeddedPoint>& embedding,
                                                   const std::vector<std::size_t>& picked) {
  std::vector<Eigen::Index> out;
  for (std::size_t v : picked)
    for (int i = 0; i < 4; ++i) out.push_back(mesh.elements(embedding[v].element, i));
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// A scalar picture's colour bar carries its labelled ticks: dark grey pixels (the seven-segment
/// labels) right of the bar in a band around each tick's row, none halfway between two ticks.
inline void expect_colour_bar_labels(const render::Image& image, const render::ScalarRange& range,
                                     const std::string& file) {
  const render::ColourBarLayout& l = render::kColourBar;
  const int half = static_cast<int>(std::ceil(l.glyph_height * image.height / 2)) + 1;
  auto dark_in_band = [&](double value) {
    const int row = static_cast<int>(std::lround(l.row_of(range, value) * image.height));
    return render::count_dark(image, static_cast<int>(l.label_left * image.width) - 1, row - half, image.width, row + half);
  };
  const std::vector<double> ticks = render::colour_bar_ticks(range);
  bool labelled = ticks.size() >= 2;
  for (std::size_t k = 0; k < ticks.size(); ++k) {
    labelled = labelled && dark_in_band(ticks[k]) > 0;
    if (k + 1 < ticks.size()) labelled = labelled && dark_in_band(0.5 * (ticks[k] + ticks[k + 1])) == 0;
  }
  expect(labelled, "the colour bar of " + file + " has a label at each tick and none between");
}

/// Self-intersecting triangle pairs of a (deformed) input, counted exactly
/// (dim3::check_generic_surface: CGAL predicates on the doubles), and per triangle whether it is
/// in one.
struct Crossings {
  std::size_t pairs = 0;
  std::vector<bool> triangle;
};
inline Crossings crossings(const dim3::Surface& surface) {
  const dim3::SurfaceGenericity g = dim3::check_generic_surface(surface, /*keep_pairs=*/true);
  Crossings c{g.intersecting_pairs, std::vector<bool>(surface.triangle_count(), false)};
  for (const auto& [i, j] : g.pairs) c.triangle[i] = c.triangle[j] = true;
  return c;
}

/// The outcome of `drop` on one mesh.
struct Dropped {
  Eigen::MatrixXd positions;
  dim3::Surface surface;
  Crossings crossing;
  std::size_t held_free_pairs = 0;  ///< intersecting triangle pairs between a held and a free part
  std::size_t inverted = 0;         ///< at the end
  std::size_t most_inverted = 0;    ///< the most at any step
  double free_drop = 0.0;           ///< mean displacement of the free input vertices along the gravity
  int newton_iterations = 0;
  int unconverged = 0;
  std::size_t held = 0;  ///< mesh vertices held
  std::vector<double> step_seconds;  ///< CPU seconds of each step (the process: all threads), in step order
};

/// A dynamic FEM run on one mesh (Figs. 3 and 22): the mesh vertices `handles` follow
/// `targets(step)` (|handles| x 3, in `handles` order; step = 1..steps), the others are simulated
/// by `steps` implicit Euler steps with `options` (gravity, ground, time step). `held_part` per
/// input vertex: whether it belongs to a held part; pairs of intersecting triangles between a
/// held and a free part are counted apart, and the free parts' mean displacement along the
/// gravity. One FemSolver for the whole run: its factorization is reused across steps as the PCG
/// preconditioner.
template <class Targets>
Dropped simulate(const deform::SimplexMesh<3>& mesh, const std::vector<deform::EmbeddedPoint>& embedding,
                 const dim3::Surface& input, const std::vector<Eigen::Index>& handles, const Targets& targets,
                 const std::vector<bool>& held_part, const deform::FemOptions& options, int steps) {
  Dropped d;
  d.held = handles.size();
  const deform::FemData<3> data = deform::fem_precompute<3>(mesh, handles, options.material);
  if (!data.ok()) throw std::runtime_error("FEM precomputation: " + data.error);
  deform::FemState<3> state{mesh.vertices, Eigen::MatrixXd::Zero(mesh.vertex_count(), 3)};
  deform::FemSolver solver;
  for (int step = 1; step <= steps; ++step) {
    const Eigen::MatrixXd target = targets(step);
    const double start = process_cpu_seconds();
    const deform::FemReport r = deform::fem_step<3>(data, state, target, options, &solver);
    d.step_seconds.push_back(process_cpu_seconds() - start);
    if (!r.error.empty()) throw std::runtime_error("FEM step: " + r.error);
    d.newton_iterations += r.newton_iterations;
    d.unconverged += r.converged ? 0 : 1;
    d.most_inverted = std::max(d.most_inverted, deform::inverted_elements<3>(state.positions, mesh.elements).size());
  }
  d.positions = state.positions;
  const Eigen::MatrixXd points = deform::embedded_positions(d.positions, mesh.elements, embedding);
  d.surface = moved_surface(input, points);
  const dim3::SurfaceGenericity g = dim3::check_generic_surface(d.surface, /*keep_pairs=*/true);
  d.crossing.pairs = g.intersecting_pairs;
  d.crossing.triangle.assign(d.surface.triangle_count(), false);
  for (const auto& [i, j] : g.pairs) {
    d.crossing.triangle[i] = d.crossing.triangle[j] = true;
    if (held_part[d.surface.triangles[i][0]] != held_part[d.surface.triangles[j][0]]) ++d.held_free_pairs;
  }
  d.inverted = deform::inverted_elements<3>(d.positions, mesh.elements).size();
  std::size_t free_count = 0;
  const Eigen::RowVector3d down = options.gravity.transpose().normalized();
  for (std::size_t v = 0; v < input.vertices.size(); ++v)
    if (!held_part[v]) {
      const auto& p = input.vertices[v];
      d.free_drop += (points.row(static_cast<Eigen::Index>(v)) - Eigen::RowVector3d(p[0], p[1], p[2])).dot(down);
      ++free_count;
    }
  if (free_count > 0) d.free_drop /= static_cast<double>(free_count);
  return d;
}

/// `simulate` with the carrying vertices of the `held` input vertices held in place (the drop of
/// Figs. 3 and 22: the held parts stay, the free ones fall).
inline Dropped drop(const deform::SimplexMesh<3>& mesh, const std::vector<deform::EmbeddedPoint>& embedding,
                    const dim3::Surface& input, const std::vector<std::size_t>& held,
                    const std::vector<bool>& held_part, const deform::FemOptions& options, int steps) {
  const std::vector<Eigen::Index> handles = carrying_vertices(mesh, embedding, held);
  const Eigen::MatrixXd rest = mesh.vertices(handles, Eigen::all);
  return simulate(mesh, embedding, input, handles, [&](int) { return rest; }, held_part, options, steps);
}

/// A picture of an input surface (as given or deformed) with its self-intersecting triangles
/// red; the picture must show red exactly when there are some.
inline void input_picture(const FigureArgs& args, const std::string& file, const std::string& label,
                          const dim3::Surface& surface, const Crossings& crossing, const render::View& view,
                          const std::string& subject = "input") {
  render::Scene scene;
  scene.parts.push_back(render::surface_part(surface, crossing.triangle, render::colors::kSurface, true));
  scene.view = view;
  if (const auto image =
          picture(args, scene, file, label + ", " + std::to_string(crossing.pairs) + " self-intersecting triangle pairs (red)")) {
    const std::size_t red = hue_pixels(*image, render::colors::kIntersecting);
    expect((red > 0) == (crossing.pairs > 0), file + " shows red exactly when the " + subject + " intersects itself");
  }
}

/// The outputs of one deformed mesh: `<stem>.vtu` (the deformed tets, for ParaView) and the
/// pictures of the deformed input surface (input_picture) and of the deformed tet mesh (by graph
/// node when `reference` is given, else one colour).
inline void deformed_outputs(const FigureArgs& args, const std::string& stem, const std::string& what,
                              const dim3::Surface& deformed_input, const Crossings& crossing,
                              const deform::SimplexMesh<3>& mesh, const Eigen::MatrixXd& positions,
                              const std::vector<int>& reference, const render::View& view) {
  write(args, stem + ".vtu", deform::format_vtu(positions, mesh.elements));
  input_picture(args, stem + "_input.png", what + ": the deformed input", deformed_input, crossing, view, "deformed input");
  render::TetStyle style;
  style.color_by = reference.empty() ? render::TetStyle::ColorBy::Single : render::TetStyle::ColorBy::Reference;
  style.edges = !args.quick;
  render::Scene tets = render::tet_mesh_scene(to_tet_mesh(mesh, positions, reference), style);
  tets.view = view;
  if (const auto image = picture(args, tets, stem + "_mesh.png",
                                 what + ": the deformed tet mesh" + (reference.empty() ? "" : ", by graph node")))
    expect(hue_pixels(*image, render::colors::kIntersecting) == 0, stem + "_mesh.png has no red (red means intersecting input triangles)");
}

}  // namespace imm::figures
