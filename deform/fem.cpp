#include "deform/fem.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <Eigen/SparseCore>

#include "core/parallel.h"
#include "deform/rotation.h"
#include "deform/sparse_cholesky.h"

namespace imm::deform {

namespace {

/// Which matrix a Newton iteration solves with. `exact`: the Hessian of the potential, with the
/// change of the rotation (dR/dF): quadratic convergence, but the co-rotated energy is not convex
/// under compression, so it can be indefinite. `projected`: the same with each element's negative
/// eigenvalues clamped to 0 (always semidefinite; converges only linearly, fast, where the clamp
/// is active, e.g. the compressed side of a bent bar). `fixed_rotation`: the classic co-rotational
/// stiffness with R held fixed (semidefinite; linear convergence, slow: about 0.75 per iteration).
enum class NewtonMatrix { exact, projected, fixed_rotation };

struct HessianPattern {
  Eigen::SparseMatrix<double> matrix;  ///< both triangles; values rewritten every Newton iteration
  std::vector<int> element_slots;      ///< per element D(D+1) x D(D+1) indices into matrix's values
  std::vector<int> vertex_slots;       ///< per vertex D x D (inertia and ground)
};

/// The potential minimized by a step: inertia (weight 1/h^2, or 0 in statics), elasticity,
/// gravity, ground penalty.
template <int D>
struct Potential {
  const FemData<D>& data;
  const FemOptions& options;
  double inertia_weight = 0.0;  // 1/h^2
  Eigen::MatrixXd predicted;    // x_n + h v_n (dynamics)

  [[nodiscard]] Eigen::Matrix<double, D, D> gradient_of(const Eigen::MatrixXd& x, Eigen::Index e) const {
    Eigen::Matrix<double, D + 1, D> corners;
    for (int i = 0; i < D + 1; ++i) corners.row(i) = x.row(data.rest.elements(e, i));
    return corners.transpose() * data.geometry[static_cast<std::size_t>(e)].gradients;
  }

  /// Per element the rotation of its deformation gradient (closest_rotation), which value()
  /// computes and gradient_and_hessian() at the same positions reuses: half the cost of an
  /// assembly after an accepted line-search trial.
  using Rotations = std::vector<Eigen::Matrix<double, D, D>>;

  /// The potential at `x`; `rotations` (if given) receives each element's rotation. The elements'
  /// energies are computed on options.threads threads and summed in element order, so the value
  /// does not depend on the thread count.
  [[nodiscard]] double value(const Eigen::MatrixXd& x, Rotations* rotations = nullptr) const {
    const double mu = options.material.mu(), lambda = options.material.lambda();
    const auto m = static_cast<std::size_t>(data.rest.element_count());
    if (rotations != nullptr) rotations->resize(m);
    std::vector<double> energies(m);
    parallel_for(resolve_threads(options.threads), m, [&](std::size_t e, unsigned) {
      const Eigen::Matrix<double, D, D> f = gradient_of(x, static_cast<Eigen::Index>(e)), r = closest_rotation<D>(f);
      if (rotations != nullptr) (*rotations)[e] = r;
      const double trace = (r.transpose() * f).trace() - D;
      energies[e] = data.geometry[e].volume * (mu * (f - r).squaredNorm() + 0.5 * lambda * trace * trace);
    }, 1024);
    double total = 0.0;
    for (double energy : energies) total += energy;
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
      const double m = data.mass[v];
      if (inertia_weight > 0.0) total += 0.5 * inertia_weight * m * (x.row(v) - predicted.row(v)).squaredNorm();
      if (options.gravity.size() == D) total -= m * x.row(v).dot(options.gravity);
      if (options.ground_normal.size() == D) {
        const double depth = options.ground_offset - x.row(v).dot(options.ground_normal);
        if (depth > 0.0) total += 0.5 * options.ground_stiffness * m * depth * depth;
      }
    }
    return total;
  }

  static constexpr int N = D * (D + 1);
  /// One element's share of the gradient and the Newton matrix.
  struct ElementTerms {
    Eigen::Matrix<double, D, D + 1> forces;  ///< column i: dE/dx_i
    Eigen::Matrix<double, N, N> matrix;      ///< d2E/dx2, vertex-major (i * D + axis)
  };

