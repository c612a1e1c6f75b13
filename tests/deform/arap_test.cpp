// ARAP (deform/arap.h) with known answers, for triangles and tetrahedra alike: rigid motions are
// reproduced to round-off with zero energy, the energy never increases, handles are met exactly.
#include <gtest/gtest.h>

#include <type_traits>

#include "deform/arap.h"
#include "deform/rotation.h"
#include "grid.h"

namespace imm::deform {
namespace {

template <class T>
class Arap : public testing::Test {};
using Dims = testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(Arap, Dims);

/// The rest positions moved by x -> R x + t.
template <int D>
Eigen::MatrixXd rigidly_moved(const Eigen::MatrixXd& rest, const Eigen::Matrix<double, D, D>& r,
                              const Eigen::Matrix<double, 1, D>& t) {
  return (rest * r.transpose()).rowwise() + t;
}

TYPED_TEST(Arap, RigidTargetsFromARigidGuessStayExactlyRigid) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(4);
  const std::vector<Eigen::Index> handles = test::vertices_where<D>(mesh, 0, 0.0, 1.0);
  const ArapData<D> data = arap_precompute<D>(mesh, handles);
  ASSERT_TRUE(data.ok()) << data.error;
  for (int seed = 0; seed < 3; ++seed) {
    const Eigen::Matrix<double, D, D> r = test::test_rotation<D>(seed);
    const Eigen::Matrix<double, 1, D> t = Eigen::Matrix<double, 1, D>::Constant(0.5 + seed);
    const Eigen::MatrixXd expected = rigidly_moved<D>(mesh.vertices, r, t);
    Eigen::MatrixXd targets(static_cast<Eigen::Index>(handles.size()), D);
    for (std::size_t k = 0; k < handles.size(); ++k) targets.row(static_cast<Eigen::Index>(k)) = expected.row(handles[k]);
    Eigen::MatrixXd x = expected;
    const ArapReport report = arap_solve<D>(data, targets, x, {.max_iterations = 3});
    EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-12) << "seed " << seed;
    EXPECT_LT(report.energies.back(), 1e-24) << "seed " << seed;
  }
}

TYPED_TEST(Arap, RigidTargetsFromRestConvergeToTheRigidMotion) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(3);
  const std::vector<Eigen::Index> handles = test::vertices_where<D>(mesh, 0, 0.0, 1.0);
  const ArapData<D> data = arap_precompute<D>(mesh, handles);
  ASSERT_TRUE(data.ok()) << data.error;
  const Eigen::Matrix<double, D, D> r = test::test_rotation<D>(7);
  const Eigen::Matrix<double, 1, D> t = Eigen::Matrix<double, 1, D>::Constant(-0.25);
  const Eigen::MatrixXd expected = rigidly_moved<D>(mesh.vertices, r, t);
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(handles.size()), D);
  for (std::size_t k = 0; k < handles.size(); ++k) targets.row(static_cast<Eigen::Index>(k)) = expected.row(handles[k]);
  Eigen::MatrixXd x = mesh.vertices;  // starts at rest: every rotation must be found
  const ArapReport report = arap_solve<D>(data, targets, x, {.max_iterations = 1000, .relative_tolerance = 0.0, .energy_tolerance = 0.0});
  EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(report.energies.back(), 1e-18);
}

TYPED_TEST(Arap, EnergyNeverIncreasesAndHandlesAreMet) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(4);
  const std::vector<Eigen::Index> handles = test::vertices_where<D>(mesh, 0, 0.0, 1.0);
  const ArapData<D> data = arap_precompute<D>(mesh, handles);
  ASSERT_TRUE(data.ok()) << data.error;
  // Bend: the x = 1 face lifted and turned, the x = 0 face fixed.
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(handles.size()), D);
  const Eigen::Matrix<double, D, D> r = test::test_rotation<D>(2);
  for (std::size_t k = 0; k < handles.size(); ++k) {
    const Eigen::Matrix<double, 1, D> p = mesh.vertices.row(handles[k]);
    targets.row(static_cast<Eigen::Index>(k)) = p(0) > 0.5 ? Eigen::Matrix<double, 1, D>(p * r.transpose() * 0.9) : p;
  }
  Eigen::MatrixXd x = mesh.vertices;
  const ArapReport report = arap_solve<D>(data, targets, x, {.max_iterations = 60, .relative_tolerance = 0.0});
  ASSERT_GE(report.energies.size(), 2u);
  EXPECT_GT(report.energies.front(), report.energies.back());
  for (std::size_t i = 1; i < report.energies.size(); ++i)
    EXPECT_LE(report.energies[i], report.energies[i - 1] * (1 + 1e-12) + 1e-15) << "iteration " << i;
  for (std::size_t k = 0; k < handles.size(); ++k)
    EXPECT_EQ(x.row(handles[k]), targets.row(static_cast<Eigen::Index>(k)));
  // The energy reported is the energy of the state returned.
  EXPECT_NEAR(arap_energy<D>(data, x), report.energies.back(), 1e-12);
}

