#include "deform/arap.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "deform/rotation.h"

namespace imm::deform {

namespace {

template <int D>
Eigen::Matrix<double, D, D> deformation_gradient(const ArapData<D>& data, const Eigen::MatrixXd& positions,
                                                 Eigen::Index e) {
  Eigen::Matrix<double, D + 1, D> corners;
  for (int i = 0; i < D + 1; ++i) corners.row(i) = positions.row(data.rest.elements(e, i));
  return corners.transpose() * data.geometry[static_cast<std::size_t>(e)].gradients;
}

}  // namespace

template <int D>
ArapData<D> arap_precompute(const SimplexMesh<D>& rest, const std::vector<Eigen::Index>& handles) {
  ArapData<D> data;
  data.rest = rest;
  data.handles = handles;
  data.geometry.resize(static_cast<std::size_t>(rest.element_count()));
  for (Eigen::Index e = 0; e < rest.element_count(); ++e) {
    data.geometry[static_cast<std::size_t>(e)] = element_geometry<D>(rest.vertices, rest.elements, e);
    if (!(data.geometry[static_cast<std::size_t>(e)].volume > 0.0)) {
      data.error = "rest element " + std::to_string(e) + " is not positively oriented (volume " +
                   std::to_string(data.geometry[static_cast<std::size_t>(e)].volume) + ")";
      return data;
    }
  }
  data.edge_length = mean_edge_length<D>(rest.vertices, rest.elements);
  for (const ElementGeometry<D>& g : data.geometry) data.volume += g.volume;
  data.pinned = unanchored_components(rest.vertex_count(), rest.elements, handles);
  std::vector<Eigen::Index> known = handles;
  known.insert(known.end(), data.pinned.begin(), data.pinned.end());
  if (!data.solver.compute(stiffness_matrix<D>(rest), known)) data.error = data.solver.error();
  return data;
}

template <int D>
double arap_energy(const ArapData<D>& data, const Eigen::MatrixXd& positions) {
  double energy = 0.0;
  for (Eigen::Index e = 0; e < data.rest.element_count(); ++e) {
    const Eigen::Matrix<double, D, D> f = deformation_gradient(data, positions, e);
    energy += data.geometry[static_cast<std::size_t>(e)].volume * (f - closest_rotation<D>(f)).squaredNorm();
  }
  return energy;
}

namespace {

/// The local step at `positions`: per element the closest rotation (into `rotations`), and the
/// energy sum_e vol_e ||F_e - R_e||^2 of `positions`, which the same rotations give for free.
/// Elements are independent: `threads` workers, each writing its own elements; the energy is
/// summed afterwards in element order, so the result does not depend on the thread count.
template <int D>
double local_step(const ArapData<D>& data, const Eigen::MatrixXd& positions, unsigned threads,
                  std::vector<Eigen::Matrix<double, D, D>>& rotations, std::vector<double>& energies) {
  const auto m = static_cast<std::size_t>(data.rest.element_count());
  rotations.resize(m);
  energies.resize(m);
  parallel_for(
      threads, m,
      [&](std::size_t e, unsigned /*worker*/) {
        const Eigen::Matrix<double, D, D> f = deformation_gradient(data, positions, static_cast<Eigen::Index>(e));
        rotations[e] = closest_rotation<D>(f);
        energies[e] = data.geometry[e].volume * (f - rotations[e]).squaredNorm();
      },
      1024);
  double energy = 0.0;
  for (double v : energies) energy += v;
  return energy;
}

}  // namespace

template <int D>
ArapReport arap_solve(const ArapData<D>& data, const Eigen::MatrixXd& handle_targets, Eigen::MatrixXd& positions,
                      const ArapOptions& options) {
  ArapReport report;
  const std::size_t h = data.handles.size();
  Eigen::MatrixXd known(static_cast<Eigen::Index>(h + data.pinned.size()), D);
  for (std::size_t k = 0; k < h; ++k) {
    known.row(static_cast<Eigen::Index>(k)) = handle_targets.row(static_cast<Eigen::Index>(k));
    positions.row(data.handles[k]) = handle_targets.row(static_cast<Eigen::Index>(k));
  }
  for (std::size_t k = 0; k < data.pinned.size(); ++k)
    known.row(static_cast<Eigen::Index>(h + k)) = positions.row(data.pinned[k]);

  const unsigned threads = resolve_threads(options.threads);
  const double step_limit = options.step_tolerance * data.edge_length;
  const Eigen::Index n = data.rest.vertex_count();
  const int window = std::max(options.anderson_window, 0);
  Eigen::MatrixXd rhs(n, D);
  std::vector<Eigen::Matrix<double, D, D>> rotations, trial_rotations;
  std::vector<double> element_energies;
  // Anderson acceleration (Peng et al. 2018) of the fixed-point map G = global(local(x)): the
  // last `window` differences of G(x_k) and of the residuals f_k = G(x_k) - x_k, as columns of
  // flattened n*D vectors. Handles are equal in every G(x_k), so the affine combination keeps them.
  Eigen::MatrixXd delta_g(n * D, window), delta_f(n * D, window);
  Eigen::VectorXd previous_g, previous_f;
  int stored = 0, next_column = 0;

  // Each local step gives the energy of the positions it starts from, so iteration k's energy
  // comes with iteration k + 1's rotations: one polar decomposition per element per iteration
  // (two when an accelerated guess is refused).
  double energy = local_step(data, positions, threads, rotations, element_energies);
  report.energies.push_back(energy);
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    // Global step: sum_e vol_e B_e B_e^T X = sum_e vol_e B_e R_e^T, all D coordinates in one solve.
    rhs.setZero();
    for (Eigen::Index e = 0; e < data.rest.element_count(); ++e) {
      const ElementGeometry<D>& g = data.geometry[static_cast<std::size_t>(e)];
      const Eigen::Matrix<double, D + 1, D> local = g.volume * g.gradients * rotations[static_cast<std::size_t>(e)].transpose();
      for (int i = 0; i < D + 1; ++i) rhs.row(data.rest.elements(e, i)) += local.row(i);
    }
    Eigen::MatrixXd next = data.solver.solve(rhs, known);
    bool accepted = false;
    if (window > 0) {
      const Eigen::VectorXd g = Eigen::Map<const Eigen::VectorXd>(next.data(), n * D);
      const Eigen::VectorXd f = g - Eigen::Map<const Eigen::VectorXd>(positions.data(), n * D);
      if (previous_g.size() == g.size()) {
        delta_g.col(next_column) = g - previous_g;
        delta_f.col(next_column) = f - previous_f;
        next_column = (next_column + 1) % window;
        stored = std::min(stored + 1, window);
      }
      previous_g = g;
      previous_f = f;
      if (stored > 0) {
        // theta = argmin |f - dF theta|; the guess G(x_k) - dG theta, kept only if it lowers the
        // energy below x_k's (the safeguard that keeps the energy from ever increasing).
        const Eigen::VectorXd theta = delta_f.leftCols(stored).colPivHouseholderQr().solve(f);
        Eigen::MatrixXd guess = next;
        Eigen::Map<Eigen::VectorXd>(guess.data(), n * D) -= delta_g.leftCols(stored) * theta;
        const double guess_energy = local_step(data, guess, threads, trial_rotations, element_energies);
        if (guess_energy < energy && std::isfinite(guess_energy)) {
          next = std::move(guess);
          rotations.swap(trial_rotations);
          energy = guess_energy;
          accepted = true;
        }  // refused: the plain step G(x_k); the history stays (its pairs are still valid)
      }
    }
    if (!accepted) energy = local_step(data, next, threads, rotations, element_energies);
    const double step = (next - positions).rowwise().norm().maxCoeff();
    positions = std::move(next);
    report.energies.push_back(energy);
    report.iterations = iteration + 1;
    report.last_step = step;
    // Converged when the energy fell by at most relative_tolerance of itself per iteration,
    // averaged over the last kStall iterations: single accelerated steps can gain little and
    // the next ones much (the near-flat hinge modes of unglued meshes), so one iteration is
    // too short a window. A relative criterion never stops an energy that falls to zero (a
    // mesh whose parts can all move rigidly: the unglued torus of Fig. 24), hence the absolute one.
    constexpr int kStall = 5;
    const int span = std::min(iteration + 1, kStall);
    const double before = report.energies[report.energies.size() - 1 - static_cast<std::size_t>(span)];
    if (before - energy <= span * options.relative_tolerance * before || step <= step_limit ||
        energy <= options.energy_tolerance * data.volume) {
      report.converged = true;
      break;
    }
  }
  return report;
}

#define IMM_ARAP_INSTANTIATE(D)                                                                        \
  template ArapData<D> arap_precompute<D>(const SimplexMesh<D>&, const std::vector<Eigen::Index>&);   \
  template double arap_energy<D>(const ArapData<D>&, const Eigen::MatrixXd&);                          \
  template ArapReport arap_solve<D>(const ArapData<D>&, const Eigen::MatrixXd&, Eigen::MatrixXd&,       \
                                    const ArapOptions&);
IMM_ARAP_INSTANTIATE(2)
IMM_ARAP_INSTANTIATE(3)
#undef IMM_ARAP_INSTANTIATE

}  // namespace imm::deform