  /// The element's forces and, if `with_matrix`, its block of the Newton matrix `hessian`.
  /// `rotations`: value()'s at these `x`, or nullptr. `shift` (n x D, with the matrix; or nullptr):
  /// the forces get d2E/dx2 shift added, the gradient of the quadratic model at x + shift.
  void element_terms(const Eigen::MatrixXd& x, Eigen::Index e, bool with_matrix, NewtonMatrix hessian,
                     const Rotations* rotations, const Eigen::MatrixXd* shift, ElementTerms& out) const {
    using Square = Eigen::Matrix<double, D, D>;
    const double mu = options.material.mu(), lambda = options.material.lambda();
    const ElementGeometry<D>& g = data.geometry[static_cast<std::size_t>(e)];
    const Square f = gradient_of(x, e);
    // Signed SVD F = U diag(s) V^T with det(U V^T) = +1 (the last singular value negated for
    // an inverted F): R = U V^T is closest_rotation(F), S = V diag(s) V^T, tr S = sum s.
    // For det F > 0 (all but inverted elements) from the polar decomposition F = R S (the
    // scaled Newton iteration of closest_rotation, as the potential's value uses) and the
    // closed-form eigenvectors of the symmetric S: 2-3 times cheaper than the Jacobi SVD,
    // which was half of the assembly. The stress needs only R and tr S (exact to round-off);
    // the closed form's lesser accuracy on clustered s touches only the Newton matrix, whose
    // twist terms of equal s_k + s_l sum to the same matrix for any basis of the cluster.
    Square u, v, r;
    Eigen::Matrix<double, D, 1> s;
    double trace = 0.0;
    if (f.determinant() > 0.0) {
      r = rotations != nullptr ? (*rotations)[static_cast<std::size_t>(e)] : closest_rotation<D>(f);
      const Square rf = r.transpose() * f;
      Eigen::SelfAdjointEigenSolver<Square> eigen;
      eigen.computeDirect(0.5 * (rf + rf.transpose()));
      v = eigen.eigenvectors();
      s = eigen.eigenvalues();
      u = r * v;
      trace = rf.trace() - D;
    } else {
      const Eigen::JacobiSVD<Square> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
      u = svd.matrixU();
      v = svd.matrixV();
      s = svd.singularValues();
      if ((u * v.transpose()).determinant() < 0.0) {
        u.col(D - 1) *= -1.0;
        s[D - 1] *= -1.0;
      }
      r = u * v.transpose();
      trace = s.sum() - D;
    }
    const Square stress = 2.0 * mu * (f - r) + lambda * trace * r;  // first Piola-Kirchhoff
    out.forces = g.volume * stress * g.gradients.transpose();  // column i: dE/dx_i
    if (!with_matrix) return;
    // dP = 2 mu dF + lambda (R:dF) R + (lambda tr(S - I) - 2 mu) dR, and dR vanishes on the
    // dF that are symmetric in the (U, V) frame, while the twists Q_kl = U (e_k e_l^T - e_l
    // e_k^T) V^T / sqrt 2 are its eigenvectors with eigenvalue 2 / (s_k + s_l) (and R:Q_kl =
    // 0). So d2Psi/dF2 = 2 mu I + lambda r r^T + sum_kl c_kl q_kl q_kl^T with c_kl = (lambda
    // tr(S - I) - 2 mu) 2 / (s_k + s_l): eigenvalues 2 mu + c_kl on the twists (negative under
    // compression; the projected matrix clamps them to 0, Smith et al. 2019's analytic
    // projection), the others >= 2 mu (lambda >= 0). With dF =
    // sum_i dx_i b_i^T, a matrix A enters the element matrix as the vector (A b_i)_i.
    Eigen::Matrix<double, N, N>& k = out.matrix;
    k.setZero();
    const Eigen::Matrix<double, D + 1, D + 1> shape = g.gradients * g.gradients.transpose();
    for (int i = 0; i < D + 1; ++i)
      for (int j = 0; j < D + 1; ++j) k.template block<D, D>(i * D, j * D).diagonal().setConstant(2.0 * mu * shape(i, j));
    Eigen::Matrix<double, N, 1> column;
    for (int i = 0; i < D + 1; ++i) column.template segment<D>(i * D) = r * g.gradients.row(i).transpose();
    k.noalias() += lambda * column * column.transpose();
    if (hessian != NewtonMatrix::fixed_rotation) {
      const Eigen::Matrix<double, D, D + 1> vb = v.transpose() * g.gradients.transpose();
      for (int a = 0; a < D; ++a)
        for (int b = a + 1; b < D; ++b) {
          const double denominator = s[a] + s[b];
          // s_a + s_b <= 0 only in a strongly inverted element, where R jumps: keep R fixed there.
          if (!(denominator > 0.0)) continue;
          const double c = (lambda * trace - 2.0 * mu) * 2.0 / denominator;
          for (int i = 0; i < D + 1; ++i)
            column.template segment<D>(i * D) = (u.col(a) * vb(b, i) - u.col(b) * vb(a, i)) * std::sqrt(0.5);
          k.noalias() += (hessian == NewtonMatrix::exact ? c : std::max(c, -2.0 * mu)) * column * column.transpose();
        }
    }
    k *= g.volume;
    if (shift == nullptr) return;
    Eigen::Matrix<double, N, 1> moved;
    for (int i = 0; i < D + 1; ++i) moved.template segment<D>(i * D) = shift->row(data.rest.elements(e, i)).transpose();
    if (!moved.isZero(0.0)) out.forces.reshaped() += k * moved;
  }

