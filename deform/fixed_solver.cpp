#include "deform/fixed_solver.h"

#include <algorithm>

namespace imm::deform {

bool FixedSolver::compute(const Eigen::SparseMatrix<double>& a, const std::vector<Eigen::Index>& known, FactorUse use,
                          const std::vector<Eigen::Index>& order) {
  n_ = a.rows();
  known_ = known;
  free_.clear();
  error_.clear();
  // slot: free variable i -> its free index (>= 0); known variable k-th -> -1 - k.
  std::vector<Eigen::Index> slot(static_cast<std::size_t>(n_), 0);
  std::vector<char> is_known(static_cast<std::size_t>(n_), 0);
  for (std::size_t k = 0; k < known_.size(); ++k) {
    is_known[static_cast<std::size_t>(known_[k])] = 1;
    slot[static_cast<std::size_t>(known_[k])] = -1 - static_cast<Eigen::Index>(k);
  }
  for (Eigen::Index i = 0; i < n_; ++i)
    if (!is_known[static_cast<std::size_t>(i)]) {
      slot[static_cast<std::size_t>(i)] = static_cast<Eigen::Index>(free_.size());
      free_.push_back(i);
    }
  std::vector<Eigen::Triplet<double>> ff, fk;
  for (Eigen::Index col = 0; col < a.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, col); it; ++it) {
      const Eigen::Index r = slot[static_cast<std::size_t>(it.row())], c = slot[static_cast<std::size_t>(it.col())];
      if (r < 0) continue;
      if (c >= 0) ff.emplace_back(r, c, it.value());
      else fk.emplace_back(r, -1 - c, it.value());
    }
  const auto f = static_cast<Eigen::Index>(free_.size());
  Eigen::SparseMatrix<double> a_ff(f, f);
  a_ff.setFromTriplets(ff.begin(), ff.end());
  a_fk_.resize(f, static_cast<Eigen::Index>(known_.size()));
  a_fk_.setFromTriplets(fk.begin(), fk.end());
  factor_.reset();
  if (f == 0) return true;
  auto factor = std::make_shared<SparseCholesky>();
  // Callers check that every connected part has a known variable (a semidefinite free block
  // otherwise); here only a matrix that is not positive definite is refused.
  bool ok = false;
  if (order.empty()) {
    ok = factor->compute(a_ff, use);
  } else {
    // The free indices in `order`'s order, then the free variables it does not list.
    std::vector<Eigen::Index> free_order;
    free_order.reserve(free_.size());
    std::vector<char> placed(free_.size(), 0);
    for (Eigen::Index v : order) {
      const Eigen::Index i = slot[static_cast<std::size_t>(v)];
      if (i < 0 || placed[static_cast<std::size_t>(i)]) continue;
      placed[static_cast<std::size_t>(i)] = 1;
      free_order.push_back(i);
    }
    for (std::size_t i = 0; i < free_.size(); ++i)
      if (!placed[i]) free_order.push_back(static_cast<Eigen::Index>(i));
    ok = factor->compute(a_ff, use, free_order);
  }
  if (!ok) {
    error_ = "the system is not positive definite on the free variables";
    return false;
  }
  factor_ = std::move(factor);
  return true;
}

std::vector<Eigen::Index> FixedSolver::ordering() const {
  std::vector<Eigen::Index> order;
  if (!factor_) return order;
  order = factor_->ordering();
  for (Eigen::Index& i : order) i = free_[static_cast<std::size_t>(i)];
  return order;
}

Eigen::MatrixXd FixedSolver::solve(const Eigen::MatrixXd& rhs, const Eigen::MatrixXd& known_values) const {
  Eigen::MatrixXd x(n_, rhs.cols());
  for (std::size_t k = 0; k < known_.size(); ++k) x.row(known_[k]) = known_values.row(static_cast<Eigen::Index>(k));
  if (free_.empty()) return x;
  Eigen::MatrixXd b(static_cast<Eigen::Index>(free_.size()), rhs.cols());
  for (std::size_t i = 0; i < free_.size(); ++i) b.row(static_cast<Eigen::Index>(i)) = rhs.row(free_[i]);
  if (!known_.empty()) b -= a_fk_ * known_values;
  const Eigen::MatrixXd xf = factor_->solve(b);
  for (std::size_t i = 0; i < free_.size(); ++i) x.row(free_[i]) = xf.row(static_cast<Eigen::Index>(i));
  return x;
}

}  // namespace imm::deform
