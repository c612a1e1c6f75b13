// Volumetric as-rigid-as-possible deformation (Sorkine & Alexa 2007; Chao et al. 2010 for
// simplices): minimize sum_e vol_e ||F_e - R_e||_F^2 over positions and per-element rotations,
// with handle vertices moved to targets. Local step: R_e = the rotation closest to F_e (polar
// decomposition). Global step: one sparse solve with the stiffness matrix, factored once in the
// precomputation (libigl's arap_precomputation / arap_solve split). The same code for triangles
// (D = 2) and tetrahedra (D = 3); the paper pulls the unglued meshes apart with it (§8, Figs.
// 1, 6, 7, 17, 20, 24).
#pragma once

#include <string>
#include <vector>

#include "deform/fixed_solver.h"
#include "deform/simplex_mesh.h"

namespace imm::deform {

template <int D>
struct ArapData {
  SimplexMesh<D> rest;
  std::vector<ElementGeometry<D>> geometry;  ///< rest gradients and volumes per element
  std::vector<Eigen::Index> handles;         ///< as given
  /// One vertex per connected part of the mesh that holds no handle, kept where the initial
  /// guess puts it (a part nobody pulls stays put, instead of a singular system).
  std::vector<Eigen::Index> pinned;
  FixedSolver solver;  ///< the stiffness matrix, known = handles + pinned, factored
  std::string error;   ///< non-empty: precomputation failed (e.g. a degenerate rest element)
  [[nodiscard]] bool ok() const { return error.empty(); }
};

struct ArapOptions {
  int max_iterations = 100;
  /// Stop when the energy decreases by less than this fraction of itself in one iteration.
  double relative_tolerance = 1e-10;
};

struct ArapReport {
  int iterations = 0;
  /// The energy at the initial guess (with handles at their targets), then after each
  /// iteration; never increasing (each half-step minimizes over its own variables).
  std::vector<double> energies;
};

/// Factors the stiffness matrix of `rest` with `handles` (vertex ids) known.
/// @pre every rest element positively oriented (else `error` names it).
template <int D>
ArapData<D> arap_precompute(const SimplexMesh<D>& rest, const std::vector<Eigen::Index>& handles);

/// Runs local-global iterations from `positions` (n x D, the initial guess; its handle rows are
/// replaced by `handle_targets`, |handles| x D, in handle order) and leaves the result there.
template <int D>
ArapReport arap_solve(const ArapData<D>& data, const Eigen::MatrixXd& handle_targets, Eigen::MatrixXd& positions,
                      const ArapOptions& options = {});

/// The ARAP energy sum_e vol_e min_R ||F_e - R||^2 of `positions` relative to the rest state.
template <int D>
double arap_energy(const ArapData<D>& data, const Eigen::MatrixXd& positions);

}  // namespace imm::deform