  /// Gradient (n x D) and, when `pattern` is given, the Newton matrix `hessian` on the free
  /// degrees of freedom written into pattern->matrix's values (its sparsity is fixed per mesh, so
  /// the factorization's symbolic analysis is done once). `rotations`: value()'s at these `x`, or
  /// nullptr. `shift` (n x D, zero on the free vertices; with `pattern`, or nullptr): the free
  /// rows of the gradient are those of the quadratic model at x + shift, gradient(x) + d2E/dx2(x)
  /// shift (the linear prediction of minimize()).
  /// On options.threads threads, chunk by chunk of elements: the elements' terms in
  /// parallel, then each thread adds them into the rows and columns of its own range of vertices,
  /// in element order; so every entry is summed in the same order as on one thread, and the
  /// result does not depend on the thread count.
  void gradient_and_hessian(const Eigen::MatrixXd& x, HessianPattern* pattern, NewtonMatrix hessian,
                            Eigen::MatrixXd& gradient, const Rotations* rotations = nullptr,
                            const Eigen::MatrixXd* shift = nullptr) const {
    gradient.setZero(x.rows(), D);
    double* values = nullptr;
    if (pattern != nullptr) {
      pattern->matrix.coeffs().setZero();
      values = pattern->matrix.valuePtr();
    }
    using Square = Eigen::Matrix<double, D, D>;
    const unsigned threads = resolve_threads(options.threads);
    const Eigen::Index n = x.rows(), m = data.rest.element_count();
    // 4096 elements' terms are 4.7 MB in 3D: the chunk stays in cache between its two passes.
    constexpr Eigen::Index kChunk = 4096;
    std::vector<ElementTerms> terms(static_cast<std::size_t>(std::min(m, kChunk)));
    for (Eigen::Index begin = 0; begin < m; begin += kChunk) {
      const Eigen::Index count = std::min(m - begin, kChunk);
      parallel_for(threads, static_cast<std::size_t>(count), [&](std::size_t i, unsigned) {
        element_terms(x, begin + static_cast<Eigen::Index>(i), pattern != nullptr, hessian, rotations,
                      pattern != nullptr ? shift : nullptr, terms[i]);
      }, 256);
      parallel_for(threads, threads, [&](std::size_t w, unsigned) {
        const Eigen::Index low = n * static_cast<Eigen::Index>(w) / threads, high = n * static_cast<Eigen::Index>(w + 1) / threads;
        for (Eigen::Index i = 0; i < count; ++i) {
          const Eigen::Index e = begin + i;
          const ElementTerms& t = terms[static_cast<std::size_t>(i)];
          for (int j = 0; j < D + 1; ++j) {  // column vertex: its gradient row and its D matrix columns
            const Eigen::Index v = data.rest.elements(e, j);
            if (v < low || v >= high) continue;
            gradient.row(v) += t.forces.col(j).transpose();
            if (values == nullptr) continue;
            const int* slots = pattern->element_slots.data() + static_cast<std::size_t>(e) * N * N + static_cast<std::size_t>(j) * D * N;
            const double* column = t.matrix.data() + static_cast<std::ptrdiff_t>(j) * D * N;
            for (int q = 0; q < D * N; ++q)
              if (slots[q] >= 0) values[slots[q]] += column[q];
          }
        }
      }, 1);
    }
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
      const double m = data.mass[v];
      double diagonal = 0.0;
      if (inertia_weight > 0.0) {
        gradient.row(v) += inertia_weight * m * (x.row(v) - predicted.row(v));
        diagonal += inertia_weight * m;
      }
      if (options.gravity.size() == D) gradient.row(v) -= m * options.gravity.transpose();
      Square ground = Square::Zero();
      if (options.ground_normal.size() == D) {
        const double depth = options.ground_offset - x.row(v).dot(options.ground_normal);
        if (depth > 0.0) {
          gradient.row(v) -= options.ground_stiffness * m * depth * options.ground_normal.transpose();
          ground = options.ground_stiffness * m * options.ground_normal * options.ground_normal.transpose();
        }
      }
      if (pattern == nullptr) continue;
      const int* slots = pattern->vertex_slots.data() + static_cast<std::size_t>(v) * D * D;
      for (int q = 0; q < D * D; ++q)
        if (slots[q] >= 0) values[slots[q]] += ground(q % D, q / D) + (q % D == q / D ? diagonal : 0.0);
    }
  }
};

