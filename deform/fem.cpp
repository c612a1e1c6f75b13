#include "deform/fem.h"

#include <cmath>

#include "deform/rotation.h"
#include "deform/sparse_cholesky.h"

namespace imm::deform {

namespace {

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

  [[nodiscard]] double value(const Eigen::MatrixXd& x) const {
    const double mu = options.material.mu(), lambda = options.material.lambda();
    double total = 0.0;
    for (Eigen::Index e = 0; e < data.rest.element_count(); ++e) {
      const Eigen::Matrix<double, D, D> f = gradient_of(x, e), r = closest_rotation<D>(f);
      const double trace = (r.transpose() * f).trace() - D;
      total += data.geometry[static_cast<std::size_t>(e)].volume * (mu * (f - r).squaredNorm() + 0.5 * lambda * trace * trace);
    }
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

  /// Gradient (n x D) and the Newton matrix on the free degrees of freedom (`dof` maps
  /// vertex * D + axis to a free index, or -1).
  void gradient_and_hessian(const Eigen::MatrixXd& x, const std::vector<Eigen::Index>& dof, Eigen::MatrixXd& gradient,
                            Eigen::SparseMatrix<double>& hessian) const {
    const double mu = options.material.mu(), lambda = options.material.lambda();
    gradient.setZero(x.rows(), D);
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(static_cast<std::size_t>(data.rest.element_count()) * (D + 1) * (D + 1) * D * D +
                     static_cast<std::size_t>(x.rows()) * D);
    for (Eigen::Index e = 0; e < data.rest.element_count(); ++e) {
      const ElementGeometry<D>& g = data.geometry[static_cast<std::size_t>(e)];
      const Eigen::Matrix<double, D, D> f = gradient_of(x, e), r = closest_rotation<D>(f);
      const double trace = (r.transpose() * f).trace() - D;
      const Eigen::Matrix<double, D, D> stress = 2.0 * mu * (f - r) + lambda * trace * r;  // first Piola-Kirchhoff
      const Eigen::Matrix<double, D, D + 1> forces = g.volume * stress * g.gradients.transpose();  // column i: dE/dx_i
      const Eigen::Matrix<double, D, D + 1> rotated = r * g.gradients.transpose();                // column i: R b_i
      for (int i = 0; i < D + 1; ++i) {
        const Eigen::Index vi = data.rest.elements(e, i);
        gradient.row(vi) += forces.col(i).transpose();
        for (int j = 0; j < D + 1; ++j) {
          const Eigen::Index vj = data.rest.elements(e, j);
          const double shape = 2.0 * mu * g.gradients.row(i).dot(g.gradients.row(j));
          const Eigen::Matrix<double, D, D> block =
              g.volume * (shape * Eigen::Matrix<double, D, D>::Identity() + lambda * rotated.col(i) * rotated.col(j).transpose());
          for (int a = 0; a < D; ++a) {
            const Eigen::Index row = dof[static_cast<std::size_t>(vi * D + a)];
            if (row < 0) continue;
            for (int b = 0; b < D; ++b) {
              const Eigen::Index col = dof[static_cast<std::size_t>(vj * D + b)];
              if (col >= 0) triplets.emplace_back(row, col, block(a, b));
            }
          }
        }
      }
    }
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
      const double m = data.mass[v];
      double diagonal = 0.0;
      if (inertia_weight > 0.0) {
        gradient.row(v) += inertia_weight * m * (x.row(v) - predicted.row(v));
        diagonal += inertia_weight * m;
      }
      if (options.gravity.size() == D) gradient.row(v) -= m * options.gravity.transpose();
      Eigen::Matrix<double, D, D> ground = Eigen::Matrix<double, D, D>::Zero();
      if (options.ground_normal.size() == D) {
        const double depth = options.ground_offset - x.row(v).dot(options.ground_normal);
        if (depth > 0.0) {
          gradient.row(v) -= options.ground_stiffness * m * depth * options.ground_normal.transpose();
          ground = options.ground_stiffness * m * options.ground_normal * options.ground_normal.transpose();
        }
      }
      for (int a = 0; a < D; ++a) {
        const Eigen::Index row = dof[static_cast<std::size_t>(v * D + a)];
        if (row < 0) continue;
        for (int b = 0; b < D; ++b) {
          const Eigen::Index col = dof[static_cast<std::size_t>(v * D + b)];
          const double value = ground(a, b) + (a == b ? diagonal : 0.0);
          if (col >= 0 && value != 0.0) triplets.emplace_back(row, col, value);
        }
      }
    }
    hessian.setFromTriplets(triplets.begin(), triplets.end());
  }
};

template <int D>
FemReport minimize(const Potential<D>& potential, Eigen::MatrixXd& x, const Eigen::MatrixXd& fixed_targets) {
  const FemData<D>& data = potential.data;
  const FemOptions& options = potential.options;
  FemReport report;
  for (std::size_t k = 0; k < data.fixed.size(); ++k) x.row(data.fixed[k]) = fixed_targets.row(static_cast<Eigen::Index>(k));
  std::vector<Eigen::Index> dof(static_cast<std::size_t>(x.rows() * D), 0);
  for (Eigen::Index v : data.fixed)
    for (int a = 0; a < D; ++a) dof[static_cast<std::size_t>(v * D + a)] = -1;
  Eigen::Index free_count = 0;
  for (Eigen::Index& d : dof)
    if (d == 0) d = free_count++;
    else d = -1;
  // (the loop above numbers the free degrees of freedom in vertex-major order)

  Eigen::MatrixXd gradient;
  Eigen::SparseMatrix<double> hessian(free_count, free_count);
  SparseCholesky factor;
  double objective = potential.value(x);
  for (int iteration = 0; iteration < options.max_newton_iterations; ++iteration) {
    potential.gradient_and_hessian(x, dof, gradient, hessian);
    if (!std::isfinite(objective) || !gradient.allFinite()) {  // forces or positions beyond doubles
      report.error = "the potential or its gradient is not finite (forces, displacements or the time step out of range)";
      break;
    }
    // A new matrix every iteration: CHOLMOD's supernodal factorization (BENCHMARKS.md).
    if (!factor.compute(hessian, FactorUse::factor_often)) {
      report.error = "the Newton matrix could not be factored";
      break;
    }
    Eigen::VectorXd rhs(free_count);
    for (std::size_t i = 0; i < dof.size(); ++i)
      if (dof[i] >= 0) rhs[dof[i]] = -gradient(static_cast<Eigen::Index>(i) / D, static_cast<Eigen::Index>(i) % D);
    const Eigen::VectorXd step = factor.solve(rhs).col(0);
    Eigen::MatrixXd direction = Eigen::MatrixXd::Zero(x.rows(), D);
    for (std::size_t i = 0; i < dof.size(); ++i)
      if (dof[i] >= 0) direction(static_cast<Eigen::Index>(i) / D, static_cast<Eigen::Index>(i) % D) = step[dof[i]];
    const double slope = -rhs.dot(step);  // directional derivative, < 0 for a descent direction
    // Backtracking (Armijo) on the true potential.
    double alpha = 1.0, trial_value = 0.0;
    Eigen::MatrixXd trial;
    bool accepted = false;
    for (int halving = 0; halving < 40; ++halving, alpha *= 0.5) {
      trial = x + alpha * direction;
      trial_value = potential.value(trial);
      if (trial_value <= objective + 1e-4 * alpha * slope) {
        accepted = true;
        break;
      }
    }
    report.newton_iterations = iteration + 1;
    report.max_step = alpha * direction.rowwise().norm().maxCoeff();
    if (!accepted) {  // no decrease representable in doubles: at the minimum up to round-off
      report.converged = direction.rowwise().norm().maxCoeff() <= 1e3 * options.step_tolerance * data.edge_length;
      break;
    }
    x = trial;
    objective = trial_value;
    if (report.max_step <= options.step_tolerance * data.edge_length) {
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
  std::vector<Eigen::Index> dof(static_cast<std::size_t>(positions.rows() * D), -1);  // no Hessian wanted
  Eigen::MatrixXd gradient;
  Eigen::SparseMatrix<double> unused(0, 0);
  potential.gradient_and_hessian(positions, dof, gradient, unused);
  return -gradient;
}

template <int D>
FemReport fem_step(const FemData<D>& data, FemState<D>& state, const Eigen::MatrixXd& fixed_targets,
                   const FemOptions& options) {
  const double h = options.time_step;
  Potential<D> potential{data, options, 1.0 / (h * h), state.positions + h * state.velocities};
  Eigen::MatrixXd x = state.positions;
  // Start from the predicted positions (free flight), the usual warm start.
  x = potential.predicted;
  FemReport report = minimize(potential, x, fixed_targets);
  state.velocities = (x - state.positions) / h;
  state.positions = x;
  return report;
}

template <int D>
FemReport fem_static(const FemData<D>& data, Eigen::MatrixXd& positions, const Eigen::MatrixXd& fixed_targets,
                     const FemOptions& options) {
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
  return minimize(potential, positions, fixed_targets);
}

#define IMM_FEM_INSTANTIATE(D)                                                                                   \
  template FemData<D> fem_precompute<D>(const SimplexMesh<D>&, const std::vector<Eigen::Index>&, const Material&); \
  template double elastic_energy<D>(const FemData<D>&, const Eigen::MatrixXd&, const Material&);                \
  template Eigen::MatrixXd elastic_forces<D>(const FemData<D>&, const Eigen::MatrixXd&, const Material&);       \
  template FemReport fem_step<D>(const FemData<D>&, FemState<D>&, const Eigen::MatrixXd&, const FemOptions&);    \
  template FemReport fem_static<D>(const FemData<D>&, Eigen::MatrixXd&, const Eigen::MatrixXd&, const FemOptions&);
IMM_FEM_INSTANTIATE(2)
IMM_FEM_INSTANTIATE(3)
#undef IMM_FEM_INSTANTIATE

}  // namespace imm::deform
