#include "deform/simplex_mesh.h"

#include <Eigen/LU>
#include <numeric>

namespace imm::deform {

template <int D>
ElementGeometry<D> element_geometry(const Eigen::MatrixXd& positions, const Eigen::MatrixXi& elements,
                                    Eigen::Index e) {
  using Square = Eigen::Matrix<double, D, D>;
  Square edges;  // column i: x_{i+1} - x_0
  const Eigen::Matrix<double, 1, D> origin = positions.row(elements(e, 0));
  for (int i = 0; i < D; ++i) edges.col(i) = (positions.row(elements(e, i + 1)) - origin).transpose();
  ElementGeometry<D> g;
  const double det = edges.determinant();
  g.volume = det / factorial(D);
  g.gradients.setZero();
  if (det == 0.0) return g;
  // lambda_i(x) = e_i^T E^{-1} (x - x0) for i >= 1: the rows of E^{-1} are the gradients.
  const Square inverse = edges.inverse();
  g.gradients.template bottomRows<D>() = inverse;
  g.gradients.row(0) = -inverse.colwise().sum();
  return g;
}

template <int D>
Eigen::VectorXd element_volumes(const Eigen::MatrixXd& positions, const Eigen::MatrixXi& elements) {
  Eigen::VectorXd volumes(elements.rows());
  for (Eigen::Index e = 0; e < elements.rows(); ++e) {
    Eigen::Matrix<double, D, D> edges;
    for (int i = 0; i < D; ++i)
      edges.col(i) = (positions.row(elements(e, i + 1)) - positions.row(elements(e, 0))).transpose();
    volumes[e] = edges.determinant() / factorial(D);
  }
  return volumes;
}

template <int D>
std::vector<Eigen::Index> inverted_elements(const Eigen::MatrixXd& positions, const Eigen::MatrixXi& elements) {
  const Eigen::VectorXd volumes = element_volumes<D>(positions, elements);
  std::vector<Eigen::Index> out;
  for (Eigen::Index e = 0; e < volumes.size(); ++e)
    if (!(volumes[e] > 0.0)) out.push_back(e);
  return out;
}

template <int D>
Eigen::SparseMatrix<double> stiffness_matrix(const SimplexMesh<D>& mesh) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(mesh.element_count()) * (D + 1) * (D + 1));
  for (Eigen::Index e = 0; e < mesh.element_count(); ++e) {
    const ElementGeometry<D> g = element_geometry<D>(mesh.vertices, mesh.elements, e);
    const Eigen::Matrix<double, D + 1, D + 1> local = std::abs(g.volume) * g.gradients * g.gradients.transpose();
    for (int i = 0; i < D + 1; ++i)
      for (int j = 0; j < D + 1; ++j) triplets.emplace_back(mesh.elements(e, i), mesh.elements(e, j), local(i, j));
  }
  Eigen::SparseMatrix<double> k(mesh.vertex_count(), mesh.vertex_count());
  k.setFromTriplets(triplets.begin(), triplets.end());
  return k;
}

template <int D>
Eigen::VectorXd lumped_mass(const SimplexMesh<D>& mesh) {
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(mesh.vertex_count());
  const Eigen::VectorXd volumes = element_volumes<D>(mesh.vertices, mesh.elements);
  for (Eigen::Index e = 0; e < mesh.element_count(); ++e)
    for (int i = 0; i < D + 1; ++i) mass[mesh.elements(e, i)] += std::abs(volumes[e]) / (D + 1);
  return mass;
}

std::vector<int> vertex_components(Eigen::Index vertex_count, const Eigen::MatrixXi& elements, int& count) {
  std::vector<int> parent(static_cast<std::size_t>(vertex_count));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (Eigen::Index e = 0; e < elements.rows(); ++e)
    for (Eigen::Index i = 1; i < elements.cols(); ++i) parent[find(elements(e, i))] = find(elements(e, 0));
  std::vector<int> component(parent.size(), -1), id_of_root(parent.size(), -1);
  count = 0;
  for (std::size_t v = 0; v < parent.size(); ++v) {
    const int root = find(static_cast<int>(v));
    if (id_of_root[root] < 0) id_of_root[root] = count++;
    component[v] = id_of_root[root];
  }
  return component;
}

std::vector<Eigen::Index> unanchored_components(Eigen::Index vertex_count, const Eigen::MatrixXi& elements,
                                                const std::vector<Eigen::Index>& anchored) {
  int count = 0;
  const std::vector<int> component = vertex_components(vertex_count, elements, count);
  std::vector<char> has_anchor(static_cast<std::size_t>(count), 0);
  for (Eigen::Index v : anchored) has_anchor[static_cast<std::size_t>(component[static_cast<std::size_t>(v)])] = 1;
  std::vector<Eigen::Index> out;
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    const auto c = static_cast<std::size_t>(component[static_cast<std::size_t>(v)]);
    if (!has_anchor[c]) {
      out.push_back(v);
      has_anchor[c] = 1;  // report each component once, at its smallest vertex
    }
  }
  return out;
}

template <int D>
double mean_edge_length(const Eigen::MatrixXd& positions, const Eigen::MatrixXi& elements) {
  double total = 0.0;
  long edges = 0;
  for (Eigen::Index e = 0; e < elements.rows(); ++e)
    for (int i = 0; i < D + 1; ++i)
      for (int j = i + 1; j < D + 1; ++j, ++edges)
        total += (positions.row(elements(e, i)) - positions.row(elements(e, j))).norm();
  return edges == 0 ? 0.0 : total / static_cast<double>(edges);
}

Eigen::MatrixXd embedded_positions(const Eigen::MatrixXd& positions, const Eigen::MatrixXi& elements,
                                   const std::vector<EmbeddedPoint>& points) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(points.size()), positions.cols());
  for (std::size_t p = 0; p < points.size(); ++p)
    for (Eigen::Index i = 0; i < elements.cols(); ++i)
      out.row(static_cast<Eigen::Index>(p)) +=
          points[p].weights[static_cast<std::size_t>(i)] * positions.row(elements(points[p].element, i));
  return out;
}

#define IMM_DEFORM_INSTANTIATE(D)                                                                           \
  template ElementGeometry<D> element_geometry<D>(const Eigen::MatrixXd&, const Eigen::MatrixXi&, Eigen::Index); \
  template Eigen::VectorXd element_volumes<D>(const Eigen::MatrixXd&, const Eigen::MatrixXi&);               \
  template std::vector<Eigen::Index> inverted_elements<D>(const Eigen::MatrixXd&, const Eigen::MatrixXi&);   \
  template Eigen::SparseMatrix<double> stiffness_matrix<D>(const SimplexMesh<D>&);                            \
  template Eigen::VectorXd lumped_mass<D>(const SimplexMesh<D>&);                                             \
  template double mean_edge_length<D>(const Eigen::MatrixXd&, const Eigen::MatrixXi&);
IMM_DEFORM_INSTANTIATE(2)
IMM_DEFORM_INSTANTIATE(3)
#undef IMM_DEFORM_INSTANTIATE

}  // namespace imm::deform
