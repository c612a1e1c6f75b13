// Weights and distances (deform/weights.h) with known answers, for triangles and tetrahedra
// alike: bounded biharmonic weights lie in [0, 1], sum to one, are 1 on their own handle and 0
// on the others; heat-method distances on a bar match the exact distance to its end face.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "deform/weights.h"
#include "grid.h"

namespace imm::deform {
namespace {

template <class T>
class Weights : public testing::Test {};
using Dims = testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(Weights, Dims);

TYPED_TEST(Weights, BoundedBiharmonicWeightsAreBoundedPartitionOfUnityAndInterpolate) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(D == 2 ? 10 : 5);
  // Three handles: the vertices at three corners of the box (all coordinates 0; x = 1 only; y = 1 only).
  std::vector<std::vector<Eigen::Index>> handles(3);
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) {
    const Eigen::Matrix<double, 1, D> p = mesh.vertices.row(v);
    if (p.norm() == 0.0) handles[0].push_back(v);
    Eigen::Matrix<double, 1, D> x = Eigen::Matrix<double, 1, D>::Zero(), y = x;
    x(0) = 1.0;
    y(1) = 1.0;
    if (p == x) handles[1].push_back(v);
    if (p == y) handles[2].push_back(v);
  }
  for (const auto& h : handles) ASSERT_EQ(h.size(), 1u);
  const WeightsResult r = bounded_biharmonic_weights<D>(mesh, handles);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.weights.rows(), mesh.vertex_count());
  ASSERT_EQ(r.weights.cols(), 3);
  EXPECT_GE(r.weights.minCoeff(), 0.0);
  EXPECT_LE(r.weights.maxCoeff(), 1.0);
  EXPECT_LT((r.weights.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-12);
  for (std::size_t k = 0; k < handles.size(); ++k)
    for (std::size_t j = 0; j < handles.size(); ++j)
      EXPECT_DOUBLE_EQ(r.weights(handles[k][0], static_cast<Eigen::Index>(j)), k == j ? 1.0 : 0.0);
  // Each weight is largest near its own handle: the opposite corner of the box gets little of handle 1.
  Eigen::Index far = 0;
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.vertices(v, 0) == 0.0 && mesh.vertices(v, 1) == 1.0 && mesh.vertices.row(v).sum() == 1.0) far = v;
  EXPECT_LT(r.weights(far, 1), 0.2);
  EXPECT_GT(r.weights(far, 2), 0.6);
}

/// The bounded biharmonic QP of handle `h` solved by an independent method: projected
/// Gauss-Seidel (exact minimization over one variable at a time, clamped to [0, 1]), which
/// converges to the minimizer of a convex quadratic over a box. Slow but simple; small meshes only.
template <int D>
Eigen::MatrixXd reference_weights(const SimplexMesh<D>& mesh, const std::vector<std::vector<Eigen::Index>>& handles) {
  const Eigen::SparseMatrix<double> k = stiffness_matrix<D>(mesh);
  const Eigen::VectorXd mass = lumped_mass<D>(mesh);
  const Eigen::SparseMatrix<double> q = Eigen::SparseMatrix<double>(k * mass.cwiseInverse().asDiagonal() * k);
  const Eigen::Index n = mesh.vertex_count();
  std::vector<int> owner(static_cast<std::size_t>(n), -1);
  for (std::size_t h = 0; h < handles.size(); ++h)
    for (Eigen::Index v : handles[h]) owner[static_cast<std::size_t>(v)] = static_cast<int>(h);
  Eigen::MatrixXd w(n, static_cast<Eigen::Index>(handles.size()));
  for (std::size_t h = 0; h < handles.size(); ++h) {
    Eigen::VectorXd x = Eigen::VectorXd::Constant(n, 0.5);
    for (Eigen::Index v = 0; v < n; ++v)
      if (owner[static_cast<std::size_t>(v)] >= 0) x[v] = owner[static_cast<std::size_t>(v)] == static_cast<int>(h) ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 200000; ++sweep) {
      double change = 0.0;
      for (Eigen::Index v = 0; v < n; ++v) {
        if (owner[static_cast<std::size_t>(v)] >= 0) continue;
        double off = 0.0, diagonal = 0.0;  // q is symmetric: column v is row v
        for (Eigen::SparseMatrix<double>::InnerIterator it(q, v); it; ++it)
          if (it.row() == v) diagonal = it.value();
          else off += it.value() * x[it.row()];
        const double value = std::clamp(-off / diagonal, 0.0, 1.0);
        change = std::max(change, std::abs(value - x[v]));
        x[v] = value;
      }
      if (change < 1e-15) break;
    }
    w.col(static_cast<Eigen::Index>(h)) = x;
  }
  for (Eigen::Index v = 0; v < n; ++v) w.row(v) /= w.row(v).sum();
  return w;
}

TYPED_TEST(Weights, BoundedBiharmonicWeightsEqualAnIndependentQpSolution) {
  constexpr int D = TypeParam::value;
  // Handles on one side of a thin box: the unconstrained biharmonic weights overshoot [0, 1] far
  // from them, so bounds are held and released (several active-set rounds).
  const SimplexMesh<D> mesh = test::bar_grid<D>(D == 2 ? 8 : 6, 4.0, D == 2 ? 3 : 2);
  std::vector<std::vector<Eigen::Index>> handles(3);
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) {
    const double x = mesh.vertices(v, 0), y = mesh.vertices(v, 1);
    if (x == 0.0 && y == 0.0) handles[0].push_back(v);
    if (x == 0.0 && y == 1.0) handles[1].push_back(v);
    if (x == 4.0 && y == 0.0) handles[2].push_back(v);
  }
  const WeightsResult r = bounded_biharmonic_weights<D>(mesh, handles);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_GT(*std::max_element(r.active_set_iterations.begin(), r.active_set_iterations.end()), 1);
  const Eigen::MatrixXd expected = reference_weights<D>(mesh, handles);
  EXPECT_LT((r.weights - expected).cwiseAbs().maxCoeff(), 1e-7);
}

