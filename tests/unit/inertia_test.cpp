// RigidInertia's inertial-parameter conversions (lever/spatial.hpp, engine/src/basics/inertia.cpp): the
// ten parameters, MJCF's principal form and the pseudo-inertia. Exact cases built from numbers
// whose products are exact in binary, round trips on random rigid bodies, and the refusals.
#include <catch2/catch.hpp>

#include <lever/error.hpp>
#include <lever/spatial.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>
#include <random>

namespace {

using lever::InertialParameters;
using lever::PrincipalInertia;
using lever::RigidInertia;

// A random rigid body: its principal moments come from the second moments (x2, y2, z2 > 0) of
// a mass distribution (Ixx = y2 + z2, ...), so they keep the triangle inequality strictly.
PrincipalInertia random_body(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PrincipalInertia p;
  p.mass = 0.1 + 5.0 * std::abs(u(rng));
  p.pos << 0.5 * u(rng), 0.5 * u(rng), 0.5 * u(rng);
  const Eigen::Vector3d second =
      p.mass * Eigen::Vector3d(0.001 + 0.05 * std::abs(u(rng)), 0.001 + 0.05 * std::abs(u(rng)),
                               0.001 + 0.05 * std::abs(u(rng)));
  p.diaginertia << second.y() + second.z(), second.x() + second.z(), second.x() + second.y();
  p.quat << u(rng), u(rng), u(rng), u(rng);
  p.quat.normalize();
  return p;
}

// The inertia about the centre of mass that a principal form gives, in the body frame.
Eigen::Matrix3d central(const PrincipalInertia& p) {
  const Eigen::Matrix3d R = lever::quat_to_mat(lever::quat_normalized(p.quat));
  return R * p.diaginertia.asDiagonal() * R.transpose();
}

double largest(const Eigen::MatrixXd& x) { return x.cwiseAbs().maxCoeff(); }

}  // namespace

TEST_CASE("inertial parameters: a point mass has m, m c and m (|c|^2 1 - c c^T)", "[inertia]") {
  // every product of these numbers is exact in binary, so the parameters are too
  const PrincipalInertia point{2.0, {0.5, -0.25, 1.0}, {1, 0, 0, 0}, {0, 0, 0}};
  const InertialParameters pi = RigidInertia::from_principal(point).to_parameters();
  const double m = 2.0, x = 0.5, y = -0.25, z = 1.0;
  InertialParameters expected;
  expected << m, m * x, m * y, m * z, m * (y * y + z * z), m * (x * x + z * z), m * (x * x + y * y),
      -m * x * y, -m * x * z, -m * y * z;
  CHECK(pi == expected);
  // its pseudo-inertia is the second moment of one point: m [c; 1] [c; 1]^T
  const Eigen::Vector4d c1(x, y, z, 1.0);
  const Eigen::Matrix4d J = RigidInertia::from_principal(point).to_pseudo_inertia();
  CHECK(J == Eigen::Matrix4d(m * c1 * c1.transpose()));
}

TEST_CASE("inertial parameters: principal axes permuted, then moved off the centre of mass",
          "[inertia]") {
  // q = (1, 1, 1, 1) / 2 turns 120 degrees about (1, 1, 1): the principal x axis is the body's y,
  // principal y is body z, principal z is body x (its matrix is a permutation, exact)
  const PrincipalInertia body{2.0, {0.5, -0.25, 1.0}, {0.5, 0.5, 0.5, 0.5}, {0.5, 0.75, 1.0}};
  const RigidInertia inertia = RigidInertia::from_principal(body);
  const double m = 2.0, x = 0.5, y = -0.25, z = 1.0;
  InertialParameters expected;
  expected << m, m * x, m * y, m * z, 1.0 + m * (y * y + z * z), 0.5 + m * (x * x + z * z),
      0.75 + m * (x * x + y * y), -m * x * y, -m * x * z, -m * y * z;
  CHECK(inertia.to_parameters() == expected);

  // and back: the centre of mass, and the moments in increasing order about axes that give the
  // same central inertia (an eigen decomposition: its rounding, a few ulps of the moments)
  const PrincipalInertia back = inertia.to_principal();
  CHECK(back.mass == m);
  CHECK(back.pos == body.pos);
  CHECK(largest(back.diaginertia - body.diaginertia) <= 8 * std::numeric_limits<double>::epsilon());
  CHECK(largest(central(back) - central(body)) <= 8 * std::numeric_limits<double>::epsilon());
}