/// The sparsity of the Newton matrix on the free degrees of freedom (`dof` maps vertex * D +
/// axis to a free index, or -1; a vertex is fixed in all its axes or none), and where each
/// element's and vertex's entries go in its value array (column-major within the element's
/// D(D+1) square; -1 for a fixed row or column), so that assembly writes values in place, in
/// element order (deterministic), without triplets. Built from the vertex graph, D x D blocks
/// per neighbouring pair: the triplets of every element entry (12 M on the quintuple torus)
/// and a search per entry took 2 s, more than a factorization.
template <int D>
HessianPattern hessian_pattern(const SimplexMesh<D>& mesh, const std::vector<Eigen::Index>& dof, Eigen::Index free_count) {
  constexpr int N = D * (D + 1);
  const Eigen::Index n = mesh.vertex_count();
  const auto free_vertex = [&](Eigen::Index v) { return dof[static_cast<std::size_t>(v * D)] >= 0; };
  // Each vertex's neighbours (itself included), sorted: `first` / `neighbours` in CSR form.
  std::vector<std::vector<int>> lists(static_cast<std::size_t>(n));
  for (Eigen::Index v = 0; v < n; ++v) lists[static_cast<std::size_t>(v)].push_back(static_cast<int>(v));
  for (Eigen::Index e = 0; e < mesh.element_count(); ++e)
    for (int i = 0; i < D + 1; ++i)
      for (int j = 0; j < D + 1; ++j)
        if (i != j) lists[static_cast<std::size_t>(mesh.elements(e, i))].push_back(mesh.elements(e, j));
  std::vector<int> first(static_cast<std::size_t>(n) + 1, 0), neighbours, offset;  // offset: free dofs of the neighbours before
  for (Eigen::Index v = 0; v < n; ++v) {
    std::vector<int>& list = lists[static_cast<std::size_t>(v)];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    int free_before = 0;
    for (int w : list) {
      neighbours.push_back(w);
      offset.push_back(free_before);
      if (free_vertex(w)) free_before += D;
    }
    first[static_cast<std::size_t>(v) + 1] = static_cast<int>(neighbours.size());
    std::vector<int>().swap(list);
  }
  // Columns in free-dof order (vertex-major): column (v, a) holds the free rows of v's neighbours.
  std::vector<int> outer(static_cast<std::size_t>(free_count) + 1, 0), inner;
  for (Eigen::Index v = 0; v < n; ++v) {
    if (!free_vertex(v)) continue;
    for (int a = 0; a < D; ++a) {
      const Eigen::Index col = dof[static_cast<std::size_t>(v * D + a)];
      for (int k = first[static_cast<std::size_t>(v)]; k < first[static_cast<std::size_t>(v) + 1]; ++k)
        if (free_vertex(neighbours[static_cast<std::size_t>(k)]))
          for (int b = 0; b < D; ++b) inner.push_back(static_cast<int>(dof[static_cast<std::size_t>(neighbours[static_cast<std::size_t>(k)] * D + b)]));
      outer[static_cast<std::size_t>(col) + 1] = static_cast<int>(inner.size());
    }
  }
  HessianPattern pattern;
  const std::vector<double> zeros(inner.size(), 0.0);
  pattern.matrix = Eigen::Map<const Eigen::SparseMatrix<double>>(free_count, free_count, static_cast<Eigen::Index>(inner.size()),
                                                                 outer.data(), inner.data(), zeros.data());
  // Where row vertex w's block starts in column vertex v's list (an index into `neighbours`),
  // and the value index of entry (w, axis b; v, axis a); -1 for a fixed vertex.
  const auto block = [&](Eigen::Index w, Eigen::Index v) -> std::ptrdiff_t {
    if (!free_vertex(w) || !free_vertex(v)) return -1;
    const int* begin = neighbours.data() + first[static_cast<std::size_t>(v)];
    const int* end = neighbours.data() + first[static_cast<std::size_t>(v) + 1];
    return std::lower_bound(begin, end, static_cast<int>(w)) - neighbours.data();
  };
  const auto slot = [&](std::ptrdiff_t k, int b, Eigen::Index v, int a) -> int {
    if (k < 0) return -1;
    return outer[static_cast<std::size_t>(dof[static_cast<std::size_t>(v * D + a)])] + offset[static_cast<std::size_t>(k)] + b;
  };
  pattern.element_slots.resize(static_cast<std::size_t>(mesh.element_count()) * N * N);
  for (Eigen::Index e = 0; e < mesh.element_count(); ++e)
    for (int i = 0; i < D + 1; ++i)      // row vertex
      for (int j = 0; j < D + 1; ++j) {  // column vertex
        const std::ptrdiff_t k = block(mesh.elements(e, i), mesh.elements(e, j));
        for (int a = 0; a < D; ++a)    // column axis
          for (int b = 0; b < D; ++b)  // row axis
            pattern.element_slots[static_cast<std::size_t>(e) * N * N + static_cast<std::size_t>((j * D + a) * N + i * D + b)] =
                slot(k, b, mesh.elements(e, j), a);
      }
  pattern.vertex_slots.resize(static_cast<std::size_t>(n) * D * D);
  for (Eigen::Index v = 0; v < n; ++v) {
    const std::ptrdiff_t k = block(v, v);
    for (int q = 0; q < D * D; ++q) pattern.vertex_slots[static_cast<std::size_t>(v) * D * D + q] = slot(k, q % D, v, q / D);
  }
  return pattern;
}

/// y = A p for `a` symmetric with both triangles stored (column-major): y_j = column j . p, one
/// dot product per column, each summed in order: deterministic, and the same on any number of
/// threads (blocks of columns on `threads` threads).
void symmetric_product(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& p, Eigen::VectorXd& y, unsigned threads) {
  y.resize(a.cols());
  const int* outer = a.outerIndexPtr();
  const int* inner = a.innerIndexPtr();
  const double* values = a.valuePtr();
  parallel_blocks(threads, static_cast<std::size_t>(a.cols()), 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t j = begin; j < end; ++j) {
      double sum = 0.0;
      for (int k = outer[j]; k < outer[j + 1]; ++k) sum += values[k] * p[inner[k]];
      y[static_cast<Eigen::Index>(j)] = sum;
    }
  });
}

