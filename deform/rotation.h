// The rotation closest to a square matrix (polar decomposition F = R S with det R = +1), the
// local step of ARAP and the frame of the co-rotational material.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace imm::deform {

/// argmin over rotations R (det R = +1) of ||F - R||_F: U V^T from the SVD F = U Sigma V^T, the
/// column of U for the smallest singular value negated when det(U V^T) < 0 (an inverted F).
template <int D>
Eigen::Matrix<double, D, D> closest_rotation(const Eigen::Matrix<double, D, D>& f) {
  Eigen::JacobiSVD<Eigen::Matrix<double, D, D>> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix<double, D, D> u = svd.matrixU();
  const Eigen::Matrix<double, D, D> v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0.0) u.col(D - 1) *= -1.0;  // singular values sorted decreasing
  return u * v.transpose();
}

}  // namespace imm::deform
