// RigidInertia's inertial-parameter conversions (lever/spatial.hpp): the ten parameters, MJCF's
// principal form and the pseudo-inertia.
#include <lever/error.hpp>
#include <lever/spatial.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace lever {

namespace {

// I of the parameters' last six, [xx, yy, zz, xy, xz, yz].
Eigen::Matrix3d rotational_inertia(const InertialParameters& pi) {
  Eigen::Matrix3d I;
  I << pi[4], pi[7], pi[8], pi[7], pi[5], pi[9], pi[8], pi[9], pi[6];
  return I;
}

}  // namespace

InertialParameters RigidInertia::to_parameters() const {
  InertialParameters pi;
  pi << m, h, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2);
  return pi;
}

RigidInertia RigidInertia::from_parameters(const InertialParameters& pi) {
  RigidInertia out;
  out.m = pi[0];
  out.h = pi.segment<3>(1);
  out.I = rotational_inertia(pi);
  return out;
}

RigidInertia RigidInertia::from_principal(const PrincipalInertia& principal) {
  const Eigen::Matrix3d R = quat_to_mat(quat_normalized(principal.quat));
  const Eigen::Matrix3d Ic = R * principal.diaginertia.asDiagonal() * R.transpose();
  return from_com(principal.mass, principal.pos, Ic);
}

PrincipalInertia RigidInertia::to_principal() const {
  if (!(m > 0) || !std::isfinite(m)) {
    throw ModelError("inertial parameters: mass " + std::to_string(m) + " is not positive.");
  }
  PrincipalInertia out;
  out.mass = m;
  out.pos = h / m;
  const Eigen::Vector3d& c = out.pos;
  // the parallel-axis theorem backwards: about the centre of mass, Ic = I - m (|c|^2 1 - c c^T)
  const Eigen::Matrix3d Ic =
      I - m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(Ic);
  const Eigen::Vector3d& d = eig.eigenvalues();  // increasing
  if (!(d[0] > 0) || d[0] + d[1] < d[2] * (1 - 1e-12)) {
    std::ostringstream s;
    s << "inertial parameters: principal moments " << d[0] << ", " << d[1] << ", " << d[2]
      << " about the centre of mass are not a rigid body's (each must be positive and at most "
         "the sum of the other two).";
    throw ModelError(s.str());
  }
  Eigen::Matrix3d R = eig.eigenvectors();
  if (R.determinant() < 0) R.col(2) = -R.col(2);  // a proper rotation
  out.quat = quat_from_mat(R);
  out.diaginertia = d;
  // A planar body sits on the triangle equality A + B = C, where identification's physical fit
  // lands whenever that constraint is active; the eigenvalues then miss it by rounding either
  // way. MuJoCo's compiler checks A + B >= C exactly, so C takes the sum (a change within the
  // 1e-12 accepted above) and the moments load back.
  out.diaginertia[2] = std::min(d[2], d[0] + d[1]);
  return out;
}

Eigen::Matrix4d RigidInertia::to_pseudo_inertia() const {
  Eigen::Matrix4d J;
  J.topLeftCorner<3, 3>() = 0.5 * I.trace() * Eigen::Matrix3d::Identity() - I;
  J.topRightCorner<3, 1>() = h;
  J.bottomLeftCorner<1, 3>() = h.transpose();
  J(3, 3) = m;
  return J;
}

RigidInertia RigidInertia::from_pseudo_inertia(const Eigen::Matrix4d& J) {
  // tr(Sigma) = tr(I)/2 3 - tr(I) = tr(I)/2, so I = tr(Sigma) 1 - Sigma
  const Eigen::Matrix3d sigma = J.topLeftCorner<3, 3>();
  RigidInertia out;
  out.m = J(3, 3);
  out.h = J.topRightCorner<3, 1>();
  out.I = sigma.trace() * Eigen::Matrix3d::Identity() - sigma;
  return out;
}

}  // namespace lever
