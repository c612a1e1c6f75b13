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
  double edge_length = 0.0;  ///< mean rest edge length (the unit of ArapOptions::step_tolerance)
  double volume = 0.0;       ///< total rest volume (the unit of ArapOptions::energy_tolerance)
  FixedSolver solver;  ///< the stiffness matrix, known = handles + pinned, factored
  std::string error;   ///< non-empty: precomputation failed (e.g. a degenerate rest element)
  [[nodiscard]] bool ok() const { return error.empty(); }
};

struct ArapOptions {
  int max_iterations = 100;
  /// Stop when the energy decreases by at most this fraction of itself per iteration, averaged
  /// over the last 5 iterations. Local-global converges only linearly, and on the unglued
  /// meshes slowly (pieces joined by thin necks bend at almost no energy): the energy of the
  /// pulled helix still falls by ~1e-6 of itself per iteration after 100 iterations, so a
  /// tighter tolerance only runs into max_iterations (BENCHMARKS.md, "Deformation").
  double relative_tolerance = 1e-5;
  /// Also stop when no vertex moved by more than this fraction of the mean rest edge length in
  /// one iteration (0: never).
  double step_tolerance = 0.0;
  /// Threads of the local step (0: one per hardware thread); the result does not depend on it.
  unsigned threads = 0;
  /// Anderson acceleration over this many past iterations (0: plain local-global). An
  /// accelerated guess is kept only when it lowers the energy, so the energy never increases.
  int anderson_window = 5;
  /// Also stop when the energy is at most this times the rest volume (the deformation gradients
  /// then differ from rotations by ~1e-9 on average): the target is reached rigidly.
  double energy_tolerance = 1e-18;
};

struct ArapReport {
  int iterations = 0;
  /// The energy at the initial guess (with handles at their targets), then after each
  /// iteration; never increasing (each half-step minimizes over its own variables).
  std::vector<double> energies;
  /// A stopping criterion was met (false: stopped by max_iterations).
  bool converged = false;
  /// The largest vertex displacement of the last iteration.
  double last_step = 0.0;
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
