#include "spectra.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace lever::test {

double spectral_radius(const Eigen::MatrixXd& A) {
  return Eigen::EigenSolver<Eigen::MatrixXd>(A, false).eigenvalues().cwiseAbs().maxCoeff();
}

double largest_real_part(const Eigen::MatrixXd& A) {
  return Eigen::EigenSolver<Eigen::MatrixXd>(A, false).eigenvalues().real().maxCoeff();
}

Eigen::VectorXd singular_values_jacobi(const Eigen::MatrixXd& J) {
  return Eigen::JacobiSVD<Eigen::MatrixXd>(J).singularValues();
}

Eigen::VectorXd singular_values_divide_and_conquer(const Eigen::MatrixXd& J) {
  return Eigen::BDCSVD<Eigen::MatrixXd>(J).singularValues();
}

}  // namespace lever::test
