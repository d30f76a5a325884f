// Eigenvalues and singular values the tests compute beside lever. The general eigensolver and
// JacobiSVD are lever/spectra.hpp's, compiled once in the engine library (the heaviest templates
// the tests would otherwise instantiate, minutes of compile time under the sanitizers); the Gram
// route is the tests' own (spectra_gram.cpp).
#pragma once

#include <Eigen/Core>

#include <lever/spectra.hpp>

namespace lever::test {

/// max |lambda| over the eigenvalues of a square matrix (general eigensolver).
inline double spectral_radius(const Eigen::MatrixXd& A) {
  return lever::eigenvalues(A).cwiseAbs().maxCoeff();
}

/// max Re(lambda) over the eigenvalues of a square matrix (general eigensolver).
inline double largest_real_part(const Eigen::MatrixXd& A) {
  return lever::eigenvalues(A).real().maxCoeff();
}

/// Singular values, largest first, by one-sided Jacobi rotations (Eigen's JacobiSVD).
inline Eigen::VectorXd singular_values_jacobi(const Eigen::MatrixXd& J) {
  return lever::singular_values(J);
}

/// Singular values, largest first, as the square roots of J J^T's eigenvalues (symmetric QR
/// iteration): a second algorithm where a test checks a program that uses JacobiSVD. Accurate to
/// about eps sigma_1^2 / sigma_i relative, which is ample for a well-conditioned J (not for one
/// near a singular pose). (Eigen's BDCSVD, the obvious second SVD, took 31 s of the 54 s that
/// compiling these functions cost in Release.)
Eigen::VectorXd singular_values_from_gram(const Eigen::MatrixXd& J);

}  // namespace lever::test
