// Finite-element elasticity on simplices (paper §8: the drop, sway and mouth examples), in the
// Vega FEM split: a material model (energy, first Piola-Kirchhoff stress and stiffness of one
// element) and an integrator (implicit Euler as the minimization of the incremental potential,
// Newton with a backtracking line search; or statics, the same minimization without inertia).
// One element loop for triangles (D = 2) and tetrahedra (D = 3).
//
// Material: co-rotational linear elasticity (Müller & Gross 2004; the "corotated" energy of
// Stomakhin et al. 2012 with the trace term), Psi(F) = mu ||F - R||^2 + lambda/2 tr(R^T F - I)^2,
// R the rotation of the polar decomposition of F. It is rotation invariant (so momentum and
// angular momentum are conserved) and defined for inverted elements (R is a proper rotation).
// Newton uses its exact Hessian (with the change of R, from the signed SVD of F), which converges
// quadratically (about 6 iterations per step instead of 50 with R held fixed); where that matrix
// is indefinite (compressed elements, far from the minimum) a failed Cholesky factorization says
// so and the iteration uses it with each element's negative twist eigenvalues clamped to 0
// (Smith et al. 2019), positive semidefinite: every Newton direction descends, and the line
// search works on the true energy.
//
// Solving the Newton systems: the numeric Cholesky factorization is the dominant cost (0.3-0.5 s
// for the 57k unknowns of the quintuple torus), and the Newton matrix changes slowly, between
// Newton iterations and between time steps. So the last factorization is kept (in a FemSolver,
// with the sparsity pattern and the symbolic analysis, across the steps of a simulation) and
// preconditions conjugate gradients on the current exact matrix; a new factorization only when
// that needs more than `max_pcg_iterations` or meets negative curvature (BENCHMARKS.md, "FEM").
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "deform/simplex_mesh.h"

