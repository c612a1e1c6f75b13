#include "deform/weights.h"

#include <cmath>
#include <limits>

#include "deform/fixed_solver.h"

namespace imm::deform {

template <int D>
WeightsResult bounded_biharmonic_weights(const SimplexMesh<D>& mesh, const std::vector<std::vector<Eigen::Index>>& handles,
                                         const WeightsOptions& options) {
  WeightsResult result;
  const Eigen::Index n = mesh.vertex_count();
  std::vector<int> handle_of(static_cast<std::size_t>(n), -1);
  std::vector<Eigen::Index> all;
  for (std::size_t k = 0; k < handles.size(); ++k) {
    if (handles[k].empty()) {
      result.error = "handle " + std::to_string(k) + " selects no vertex";
      return result;
    }
    for (Eigen::Index v : handles[k]) {
      if (v < 0 || v >= n) {
        result.error = "handle " + std::to_string(k) + ": vertex " + std::to_string(v) + " out of range";
        return result;
      }
      if (handle_of[static_cast<std::size_t>(v)] >= 0) {
        result.error = "vertex " + std::to_string(v) + " is in handles " + std::to_string(handle_of[static_cast<std::size_t>(v)]) +
                       " and " + std::to_string(k);
        return result;
      }
      handle_of[static_cast<std::size_t>(v)] = static_cast<int>(k);
      all.push_back(v);
    }
  }
  const std::vector<Eigen::Index> loose = unanchored_components(n, mesh.elements, all);
  if (!loose.empty()) {
    result.error = "a connected part of the mesh (with vertex " + std::to_string(loose.front()) +
                   ") has no handle: its weights are undetermined";
    return result;
  }
  const Eigen::SparseMatrix<double> k = stiffness_matrix<D>(mesh);
  const Eigen::VectorXd mass = lumped_mass<D>(mesh);
  const Eigen::SparseMatrix<double> q = Eigen::SparseMatrix<double>(k.transpose() * mass.cwiseInverse().asDiagonal() * k);
  const Eigen::MatrixXd zero_rhs = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(handles.size()));
  // Round-off of one solve: weights are O(1), so a value within 1e-10 of a bound is on it.
  constexpr double kRoundOff = 1e-10;
  const double q_scale = q.diagonal().cwiseAbs().maxCoeff();

