// The rotation closest to a square matrix (polar decomposition F = R S with det R = +1), the
// local step of ARAP and the frame of the co-rotational material.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

namespace imm::deform {

/// argmin over rotations R (det R = +1) of ||F - R||_F by the SVD: U V^T from F = U Sigma V^T,
/// the column of U for the smallest singular value negated when det(U V^T) < 0 (an inverted F).
template <int D>
Eigen::Matrix<double, D, D> closest_rotation_svd(const Eigen::Matrix<double, D, D>& f) {
  Eigen::JacobiSVD<Eigen::Matrix<double, D, D>> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix<double, D, D> u = svd.matrixU();
  const Eigen::Matrix<double, D, D> v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0.0) u.col(D - 1) *= -1.0;  // singular values sorted decreasing
  return u * v.transpose();
}

/// The same rotation. When det F > 0 it is the orthogonal polar factor of F, computed by the
/// scaled Newton iteration X <- (g X + X^{-T} / g) / 2 (Higham 1986), which converges
/// quadratically (4 iterations on ARAP's near-rigid elements) and is 3-4 times cheaper than the
/// 3x3 Jacobi SVD; the result agrees with the SVD's to round-off (deform tests). Inverted or flat
/// elements, and an iteration that has not converged in 30 steps, take the SVD.
template <int D>
Eigen::Matrix<double, D, D> closest_rotation(const Eigen::Matrix<double, D, D>& f) {
  using Square = Eigen::Matrix<double, D, D>;
  if (!(f.determinant() > 0.0)) return closest_rotation_svd<D>(f);
  Square x = f;
  for (int iteration = 0; iteration < 30; ++iteration) {
    const Square inverse_transpose = x.inverse().transpose();
    // Scaling by the Frobenius norms (Higham's g) makes the first steps fast on stretched F.
    const double g = std::sqrt(std::sqrt(inverse_transpose.squaredNorm() / x.squaredNorm()));
    const Square next = 0.5 * (g * x + inverse_transpose / g);
    const double change = (next - x).squaredNorm();
    x = next;
    // Quadratic convergence: a change of 1e-13 means the iterate before it was already exact
    // to ~1e-13 and this one to round-off (D x D entries of size 1).
    if (change < 1e-26) return x;
  }
  return closest_rotation_svd<D>(f);
}

}  // namespace imm::deform