namespace imm::deform {

struct Material {
  double youngs_modulus = 1e4;
  double poisson_ratio = 0.3;
  double density = 1.0;
  [[nodiscard]] double mu() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
  [[nodiscard]] double lambda() const {
    return youngs_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
  }
};

struct FemOptions {
  Material material;
  double time_step = 1.0 / 60.0;
  /// Gravity acceleration, D entries (empty: none).
  Eigen::VectorXd gravity;
  /// Ground: the half-space {x : ground_normal . x >= ground_offset}, kept by a penalty
  /// ground_stiffness/2 * m_i * depth^2 per vertex below it (empty normal: no ground).
  Eigen::VectorXd ground_normal;
  double ground_offset = 0.0;
  double ground_stiffness = 1e4;
  int max_newton_iterations = 50;
  /// Newton stops when the largest step of a vertex is below this fraction of the mean edge
  /// length, or when the distance left after it, estimated from the contraction of the last two
  /// full steps (step theta / (1 - theta), theta = step / previous step < 1/2), is.
  double step_tolerance = 1e-9;
  /// Conjugate-gradient iterations allowed per Newton iteration, preconditioned by the last
  /// numeric factorization, before the Newton matrix is factored anew. 0: factor every Newton
  /// iteration and solve directly (the reference the preconditioned path is tested against).
  int max_pcg_iterations = 20;
  /// A preconditioned Newton step is solved to a residual of at most 0.1 |gradient|, tightened as
  /// the gradient falls, down to pcg_tolerance |gradient|: the step is then the Newton step to
  /// about that relative accuracy, so the step test above keeps its meaning.
  double pcg_tolerance = 1e-4;
  /// When the fixed vertices move (their targets differ from where the step starts them: their
  /// previous positions in statics, x_n + h v_n in dynamics), first give the free vertices the
  /// motion that the linearization of the potential there predicts (one solve with the Newton
  /// matrix there, counted as a Newton iteration), kept if it lowers the potential. Newton
  /// converges to the same stopping test from there, in fewer iterations after a sudden handle
  /// jump (BENCHMARKS.md, "FEM"). false: start from the targets alone.
  bool predict_fixed_motion = true;
  /// Threads for the element loops (0 = all cores). The results do not depend on it: every
  /// sum is taken in element order.
  unsigned threads = 0;
};

template <int D>
struct FemData {
  SimplexMesh<D> rest;
  std::vector<ElementGeometry<D>> geometry;
  Eigen::VectorXd mass;              ///< lumped, density * volume share
  std::vector<Eigen::Index> fixed;   ///< vertices moved by the user (targets per step)
  double edge_length = 0.0;          ///< mean rest edge length (the step tolerance's unit)
  std::string error;
  [[nodiscard]] bool ok() const { return error.empty(); }
};

template <int D>
struct FemState {
  Eigen::MatrixXd positions;   ///< n x D
  Eigen::MatrixXd velocities;  ///< n x D
};

/// CPU seconds per stage of one solve (the process's: all threads).
struct FemSeconds {
  double analysis = 0.0;       ///< sparsity pattern and symbolic factorization (once per FemSolver: fem_prepare's, or the first step's)
  double assembly = 0.0;       ///< per-element SVDs, gradient and Newton matrix
  double factorization = 0.0;  ///< numeric factorizations, failed ones included
  double solve = 0.0;          ///< triangular solves and conjugate gradients
  double line_search = 0.0;    ///< potential evaluations
};

struct FemReport {
  int newton_iterations = 0;   ///< the linear prediction's solve, when it ran (FemOptions::predict_fixed_motion), counted as one
  bool converged = false;
  double objective = 0.0;       ///< the minimized potential at the result
  double max_step = 0.0;        ///< the last Newton step (largest vertex displacement)
  std::string error;            ///< non-empty: not solved (a singular static problem)
  int factorizations = 0;       ///< numeric factorizations (failed ones, of indefinite matrices, included)
  int pcg_iterations = 0;       ///< preconditioned conjugate-gradient iterations, all Newton iterations
  Eigen::Index unknowns = 0;    ///< the Newton system's size (free degrees of freedom)
  Eigen::Index nonzeros = 0;    ///< its stored entries (both triangles)
  FemSeconds seconds;
};

/// What consecutive solves on one FemData keep (fem_step / fem_static): the Newton matrix's
/// sparsity pattern, its symbolic analysis and the last numeric factorization, the
/// preconditioner of later Newton systems. Given to every step of a simulation, it saves the
/// analysis and most factorizations; a solver given a different mesh or fixed set starts over,
/// so it only ever changes the cost and the round-off, not what a step converges to.
class FemSolver {
 public:
  FemSolver();
  ~FemSolver();
  FemSolver(FemSolver&&) noexcept;
  FemSolver& operator=(FemSolver&&) noexcept;
  struct Impl;  ///< deform/fem.cpp's
  [[nodiscard]] Impl& impl() { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

/// @pre rest elements positively oriented (else `error`).
template <int D>
FemData<D> fem_precompute(const SimplexMesh<D>& rest, const std::vector<Eigen::Index>& fixed, const Material& material);

/// Sets `solver` up for the steps of a simulation on `data` (its mesh and fixed set): the Newton
/// matrix's sparsity pattern, its fill-reducing ordering and symbolic factorization, which the
/// first fem_step / fem_static given `solver` would otherwise do (and report in its
/// seconds.analysis). They depend on neither the positions nor the options, so a simulation can
/// pay for them before its first step; the returned report says what they cost
/// (seconds.analysis, unknowns, nonzeros; nothing else is solved).
template <int D>
FemReport fem_prepare(const FemData<D>& data, FemSolver& solver);

/// Elastic energy sum_e vol_e Psi(F_e) at `positions`.
template <int D>
double elastic_energy(const FemData<D>& data, const Eigen::MatrixXd& positions, const Material& material);

/// Elastic forces -dE/dx at `positions` (n x D).
template <int D>
Eigen::MatrixXd elastic_forces(const FemData<D>& data, const Eigen::MatrixXd& positions, const Material& material);

/// One implicit Euler step of length options.time_step: the fixed vertices go to
/// `fixed_targets` (|fixed| x D, in `fixed` order), the others minimize
/// 1/(2h^2) |x - x_n - h v_n|_M^2 + E(x) - m g.x + ground penalty; velocities = (x - x_n)/h.
/// `solver`: kept between the steps of one simulation (nullptr: a fresh one for this step).
template <int D>
FemReport fem_step(const FemData<D>& data, FemState<D>& state, const Eigen::MatrixXd& fixed_targets,
                   const FemOptions& options, FemSolver* solver = nullptr);

/// Static equilibrium under the fixed targets, gravity and ground (no inertia), from `positions`.
template <int D>
FemReport fem_static(const FemData<D>& data, Eigen::MatrixXd& positions, const Eigen::MatrixXd& fixed_targets,
                     const FemOptions& options, FemSolver* solver = nullptr);

}  // namespace imm::deform
