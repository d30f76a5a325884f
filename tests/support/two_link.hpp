// Lesson 5.1's two-link arm as the lesson names it, read from a compiled model, and its hand
// formulas: the tip position, the gravity torque and the mass matrix. Shared by the tests that
// hold lever (tests/analytic) and `lever check` (tests/cli) to the lesson.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <stdexcept>

#include <lever/model.hpp>

namespace lever::test {

struct TwoLink {
  double L1, L2;             ///< shoulder to elbow, elbow to the ee site (m)
  double m1, m2;             ///< masses (kg)
  double c1, c2;             ///< centres of mass from their joints (m)
  double I1, I2;             ///< moments of inertia about the centres of mass, hinge axis (kg m^2)
  double g;                  ///< gravity (m/s^2)
  Eigen::Vector3d shoulder;  ///< the shoulder axis' position in the world (m)
  double r1, r2;             ///< capsule radii of the links (m), for the inferred masses
  double limit1, limit2;     ///< motor limits (N m)
  double lower1;             ///< the shoulder's lower stop (rad)
};

/// The parameters of a model shaped like arm2.xml (bodies link1, link2, site ee, geoms link1,
/// link2, two motors); throws std::runtime_error if it is not.
inline TwoLink two_link(const Model& model) {
  const int link1 = model.body("link1"), link2 = model.body("link2"), ee = model.site("ee");
  const int geom1 = model.geom("link1"), geom2 = model.geom("link2");
  if (link1 <= 0 || link2 <= 0 || ee < 0 || geom1 < 0 || geom2 < 0 || model.nu < 2) {
    throw std::runtime_error("not a two-link arm shaped like arm2.xml");
  }
  TwoLink p;
  p.L1 = model.body_pos[link2].x();
  p.L2 = model.site_pos[ee].x();
  p.m1 = model.body_mass[link1];
  p.m2 = model.body_mass[link2];
  p.c1 = model.body_ipos[link1].x();
  p.c2 = model.body_ipos[link2].x();
  p.I1 =
      model.body_inertia[link1].y();  // the hinges turn about -y; the principal axes are the body's
  p.I2 = model.body_inertia[link2].y();
  p.g = -model.opt.gravity.z();
  p.shoulder = model.body_pos[link1];
  p.r1 = model.geom_size[geom1].x();
  p.r2 = model.geom_size[geom2].x();
  p.limit1 = model.actuator_ctrlrange[0][1];
  p.limit2 = model.actuator_ctrlrange[1][1];
  p.lower1 = model.jnt_range[0][0];
  return p;
}

/// Tip position: shoulder + (L1 cos q1 + L2 cos(q1 + q2), 0, L1 sin q1 + L2 sin(q1 + q2)).
inline Eigen::Vector3d tip(const TwoLink& p, double q1, double q2) {
  return p.shoulder + Eigen::Vector3d(p.L1 * std::cos(q1) + p.L2 * std::cos(q1 + q2), 0.0,
                                      p.L1 * std::sin(q1) + p.L2 * std::sin(q1 + q2));
}

/// tau_g = dV/dq with V = g [m1 c1 sin q1 + m2 (L1 sin q1 + c2 sin(q1 + q2))].
inline Eigen::Vector2d gravity_torque(const TwoLink& p, double q1, double q2) {
  const double t2 = p.g * p.m2 * p.c2 * std::cos(q1 + q2);
  return {p.g * (p.m1 * p.c1 + p.m2 * p.L1) * std::cos(q1) + t2, t2};
}

/// The 2x2 mass matrix: M11 = I1 + I2 + m1 c1^2 + m2 (L1^2 + c2^2 + 2 L1 c2 cos q2), ...
inline Eigen::Matrix2d mass_matrix(const TwoLink& p, double q2) {
  const double c = std::cos(q2);
  const double m22 = p.I2 + p.m2 * p.c2 * p.c2;
  const double m12 = m22 + p.m2 * p.L1 * p.c2 * c;
  const double m11 =
      p.I1 + p.m1 * p.c1 * p.c1 + p.I2 + p.m2 * (p.L1 * p.L1 + p.c2 * p.c2 + 2 * p.L1 * p.c2 * c);
  Eigen::Matrix2d M;
  M << m11, m12, m12, m22;
  return M;
}

}  // namespace lever::test
