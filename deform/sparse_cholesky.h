// One sparse Cholesky factorization behind a small interface, so that only one translation unit
// sees the backend: CHOLMOD (SuiteSparse, through Eigen's CholmodSupport) when the build found
// it, Eigen's SimplicialLDLT otherwise. CHOLMOD orders with METIS or AMD, whichever fills less,
// and its supernodal factorization is several times faster on tet meshes (BENCHMARKS.md,
// "Deformation"); Eigen's is the fallback that needs nothing installed.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

namespace imm::deform {

/// How a factor will be used: factored once and solved with many times (ARAP: CHOLMOD's
/// simplicial factor, whose triangular solves are the fastest), or factored often (the active
/// sets of the weights, the FEM Newton matrices: CHOLMOD's supernodal factorization).
enum class FactorUse { solve_often, factor_often };

class SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  /// Factors the symmetric matrix `a` (both triangles stored). Returns false when `a` is not
  /// (numerically) positive definite.
  bool compute(const Eigen::SparseMatrix<double>& a, FactorUse use = FactorUse::solve_often);
  /// The two halves of compute(), for a sequence of matrices with one sparsity pattern (the FEM
  /// Newton iterations): the fill-reducing ordering and symbolic factorization of `pattern` once,
  /// then a numeric factorization per matrix. factorize() returns false as compute() does.
  /// @pre factorize: analyze() ran on a matrix with the same pattern (both triangles stored).
  void analyze(const Eigen::SparseMatrix<double>& pattern, FactorUse use = FactorUse::solve_often);
  bool factorize(const Eigen::SparseMatrix<double>& a);
  /// compute() with the fill-reducing ordering given instead of searched for: row `ordering[i]`
  /// of `a` is eliminated i-th (a permutation of 0..n-1). For a sequence of related matrices
  /// (the free blocks of the weights' active sets, each a subset of one matrix's rows), the
  /// ordering of the largest one restricted to each: CHOLMOD's search (AMD, then METIS) costs a
  /// fifth of the weights' factorizations. Eigen's fallback orders by itself and ignores it.
  bool compute(const Eigen::SparseMatrix<double>& a, FactorUse use, const std::vector<Eigen::Index>& ordering);
  /// The fill-reducing ordering of the last factorization: row `ordering()[i]` of the matrix was
  /// eliminated i-th. Empty when the backend does not say (Eigen's fallback).
  [[nodiscard]] std::vector<Eigen::Index> ordering() const;
  /// A^{-1} b for every column of `b`. @pre compute() returned true.
  [[nodiscard]] Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;
  /// The backend's name, for reports ("CHOLMOD" or "Eigen SimplicialLDLT").
  [[nodiscard]] static const char* backend();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace imm::deform
