#include "deform/sparse_cholesky.h"

#ifdef IMM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#else
#include <Eigen/SparseCholesky>
#endif

namespace imm::deform {

#ifdef IMM_HAVE_CHOLMOD
struct SparseCholesky::Impl {
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> factor;
};

bool SparseCholesky::compute(const Eigen::SparseMatrix<double>& a, FactorUse use) {
  impl_ = std::make_unique<Impl>();
  impl_->factor.cholmod().print = 0;  // a refused matrix is reported by the return value, not on stderr
  impl_->factor.setMode(use == FactorUse::solve_often ? Eigen::CholmodSimplicialLLt : Eigen::CholmodSupernodalLLt);
  impl_->factor.compute(a);
  return impl_->factor.info() == Eigen::Success;
}

void SparseCholesky::analyze(const Eigen::SparseMatrix<double>& pattern, FactorUse use) {
  impl_ = std::make_unique<Impl>();
  impl_->factor.cholmod().print = 0;
  impl_->factor.setMode(use == FactorUse::solve_often ? Eigen::CholmodSimplicialLLt : Eigen::CholmodSupernodalLLt);
  impl_->factor.analyzePattern(pattern);
}

bool SparseCholesky::factorize(const Eigen::SparseMatrix<double>& a) {
  impl_->factor.factorize(a);
  return impl_->factor.info() == Eigen::Success;
}

const char* SparseCholesky::backend() { return "CHOLMOD"; }
#else
struct SparseCholesky::Impl {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor;
};

bool SparseCholesky::compute(const Eigen::SparseMatrix<double>& a, FactorUse /*use*/) {
  impl_ = std::make_unique<Impl>();
  impl_->factor.compute(a);
  // LDL^T succeeds on indefinite matrices too: positive definite means every pivot positive.
  return impl_->factor.info() == Eigen::Success && (a.rows() == 0 || impl_->factor.vectorD().minCoeff() > 0.0);
}

void SparseCholesky::analyze(const Eigen::SparseMatrix<double>& pattern, FactorUse /*use*/) {
  impl_ = std::make_unique<Impl>();
  impl_->factor.analyzePattern(pattern);
}

bool SparseCholesky::factorize(const Eigen::SparseMatrix<double>& a) {
  impl_->factor.factorize(a);
  return impl_->factor.info() == Eigen::Success && (a.rows() == 0 || impl_->factor.vectorD().minCoeff() > 0.0);
}

const char* SparseCholesky::backend() { return "Eigen SimplicialLDLT"; }
#endif

SparseCholesky::SparseCholesky() = default;
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& b) const { return impl_->factor.solve(b); }

}  // namespace imm::deform