enum class PcgStatus { converged, negative_curvature, too_many_iterations };

/// Conjugate gradients on a x = b preconditioned by the factor `m` of a nearby matrix, from x =
/// 0, until |b - a x| <= tolerance |b|. Stops at a direction of non-positive curvature (a
/// indefinite there: its Newton step may not descend) or after `max_iterations`. Every iterate is a
/// descent direction for a positive definite a (b.x = x^T a x > 0 by the Galerkin property).
/// Written here rather than with Eigen's ConjugateGradient, which divides by a non-positive
/// curvature without saying so: that signal is what switches the step to the projected matrix.
PcgStatus preconditioned_cg(const Eigen::SparseMatrix<double>& a, const SparseCholesky& m, const Eigen::VectorXd& b,
                            double tolerance, int max_iterations, unsigned threads, Eigen::VectorXd& x, int& iterations) {
  x.setZero(b.size());
  iterations = 0;
  const double stop = tolerance * b.norm();
  if (b.norm() == 0.0) return PcgStatus::converged;
  Eigen::VectorXd r = b, z = m.solve(r).col(0), p = z, q;
  double rz = r.dot(z);
  while (iterations < max_iterations) {
    ++iterations;
    symmetric_product(a, p, q, threads);
    const double curvature = p.dot(q);
    if (!(curvature > 0.0)) return PcgStatus::negative_curvature;
    const double alpha = rz / curvature;
    x += alpha * p;
    r -= alpha * q;
    if (r.norm() <= stop) return PcgStatus::converged;
    z = m.solve(r).col(0);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return PcgStatus::too_many_iterations;
}

/// Adds the process's CPU time (all threads: the element loops run on several) from construction
/// to destruction to `seconds`.
class StageTimer {
 public:
  explicit StageTimer(double& seconds) : seconds_(seconds), start_(process_cpu_seconds()) {}
  ~StageTimer() { seconds_ += process_cpu_seconds() - start_; }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  double& seconds_;
  double start_;
};

}  // namespace

struct FemSolver::Impl {
  // What the pattern was built for: the elements and the free-dof numbering.
  Eigen::MatrixXi elements;
  std::vector<Eigen::Index> dof;
  HessianPattern pattern;
  SparseCholesky factor;
  bool has_factor = false;  ///< `factor` holds a successful numeric factorization (of some earlier matrix)
  int pcg_since_factor = 0;  ///< conjugate-gradient iterations preconditioned by it so far
};

FemSolver::FemSolver() : impl_(std::make_unique<Impl>()) {}
FemSolver::~FemSolver() = default;
FemSolver::FemSolver(FemSolver&&) noexcept = default;
FemSolver& FemSolver::operator=(FemSolver&&) noexcept = default;

