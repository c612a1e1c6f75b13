// The naive glued baseline the paper compares against (§8, Figs. 1, 2, 4): the same background
// elements the unglued mesh is made of, ONE copy each, every shared vertex merged. It covers
// exactly the domain of the unglued mesh and carries the same embedding (an input point in an
// element copy lies in that copy's background element, with the same weights), so a
// deformation or a weight computed on both differs only by the gluing.
#pragma once

#include <vector>

#include "deform/simplex_mesh.h"

namespace imm::deform {

template <int D>
struct GluedMesh {
  SimplexMesh<D> mesh;
  /// Per copy (element of the unglued mesh): its element in the glued mesh.
  std::vector<Eigen::Index> element_of_copy;
  /// Per glued vertex: its background vertex.
  std::vector<Eigen::Index> background_vertex;
};

/// Builds the glued baseline from the background mesh and, per element copy of the unglued
/// mesh, the background element it copies (MeshResult::background_triangle / background_tet).
/// Glued elements come in increasing background order, vertices in order of first use; corners
/// keep the background corner order (as the copies do).
template <int D>
GluedMesh<D> glue_copies(const SimplexMesh<D>& background, const std::vector<int>& background_element);

/// The embedding carried over: each point's element replaced by its glued element.
std::vector<EmbeddedPoint> glued_embedding(const std::vector<EmbeddedPoint>& points,
                                           const std::vector<Eigen::Index>& element_of_copy);

}  // namespace imm::deform
