#include "deform/sparse_cholesky.h"

#ifdef IMM_HAVE_CHOLMOD
#include <omp.h>

#include <Eigen/CholmodSupport>
#include <mutex>
#else
#include <Eigen/SparseCholesky>
#endif

namespace imm::deform {

#ifdef IMM_HAVE_CHOLMOD
namespace {

/// Debian's CHOLMOD 3 runs parts of its supernodal factorization in OpenMP teams of a fixed 4
/// threads (`num_threads(4)` clauses, which OMP_NUM_THREADS does not lower), whatever the cores.
/// Measured on 2 cores (BENCHMARKS.md, "CHOLMOD without its OpenMP team"): the team's spinning
/// and futex traffic doubled the CPU time of the weights and made wall time swing by 3x under
/// load, and it gained nothing on an idle machine. So CHOLMOD runs with OpenMP's
/// max-active-levels at 0 (every parallel region a team of one), as OMP_THREAD_LIMIT=1 would do.
/// That setting is process-wide in libgomp: it is lowered while any CHOLMOD call of this file
/// runs and restored when the last one returns, so a host program's own OpenMP is left alone
/// outside those calls.
class SerialOpenMp {
 public:
  SerialOpenMp() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (depth_++ == 0) {
      saved_ = omp_get_max_active_levels();
      omp_set_max_active_levels(0);
    }
  }
  ~SerialOpenMp() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (--depth_ == 0) omp_set_max_active_levels(saved_);
  }
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;

 private:
  static inline std::mutex mutex_;
  static inline int depth_ = 0;  ///< CHOLMOD calls running (on any thread)
  static inline int saved_ = 0;  ///< the setting before the first of them
};

}  // namespace

/// Eigen's wrapper, opened up for the permutation CHOLMOD chose (its factor is a protected member).
class CholmodFactor : public Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  [[nodiscard]] const cholmod_factor* raw() const { return m_cholmodFactor; }
  /// factorize(), given the upper triangle of `a` (both triangles stored) instead of the lower
  /// one. A supernodal factorization works on the lower triangle of the permuted matrix, which
  /// CHOLMOD forms from an upper triangle with one transpose and from a lower one with two
  /// (cholmod_factorize.c); a simplicial one is the other way round.
  void factorize_upper(const Eigen::SparseMatrix<double>& a) {
    cholmod_sparse upper = Eigen::viewAsCholmod(a.selfadjointView<Eigen::Upper>());
    cholmod_factorize_p(&upper, m_shiftOffset, nullptr, 0, m_cholmodFactor, &cholmod());
    m_info = m_cholmodFactor->minor == m_cholmodFactor->n ? Eigen::Success : Eigen::NumericalIssue;
    m_factorizationIsOk = true;
  }
};

struct SparseCholesky::Impl {
  /// A factor for `use`: CHOLMOD's simplicial or supernodal mode, silent (a refused matrix is
  /// reported by the return value, not on stderr).
  explicit Impl(FactorUse use) {
    factor.cholmod().print = 0;
    factor.setMode(use == FactorUse::solve_often ? Eigen::CholmodSimplicialLLt : Eigen::CholmodSupernodalLLt);
  }
  CholmodFactor factor;
  /// Non-empty: the factor is of P a P^T (the caller's ordering), solves permute around it.
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> given;
  std::vector<Eigen::Index> given_order;
};

bool SparseCholesky::compute(const Eigen::SparseMatrix<double>& a, FactorUse use) {
  impl_ = std::make_unique<Impl>(use);
  const SerialOpenMp serial;
  impl_->factor.compute(a);
  return impl_->factor.info() == Eigen::Success;
}

bool SparseCholesky::compute(const Eigen::SparseMatrix<double>& a, FactorUse use, const std::vector<Eigen::Index>& ordering) {
  impl_ = std::make_unique<Impl>(use);
  // The natural ordering of the permuted matrix, no search. CHOLMOD still postorders its
  // elimination tree (a permutation that changes no fill, for the supernodes).
  impl_->factor.cholmod().nmethods = 1;
  impl_->factor.cholmod().method[0].ordering = CHOLMOD_NATURAL;
  impl_->given.resize(static_cast<Eigen::Index>(ordering.size()));
  for (std::size_t i = 0; i < ordering.size(); ++i) impl_->given.indices()[ordering[i]] = static_cast<int>(i);
  impl_->given_order = ordering;
  Eigen::SparseMatrix<double> permuted;
  permuted = a.twistedBy(impl_->given);
  const SerialOpenMp serial;
  impl_->factor.compute(permuted);
  return impl_->factor.info() == Eigen::Success;
}

std::vector<Eigen::Index> SparseCholesky::ordering() const {
  const cholmod_factor* l = impl_->factor.raw();
  std::vector<Eigen::Index> order;
  if (l == nullptr || l->Perm == nullptr) return order;
  const int* perm = static_cast<const int*>(l->Perm);
  order.reserve(l->n);
  for (std::size_t i = 0; i < l->n; ++i)
    order.push_back(impl_->given_order.empty() ? perm[i] : impl_->given_order[static_cast<std::size_t>(perm[i])]);
  return order;
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& b) const {
  const SerialOpenMp serial;
  if (impl_->given_order.empty()) return impl_->factor.solve(b);
  const Eigen::MatrixXd permuted = impl_->given * b;
  return impl_->given.inverse() * Eigen::MatrixXd(impl_->factor.solve(permuted));
}

void SparseCholesky::analyze(const Eigen::SparseMatrix<double>& pattern, FactorUse use) {
  impl_ = std::make_unique<Impl>(use);
  const SerialOpenMp serial;
  impl_->factor.analyzePattern(pattern);
}

bool SparseCholesky::factorize(const Eigen::SparseMatrix<double>& a) {
  const SerialOpenMp serial;
  if (impl_->factor.raw()->is_super) impl_->factor.factorize_upper(a);
  else impl_->factor.factorize(a);
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

bool SparseCholesky::compute(const Eigen::SparseMatrix<double>& a, FactorUse use, const std::vector<Eigen::Index>& /*ordering*/) {
  return compute(a, use);
}

std::vector<Eigen::Index> SparseCholesky::ordering() const { return {}; }

const char* SparseCholesky::backend() { return "Eigen SimplicialLDLT"; }
#endif

SparseCholesky::SparseCholesky() = default;
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

}  // namespace imm::deform