namespace {

/// The free degrees of freedom of `data`: vertex * D + axis -> its index among them (vertex-major
/// order), or -1 for a fixed vertex's axes; `free_count` receives their number.
template <int D>
std::vector<Eigen::Index> free_dofs(const FemData<D>& data, Eigen::Index& free_count) {
  std::vector<Eigen::Index> dof(static_cast<std::size_t>(data.rest.vertex_count() * D), 0);
  for (Eigen::Index v : data.fixed)
    for (int a = 0; a < D; ++a) dof[static_cast<std::size_t>(v * D + a)] = -1;
  free_count = 0;
  for (Eigen::Index& d : dof)
    if (d == 0) d = free_count++;
    else d = -1;
  return dof;
}

/// One pattern, ordering and symbolic factorization per solver (a simulation): builds them
/// for `data`'s mesh and free degrees of freedom `dof` unless `solver` already holds them (the
/// mesh and the fixed set unchanged, or fem_prepare ran), timed in report.seconds.analysis.
template <int D>
void prepare(const FemData<D>& data, const std::vector<Eigen::Index>& dof, Eigen::Index free_count,
             FemSolver::Impl& solver, FemReport& report) {
  report.unknowns = free_count;
  if (solver.dof != dof || solver.elements.rows() != data.rest.elements.rows() ||
      solver.elements.cols() != data.rest.elements.cols() || solver.elements != data.rest.elements) {
    const StageTimer timer(report.seconds.analysis);
    solver.elements = data.rest.elements;
    solver.dof = dof;
    solver.pattern = hessian_pattern<D>(data.rest, dof, free_count);
    solver.factor.analyze(solver.pattern.matrix, FactorUse::factor_often);
    solver.has_factor = false;
  }
  report.nonzeros = solver.pattern.matrix.nonZeros();
}

template <int D>
FemReport minimize(const Potential<D>& potential, Eigen::MatrixXd& x, const Eigen::MatrixXd& fixed_targets,
                   FemSolver::Impl& solver) {
  const FemData<D>& data = potential.data;
  const FemOptions& options = potential.options;
  FemReport report;
  // The fixed vertices' motion in this solve: from where `x` has them (their previous positions
  // in statics, their free flight x_n + h v_n in dynamics) to the targets.
  const Eigen::MatrixXd start = x;
  Eigen::MatrixXd shift = Eigen::MatrixXd::Zero(x.rows(), D);
  for (std::size_t k = 0; k < data.fixed.size(); ++k) {
    x.row(data.fixed[k]) = fixed_targets.row(static_cast<Eigen::Index>(k));
    shift.row(data.fixed[k]) = x.row(data.fixed[k]) - start.row(data.fixed[k]);
  }
  Eigen::Index free_count = 0;
  const std::vector<Eigen::Index> dof = free_dofs(data, free_count);
  if (free_count == 0) {  // every vertex placed by the user: nothing to solve (nor to factor)
    report.converged = true;
    report.objective = potential.value(x);
    return report;
  }
  // CHOLMOD's supernodal numeric factorization when needed, on the solver's symbolic one.
  prepare(data, dof, free_count, solver, report);
  HessianPattern& pattern = solver.pattern;
  const auto factorize = [&] {
    const StageTimer timer(report.seconds.factorization);
    ++report.factorizations;
    solver.has_factor = solver.factor.factorize(pattern.matrix);
    solver.pcg_since_factor = 0;
    return solver.has_factor;
  };
  typename Potential<D>::Rotations rotations, trial_rotations;  // value()'s at x and at the trial
  bool predicting = false;  // the linear prediction below: the model at `start` moved by `shift`
  const auto assemble = [&](NewtonMatrix matrix, Eigen::MatrixXd& gradient) {
    const StageTimer timer(report.seconds.assembly);
    if (predicting) potential.gradient_and_hessian(start, &pattern, matrix, gradient, nullptr, &shift);
    else potential.gradient_and_hessian(x, &pattern, matrix, gradient, &rotations);
  };
  const auto free_rows = [&](const Eigen::MatrixXd& gradient) {  // -gradient on the free dofs
    Eigen::VectorXd rhs(free_count);
    for (std::size_t i = 0; i < dof.size(); ++i)
      if (dof[i] >= 0) rhs[dof[i]] = -gradient(static_cast<Eigen::Index>(i) / D, static_cast<Eigen::Index>(i) % D);
    return rhs;
  };
  // Solves the assembled Newton system `matrix` step = rhs (rhs = free_rows(gradient)) to the
  // relative residual `forcing`. First conjugate gradients on the exact matrix, preconditioned
  // by the last factorization (of this step's or an earlier step's matrix). Negative curvature
  // proves the exact matrix indefinite (compressed elements far from the minimum; at a minimum
  // it is semidefinite, so the last iterations use it); then the projected one, always positive
  // semidefinite. A factor that has cost as many preconditioned iterations as
  // max_pcg_iterations is replaced, like one on which a single solve needs that many (rent
  // until the rent paid equals the price: on the quintuple torus a factorization costs about 20
  // iterations). False: not even the fixed-rotation matrix could be factored.
  const auto solve = [&](NewtonMatrix& matrix, Eigen::MatrixXd& gradient, Eigen::VectorXd& rhs, double forcing,
                         Eigen::VectorXd& step) {
    bool solved = false;
    if (solver.has_factor && options.max_pcg_iterations > 0 && solver.pcg_since_factor < options.max_pcg_iterations) {
      for (;;) {
        int iterations = 0;
        PcgStatus status = PcgStatus::too_many_iterations;
        {
          const StageTimer timer(report.seconds.solve);
          status = preconditioned_cg(pattern.matrix, solver.factor, rhs, forcing, options.max_pcg_iterations,
                                      resolve_threads(options.threads), step, iterations);
        }
        report.pcg_iterations += iterations;
        solver.pcg_since_factor += iterations;
        solved = status == PcgStatus::converged;
        if (status != PcgStatus::negative_curvature || matrix != NewtonMatrix::exact) break;
        matrix = NewtonMatrix::projected;
        assemble(matrix, gradient);
        rhs = free_rows(gradient);
      }
    }
    if (!solved) {
      // The preconditioner is too far from this matrix (or there is none yet): factor it. A
      // failed Cholesky factorization proves it indefinite, and this iteration uses the projected
      // matrix, then, should that sum be singular, the fixed-rotation one.
      bool factored = factorize();
      while (!factored && matrix != NewtonMatrix::fixed_rotation) {
        matrix = matrix == NewtonMatrix::exact ? NewtonMatrix::projected : NewtonMatrix::fixed_rotation;
        assemble(matrix, gradient);
        rhs = free_rows(gradient);
        factored = factorize();
      }
      if (!factored) return false;
      const StageTimer timer(report.seconds.solve);
      step = solver.factor.solve(rhs).col(0);
    }
    return true;
  };

  Eigen::MatrixXd gradient;
  double objective = 0.0;
  {
    const StageTimer timer(report.seconds.line_search);
    objective = potential.value(x, &rotations);
  }
  // Linear prediction of a handle motion. Moved at once, the handles shear the layer of
  // elements next to them and leave the rest where it was, a poor start for Newton, which then
  // spends its first iterations spreading the motion. Instead, the free vertices first take the
  // motion the quadratic model of the potential at `start` gives them (linear elasticity about
  // it: the matrix K there, gradient g + K shift on the free rows), which spreads the motion over
  // the whole mesh in one solve with K, as a Newton iteration solves (PCG on the kept factor, or a
  // factorization). The result is only a start: it is kept if it lowers the potential, and Newton
  // then runs to the same stopping test.
  if (options.predict_fixed_motion && !shift.isZero(0.0)) {
    predicting = true;
    NewtonMatrix matrix = NewtonMatrix::exact;
    assemble(matrix, gradient);
    Eigen::VectorXd rhs = free_rows(gradient), step;
    const bool solved = gradient.allFinite() && solve(matrix, gradient, rhs, 0.1, step);
    predicting = false;
    if (solved) ++report.newton_iterations;  // a solve ran: counted as a Newton iteration
    // A factorization made for the prediction (no factor kept, as in a simulation's first step,
    // or the kept one used up) is of the matrix before the handles moved, which the Newton
    // iterations leave at once: preconditioned by it, the first step of the quintuple-torus jump
    // took 23 PCG iterations and still refactored at its end. The first Newton iteration
    // factors its own matrix instead (12 PCG iterations, and one Newton iteration fewer: its
    // step is exact); a kept factor that PCG used for the prediction stays under the rent rule.
    if (report.factorizations > 0) solver.has_factor = false;
    if (solved) {
      const StageTimer timer(report.seconds.line_search);
      Eigen::MatrixXd trial = x;
      for (std::size_t i = 0; i < dof.size(); ++i)
        if (dof[i] >= 0) trial(static_cast<Eigen::Index>(i) / D, static_cast<Eigen::Index>(i) % D) += step[dof[i]];
      const double trial_value = potential.value(trial, &trial_rotations);
      if (trial_value < objective) {
        x = trial;
        objective = trial_value;
        rotations.swap(trial_rotations);
      }
    }
  }
  const int predictions = report.newton_iterations;
  double first_residual = 0.0, previous_step = 0.0;
  for (int iteration = 0; iteration < options.max_newton_iterations; ++iteration) {
    NewtonMatrix matrix = NewtonMatrix::exact;
    assemble(matrix, gradient);
    if (!std::isfinite(objective) || !gradient.allFinite()) {  // forces or positions beyond doubles
      report.error = "the potential or its gradient is not finite (forces, displacements or the time step out of range)";
      break;
    }
    Eigen::VectorXd rhs = free_rows(gradient);
    if (iteration == 0) first_residual = rhs.norm();
    // The accuracy asked of a preconditioned solve (the forcing term of inexact Newton,
    // Eisenstat & Walker 1996): 0.1 far from the minimum, where a Newton step is only a
    // direction, then the gradient's reduction so far, which keeps the convergence
    // superlinear, down to pcg_tolerance.
    const double forcing = std::clamp(rhs.norm() / first_residual, std::min(options.pcg_tolerance, 0.1), 0.1);
    Eigen::VectorXd step;
    if (!solve(matrix, gradient, rhs, forcing, step)) {
      report.error = "the Newton matrix could not be factored";
      break;
    }
    const StageTimer timer(report.seconds.line_search);
    Eigen::MatrixXd direction = Eigen::MatrixXd::Zero(x.rows(), D);
    for (std::size_t i = 0; i < dof.size(); ++i)
      if (dof[i] >= 0) direction(static_cast<Eigen::Index>(i) / D, static_cast<Eigen::Index>(i) % D) = step[dof[i]];
    const double slope = -rhs.dot(step);  // directional derivative, < 0 for a descent direction
    // Backtracking (Armijo) on the true potential. Near the minimum a quadratically convergent
    // Newton step decreases the potential by less than the round-off of its sum over elements
    // (about 1e-14 of it): the test allows that much, else it would take a tiny damped step
    // there, which the step test below would mistake for convergence.
    const double round_off = 1e-12 * std::abs(objective);
    double alpha = 1.0, trial_value = 0.0;
    Eigen::MatrixXd trial;
    bool accepted = false;
    for (int halving = 0; halving < 40; ++halving, alpha *= 0.5) {
      trial = x + alpha * direction;
      trial_value = potential.value(trial, &trial_rotations);
      if (trial_value <= objective + 1e-4 * alpha * slope + round_off) {
        accepted = true;
        break;
      }
    }
    report.newton_iterations = predictions + iteration + 1;
    report.max_step = alpha * direction.rowwise().norm().maxCoeff();
    if (!accepted) {  // no decrease representable in doubles: at the minimum up to round-off
      report.converged = direction.rowwise().norm().maxCoeff() <= 1e3 * options.step_tolerance * data.edge_length;
      break;
    }
    x = trial;
    objective = trial_value;
    rotations.swap(trial_rotations);
    // Converged when this step, or what remains after it, is below the tolerance. What
    // remains is estimated from the contraction theta of the last two full steps: steps that
    // keep contracting by theta sum to step theta / (1 - theta) (Deuflhard 2004, 2.1.2), and
    // Newton's contraction only improves near the minimum. That saves the one iteration whose
    // only purpose is to show that a quadratically small step was already small.
    const double tolerance = options.step_tolerance * data.edge_length;
    const double theta = alpha == 1.0 && previous_step > 0.0 ? report.max_step / previous_step : 1.0;
    previous_step = alpha == 1.0 ? report.max_step : 0.0;
    if (report.max_step <= tolerance || (theta < 0.5 && report.max_step * theta / (1.0 - theta) <= tolerance)) {
      report.converged = true;
      break;
    }
  }
  report.objective = objective;
  return report;
}

}  // namespace

