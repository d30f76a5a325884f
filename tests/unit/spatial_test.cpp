// Spatial algebra against its matrix definitions (Featherstone, RBDA chapter 2).
#include <catch2/catch.hpp>

#include <lever/spatial.hpp>

#include <random>

namespace {

using lever::Motion;

Eigen::Matrix<double, 6, 6> crm(const Motion& v) {  // v x, as a 6x6 matrix (eq. 2.31)
  Eigen::Matrix<double, 6, 6> X = Eigen::Matrix<double, 6, 6>::Zero();
  X.topLeftCorner<3, 3>() = lever::skew(v.head<3>());
  X.bottomRightCorner<3, 3>() = lever::skew(v.head<3>());
  X.bottomLeftCorner<3, 3>() = lever::skew(v.tail<3>());
  return X;
}

Motion random6(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-2, 2);
  Motion v;
  for (int i = 0; i < 6; ++i) v[i] = u(rng);
  return v;
}

// A valid rigid-body inertia: positive mass, centre of mass c, SPD rotational inertia about c.
lever::RigidInertia random_inertia(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.1, 2);
  const Eigen::Vector3d c(u(rng) - 1, u(rng) - 1, u(rng) - 1);
  Eigen::Matrix3d A = Eigen::Matrix3d::Random();
  const Eigen::Matrix3d Ic = A * A.transpose() + 0.1 * Eigen::Matrix3d::Identity();
  return lever::RigidInertia::from_com(u(rng), c, Ic);
}

constexpr double kTight = 1e-13;  // a handful of roundings on O(1) numbers

}  // namespace

TEST_CASE("cross_motion and cross_force are v x and -(v x)^T", "[spatial]") {
  std::mt19937_64 rng(1);
  for (int trial = 0; trial < 100; ++trial) {
    const Motion v = random6(rng), m = random6(rng), f = random6(rng);
    CHECK((lever::cross_motion(v, m) - crm(v) * m).norm() < kTight);
    CHECK((lever::cross_force(v, f) + crm(v).transpose() * f).norm() < kTight);
    CHECK(lever::cross_motion(v, v).norm() < kTight);  // a body's velocity does not turn itself
  }
}

TEST_CASE("RigidInertia times a motion equals its 6x6 matrix times it", "[spatial]") {
  std::mt19937_64 rng(2);
  for (int trial = 0; trial < 100; ++trial) {
    const lever::RigidInertia I = random_inertia(rng);
    const Motion v = random6(rng);
    CHECK(((I * v) - I.matrix() * v).norm() < kTight);
    // kinetic energy 1/2 v.Iv is positive for any motion
    CHECK(v.dot(I * v) > 0);
    const Eigen::Matrix<double, 6, 6> M = I.matrix();
    CHECK((M - M.transpose()).norm() == 0.0);
  }
}

TEST_CASE("from_com: a point mass at c has I = m (|c|^2 1 - c c^T)", "[spatial]") {
  const Eigen::Vector3d c(0.3, -0.2, 0.5);
  const double m = 2.0;
  const lever::RigidInertia I = lever::RigidInertia::from_com(m, c, Eigen::Matrix3d::Zero());
  const Eigen::Matrix3d expected =
      m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  CHECK((I.I - expected).norm() < kTight);
  CHECK((I.h - m * c).norm() == 0.0);
}

TEST_CASE("quaternions: composition matches rotation matrices, and normalization", "[spatial]") {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const lever::Quat a = lever::quat_from_axis_angle(axis, 3 * u(rng));
    const lever::Quat b = lever::quat_normalized(lever::Quat(u(rng), u(rng), u(rng), u(rng)));
    const Eigen::Matrix3d Ra = lever::quat_to_mat(a), Rb = lever::quat_to_mat(b);
    CHECK((lever::quat_to_mat(lever::quat_mul(a, b)) - Ra * Rb).norm() < kTight);
    CHECK((Ra * Ra.transpose() - Eigen::Matrix3d::Identity()).norm() < kTight);
    CHECK(std::abs(Ra.determinant() - 1) < kTight);
    // back from the matrix: the same rotation (q or -q)
    const lever::Quat back = lever::quat_from_mat(Ra);
    CHECK(std::min((back - a).norm(), (back + a).norm()) < 1e-12);
    // the rotation about axis maps axis to itself
    CHECK((Ra * axis - axis).norm() < kTight);
  }
  CHECK(lever::quat_normalized(lever::Quat::Zero()) == lever::Quat(1, 0, 0, 0));
}
