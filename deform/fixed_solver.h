// Minimizing a quadratic with some variables fixed (libigl's min_quad_with_fixed): the
// precomputation splits the variables into free and known and factors the free block once;
// each solve is two triangular solves. The building block of ARAP's global step, the weights
// and the geodesics.
#pragma once

#include <Eigen/Sparse>
#include <memory>
#include <string>
#include <vector>

#include "deform/sparse_cholesky.h"

namespace imm::deform {

/// Solves A x = b on the free rows of a symmetric positive (semi)definite A, with x given on the
/// known rows: x_f = A_ff^{-1} (b_f - A_fk x_k). A_ff is factored once (sparse LDL^T).
class FixedSolver {
 public:
  /// Factors the free block of `a` (n x n). `known` lists the fixed variables (any order, no
  /// duplicates). Returns false (and `error()` says why) when A_ff is not positive definite,
  /// e.g. a connected part of the mesh without a known variable.
  /// `order` (optional): a fill-reducing elimination order of variables of `a`, e.g. the
  /// ordering() of a solver of the same `a` with fewer known variables; the free block is then
  /// factored in that order (free variables it lacks last) instead of searching for one.
  bool compute(const Eigen::SparseMatrix<double>& a, const std::vector<Eigen::Index>& known,
               FactorUse use = FactorUse::solve_often, const std::vector<Eigen::Index>& order = {});

  /// The full solution (n x c): `known_values` (|known| x c, in `known` order) on the known rows,
  /// the minimizer on the free rows. `rhs` is n x c (its known rows are ignored).
  [[nodiscard]] Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs, const Eigen::MatrixXd& known_values) const;

  [[nodiscard]] const std::string& error() const { return error_; }
  [[nodiscard]] Eigen::Index free_count() const { return static_cast<Eigen::Index>(free_.size()); }
  [[nodiscard]] const std::vector<Eigen::Index>& known() const { return known_; }
  [[nodiscard]] const std::vector<Eigen::Index>& free() const { return free_; }
  /// The free variables (ids of `a`) in the order the factor eliminates them; empty when the
  /// backend does not say (SparseCholesky::ordering) or nothing is free.
  [[nodiscard]] std::vector<Eigen::Index> ordering() const;

 private:
  Eigen::Index n_ = 0;
  std::vector<Eigen::Index> known_, free_;
  Eigen::SparseMatrix<double> a_fk_;
  /// Shared (immutable once computed) so that data structs holding a solver can be moved and copied.
  std::shared_ptr<const SparseCholesky> factor_;
  std::string error_;
};

}  // namespace imm::deform
