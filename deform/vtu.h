// VTK XML unstructured grid (ASCII .vtu, ParaView) of a simplicial mesh of any dimension, with
// per-vertex scalar fields (weights, distances) and per-element integer fields (references).
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

namespace imm::deform {

struct VtuFields {
  std::vector<std::pair<std::string, Eigen::VectorXd>> point_scalars;
  std::vector<std::pair<std::string, std::vector<int>>> cell_integers;
};

/// `vertices` n x D (D = 2 or 3; 2D points get z = 0), `elements` m x 3 (triangles) or m x 4
/// (tetrahedra). Full double precision.
std::string format_vtu(const Eigen::MatrixXd& vertices, const Eigen::MatrixXi& elements, const VtuFields& fields = {});

}  // namespace imm::deform
