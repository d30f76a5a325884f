// The physical fit's coordinates for one body: log-Cholesky factors of its pseudo-inertia, which
// keep it positive definite, and the geodesic distance between pseudo-inertias. Internal to
// identification; the conversions between a body's parameters and its pseudo-inertia are the
// engine's (RigidInertia::to_pseudo_inertia / from_pseudo_inertia, lever/spatial.hpp).
//
// The pseudo-inertia (Wensing, Kim and Slotine 2017) of a body with parameters
// pi = [m, h = m c, I about the frame origin] is J = [Sigma h; h^T m], Sigma = tr(I)/2 1 - I,
// and pi belongs to a rigid body (some nonnegative mass distribution) exactly when J is positive
// semidefinite: m >= 0, and the principal moments about the centre of mass positive and within
// the triangle inequality, which is Sigma - h h^T / m >= 0.
//
// Log-Cholesky coordinates (Rucker and Wensing 2022): J = U U^T with
//   U = e^alpha [e^d1 s12 s13 t1; 0 e^d2 s23 t2; 0 0 e^d3 t3; 0 0 0 1],
// theta = [alpha, d1, d2, d3, s12, s23, s13, t1, t2, t3] free in R^10, every theta a positive
// definite J and every positive definite J one theta. m = e^(2 alpha).
#pragma once

#include <Eigen/Core>

#include <lever/spatial.hpp>

namespace lever::identify::detail {

using Matrix4 = Eigen::Matrix4d;
using LogCholesky = Eigen::Matrix<double, 10, 1>;
using Jacobian10 = Eigen::Matrix<double, 10, 10>;

/// U of theta.
Matrix4 upper_factor(const LogCholesky& theta);

/// theta of a positive definite J. @pre J positive definite (else the result is not finite).
LogCholesky log_cholesky_of(const Matrix4& J);

/// pi of theta and d pi / d theta (10 x 10).
InertialParameters parameters_of(const LogCholesky& theta, Jacobian10* jacobian);

/// Lee and Park's geodesic distance on positive definite matrices, written as residuals:
/// r(J) = the upper triangle of log(L0^-1 J L0^-T) (J0 = L0 L0^T), off-diagonal entries times
/// sqrt(2), so |r|^2 = |log(J0^-1/2 J J0^-1/2)|_F^2 = sum_i log^2 lambda_i(J0^-1 J). Invariant
/// under a change of body frame and of units (J -> T J T^T for both), zero only at J = J0.
class GeodesicResidual {
 public:
  /// @pre J0 positive definite.
  explicit GeodesicResidual(const Matrix4& J0);
  /// r at J, and d r / d theta through the log-Cholesky factor (when jacobian is not null).
  Eigen::Matrix<double, 10, 1> operator()(const LogCholesky& theta, Jacobian10* jacobian) const;

 private:
  Matrix4 L0_inverse_;
};

/// The smallest eigenvalue of J normalised by its trace (J's scale): >= 0 for a rigid body.
double smallest_relative_eigenvalue(const Matrix4& J);

}  // namespace lever::identify::detail
