// Simplicial meshes of dimension D for deformation and simulation (paper §8): triangles in 2D,
// tetrahedra in 3D, one code path. CGAL-free; Eigen at the boundary (CONVENTIONS "Deformation
// and simulation"): vertices `Eigen::MatrixXd` (n x D), elements `Eigen::MatrixXi` (m x (D+1)),
// sparse systems `Eigen::SparseMatrix<double>`.
//
// Every operator here is built from one per-element fact: the gradients of the D + 1 barycentric
// (linear hat) functions of a simplex, the rows of `ElementGeometry<D>::gradients`. The
// deformation gradient of a map x is F = sum_i x_i grad(lambda_i)^T, the stiffness (cotangent)
// matrix is sum_e vol_e B_e B_e^T, and so on; nothing below tests D.
#pragma once

#include <Eigen/Core>
#include <Eigen/Sparse>
#include <string>
#include <vector>

namespace imm::deform {

/// D! : the volume of a simplex is |det(x1 - x0, ..., xD - x0)| / D!.
constexpr double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

/// A simplicial mesh: `vertices` n x D, `elements` m x (D + 1) (0-based vertex ids). Elements are
/// expected positively oriented (det(x1 - x0, ..., xD - x0) > 0) in the rest state; the output of
/// `immerse mesh` is.
template <int D>
struct SimplexMesh {
  static constexpr int kDim = D;
  static constexpr int kCorners = D + 1;
  Eigen::MatrixXd vertices;  ///< n x D
  Eigen::MatrixXi elements;  ///< m x (D + 1)

  [[nodiscard]] Eigen::Index vertex_count() const { return vertices.rows(); }
  [[nodiscard]] Eigen::Index element_count() const { return elements.rows(); }
};

/// The rest-state geometry of one simplex.
template <int D>
struct ElementGeometry {
  /// Row i: the gradient of barycentric function i (constant on the simplex).
  Eigen::Matrix<double, D + 1, D> gradients;
  double volume = 0.0;  ///< signed (area in 2D)
};

/// Gradients and signed volume of simplex `e` of `mesh` at positions `positions` (n x D).
/// A degenerate simplex gives volume 0 and zero gradients.
template <int D>
ElementGeometry<D> element_geometry(const Eigen::MatrixXd& positions, const Eigen::MatrixXi& elements,
                                    Eigen::Index e);

/// The signed volume of every element at `positions`.
template <int D>
Eigen::VectorXd element_volumes(const Eigen::MatrixXd& positions, const Eigen::MatrixXi& elements);

/// Elements whose signed volume at `positions` is <= 0 (inverted or flat). Doubles: this is a
/// report on a deformed state, not a topological decision.
template <int D>
std::vector<Eigen::Index> inverted_elements(const Eigen::MatrixXd& positions, const Eigen::MatrixXi& elements);

/// The stiffness (cotangent Laplacian) matrix K = sum_e vol_e B_e B_e^T, n x n, symmetric
/// positive semidefinite, rows summing to zero.
template <int D>
Eigen::SparseMatrix<double> stiffness_matrix(const SimplexMesh<D>& mesh);

/// Lumped mass: each vertex gets vol_e / (D + 1) of every element around it (n entries).
template <int D>
Eigen::VectorXd lumped_mass(const SimplexMesh<D>& mesh);

/// Connected components of the element graph (elements sharing a vertex); per vertex the
/// component id (vertices used by no element get their own component), and the count.
std::vector<int> vertex_components(Eigen::Index vertex_count, const Eigen::MatrixXi& elements, int& count);

/// The connected components (of elements) that contain no vertex of `anchored`: per such
/// component its smallest vertex id. A vertex in no element is a component of its own.
std::vector<Eigen::Index> unanchored_components(Eigen::Index vertex_count, const Eigen::MatrixXi& elements,
                                                const std::vector<Eigen::Index>& anchored);

/// Mean edge length of the mesh at `positions`.
template <int D>
double mean_edge_length(const Eigen::MatrixXd& positions, const Eigen::MatrixXi& elements);

/// A point carried by a mesh: the element it lies in and its barycentric weights there (the
/// `.emb` lines of `immerse mesh`).
struct EmbeddedPoint {
  Eigen::Index element = -1;
  std::vector<double> weights;  ///< D + 1 weights, in the element's corner order
};

/// Positions of embedded points under the deformed vertex positions `positions`:
/// sum_i weights[i] * positions(elements(element, i)).
/// @pre every element index valid, weights.size() == elements.cols().
Eigen::MatrixXd embedded_positions(const Eigen::MatrixXd& positions, const Eigen::MatrixXi& elements,
                                   const std::vector<EmbeddedPoint>& points);

extern template ElementGeometry<2> element_geometry<2>(const Eigen::MatrixXd&, const Eigen::MatrixXi&, Eigen::Index);
extern template ElementGeometry<3> element_geometry<3>(const Eigen::MatrixXd&, const Eigen::MatrixXi&, Eigen::Index);

}  // namespace imm::deform
