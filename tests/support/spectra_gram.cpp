// Singular values from the Gram matrix's symmetric eigenvalues (spectra.hpp), compiled once for
// every test executable.
#include <Eigen/Eigenvalues>

#include "spectra.hpp"

namespace lever::test {

Eigen::VectorXd singular_values_from_gram(const Eigen::MatrixXd& J) {
  const bool wide = J.rows() <= J.cols();  // the smaller Gram matrix has the nonzero ones
  const Eigen::MatrixXd gram =
      wide ? Eigen::MatrixXd(J * J.transpose()) : Eigen::MatrixXd(J.transpose() * J);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram, Eigen::EigenvaluesOnly);
  // ascending eigenvalues; rounding can leave the smallest a little below zero
  return eig.eigenvalues().reverse().cwiseMax(0.0).cwiseSqrt();
}

}  // namespace lever::test
