// lever/spatial.hpp: the spatial (6D) algebra of Featherstone's "Rigid Body Dynamics Algorithms"
// (2008), chapter 2, and the quaternion helpers the kinematics needs.
//
// Conventions, as in the book and in MuJoCo:
//   Motion m = [angular; linear]   (omega; v at the frame origin)
//   Force  f = [moment;  force]    (n about the frame origin; f)
//   Transform X = ^B X_A = rot(E) xlt(r): maps motion vectors from A coordinates to B coordinates;
//     E rotates A coordinates into B coordinates, r is B's origin expressed in A.
//   Quaternions are (w, x, y, z), as in MuJoCo.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lever {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Motion = Vector6d;  ///< spatial motion vector [angular; linear]
using Force = Vector6d;   ///< spatial force vector [moment; force]

/// Skew-symmetric matrix of a 3-vector: skew(a) b = a x b.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d s;
  s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return s;
}

/// Plücker coordinate transform ^B X_A = rot(E) xlt(r) (Featherstone eq. 2.24).
struct Transform {
  Eigen::Matrix3d E = Eigen::Matrix3d::Identity();  ///< A coordinates -> B coordinates
  Eigen::Vector3d r = Eigen::Vector3d::Zero();      ///< B's origin, A coordinates

  /// X m: the motion vector m (A coordinates) in B coordinates.
  Motion apply(const Motion& m) const {
    Motion out;
    const Eigen::Vector3d w = m.head<3>();
    out.head<3>().noalias() = E * w;
    out.tail<3>().noalias() = E * (m.tail<3>() - r.cross(w));
    return out;
  }

  /// X^T f = ^A X_B^* f: the force f (B coordinates) in A coordinates.
  Force apply_transpose(const Force& f) const {
    Force out;
    out.tail<3>().noalias() = E.transpose() * f.tail<3>();
    out.head<3>().noalias() = E.transpose() * f.head<3>();
    out.head<3>() += r.cross(out.tail<3>());
    return out;
  }

  /// ^B X_C = ^B X_A * ^A X_C.
  Transform operator*(const Transform& A_X_C) const {
    Transform out;
    out.E.noalias() = E * A_X_C.E;
    out.r = A_X_C.r + A_X_C.E.transpose() * r;
    return out;
  }
};

/// Spatial inertia of a rigid body (or of a rigid assembly) about a frame's origin, in that frame
/// (Featherstone eq. 2.63): mass m, first moment h = m c, rotational inertia I about the origin.
struct RigidInertia {
  double m = 0.0;
  Eigen::Vector3d h = Eigen::Vector3d::Zero();
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();

  /// The momentum I v of a body moving with v.
  Force operator*(const Motion& v) const {
    Force out;
    const Eigen::Vector3d w = v.head<3>();
    const Eigen::Vector3d lin = v.tail<3>();
    out.head<3>().noalias() = I * w;
    out.head<3>() += h.cross(lin);
    out.tail<3>() = m * lin - h.cross(w);
    return out;
  }

  RigidInertia& operator+=(const RigidInertia& other) {
    m += other.m;
    h += other.h;
    I += other.I;
    return *this;
  }

  /// X^T I X, where I is expressed in B coordinates and X = ^B X_A: the same inertia in A
  /// coordinates (Featherstone eq. 2.66, in its compact form).
  RigidInertia expressed_in_parent(const Transform& X) const {
    RigidInertia out;
    out.m = m;
    const Eigen::Vector3d hA = X.E.transpose() * h;  // first moment about B's origin, A axes
    out.h = hA + m * X.r;
    const Eigen::Matrix3d IA = X.E.transpose() * I * X.E;  // about B's origin, A axes
    // shift from B's origin to A's origin (B's origin sits at r in A): I + r x h x + (h + m r) x r x
    const Eigen::Matrix3d rx = skew(X.r);
    out.I = IA - rx * skew(hA) - skew(out.h) * rx;
    return out;
  }

  /// A body of mass m, centre of mass c and rotational inertia Ic about c, all in this frame.
  static RigidInertia from_com(double mass, const Eigen::Vector3d& c, const Eigen::Matrix3d& Ic) {
    RigidInertia out;
    out.m = mass;
    out.h = mass * c;
    const Eigen::Matrix3d cx = skew(c);
    out.I = Ic - mass * cx * cx;
    return out;
  }

  /// 6x6 matrix form (for tests and printing).
  Eigen::Matrix<double, 6, 6> matrix() const {
    Eigen::Matrix<double, 6, 6> M;
    const Eigen::Matrix3d hx = skew(h);
    M << I, hx, hx.transpose(), m * Eigen::Matrix3d::Identity();
    return M;
  }
};

/// v x m: the derivative of motion vector m moving with velocity v (Featherstone eq. 2.31).
inline Motion cross_motion(const Motion& v, const Motion& m) {
  Motion out;
  const Eigen::Vector3d w = v.head<3>();
  out.head<3>() = w.cross(m.head<3>());
  out.tail<3>() = w.cross(m.tail<3>()) + v.tail<3>().cross(m.head<3>());
  return out;
}

/// v x* f: the derivative of force vector f moving with velocity v (Featherstone eq. 2.32).
inline Force cross_force(const Motion& v, const Force& f) {
  Force out;
  const Eigen::Vector3d w = v.head<3>();
  out.head<3>() = w.cross(f.head<3>()) + v.tail<3>().cross(f.tail<3>());
  out.tail<3>() = w.cross(f.tail<3>());
  return out;
}

// ---- quaternions (w, x, y, z) -----------------------------------------------------------------

using Quat = Eigen::Vector4d;

/// Hamilton product a * b.
inline Quat quat_mul(const Quat& a, const Quat& b) {
  return Quat(a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
              a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
              a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
              a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]);
}

/// The rotation matrix of a unit quaternion (maps local to parent coordinates).
inline Eigen::Matrix3d quat_to_mat(const Quat& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Eigen::Matrix3d R;
  R << w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y),
      2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x),
      2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z;
  return R;
}

/// q / |q|, or the identity for a (near) zero quaternion.
inline Quat quat_normalized(const Quat& q) {
  const double n = q.norm();
  return n < 1e-15 ? Quat(1, 0, 0, 0) : Quat(q / n);
}

/// Rotation by angle (rad) about a unit axis.
Quat quat_from_axis_angle(const Eigen::Vector3d& axis, double angle);

/// A unit quaternion for a proper rotation matrix.
Quat quat_from_mat(const Eigen::Matrix3d& R);

}  // namespace lever
