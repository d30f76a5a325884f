// identify's log-Cholesky coordinates of the pseudo-inertia (identify/src/pseudo_inertia.hpp): the
// conversions round-trip, the Jacobians equal central differences, and the geodesic distance is
// what its definition says and does not depend on the body frame. (The pseudo-inertia itself is
// the engine's, RigidInertia::to_pseudo_inertia: tests/unit/inertia_test.cpp.)
#include <catch2/catch.hpp>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <lever/regressor.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include <lever/harness/models.hpp>

#include "pseudo_inertia.hpp"

namespace lever::test {

namespace {

using identify::detail::GeodesicResidual;
using identify::detail::Jacobian10;
using identify::detail::LogCholesky;
using identify::detail::Matrix4;

LogCholesky random_theta(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  LogCholesky theta;
  for (int k = 0; k < 10; ++k) theta[k] = u(rng);
  return theta;
}

}  // namespace

TEST_CASE("log-Cholesky: every body of panda7 round-trips", "[identify]") {
  const Model panda = mjcf::load_file(model_path("models/panda7.xml"));
  for (int b = 1; b < panda.nbody; ++b) {
    INFO(panda.body_name[b]);
    const InertialParameters pi = body_parameters(panda, b);
    const Matrix4 J = RigidInertia::from_parameters(pi).to_pseudo_inertia();
    // a real body's J is positive definite, and its log-Cholesky coordinates give it back
    CHECK(Eigen::SelfAdjointEigenSolver<Matrix4>(J).eigenvalues()[0] > 0);
    const LogCholesky theta = identify::detail::log_cholesky_of(J);
    const InertialParameters back = identify::detail::parameters_of(theta, nullptr);
    CHECK((back - pi).cwiseAbs().maxCoeff() <= 1e-13 * pi.cwiseAbs().maxCoeff());
    CHECK(std::exp(2 * theta[0]) == Approx(pi[0]).epsilon(1e-14));  // m = e^(2 alpha)
  }
}

TEST_CASE(
    "pseudo-inertia: d pi / d theta and the geodesic residual's Jacobian are the "
    "derivatives",
    "[identify]") {
  std::mt19937_64 rng(3);
  const double h = 1e-6;
  for (int trial = 0; trial < 20; ++trial) {
    const LogCholesky theta = random_theta(rng);
    const Matrix4 U0 = identify::detail::upper_factor(random_theta(rng));
    const GeodesicResidual distance(U0 * U0.transpose());
    Jacobian10 dpi, dr;
    identify::detail::parameters_of(theta, &dpi);
    distance(theta, &dr);
    for (int k = 0; k < 10; ++k) {
      LogCholesky up = theta, down = theta;
      up[k] += h;
      down[k] -= h;
      const Eigen::Matrix<double, 10, 1> fd_pi = (identify::detail::parameters_of(up, nullptr) -
                                                  identify::detail::parameters_of(down, nullptr)) /
                                                 (2 * h);
      const Eigen::Matrix<double, 10, 1> fd_r =
          (distance(up, nullptr) - distance(down, nullptr)) / (2 * h);
      INFO("trial " << trial << ", theta_" << k);
      // central differences: truncation h^2/6 |f'''| and rounding eps |f| / h, both below 1e-8
      // of the scale here (|theta| <= 1)
      CHECK((dpi.col(k) - fd_pi).cwiseAbs().maxCoeff() <=
            1e-7 * std::max(1.0, dpi.cwiseAbs().maxCoeff()));
      CHECK((dr.col(k) - fd_r).cwiseAbs().maxCoeff() <=
            1e-7 * std::max(1.0, dr.cwiseAbs().maxCoeff()));
    }
  }
}

TEST_CASE("pseudo-inertia: the geodesic distance is Lee and Park's and frame-independent",
          "[identify]") {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const Matrix4 U0 = identify::detail::upper_factor(random_theta(rng));
    const Matrix4 J0 = U0 * U0.transpose();
    const LogCholesky theta = random_theta(rng);
    const Matrix4 U = identify::detail::upper_factor(theta);
    const Matrix4 J = U * U.transpose();
    // sum of log^2 of the generalised eigenvalues of (J, J0)
    const Eigen::GeneralizedSelfAdjointEigenSolver<Matrix4> pencil(J, J0);
    const double expected = std::sqrt(pencil.eigenvalues().array().log().square().sum());
    const double distance = GeodesicResidual(J0)(theta, nullptr).norm();
    CHECK(distance == Approx(expected).epsilon(1e-12));
    CHECK(GeodesicResidual(J)(identify::detail::log_cholesky_of(J), nullptr).norm() <= 1e-12);
    // another body frame and other units: J -> T J T^T with T = [s R, s p; 0 1] for both
    Eigen::Matrix3d R = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    Matrix4 T = Matrix4::Identity();
    T.topLeftCorner<3, 3>() = 2.5 * R;
    T.topRightCorner<3, 1>() << 0.3, -1.0, 0.7;
    const Matrix4 J0_moved = T * J0 * T.transpose(), J_moved = T * J * T.transpose();
    const double moved =
        GeodesicResidual(J0_moved)(identify::detail::log_cholesky_of(J_moved), nullptr).norm();
    // the distance is frame-independent in exact arithmetic; the moved matrices carry the
    // transform's rounding through a log and a Cholesky factor
    CHECK(moved == Approx(distance).epsilon(1e-10));
  }
}

}  // namespace lever::test