template <int D>
FemData<D> fem_precompute(const SimplexMesh<D>& rest, const std::vector<Eigen::Index>& fixed, const Material& material) {
  FemData<D> data;
  data.rest = rest;
  data.fixed = fixed;
  data.geometry.resize(static_cast<std::size_t>(rest.element_count()));
  for (Eigen::Index e = 0; e < rest.element_count(); ++e) {
    data.geometry[static_cast<std::size_t>(e)] = element_geometry<D>(rest.vertices, rest.elements, e);
    if (!(data.geometry[static_cast<std::size_t>(e)].volume > 0.0)) {
      data.error = "rest element " + std::to_string(e) + " is not positively oriented";
      return data;
    }
  }
  data.mass = material.density * lumped_mass<D>(rest);
  data.edge_length = mean_edge_length<D>(rest.vertices, rest.elements);
  return data;
}

template <int D>
FemReport fem_prepare(const FemData<D>& data, FemSolver& solver) {
  FemReport report;
  Eigen::Index free_count = 0;
  const std::vector<Eigen::Index> dof = free_dofs(data, free_count);
  if (free_count > 0) prepare(data, dof, free_count, solver.impl(), report);
  return report;
}

template <int D>
double elastic_energy(const FemData<D>& data, const Eigen::MatrixXd& positions, const Material& material) {
  FemOptions options;
  options.material = material;
  const Potential<D> potential{data, options};
  return potential.value(positions);  // no inertia, gravity or ground: elasticity alone
}