  // Warm start: the unconstrained biharmonic weights of every handle, one factorization and one
  // solve with a column per handle. Their bound violations are the first active sets. Its
  // fill-reducing ordering (of every non-handle vertex) is kept for the rounds: each round's
  // free block is a subset of these rows, and the ordering search (AMD, then METIS) would
  // otherwise cost a fifth of every round (BENCHMARKS.md, "BBW").
  Eigen::MatrixXd unconstrained;
  std::vector<Eigen::Index> order;
  {
    FixedSolver solver;
    if (!solver.compute(q, all, FactorUse::factor_often)) {
      result.error = solver.error();
      return result;
    }
    Eigen::MatrixXd values = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(all.size()), static_cast<Eigen::Index>(handles.size()));
    for (std::size_t i = 0; i < all.size(); ++i) values(static_cast<Eigen::Index>(i), handle_of[static_cast<std::size_t>(all[i])]) = 1.0;
    unconstrained = solver.solve(zero_rhs, values);
    order = solver.ordering();
  }

  result.weights.resize(n, static_cast<Eigen::Index>(handles.size()));
  for (std::size_t h = 0; h < handles.size(); ++h) {
    // Active set: 0 = free, -1 = held at 0, +1 = held at 1 (handles are always known).
    std::vector<signed char> active(static_cast<std::size_t>(n), 0);
    Eigen::VectorXd w = unconstrained.col(static_cast<Eigen::Index>(h));
    int rounds = 0;  // solutions of held sets (factorizations) after the warm start
    for (;;) {
      // The KKT conditions of the last solution w (the minimizer with the current set held):
      // bounds violated by free variables, and held variables whose multiplier has the wrong
      // sign ((Q w)_v >= 0 at a lower bound, <= 0 at an upper one); multipliers below round-off
      // of Q's scale are zero. Neither: w is the minimizer.
      std::vector<Eigen::Index> violated, wrong;
      const Eigen::VectorXd gradient = q * w;
      Eigen::Index worst = -1;
      double worst_value = kRoundOff * q_scale;
      for (Eigen::Index v = 0; v < n; ++v) {
        if (handle_of[static_cast<std::size_t>(v)] >= 0) continue;
        const signed char a = active[static_cast<std::size_t>(v)];
        if (a == 0) {
          if (w[v] < -kRoundOff || w[v] > 1.0 + kRoundOff) violated.push_back(v);
          continue;
        }
        const double value = a < 0 ? -gradient[v] : gradient[v];
        if (value > kRoundOff * q_scale) wrong.push_back(v);
        if (value > worst_value) worst = v, worst_value = value;
      }
      if (violated.empty() && wrong.empty()) break;  // KKT point: the minimizer
      if (rounds + 1 >= options.max_active_set_iterations) {
        result.error = "the active-set iteration for handle " + std::to_string(h) + " did not converge in " +
                       std::to_string(options.max_active_set_iterations) + " iterations";
        return result;
      }
      // Hold every violated bound and, in the first kBulkRounds rounds, release every
      // wrong-signed multiplier in the same round (the primal-dual active-set step of
      // Hintermueller, Ito & Kunisch 2002; libigl's active_set releases only at feasible points,
      // which takes two rounds per release). The rounds shrink an over-held set by its frontier:
      // the unconstrained solution violates the bounds on many more vertices than the minimizer
      // holds (quintuple torus: 13k held at first, 4k at the end), and only the frontier has
      // wrong-signed multipliers. After kBulkRounds rounds, the classic rule that cannot cycle:
      // release only at a feasible point, and only the most wrong multiplier.
      constexpr int kBulkRounds = 100;
      for (Eigen::Index v : violated) active[static_cast<std::size_t>(v)] = w[v] < 0.0 ? -1 : 1;
      if (rounds < kBulkRounds)
        for (Eigen::Index v : wrong) active[static_cast<std::size_t>(v)] = 0;
      else if (violated.empty())
        active[static_cast<std::size_t>(worst)] = 0;
      ++rounds;
      std::vector<Eigen::Index> known = all;
      for (Eigen::Index v = 0; v < n; ++v)
        if (active[static_cast<std::size_t>(v)] != 0) known.push_back(v);
      Eigen::MatrixXd values(static_cast<Eigen::Index>(known.size()), 1);
      for (std::size_t i = 0; i < known.size(); ++i) {
        const Eigen::Index v = known[i];
        const int owner = handle_of[static_cast<std::size_t>(v)];
        values(static_cast<Eigen::Index>(i), 0) =
            owner >= 0 ? (owner == static_cast<int>(h) ? 1.0 : 0.0) : (active[static_cast<std::size_t>(v)] > 0 ? 1.0 : 0.0);
      }
      FixedSolver solver;
      if (!solver.compute(q, known, FactorUse::factor_often, order)) {
        result.error = solver.error();
        return result;
      }
      w = solver.solve(zero_rhs.leftCols(1), values).col(0);
    }
    result.active_set_iterations.push_back(rounds + 1);
    result.weights.col(static_cast<Eigen::Index>(h)) = w.cwiseMax(0.0).cwiseMin(1.0);  // the round-off only
  }
  const Eigen::VectorXd sums = result.weights.rowwise().sum();
  for (Eigen::Index v = 0; v < n; ++v) {
    if (!(sums[v] > 0.0)) {
      result.error = "every weight is zero at vertex " + std::to_string(v);
      return result;
    }
    result.weights.row(v) /= sums[v];
  }
  return result;
}

