// lever/spectra.hpp's eigenvalues: Eigen's general EigenSolver, instantiated once.
#include <lever/spectra.hpp>

#include <Eigen/Eigenvalues>

namespace lever {

Eigen::VectorXcd eigenvalues(const Eigen::MatrixXd& A) {
  return Eigen::EigenSolver<Eigen::MatrixXd>(A, false).eigenvalues();
}

}  // namespace lever