template <int D>
Eigen::MatrixXd elastic_forces(const FemData<D>& data, const Eigen::MatrixXd& positions, const Material& material) {
  FemOptions options;
  options.material = material;
  const Potential<D> potential{data, options};
  Eigen::MatrixXd gradient;
  potential.gradient_and_hessian(positions, nullptr, NewtonMatrix::fixed_rotation, gradient);  // no Hessian wanted
  return -gradient;
}

template <int D>
FemReport fem_step(const FemData<D>& data, FemState<D>& state, const Eigen::MatrixXd& fixed_targets,
                   const FemOptions& options, FemSolver* solver) {
  FemSolver own;
  const double h = options.time_step;
  Potential<D> potential{data, options, 1.0 / (h * h), state.positions + h * state.velocities};
  // Start from the predicted positions (free flight), the usual warm start.
  Eigen::MatrixXd x = potential.predicted;
  FemReport report = minimize(potential, x, fixed_targets, (solver != nullptr ? *solver : own).impl());
  state.velocities = (x - state.positions) / h;
  state.positions = x;
  return report;
}

template <int D>
FemReport fem_static(const FemData<D>& data, Eigen::MatrixXd& positions, const Eigen::MatrixXd& fixed_targets,
                     const FemOptions& options, FemSolver* solver) {
  {
    const std::vector<Eigen::Index> loose = unanchored_components(data.rest.vertex_count(), data.rest.elements, data.fixed);
    if (!loose.empty()) {
      FemReport report;
      report.error = "a connected part of the mesh (with vertex " + std::to_string(loose.front()) +
                     ") has no fixed vertex: its static position is undetermined";
      return report;
    }
  }
  const Potential<D> potential{data, options};
  FemSolver own;
  return minimize(potential, positions, fixed_targets, (solver != nullptr ? *solver : own).impl());
}

#define IMM_FEM_INSTANTIATE(D)                                                                                   \
  template FemData<D> fem_precompute<D>(const SimplexMesh<D>&, const std::vector<Eigen::Index>&, const Material&); \
  template FemReport fem_prepare<D>(const FemData<D>&, FemSolver&);                                              \
  template double elastic_energy<D>(const FemData<D>&, const Eigen::MatrixXd&, const Material&);                \
  template Eigen::MatrixXd elastic_forces<D>(const FemData<D>&, const Eigen::MatrixXd&, const Material&);       \
  template FemReport fem_step<D>(const FemData<D>&, FemState<D>&, const Eigen::MatrixXd&, const FemOptions&,       \
                                 FemSolver*);                                                                  \
  template FemReport fem_static<D>(const FemData<D>&, Eigen::MatrixXd&, const Eigen::MatrixXd&, const FemOptions&, \
                                   FemSolver*);
IMM_FEM_INSTANTIATE(2)
IMM_FEM_INSTANTIATE(3)
#undef IMM_FEM_INSTANTIATE

}  // namespace imm::deform
