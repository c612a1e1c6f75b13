#include "deform/arap.h"

#include <cmath>

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

  const Eigen::Index n = data.rest.vertex_count();
  Eigen::MatrixXd rhs(n, D);
  report.energies.push_back(arap_energy(data, positions));
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    // Local step: the best rotation per element; global step: sum_e vol_e B_e B_e^T X = sum_e vol_e B_e R_e^T.
    rhs.setZero();
    for (Eigen::Index e = 0; e < data.rest.element_count(); ++e) {
      const ElementGeometry<D>& g = data.geometry[static_cast<std::size_t>(e)];
      const Eigen::Matrix<double, D, D> r = closest_rotation<D>(deformation_gradient(data, positions, e));
      const Eigen::Matrix<double, D + 1, D> local = g.volume * g.gradients * r.transpose();
      for (int i = 0; i < D + 1; ++i) rhs.row(data.rest.elements(e, i)) += local.row(i);
    }
    positions = data.solver.solve(rhs, known);
    report.energies.push_back(arap_energy(data, positions));
    report.iterations = iteration + 1;
    const double before = report.energies[report.energies.size() - 2], after = report.energies.back();
    if (before - after <= options.relative_tolerance * before) break;
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
