// Eigenvalues and singular values the tests compute beside lever, compiled once for every test
// executable (tests/support/spectra_*.cpp, one file per algorithm so that a parallel build
// compiles them side by side): Eigen's general eigensolver and SVDs are the heaviest templates the
// tests instantiate, minutes of compile time each under the sanitizers.
#pragma once

#include <Eigen/Core>

namespace lever::test {

/// max |lambda| over the eigenvalues of a square matrix (general eigensolver).
double spectral_radius(const Eigen::MatrixXd& A);

/// max Re(lambda) over the eigenvalues of a square matrix (general eigensolver).
double largest_real_part(const Eigen::MatrixXd& A);

/// Singular values, largest first, by one-sided Jacobi rotations (Eigen's JacobiSVD).
Eigen::VectorXd singular_values_jacobi(const Eigen::MatrixXd& J);

/// Singular values, largest first, as the square roots of J J^T's eigenvalues (symmetric QR
/// iteration): a second algorithm where a test checks a program that uses JacobiSVD. Accurate to
/// about eps sigma_1^2 / sigma_i relative, which is ample for a well-conditioned J (not for one
/// near a singular pose). (Eigen's BDCSVD, the obvious second SVD, took 31 s of the 54 s that
/// compiling these functions cost in Release.)
Eigen::VectorXd singular_values_from_gram(const Eigen::MatrixXd& J);

}  // namespace lever::test
