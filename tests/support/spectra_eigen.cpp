#include <Eigen/Eigenvalues>

#include "spectra.hpp"

namespace lever::test {

double spectral_radius(const Eigen::MatrixXd& A) {
  return Eigen::EigenSolver<Eigen::MatrixXd>(A, false).eigenvalues().cwiseAbs().maxCoeff();
}

double largest_real_part(const Eigen::MatrixXd& A) {
  return Eigen::EigenSolver<Eigen::MatrixXd>(A, false).eigenvalues().real().maxCoeff();
}

}  // namespace lever::test