TYPED_TEST(Arap, APartWithoutHandlesStaysWhereItIs) {
  constexpr int D = TypeParam::value;
  // Two disjoint grids: the second one has no handle.
  const SimplexMesh<D> one = test::unit_grid<D>(2);
  SimplexMesh<D> two;
  two.vertices.resize(2 * one.vertex_count(), D);
  two.vertices << one.vertices, (one.vertices.array() + 3.0).matrix();
  two.elements.resize(2 * one.element_count(), D + 1);
  two.elements << one.elements, (one.elements.array() + static_cast<int>(one.vertex_count())).matrix();
  const std::vector<Eigen::Index> handles = test::vertices_where<D>(one, 0, 0.0, 1.0);
  const ArapData<D> data = arap_precompute<D>(two, handles);
  ASSERT_TRUE(data.ok()) << data.error;
  ASSERT_EQ(data.pinned.size(), 1u);
  EXPECT_GE(data.pinned[0], one.vertex_count());
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(handles.size()), D);
  for (std::size_t k = 0; k < handles.size(); ++k)
    targets.row(static_cast<Eigen::Index>(k)) = one.vertices.row(handles[k]).array() + 0.5;
  Eigen::MatrixXd x = two.vertices;
  arap_solve<D>(data, targets, x);
  EXPECT_LT((x.bottomRows(one.vertex_count()) - two.vertices.bottomRows(one.vertex_count())).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((x.topRows(one.vertex_count()).array() - one.vertices.array() - 0.5).abs().maxCoeff(), 1e-9);
}

TYPED_TEST(Arap, PolarNewtonRotationEqualsTheSvdRotation) {
  constexpr int D = TypeParam::value;
  using Square = Eigen::Matrix<double, D, D>;
  // Near-rigid, stretched, nearly flat and inverted matrices: the Newton polar iteration (det > 0)
  // and its SVD fallback must both give the SVD's closest proper rotation.
  std::srand(11);
  for (int trial = 0; trial < 400; ++trial) {
    Square f = test::test_rotation<D>(trial % 13) * (Square::Identity() + (0.02 + 0.01 * (trial % 50)) * Square::Random());
    if (trial % 7 == 0) f.col(0) *= 1e-7;  // nearly flat
    if (trial % 5 == 0) f.col(1) *= -1.0;  // inverted
    const Square r = closest_rotation<D>(f), expected = closest_rotation_svd<D>(f);
    EXPECT_LT((r - expected).cwiseAbs().maxCoeff(), 1e-11) << "trial " << trial << "\n" << f;
    EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  }
}

TYPED_TEST(Arap, ResultDoesNotDependOnTheThreadCountOrTheAcceleration) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(4);
  const std::vector<Eigen::Index> handles = test::vertices_where<D>(mesh, 0, 0.0, 1.0);
  const ArapData<D> data = arap_precompute<D>(mesh, handles);
  ASSERT_TRUE(data.ok()) << data.error;
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(handles.size()), D);
  for (std::size_t k = 0; k < handles.size(); ++k) {
    Eigen::Matrix<double, 1, D> p = mesh.vertices.row(handles[k]);
    if (p(0) > 0.5) p(D - 1) += 0.7, p(0) += 0.3;
    targets.row(static_cast<Eigen::Index>(k)) = p;
  }
  Eigen::MatrixXd one = mesh.vertices, two = mesh.vertices, plain = mesh.vertices;
  const ArapReport r1 = arap_solve<D>(data, targets, one, {.max_iterations = 40, .threads = 1});
  const ArapReport r2 = arap_solve<D>(data, targets, two, {.max_iterations = 40, .threads = 2});
  EXPECT_EQ(one, two);  // bit for bit: each element is written by one thread, sums in element order
  EXPECT_EQ(r1.energies, r2.energies);
  // Plain local-global and the accelerated one reach the same minimum; the accelerated one in
  // fewer iterations.
  const ArapReport rp = arap_solve<D>(data, targets, plain, {.max_iterations = 2000, .relative_tolerance = 1e-12, .anderson_window = 0});
  const ArapReport ra = arap_solve<D>(data, targets, one, {.max_iterations = 2000, .relative_tolerance = 1e-12});
  EXPECT_TRUE(rp.converged && ra.converged);
  EXPECT_LT(ra.iterations, rp.iterations);
  EXPECT_NEAR(ra.energies.back(), rp.energies.back(), 1e-8 * rp.energies.back());
  EXPECT_LT((one - plain).cwiseAbs().maxCoeff(), 1e-4);
}

TYPED_TEST(Arap, InvertedRestElementIsReported) {
  constexpr int D = TypeParam::value;
  SimplexMesh<D> mesh = test::unit_grid<D>(1);
  std::swap(mesh.elements(0, 0), mesh.elements(0, 1));
  const ArapData<D> data = arap_precompute<D>(mesh, {0});
  EXPECT_FALSE(data.ok());
  EXPECT_NE(data.error.find("element 0"), std::string::npos) << data.error;
}

}  // namespace
}  // namespace imm::deform