TEST_CASE("inertial parameters: random rigid bodies round-trip through every form", "[inertia]") {
  std::mt19937_64 rng(20);
  const double eps = std::numeric_limits<double>::epsilon();
  for (int trial = 0; trial < 1000; ++trial) {
    INFO("trial " << trial);
    const PrincipalInertia body = random_body(rng);
    const RigidInertia inertia = RigidInertia::from_principal(body);
    const InertialParameters pi = inertia.to_parameters();

    // the ten parameters are the spatial inertia's numbers: bit for bit both ways
    const RigidInertia again = RigidInertia::from_parameters(pi);
    CHECK(again.m == inertia.m);
    CHECK(again.h == inertia.h);
    CHECK(again.I == inertia.I);
    CHECK(again.to_parameters() == pi);
    CHECK(inertia.matrix() == again.matrix());

    // the pseudo-inertia: positive definite for a body whose moments keep the triangle strictly;
    // back to the parameters through traces (a sum of three, a few ulps of I)
    const Eigen::Matrix4d J = inertia.to_pseudo_inertia();
    CHECK(J(3, 3) == body.mass);
    CHECK(J.topRightCorner<3, 1>() == inertia.h);
    CHECK(J == J.transpose());
    CHECK(Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(J).eigenvalues()[0] > 0);
    const InertialParameters from_J = RigidInertia::from_pseudo_inertia(J).to_parameters();
    CHECK(largest(from_J - pi) <= 4 * eps * largest(pi));

    // the principal form: mass exact, centre of mass h / m, the same central inertia. That is I
    // minus the parallel-axis term, so it is rounded to the parameters' scale, not to the
    // (smaller) principal moments' (seen here: 1.1 eps of the parameters, 38 eps of the moments)
    const PrincipalInertia back = inertia.to_principal();
    CHECK(back.mass == body.mass);
    CHECK(largest(back.pos - body.pos) <= 4 * eps * largest(body.pos));
    CHECK(largest(central(back) - central(body)) <= 4 * eps * largest(pi));
    CHECK(back.diaginertia[0] <= back.diaginertia[1]);
    CHECK(back.diaginertia[1] <= back.diaginertia[2]);
    CHECK(std::abs(back.quat.norm() - 1.0) <= 4 * eps);
    CHECK(lever::quat_to_mat(back.quat).determinant() > 0);
    // and once more to the parameters
    const InertialParameters round = RigidInertia::from_principal(back).to_parameters();
    CHECK(largest(round - pi) <= 4 * eps * largest(pi));
  }
}

TEST_CASE("inertial parameters: the pseudo-inertia is linear and adds as bodies do", "[inertia]") {
  std::mt19937_64 rng(7);
  const RigidInertia a = RigidInertia::from_principal(random_body(rng));
  const RigidInertia b = RigidInertia::from_principal(random_body(rng));
  RigidInertia sum = a;
  sum += b;
  const Eigen::Matrix4d expected = a.to_pseudo_inertia() + b.to_pseudo_inertia();
  CHECK(largest(sum.to_pseudo_inertia() - expected) <=
        4 * std::numeric_limits<double>::epsilon() * largest(expected));
  CHECK(sum.to_parameters() == a.to_parameters() + b.to_parameters());
}

