// The 2D pull-apart of paper §8 shared by the figure programs of Figs. 6 (right) and 7: handle
// vertices moved with 2D ARAP in warm-started steps, the input curves carried by the embedding
// (deform::embedded_positions) and their crossings counted exactly (dim2::check_generic), and the
// picture of a deformed mesh seen from above with the deformed curves and, as in the paper's
// Fig. 6, the handles as green dots.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "deform/arap.h"
#include "deform/simplex_mesh.h"
#include "dim2/generators.h"
#include "render/scene.h"

namespace imm::figures {

/// One handle: mesh vertices moved together by `move` at the end of the pull (zero: fixed).
struct Handle2 {
  std::vector<Eigen::Index> vertices;
  Eigen::RowVector2d move = Eigen::RowVector2d::Zero();
};

struct Pulled2 {
  Eigen::MatrixXd positions;  ///< deformed mesh vertices
  dim2::CurveSet curves;      ///< the input curves carried by the embedding
  dim2::GenericityReport genericity;  ///< of the deformed curves: crossings counted exactly
  std::size_t inverted = 0;           ///< triangles with signed area <= 0
  int iterations = 0;                 ///< ARAP local-global iterations, all steps
  std::size_t handle_vertices = 0;
  std::vector<Eigen::RowVector2d> handle_points;  ///< per handle, the mean of its deformed vertices
  [[nodiscard]] std::size_t crossings() const { return genericity.crossings; }
};

/// Moves the handles to their targets in `steps` warm-started ARAP solves (as an interactive
/// session would: each step starts from the previous result) and carries `curves` (whose
/// vertices are embedded by `embedding`, in curve order) along. A vertex in two handles follows
/// the first.
inline Pulled2 pull_2d(const deform::SimplexMesh<2>& mesh, const std::vector<deform::EmbeddedPoint>& embedding,
                       const dim2::CurveSet& curves, const std::vector<Handle2>& handles, int steps = 4) {
  std::map<Eigen::Index, Eigen::RowVector2d> move;
  for (const Handle2& h : handles)
    for (Eigen::Index v : h.vertices) move.emplace(v, h.move);
  std::vector<Eigen::Index> vertices;
  Eigen::MatrixXd displacement(static_cast<Eigen::Index>(move.size()), 2);
  for (const auto& [v, d] : move) {
    displacement.row(static_cast<Eigen::Index>(vertices.size())) = d;
    vertices.push_back(v);
  }
  const deform::ArapData<2> data = deform::arap_precompute<2>(mesh, vertices);
  if (!data.ok()) throw std::runtime_error("ARAP precomputation: " + data.error);
  const Eigen::MatrixXd rest = mesh.vertices(vertices, Eigen::all);
  Pulled2 p;
  p.handle_vertices = vertices.size();
  p.positions = mesh.vertices;
  for (int step = 1; step <= steps; ++step)
    p.iterations += deform::arap_solve<2>(data, rest + displacement * (static_cast<double>(step) / steps), p.positions,
                                          {.max_iterations = 100})
                        .iterations;
  const Eigen::MatrixXd points = deform::embedded_positions(p.positions, mesh.elements, embedding);
  p.curves = curves;
  Eigen::Index i = 0;
  for (dim2::Curve& c : p.curves.curves)
    for (dim2::Point& q : c.vertices) q = {points(i, 0), points(i, 1)}, ++i;
  p.genericity = dim2::check_generic(p.curves);
  p.inverted = deform::inverted_elements<2>(p.positions, mesh.elements).size();
  for (const Handle2& h : handles) {
    Eigen::RowVector2d sum = Eigen::RowVector2d::Zero();
    for (Eigen::Index v : h.vertices) sum += p.positions.row(v);
    p.handle_points.push_back(sum / static_cast<double>(std::max<std::size_t>(1, h.vertices.size())));
  }
  return p;
}

/// The handle dots' green: palette entry 2 (hue 120). A picture with dots draws its graph nodes
/// in the other palette entries, so its green pixels are the dots.
inline constexpr std::size_t kHandlePaletteEntry = 2;
inline render::Color handle_color() { return render::palette(kHandlePaletteEntry); }
inline render::Color node_color(std::size_t node, bool skip_handle_color) {
  if (!skip_handle_color) return render::palette(node);
  std::size_t k = node % (render::palette_size() - 1);
  return render::palette(k >= kHandlePaletteEntry ? k + 1 : k);
}

/// The deformed mesh (triangles by graph node when `reference` is given, else one colour) with
/// the deformed curves on top and a green dot at each of `handle_points`, seen from above.
inline render::Scene pulled_scene(const deform::SimplexMesh<2>& mesh, const Eigen::MatrixXd& positions,
                                  const std::vector<int>& reference, const dim2::CurveSet& curves,
                                  const std::vector<Eigen::RowVector2d>& handle_points = {}) {
  render::Scene scene;
  scene.ground = false;
  scene.view = render::View{0, 0, 1};
  render::Part part;
  part.name = "deformed mesh";
  for (Eigen::Index v = 0; v < positions.rows(); ++v) part.vertices.push_back({positions(v, 0), positions(v, 1), 0.0});
  const bool dots = !handle_points.empty();
  for (Eigen::Index e = 0; e < mesh.element_count(); ++e) {
    part.triangles.push_back({static_cast<std::uint32_t>(mesh.elements(e, 0)), static_cast<std::uint32_t>(mesh.elements(e, 1)),
                              static_cast<std::uint32_t>(mesh.elements(e, 2))});
    part.triangle_colors.push_back(
        reference.empty() ? render::colors::kSurface
                          : node_color(static_cast<std::size_t>(std::max(0, reference[static_cast<std::size_t>(e)])), dots));
  }
  scene.parts.push_back(std::move(part));
  for (const dim2::Curve& c : curves.curves) {
    render::Polyline line;
    line.closed = true;
    line.color = render::colors::kEdge;
    for (const dim2::Point& q : c.vertices) line.points.push_back({q.x, q.y, 1.0});
    scene.polylines.push_back(std::move(line));
  }
  if (dots) {
    // Dots 1.5% of the deformed mesh's extent in radius, above the mesh and the curves.
    const double extent = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
    const double radius = 0.015 * extent;
    constexpr int kSides = 24;
    render::Part dot;
    dot.name = "handles";
    dot.color = handle_color();
    for (const Eigen::RowVector2d& c : handle_points) {
      const auto centre = static_cast<std::uint32_t>(dot.vertices.size());
      dot.vertices.push_back({c(0), c(1), 2.0});
      for (int k = 0; k < kSides; ++k) {
        const double a = 2 * std::numbers::pi * k / kSides;
        dot.vertices.push_back({c(0) + radius * std::cos(a), c(1) + radius * std::sin(a), 2.0});
        dot.triangles.push_back({centre, centre + 1 + static_cast<std::uint32_t>(k),
                                 centre + 1 + static_cast<std::uint32_t>((k + 1) % kSides)});
      }
    }
    scene.parts.push_back(std::move(dot));
  }
  return scene;
}

}  // namespace imm::figures
