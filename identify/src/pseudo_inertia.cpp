// Pseudo-inertia, log-Cholesky coordinates and the geodesic distance (see pseudo_inertia.hpp).
#include "pseudo_inertia.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <cmath>

namespace lever::identify::detail {

namespace {

// theta's off-diagonal entries: (row, column) of U for theta[4..9]
constexpr int kOffDiagonal[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};

// the upper triangle of a symmetric 4x4 as ten numbers, off-diagonal entries times sqrt(2), so
// that the Euclidean norm of the ten is the Frobenius norm of the matrix
Eigen::Matrix<double, 10, 1> upper_triangle(const Matrix4& S) {
  static const double root2 = std::sqrt(2.0);
  Eigen::Matrix<double, 10, 1> out;
  out << S(0, 0), S(1, 1), S(2, 2), S(3, 3), root2 * S(0, 1), root2 * S(0, 2), root2 * S(0, 3),
      root2 * S(1, 2), root2 * S(1, 3), root2 * S(2, 3);
  return out;
}

// (log a - log b) / (a - b), and its limit 1/a as b -> a, for a, b > 0
double log_difference_quotient(double a, double b) {
  const double x = (b - a) / a;
  if (std::abs(x) < 1e-8) return (1.0 - 0.5 * x) / a;
  return std::log1p(x) / (a * x);
}

// d J / d theta_k for J = U U^T: dU U^T + U dU^T
Matrix4 pseudo_inertia_derivative(const LogCholesky& theta, const Matrix4& U, int k) {
  Matrix4 dU = Matrix4::Zero();
  const double scale = std::exp(theta[0]);
  if (k == 0) {
    dU = U;  // U is e^alpha times a matrix free of alpha
  } else if (k <= 3) {
    dU(k - 1, k - 1) = scale * std::exp(theta[k]);
  } else {
    dU(kOffDiagonal[k - 4][0], kOffDiagonal[k - 4][1]) = scale;
  }
  const Matrix4 product = dU * U.transpose();
  return product + product.transpose();
}

}  // namespace

Matrix4 upper_factor(const LogCholesky& theta) {
  Matrix4 U = Matrix4::Zero();
  for (int i = 0; i < 3; ++i) U(i, i) = std::exp(theta[1 + i]);
  U(3, 3) = 1.0;
  for (int k = 0; k < 6; ++k) U(kOffDiagonal[k][0], kOffDiagonal[k][1]) = theta[4 + k];
  return std::exp(theta[0]) * U;
}

LogCholesky log_cholesky_of(const Matrix4& J) {
  // J = U U^T with U upper triangular: the Cholesky factor of J with rows and columns reversed
  const Matrix4 reversed = J.reverse();
  const Matrix4 L = reversed.llt().matrixL();
  const Matrix4 U = L.reverse();
  LogCholesky theta;
  theta[0] = std::log(U(3, 3));
  const double scale = U(3, 3);
  for (int i = 0; i < 3; ++i) theta[1 + i] = std::log(U(i, i) / scale);
  for (int k = 0; k < 6; ++k) theta[4 + k] = U(kOffDiagonal[k][0], kOffDiagonal[k][1]) / scale;
  return theta;
}

InertialParameters parameters_of(const LogCholesky& theta, Jacobian10* jacobian) {
  const Matrix4 U = upper_factor(theta);
  if (jacobian != nullptr) {
    for (int k = 0; k < 10; ++k) {
      jacobian->col(k) =
          RigidInertia::from_pseudo_inertia(pseudo_inertia_derivative(theta, U, k)).to_parameters();
    }
  }
  return RigidInertia::from_pseudo_inertia(U * U.transpose()).to_parameters();
}

GeodesicResidual::GeodesicResidual(const Matrix4& J0)
    : L0_inverse_(J0.llt().matrixL().solve(Matrix4::Identity())) {}

Eigen::Matrix<double, 10, 1> GeodesicResidual::operator()(const LogCholesky& theta,
                                                          Jacobian10* jacobian) const {
  const Matrix4 U = upper_factor(theta);
  const Matrix4 A = L0_inverse_ * U * U.transpose() * L0_inverse_.transpose();
  const Eigen::SelfAdjointEigenSolver<Matrix4> eig(A);
  const Eigen::Vector4d& lambda = eig.eigenvalues();
  const Matrix4& V = eig.eigenvectors();
  const Eigen::Vector4d log_lambda = lambda.array().log();
  if (jacobian != nullptr) {
    // the derivative of the matrix logarithm (Daleckii and Krein): in A's eigenbasis,
    // d log A = V (F o (V^T dA V)) V^T, F_ij = (log l_i - log l_j) / (l_i - l_j) (1 / l_i if equal)
    Matrix4 F;
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) F(i, j) = log_difference_quotient(lambda[i], lambda[j]);
    }
    for (int k = 0; k < 10; ++k) {
      const Matrix4 dA =
          L0_inverse_ * pseudo_inertia_derivative(theta, U, k) * L0_inverse_.transpose();
      const Matrix4 in_basis = V.transpose() * dA * V;
      jacobian->col(k) = upper_triangle(V * F.cwiseProduct(in_basis) * V.transpose());
    }
  }
  return upper_triangle(V * log_lambda.asDiagonal() * V.transpose());
}

double smallest_relative_eigenvalue(const Matrix4& J) {
  const Eigen::SelfAdjointEigenSolver<Matrix4> eig(J, Eigen::EigenvaluesOnly);
  const double trace = J.trace();
  return trace > 0 ? eig.eigenvalues()[0] / trace : eig.eigenvalues()[0];
}

}  // namespace lever::identify::detail
