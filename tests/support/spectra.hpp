// Eigenvalues and singular values the tests compute beside lever, compiled once for every test
// executable (tests/support/spectra.cpp): Eigen's general eigensolver and SVDs are the heaviest
// templates the tests instantiate, minutes of compile time each under the sanitizers.
#pragma once

#include <Eigen/Core>

namespace lever::test {

/// max |lambda| over the eigenvalues of a square matrix (general eigensolver).
double spectral_radius(const Eigen::MatrixXd& A);

/// max Re(lambda) over the eigenvalues of a square matrix (general eigensolver).
double largest_real_part(const Eigen::MatrixXd& A);

/// Singular values, largest first, by one-sided Jacobi rotations (Eigen's JacobiSVD).
Eigen::VectorXd singular_values_jacobi(const Eigen::MatrixXd& J);

/// Singular values, largest first, by bidiagonal divide and conquer (Eigen's BDCSVD): a second
/// algorithm where a test checks a program that uses JacobiSVD.
Eigen::VectorXd singular_values_divide_and_conquer(const Eigen::MatrixXd& J);

}  // namespace lever::test