TEST_CASE("inertial parameters: the pseudo-inertia is semidefinite exactly for a rigid body",
          "[inertia]") {
  // principal moments (1, 1, 2) are a flat disc's (the triangle inequality with equality): J is
  // singular, one moment more breaks it, one less makes it definite
  PrincipalInertia disc{2.0, {0.1, -0.2, 0.3}, {1, 0, 0, 0}, {1.0, 1.0, 2.0}};
  const auto smallest = [](const PrincipalInertia& p) {
    const Eigen::Matrix4d J = RigidInertia::from_principal(p).to_pseudo_inertia();
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(J).eigenvalues()[0];
  };
  CHECK(std::abs(smallest(disc)) <= 1e-14);
  CHECK_NOTHROW(RigidInertia::from_principal(disc).to_principal());
  disc.diaginertia[2] = 2.01;  // A + B < C: no body has these moments
  CHECK(smallest(disc) < -1e-4);
  CHECK_THROWS_WITH(RigidInertia::from_principal(disc).to_principal(),
                    Catch::Contains("not a rigid body's"));
  disc.diaginertia[2] = 1.99;
  CHECK(smallest(disc) > 1e-4);
}

TEST_CASE("inertial parameters: what is no rigid body has no principal form", "[inertia]") {
  const PrincipalInertia rod{1.0, {0.25, 0, 0}, {1, 0, 0, 0}, {0.0001, 0.02, 0.02}};
  const InertialParameters pi = RigidInertia::from_principal(rod).to_parameters();
  CHECK_NOTHROW(RigidInertia::from_parameters(pi).to_principal());
  for (const double mass : {-1.0, 0.0, std::numeric_limits<double>::quiet_NaN(),
                            std::numeric_limits<double>::infinity()}) {
    INFO("mass " << mass);
    InertialParameters bad = pi;
    bad[0] = mass;
    CHECK_THROWS_AS(RigidInertia::from_parameters(bad).to_principal(), lever::ModelError);
    CHECK_THROWS_WITH(RigidInertia::from_parameters(bad).to_principal(),
                      Catch::Contains("is not positive"));
  }
  InertialParameters flat = pi;
  flat[4] += 1.0;  // Ixx far above Iyy + Izz
  CHECK_THROWS_WITH(RigidInertia::from_parameters(flat).to_principal(),
                    Catch::Contains("not a rigid body's"));
  InertialParameters negative = pi;
  negative[5] = -negative[5];  // a negative principal moment
  CHECK_THROWS_WITH(RigidInertia::from_parameters(negative).to_principal(),
                    Catch::Contains("each must be positive"));
}

TEST_CASE("inertial parameters: a planar body's principal moments load back (A + B >= C exactly)",
          "[inertia]") {
  // A flat body (all its mass in one plane: one second moment zero) sits on the triangle
  // equality, where identification's physical fit lands when that constraint is active; the
  // eigenvalues miss it by rounding either way, and MuJoCo's compiler checks A + B >= C exactly.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int off_by_rounding = 0;
  for (int k = 0; k < 1000; ++k) {
    PrincipalInertia flat = random_body(rng);
    const double x2 = flat.diaginertia[1] + flat.diaginertia[2] - flat.diaginertia[0];
    const double y2 = flat.diaginertia[0] + flat.diaginertia[2] - flat.diaginertia[1];
    flat.diaginertia << y2 / 2, x2 / 2, (x2 + y2) / 2;  // z2 = 0: C = A + B
    const RigidInertia body = RigidInertia::from_principal(flat);
    const Eigen::Matrix3d Ic = central(flat);
    const Eigen::Vector3d d = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(Ic).eigenvalues();
    off_by_rounding += d[0] + d[1] < d[2];
    const PrincipalInertia p = body.to_principal();
    CHECK(p.diaginertia[0] + p.diaginertia[1] >= p.diaginertia[2]);
    // and it is the same body, to rounding
    CHECK(largest(central(p) - Ic) <= 1e-14 * Ic.norm());
  }
  // the case is real: without the correction some of these would not load
  CHECK(off_by_rounding > 0);
}