template <int D>
Eigen::VectorXd heat_geodesic(const SimplexMesh<D>& mesh, const std::vector<Eigen::Index>& sources, double time_factor) {
  const Eigen::Index n = mesh.vertex_count();
  const double h = mean_edge_length<D>(mesh.vertices, mesh.elements);
  const double t = time_factor * h * h;
  const Eigen::SparseMatrix<double> k = stiffness_matrix<D>(mesh);
  const Eigen::VectorXd mass = lumped_mass<D>(mesh);
  // Parts without a source are solved with one vertex pinned and reported as +infinity.
  int count = 0;
  const std::vector<int> component = vertex_components(n, mesh.elements, count);
  std::vector<char> reached(static_cast<std::size_t>(count), 0);
  for (Eigen::Index s : sources) reached[static_cast<std::size_t>(component[static_cast<std::size_t>(s)])] = 1;
  const std::vector<Eigen::Index> loose = unanchored_components(n, mesh.elements, sources);

  // 1. Heat: (M + t K) u = delta_sources (u = 0 pinned on unreached parts).
  Eigen::SparseMatrix<double> heat = t * k;
  for (Eigen::Index v = 0; v < n; ++v) heat.coeffRef(v, v) += mass[v];
  Eigen::MatrixXd delta = Eigen::MatrixXd::Zero(n, 1);
  for (Eigen::Index s : sources) delta(s, 0) = 1.0;
  FixedSolver heat_solver;
  heat_solver.compute(heat, {});
  const Eigen::VectorXd u = heat_solver.solve(delta, Eigen::MatrixXd(0, 1)).col(0);

  // 2. X = -grad u / |grad u| per element; 3. divergence: rhs_i = sum_e vol_e b_i . X_e.
  Eigen::MatrixXd divergence = Eigen::MatrixXd::Zero(n, 1);
  for (Eigen::Index e = 0; e < mesh.element_count(); ++e) {
    const ElementGeometry<D> g = element_geometry<D>(mesh.vertices, mesh.elements, e);
    Eigen::Matrix<double, 1, D> gradient = Eigen::Matrix<double, 1, D>::Zero();
    for (int i = 0; i < D + 1; ++i) gradient += u[mesh.elements(e, i)] * g.gradients.row(i);
    const double norm = gradient.norm();
    if (!(norm > 0.0)) continue;
    const Eigen::Matrix<double, 1, D> field = -gradient / norm;
    for (int i = 0; i < D + 1; ++i) divergence(mesh.elements(e, i), 0) += std::abs(g.volume) * g.gradients.row(i).dot(field);
  }
  // 4. K phi = div X (the least-squares fit of grad phi to X), phi = 0 at the sources.
  std::vector<Eigen::Index> known = sources;
  known.insert(known.end(), loose.begin(), loose.end());
  FixedSolver poisson;
  poisson.compute(k, known);
  Eigen::VectorXd phi = poisson.solve(divergence, Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(known.size()), 1)).col(0);
  for (Eigen::Index v = 0; v < n; ++v)
    if (!reached[static_cast<std::size_t>(component[static_cast<std::size_t>(v)])]) phi[v] = std::numeric_limits<double>::infinity();
  return phi;
}

#define IMM_WEIGHTS_INSTANTIATE(D)                                                                           \
  template WeightsResult bounded_biharmonic_weights<D>(const SimplexMesh<D>&,                               \
                                                       const std::vector<std::vector<Eigen::Index>>&,        \
                                                       const WeightsOptions&);                               \
  template Eigen::VectorXd heat_geodesic<D>(const SimplexMesh<D>&, const std::vector<Eigen::Index>&, double);
IMM_WEIGHTS_INSTANTIATE(2)
IMM_WEIGHTS_INSTANTIATE(3)
#undef IMM_WEIGHTS_INSTANTIATE

}  // namespace imm::deform
