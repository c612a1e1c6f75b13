// Volumetric weights and distances on simplicial meshes (paper §8, Fig. 4): bounded biharmonic
// weights (Jacobson et al. 2011) and heat-method geodesic distances (Crane et al. 2013). On an
// unglued mesh they flow only through the material: a handle's weight does not leak into an
// overlapping part that shares no element with it.
#pragma once

#include <string>
#include <vector>

#include "deform/simplex_mesh.h"

namespace imm::deform {

struct WeightsOptions {
  int max_active_set_iterations = 2000;
};

struct WeightsResult {
  Eigen::MatrixXd weights;  ///< n x (number of handles)
  /// Active-set rounds per handle: the solutions whose KKT conditions were checked, the warm
  /// start's included (1: the unconstrained weights already satisfy them). Every round after the
  /// first factors the free block once; the warm start's factorization is shared by all handles.
  std::vector<int> active_set_iterations;
  std::string error;  ///< non-empty: not computed (bad handles, a part of the mesh without a handle)
  [[nodiscard]] bool ok() const { return error.empty(); }
};

/// Bounded biharmonic weights: per handle k, minimize w^T (K M^{-1} K) w (K the stiffness
/// matrix, M the lumped mass) with w = 1 on handle k's vertices, 0 on the other handles', and
/// 0 <= w <= 1 elsewhere (an active-set method warm-started from the unconstrained biharmonic
/// weights, holding every violated bound and releasing every wrong-signed multiplier in the same
/// round, a primal-dual active-set step; each round one sparse factorization, all in the warm
/// start's fill-reducing order), until the KKT conditions hold up to round-off (bounds within
/// 1e-10, multipliers within 1e-10 of the largest diagonal entry of K M^{-1} K),
/// then every row divided by its sum: the partition of unity (libigl's bbw + normalize).
/// @pre handles non-empty, disjoint vertex sets.
template <int D>
WeightsResult bounded_biharmonic_weights(const SimplexMesh<D>& mesh, const std::vector<std::vector<Eigen::Index>>& handles,
                                         const WeightsOptions& options = {});

/// Heat-method geodesic distance from `sources` (vertex ids): heat diffused for time t = h^2 (h
/// the mean edge length, times `time_factor`), its normalized negative gradient per element,
/// then the Poisson solve K phi = div X with phi = 0 at the sources. Vertices in a connected
/// part without a source get +infinity.
template <int D>
Eigen::VectorXd heat_geodesic(const SimplexMesh<D>& mesh, const std::vector<Eigen::Index>& sources, double time_factor = 1.0);

}  // namespace imm::deform
