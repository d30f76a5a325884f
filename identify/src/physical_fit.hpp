// The physically consistent parameter set that fits the data (internal to lever::identify; see
// docs/derivatives.md, "Physical consistency").
//
// Given the least-squares estimate beta_hat of the base parameters and the data's metric
// |W (beta - beta_hat)| = |R (beta - beta_hat)| (W = Q R, so this is exactly how much the sum of
// squared residuals grows), find the full parameters pi, every body's pseudo-inertia positive
// definite, that
//   1. fit the data first: K pi = beta_hat when a physical pi has those base parameters, else
//      the base parameters nearest beta_hat in the data's metric that a physical pi has;
//   2. among those, are closest to the prior: the sum over bodies of Lee and Park's squared
//      geodesic distance between pseudo-inertias, plus sum ((p - p0) / scale)^2 over armature,
//      damping and estimated gains.
// Each body is written in log-Cholesky coordinates (pseudo_inertia.hpp), so every iterate is
// physical, and the problem is a smooth nonlinear least-squares problem: Levenberg-Marquardt
// on the stacked residual [rho s R (K pi(x) - t); geodesic residuals; (p - p0) / scale], with
// the target t moved by the method of multipliers (t += beta_hat - K pi) until K pi = beta_hat.
// When beta_hat is not physical the multipliers keep growing and the iterates approach the
// physical base parameters nearest beta_hat (the projection onto the convex set of physical
// base parameters does not move as t moves out along its normal).
#pragma once

#include <Eigen/Core>

#include <vector>

namespace lever::identify::detail {

/// Inertial parameters per body in the parameter vector (lever/parameters.hpp's layout).
constexpr int kPerBody = 10;

struct PhysicalProblem {
  Eigen::VectorXd prior;        ///< (n) the prior's parameters (a known body's: its known ones)
  Eigen::MatrixXd K;            ///< (rank x n) base parameters = K pi
  Eigen::MatrixXd R;            ///< (estimated x rank) |W d| = |R d|
  Eigen::VectorXd estimate;     ///< (rank) the least-squares estimate beta_hat
  std::vector<char> body_free;  ///< (bodies) fit this body's ten parameters; else keep prior's
  std::vector<int> linear;      ///< other columns fitted (armature, damping, estimated gains)
  /// (linear) the column is nonnegative (armature, damping): it is fitted as the square of an
  /// unknown, so that no iterate has a negative one
  std::vector<char> linear_nonnegative;
  Eigen::VectorXd linear_scale;  ///< (n) the scale of each linear column's distance
};

struct PhysicalFit {
  Eigen::VectorXd parameters;    ///< (n) pi
  Eigen::VectorXd base;          ///< (rank) K pi
  double misfit = 0.0;           ///< |R (K pi - beta_hat)|: the residual's growth, as a norm
  bool reached = false;          ///< K pi = beta_hat (to 1e-10 of |R beta_hat|)
  std::vector<double> distance;  ///< (bodies) geodesic distance from the prior (0 if fixed)
  int iterations = 0;            ///< Levenberg-Marquardt iterations, all targets together
};

PhysicalFit fit_physical(const PhysicalProblem& problem);

}  // namespace lever::identify::detail
