// The sparse factor with a caller's fill-reducing ordering (deform/sparse_cholesky.h) and the
// fixed-variable solver that passes one on (deform/fixed_solver.h): the same solutions as with
// the backend's own ordering, for triangles and tetrahedra alike.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <string>
#include <type_traits>

#include "deform/fixed_solver.h"
#include "deform/sparse_cholesky.h"
#include "grid.h"

namespace imm::deform {
namespace {

template <class T>
class SparseCholeskyOrdering : public testing::Test {};
using Dims = testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(SparseCholeskyOrdering, Dims);

/// A symmetric positive definite matrix with a mesh's pattern: stiffness plus lumped mass.
template <int D>
Eigen::SparseMatrix<double> spd_matrix(const SimplexMesh<D>& mesh) {
  Eigen::SparseMatrix<double> a = stiffness_matrix<D>(mesh);
  const Eigen::VectorXd mass = lumped_mass<D>(mesh);
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) a.coeffRef(v, v) += mass[v];
  return a;
}

TYPED_TEST(SparseCholeskyOrdering, AGivenOrderingSolvesTheSameSystem) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(D == 2 ? 12 : 5);
  const Eigen::SparseMatrix<double> a = spd_matrix<D>(mesh);
  const Eigen::Index n = a.rows();
  Eigen::MatrixXd b(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) b(i, 0) = std::sin(1.0 + static_cast<double>(i)), b(i, 1) = static_cast<double>(i % 7) - 3.0;
  SparseCholesky own;
  ASSERT_TRUE(own.compute(a, FactorUse::factor_often));
  const Eigen::MatrixXd expected = own.solve(b);
  // A shuffled ordering: a solve that forgot to permute back (or permuted the wrong way) fails.
  std::vector<Eigen::Index> shuffled(static_cast<std::size_t>(n));
  std::iota(shuffled.begin(), shuffled.end(), Eigen::Index{0});
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(7));
  for (FactorUse use : {FactorUse::factor_often, FactorUse::solve_often}) {
    SparseCholesky given;
    ASSERT_TRUE(given.compute(a, use, shuffled));
    const Eigen::MatrixXd x = given.solve(b);
    EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());
    EXPECT_LT((a * x - b).cwiseAbs().maxCoeff(), 1e-10 * b.cwiseAbs().maxCoeff());
  }
  if (std::string(SparseCholesky::backend()) != "CHOLMOD") GTEST_SKIP() << "the fallback does not report its ordering";
  std::vector<Eigen::Index> order = own.ordering();
  std::sort(order.begin(), order.end());
  std::vector<Eigen::Index> identity(static_cast<std::size_t>(n));
  std::iota(identity.begin(), identity.end(), Eigen::Index{0});
  EXPECT_EQ(order, identity);  // a permutation of the rows
}

// One symbolic analysis, then numeric factorizations of matrices with its pattern (the FEM Newton
// matrices): each solves its own system, and an indefinite one is refused. (Which triangle a
// factorization reads, the upper one for CHOLMOD's supernodal factor, is not observable with both
// stored, as the contract requires: the solves are what is checked.)
TYPED_TEST(SparseCholeskyOrdering, AnalyzedPatternFactorsEachMatrixAndRefusesAnIndefiniteOne) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(D == 2 ? 12 : 5);
  const Eigen::SparseMatrix<double> a = spd_matrix<D>(mesh);
  const Eigen::Index n = a.rows();
  Eigen::SparseMatrix<double> twice = 2.0 * a, indefinite = a;
  for (Eigen::Index i = 0; i < n; ++i) indefinite.coeffRef(i, i) -= 10.0 * a.coeff(i, i);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  for (FactorUse use : {FactorUse::factor_often, FactorUse::solve_often}) {
    SparseCholesky factor;
    factor.analyze(a, use);
    ASSERT_TRUE(factor.factorize(a));
    Eigen::VectorXd x = factor.solve(b).col(0);
    EXPECT_LT((a * x - b).cwiseAbs().maxCoeff(), 1e-10 * b.cwiseAbs().maxCoeff());
    EXPECT_FALSE(factor.factorize(indefinite));
    ASSERT_TRUE(factor.factorize(twice));
    x = factor.solve(b).col(0);
    EXPECT_LT((twice * x - b).cwiseAbs().maxCoeff(), 1e-10 * b.cwiseAbs().maxCoeff());
  }
}

TYPED_TEST(SparseCholeskyOrdering, FixedSolverWithAnotherSolversOrderingSolvesTheSameSystem) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(D == 2 ? 12 : 5);
  const Eigen::SparseMatrix<double> a = spd_matrix<D>(mesh);
  const Eigen::Index n = a.rows();
  // The ordering of a solver with one known variable, reused with every third variable known.
  FixedSolver first;
  ASSERT_TRUE(first.compute(a, {0}, FactorUse::factor_often));
  const std::vector<Eigen::Index> order = first.ordering();
  if (std::string(SparseCholesky::backend()) == "CHOLMOD") {
    std::vector<Eigen::Index> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, first.free());  // the free variables, each once
  }
  std::vector<Eigen::Index> known;
  for (Eigen::Index v = 0; v < n; v += 3) known.push_back(v);
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Constant(n, 1, 1.0);
  Eigen::MatrixXd values(static_cast<Eigen::Index>(known.size()), 1);
  for (Eigen::Index i = 0; i < values.rows(); ++i) values(i, 0) = 0.1 * static_cast<double>(i % 5);
  FixedSolver own, reordered;
  ASSERT_TRUE(own.compute(a, known, FactorUse::factor_often));
  ASSERT_TRUE(reordered.compute(a, known, FactorUse::factor_often, order));
  const Eigen::MatrixXd expected = own.solve(rhs, values);
  EXPECT_LT((reordered.solve(rhs, values) - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace imm::deform
