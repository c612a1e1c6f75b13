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
// search works on the true energy. The sparsity is analyzed once per step, factored per iteration.
#pragma once

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
  /// Newton stops when the largest step of a vertex is below this fraction of the mean edge length.
  double step_tolerance = 1e-9;
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

struct FemReport {
  int newton_iterations = 0;
  bool converged = false;
  double objective = 0.0;       ///< the minimized potential at the result
  double max_step = 0.0;        ///< the last Newton step (largest vertex displacement)
  std::string error;            ///< non-empty: not solved (a singular static problem)
};

/// @pre rest elements positively oriented (else `error`).
template <int D>
FemData<D> fem_precompute(const SimplexMesh<D>& rest, const std::vector<Eigen::Index>& fixed, const Material& material);

/// Elastic energy sum_e vol_e Psi(F_e) at `positions`.
template <int D>
double elastic_energy(const FemData<D>& data, const Eigen::MatrixXd& positions, const Material& material);

/// Elastic forces -dE/dx at `positions` (n x D).
template <int D>
Eigen::MatrixXd elastic_forces(const FemData<D>& data, const Eigen::MatrixXd& positions, const Material& material);

/// One implicit Euler step of length options.time_step: the fixed vertices go to
/// `fixed_targets` (|fixed| x D, in `fixed` order), the others minimize
/// 1/(2h^2) |x - x_n - h v_n|_M^2 + E(x) - m g.x + ground penalty; velocities = (x - x_n)/h.
template <int D>
FemReport fem_step(const FemData<D>& data, FemState<D>& state, const Eigen::MatrixXd& fixed_targets,
                   const FemOptions& options);

/// Static equilibrium under the fixed targets, gravity and ground (no inertia), from `positions`.
template <int D>
FemReport fem_static(const FemData<D>& data, Eigen::MatrixXd& positions, const Eigen::MatrixXd& fixed_targets,
                     const FemOptions& options);

}  // namespace imm::deform
