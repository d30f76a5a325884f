// Singular values and eigenvalues of dense matrices, compiled once in the engine library for every
// reader (lever check's singular poses and step stability, identification, the tests, the
// lessons' programs): Eigen's JacobiSVD and general EigenSolver are the heaviest templates lever
// instantiates, some twenty seconds of compile time each wherever they are spelled out.
#pragma once

#include <Eigen/Core>

namespace lever {

/// Singular values of A, largest first, by one-sided Jacobi rotations (Eigen's JacobiSVD).
Eigen::VectorXd singular_values(const Eigen::MatrixXd& A);

/// A's singular values (largest first) and its right singular vectors, the columns of the full
/// cols x cols V (for a tall A the thin V is the same matrix).
struct SingularValueDecomposition {
  Eigen::VectorXd sigma;
  Eigen::MatrixXd V;
};
SingularValueDecomposition singular_value_decomposition(const Eigen::MatrixXd& A);

/// The eigenvalues of a square real matrix (Eigen's general EigenSolver, no eigenvectors), in
/// the solver's order.
Eigen::VectorXcd eigenvalues(const Eigen::MatrixXd& A);

}  // namespace lever