/// With two handles the weights need no normalization: 1 - w of one handle's problem is feasible
/// for the other's, with the same objective (Q 1 = K M^{-1} K 1 = 0), so the two minimizers sum
/// to one. The returned weights are then the QP's minimizers themselves, and their KKT conditions
/// can be checked directly: every value in [0, 1]; the gradient Q w zero where 0 < w < 1, >= 0
/// where w = 0 (the lower bound held), <= 0 where w = 1. A bound never held (a violated value)
/// or held where it should have been released (a wrong-signed gradient) fails.
TYPED_TEST(Weights, TwoHandleWeightsSatisfyTheKktConditions) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::bar_grid<D>(D == 2 ? 24 : 12, 4.0, D == 2 ? 4 : 3);
  // Handle 0 at the corner x = y = 0, handle 1 the vertex x = 1, y = 1: the unconstrained weight
  // of handle 0 undershoots 0 past handle 1, over a region the minimizer holds only in part.
  std::vector<std::vector<Eigen::Index>> handles(2);
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) {
    const double x = mesh.vertices(v, 0), y = mesh.vertices(v, 1), rest = mesh.vertices.row(v).tail(D - 2).sum();
    if (x == 0.0 && y == 0.0 && rest == 0.0) handles[0].push_back(v);
    if (x == 1.0 && y == 1.0 && rest == 0.0) handles[1].push_back(v);
  }
  ASSERT_EQ(handles[0].size(), 1u);
  ASSERT_EQ(handles[1].size(), 1u);
  const WeightsResult r = bounded_biharmonic_weights<D>(mesh, handles);
  ASSERT_TRUE(r.ok()) << r.error;
  const Eigen::SparseMatrix<double> k = stiffness_matrix<D>(mesh);
  const Eigen::VectorXd mass = lumped_mass<D>(mesh);
  const Eigen::SparseMatrix<double> q = Eigen::SparseMatrix<double>(k * mass.cwiseInverse().asDiagonal() * k);
  const double tolerance = 1e-9 * q.diagonal().maxCoeff();
  int at_zero = 0, at_one = 0;
  for (int h = 0; h < 2; ++h) {
    const Eigen::VectorXd w = r.weights.col(h);
    const Eigen::VectorXd gradient = q * w;
    for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) {
      if (v == handles[0][0] || v == handles[1][0]) continue;
      ASSERT_GE(w[v], 0.0);
      ASSERT_LE(w[v], 1.0);
      if (w[v] == 0.0) {
        ++at_zero;
        EXPECT_GE(gradient[v], -tolerance) << "vertex " << v << " handle " << h;
      } else if (w[v] == 1.0) {
        ++at_one;
        EXPECT_LE(gradient[v], tolerance) << "vertex " << v << " handle " << h;
      } else {
        EXPECT_LT(std::abs(gradient[v]), tolerance) << "vertex " << v << " handle " << h;
      }
    }
  }
  // The bounds matter: some values sit on them, after several rounds.
  EXPECT_GT(at_zero, 0);
  EXPECT_GT(at_one, 0);
  EXPECT_GT(*std::max_element(r.active_set_iterations.begin(), r.active_set_iterations.end()), 2);
}

TYPED_TEST(Weights, BadHandlesAreRefused) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(2);
  EXPECT_FALSE((bounded_biharmonic_weights<D>(mesh, {{0}, {}}).ok()));
  EXPECT_FALSE((bounded_biharmonic_weights<D>(mesh, {{0}, {0}}).ok()));
  EXPECT_FALSE((bounded_biharmonic_weights<D>(mesh, {{0}, {mesh.vertex_count()}}).ok()));
}

TYPED_TEST(Weights, HeatGeodesicOnABarMatchesTheDistanceToItsEnd) {
  constexpr int D = TypeParam::value;
  const int along = D == 2 ? 40 : 24;
  const double length = 8.0;
  const SimplexMesh<D> bar = test::bar_grid<D>(along, length, D == 2 ? 4 : 3);
  const std::vector<Eigen::Index> sources = test::vertices_where<D>(bar, 0, 0.0, 1e300);  // the x = 0 face
  const Eigen::VectorXd distance = heat_geodesic<D>(bar, sources);
  const double h = length / along;
  double worst = 0.0;
  for (Eigen::Index v = 0; v < bar.vertex_count(); ++v) worst = std::max(worst, std::abs(distance[v] - bar.vertices(v, 0)));
  // Within the discretization: a small multiple of the element size over a bar 8 long.
  EXPECT_LT(worst, 2.0 * h);
  EXPECT_GT(distance.maxCoeff(), 7.0);
}

TYPED_TEST(Weights, HeatGeodesicDoesNotCrossToAPartWithoutSource) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> one = test::unit_grid<D>(2);
  SimplexMesh<D> two;
  two.vertices.resize(2 * one.vertex_count(), D);
  two.vertices << one.vertices, (one.vertices.array() + 1.5).matrix();
  two.elements.resize(2 * one.element_count(), D + 1);
  two.elements << one.elements, (one.elements.array() + static_cast<int>(one.vertex_count())).matrix();
  const Eigen::VectorXd distance = heat_geodesic<D>(two, {0});
  EXPECT_TRUE(distance.head(one.vertex_count()).allFinite());
  EXPECT_TRUE(std::isinf(distance[one.vertex_count()]));
}

}  // namespace
}  // namespace imm::deform
