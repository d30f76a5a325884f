// lever/spectra.hpp's singular values: Eigen's JacobiSVD, instantiated once (its own unit, so that
// a parallel build compiles it beside the eigenvalues).
#include <lever/spectra.hpp>

#include <Eigen/SVD>

namespace lever {

Eigen::VectorXd singular_values(const Eigen::MatrixXd& A) {
  return Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
}

SingularValueDecomposition singular_value_decomposition(const Eigen::MatrixXd& A) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  return {svd.singularValues(), svd.matrixV()};
}

}  // namespace lever
