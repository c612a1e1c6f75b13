// Structured simplicial meshes of a box for the deformation tests: a lattice of D-cubes, each
// cut into D! Kuhn simplices (one per ordering of the axes), all positively oriented. The same
// code for triangles and tetrahedra.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <numeric>

#include "deform/simplex_mesh.h"

namespace imm::deform::test {

/// `cells[a]` cubes of side `size[a] / cells[a]` along axis a, from the origin.
template <int D>
SimplexMesh<D> box_grid(const std::array<int, D>& cells, const std::array<double, D>& size) {
  SimplexMesh<D> mesh;
  std::array<int, D> stride{};
  int count = 1;
  for (int a = 0; a < D; ++a) stride[a] = count, count *= cells[a] + 1;
  mesh.vertices.resize(count, D);
  for (int v = 0; v < count; ++v)
    for (int a = 0; a < D; ++a) mesh.vertices(v, a) = size[a] * ((v / stride[a]) % (cells[a] + 1)) / cells[a];
  std::vector<std::array<int, D + 1>> elements;
  int cubes = 1;
  for (int a = 0; a < D; ++a) cubes *= cells[a];
  for (int c = 0; c < cubes; ++c) {
    int base = 0, rest = c;
    for (int a = 0; a < D; ++a) base += (rest % cells[a]) * stride[a], rest /= cells[a];
    std::array<int, D> order{};
    std::iota(order.begin(), order.end(), 0);
    do {
      std::array<int, D + 1> s{};
      s[0] = base;
      for (int k = 0; k < D; ++k) s[k + 1] = s[k] + stride[order[k]];
      elements.push_back(s);
    } while (std::next_permutation(order.begin(), order.end()));
  }
  mesh.elements.resize(static_cast<Eigen::Index>(elements.size()), D + 1);
  for (std::size_t e = 0; e < elements.size(); ++e) {
    // Swap two corners of negatively oriented simplices (odd permutations of the axes).
    Eigen::Matrix<double, D, D> edges;
    for (int i = 0; i < D; ++i) edges.col(i) = (mesh.vertices.row(elements[e][i + 1]) - mesh.vertices.row(elements[e][0])).transpose();
    if (edges.determinant() < 0) std::swap(elements[e][1], elements[e][2]);
    for (int i = 0; i < D + 1; ++i) mesh.elements(static_cast<Eigen::Index>(e), i) = elements[e][i];
  }
  return mesh;
}

/// A bar along x: `along` cells over `length`, `across` cells over `width` on the other axes.
template <int D>
SimplexMesh<D> bar_grid(int along, double length, int across, double width = 1.0) {
  std::array<int, D> cells{};
  std::array<double, D> size{};
  cells.fill(across);
  size.fill(width);
  cells[0] = along;
  size[0] = length;
  return box_grid<D>(cells, size);
}

/// A cube-ish grid with `n` cells per side of length 1.
template <int D>
SimplexMesh<D> unit_grid(int n) {
  std::array<int, D> cells{};
  std::array<double, D> size{};
  cells.fill(n);
  size.fill(1.0);
  return box_grid<D>(cells, size);
}

/// A rotation matrix from a seed, built by Gram-Schmidt (Householder QR) of a fixed matrix,
/// independently of the code under test.
template <int D>
Eigen::Matrix<double, D, D> test_rotation(int seed) {
  Eigen::Matrix<double, D, D> m;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) m(i, j) = std::sin(1.7 * (seed + 1) * (i + 1) + 0.9 * j * j + 0.3 * seed);
  Eigen::HouseholderQR<Eigen::Matrix<double, D, D>> qr(m);
  Eigen::Matrix<double, D, D> q = qr.householderQ();
  if (q.determinant() < 0) q.col(0) *= -1.0;
  return q;
}

/// Vertices whose coordinate `axis` is <= lo or >= hi.
template <int D>
std::vector<Eigen::Index> vertices_where(const SimplexMesh<D>& mesh, int axis, double lo, double hi) {
  std::vector<Eigen::Index> out;
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.vertices(v, axis) <= lo || mesh.vertices(v, axis) >= hi) out.push_back(v);
  return out;
}

}  // namespace imm::deform::test
