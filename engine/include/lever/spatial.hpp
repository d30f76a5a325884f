// lever/spatial.hpp: the spatial (6D) algebra of Featherstone's "Rigid Body Dynamics Algorithms"
// (2008), chapter 2, and the quaternion helpers the kinematics needs.
//
// Conventions, as in the book and in MuJoCo:
//   Motion m = [angular; linear]   (omega; v of the body point at the frame origin)
//   Force  f = [moment;  force]    (n about the frame origin; f)
//   Quaternions are (w, x, y, z), as in MuJoCo.
// lever's algorithms express every spatial vector in one frame (see data.hpp), so no coordinate
// transforms appear in them.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace lever {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Motion = Vector6d;  ///< spatial motion vector [angular; linear]
using Force = Vector6d;   ///< spatial force vector [moment; force]
/// A rotation matrix, stored row by row as MuJoCo stores xmat, so that an array of them is an
/// (n, 9) array in MuJoCo's layout (the Python and JavaScript views rely on it).
using Mat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

/// Skew-symmetric matrix of a 3-vector: skew(a) b = a x b.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d s;
  s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return s;
}

/// R v for a 3x3 rotation R, written out (the compiler schedules it better than a generic product).
inline Eigen::Vector3d rotate(const Mat3& R, const Eigen::Vector3d& v) {
  return Eigen::Vector3d(R(0, 0) * v[0] + R(0, 1) * v[1] + R(0, 2) * v[2],
                         R(1, 0) * v[0] + R(1, 1) * v[1] + R(1, 2) * v[2],
                         R(2, 0) * v[0] + R(2, 1) * v[1] + R(2, 2) * v[2]);
}

/// R^T v.
inline Eigen::Vector3d rotate_back(const Mat3& R, const Eigen::Vector3d& v) {
  return Eigen::Vector3d(R(0, 0) * v[0] + R(1, 0) * v[1] + R(2, 0) * v[2],
                         R(0, 1) * v[0] + R(1, 1) * v[1] + R(2, 1) * v[2],
                         R(0, 2) * v[0] + R(1, 2) * v[1] + R(2, 2) * v[2]);
}

/// a x b.
inline Eigen::Vector3d cross(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return Eigen::Vector3d(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                         a[0] * b[1] - a[1] * b[0]);
}

// ---- inertial parameters: the forms of a body's inertia besides the spatial one ------
// RigidInertia converts to and from each (its members at the end of the struct, defined in
// engine/src/basics/inertia.cpp), as Pinocchio's Inertia::toDynamicParameters / FromDynamicParameters.

/// The ten inertial parameters of a body about a frame, in that frame (Atkeson, An and Hollerbach
/// 1986): [m, h = m c (3), I about the origin (xx, yy, zz, xy, xz, yz)]. Inverse dynamics is linear
/// in them (the regressor's columns, lever/regressor.hpp), and those of two bodies add.
using InertialParameters = Eigen::Matrix<double, 10, 1>;

/// A body's inertia as MJCF's <inertial> gives it, and Model's body_mass, body_ipos, body_iquat,
/// body_inertia hold it: mass, centre of mass (pos), principal axes (quat, w x y z: the principal
/// frame in this frame) and the principal moments about the centre of mass (diaginertia).
struct PrincipalInertia {
  double mass = 0.0;
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();
  Eigen::Vector4d quat{1, 0, 0, 0};
  Eigen::Vector3d diaginertia = Eigen::Vector3d::Zero();
};

/// Spatial inertia of a rigid body (or of a rigid assembly) about a frame's origin, in that frame
/// (Featherstone eq. 2.63): mass m, first moment h = m c, rotational inertia I about the origin.
struct RigidInertia {
  double m = 0.0;
  Eigen::Vector3d h = Eigen::Vector3d::Zero();
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();  ///< symmetric

  /// The momentum I v of a body moving with v: [I w + h x v; m v - h x w].
  /// Written out on I's elements: I is column-major, and a product through rotate() (row-major)
  /// would copy it first. Each angular row is summed left to right, I's three terms and then
  /// h x v's two, as MuJoCo's mju_mulInertVec sums it: where the terms cancel (a thin rod's axial
  /// entry of M), another order rounds to another last bit, which the cancellation magnifies.
  Force operator*(const Motion& v) const {
    const double w0 = v[0], w1 = v[1], w2 = v[2], l0 = v[3], l1 = v[4], l2 = v[5];
    Force out;
    out[0] = I(0, 0) * w0 + I(0, 1) * w1 + I(0, 2) * w2 - h[2] * l1 + h[1] * l2;
    out[1] = I(1, 0) * w0 + I(1, 1) * w1 + I(1, 2) * w2 + h[2] * l0 - h[0] * l2;
    out[2] = I(2, 0) * w0 + I(2, 1) * w1 + I(2, 2) * w2 - h[1] * l0 + h[0] * l1;
    out[3] = m * l0 - (h[1] * w2 - h[2] * w1);
    out[4] = m * l1 - (h[2] * w0 - h[0] * w2);
    out[5] = m * l2 - (h[0] * w1 - h[1] * w0);
    return out;
  }

  RigidInertia& operator+=(const RigidInertia& other) {
    m += other.m;
    h += other.h;
    I += other.I;
    return *this;
  }

  /// A body of mass m, centre of mass c and rotational inertia Ic about c, all in this frame:
  /// the parallel-axis theorem, I = Ic + m (|c|^2 1 - c c^T).
  static RigidInertia from_com(double mass, const Eigen::Vector3d& c, const Eigen::Matrix3d& Ic) {
    RigidInertia out;
    out.m = mass;
    out.h = mass * c;
    const Eigen::Vector3d& mc = out.h;
    out.I(0, 0) = Ic(0, 0) + (mc[1] * c[1] + mc[2] * c[2]);
    out.I(1, 1) = Ic(1, 1) + (mc[0] * c[0] + mc[2] * c[2]);
    out.I(2, 2) = Ic(2, 2) + (mc[0] * c[0] + mc[1] * c[1]);
    out.I(0, 1) = out.I(1, 0) = Ic(0, 1) - mc[0] * c[1];
    out.I(0, 2) = out.I(2, 0) = Ic(0, 2) - mc[0] * c[2];
    out.I(1, 2) = out.I(2, 1) = Ic(1, 2) - mc[1] * c[2];
    return out;
  }

  /// 6x6 matrix form (for tests and printing).
  Eigen::Matrix<double, 6, 6> matrix() const {
    Eigen::Matrix<double, 6, 6> M;
    const Eigen::Matrix3d hx = skew(h);
    M << I, hx, hx.transpose(), m * Eigen::Matrix3d::Identity();
    return M;
  }

  // ---- inertial parameters (engine/src/basics/inertia.cpp) ----

  /// The ten parameters [m, h, Ixx, Iyy, Izz, Ixy, Ixz, Iyz].
  InertialParameters to_parameters() const;
  /// The inertia of ten parameters: any ten numbers (linear; not checked to be a rigid body's).
  static RigidInertia from_parameters(const InertialParameters& pi);

  /// An <inertial> moved to the frame's origin (quat normalised; the parallel-axis theorem).
  static RigidInertia from_principal(const PrincipalInertia& principal);
  /// The <inertial> of this inertia: centre of mass h / m, its principal axes (a proper rotation)
  /// and moments (increasing). Throws ModelError unless it is a rigid body's: m > 0 and finite,
  /// principal moments > 0, each at most the sum of the other two (to 1e-12 of the largest).
  PrincipalInertia to_principal() const;

  /// The pseudo-inertia (Wensing, Kim and Slotine 2017), the 4x4 second moment of the mass
  /// distribution, J = [Sigma h; h^T m] with Sigma = integral of x x^T dm = tr(I)/2 1 - I. Linear
  /// in the parameters; positive semidefinite exactly when they are a rigid body's (some
  /// nonnegative mass distribution has them).
  Eigen::Matrix4d to_pseudo_inertia() const;
  /// The inertia of a pseudo-inertia (linear; the inverse of to_pseudo_inertia, J symmetric).
  static RigidInertia from_pseudo_inertia(const Eigen::Matrix4d& J);
};

/// m . f, the power of force f on motion m, summed as MuJoCo's mju_dot sums six numbers (pairs
/// of the first four, then the last two), not as Eigen's dot does: a sum whose terms cancel
/// (CRBA's entry for a thin rod's axial turn) keeps MuJoCo's last bit only in MuJoCo's order.
inline double power(const Motion& m, const Force& f) {
  return ((m[0] * f[0] + m[2] * f[2]) + (m[1] * f[1] + m[3] * f[3])) + (m[4] * f[4] + m[5] * f[5]);
}

/// v x m: the derivative of motion vector m moving with velocity v (Featherstone eq. 2.31).
/// Written out on the elements: [w x m_w; w x m_o + v_o x m_w], with no 3-vector temporaries.
inline Motion cross_motion(const Motion& v, const Motion& m) {
  const double w0 = v[0], w1 = v[1], w2 = v[2], o0 = v[3], o1 = v[4], o2 = v[5];
  Motion out;
  out[0] = w1 * m[2] - w2 * m[1];
  out[1] = w2 * m[0] - w0 * m[2];
  out[2] = w0 * m[1] - w1 * m[0];
  out[3] = (w1 * m[5] - w2 * m[4]) + (o1 * m[2] - o2 * m[1]);
  out[4] = (w2 * m[3] - w0 * m[5]) + (o2 * m[0] - o0 * m[2]);
  out[5] = (w0 * m[4] - w1 * m[3]) + (o0 * m[1] - o1 * m[0]);
  return out;
}

/// v x* f: the derivative of force vector f moving with velocity v (Featherstone eq. 2.32).
inline Force cross_force(const Motion& v, const Force& f) {
  const Eigen::Vector3d w = v.head<3>();
  Force out;
  out.head<3>() = cross(w, f.head<3>()) + cross(v.tail<3>(), f.tail<3>());
  out.tail<3>() = cross(w, f.tail<3>());
  return out;
}

/// The 6x6 matrix C = v x* I - I (v x) + (I v) xbar* of a body with inertia I moving with v (the
/// change of its net force with its velocity, besides 2 I), or its sum over a subtree. Its right
/// column of 3x3 blocks is zero and the rest is the symmetric S and the momentum (n, p) = I v
/// (derivatives/inverse_dynamics.cpp derives it):
///   C = [[S - [n], 0], [-2 [p], 0]],   [a] the matrix of a x.
/// Both parts sum over bodies, so a subtree's C is kept the same way.
struct VelocityCoupling {
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();  ///< symmetric
  Force momentum = Force::Zero();               ///< (n, p)

  /// C m
  Force operator*(const Motion& m) const {
    const Eigen::Vector3d w = m.head<3>();
    Force out;
    out.head<3>() = S * w + cross(w, momentum.head<3>());
    out.tail<3>() = 2 * cross(w, momentum.tail<3>());
    return out;
  }

  /// The angular part of C^T m (its linear part is zero).
  Eigen::Vector3d transpose_times(const Motion& m) const {
    return S * m.head<3>() + cross(momentum.head<3>(), m.head<3>()) +
           2 * cross(momentum.tail<3>(), m.tail<3>());
  }

  VelocityCoupling& operator+=(const VelocityCoupling& other) {
    S += other.S;
    momentum += other.momentum;
    return *this;
  }
};

// ---- quaternions (w, x, y, z) -----------------------------------------------------------------

using Quat = Eigen::Vector4d;

/// Hamilton product a * b.
inline Quat quat_mul(const Quat& a, const Quat& b) {
  return Quat(a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
              a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
              a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
              a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]);
}

/// q * (c, s e_k): the product with a rotation about coordinate axis k (0, 1, 2 for x, y, z),
/// where (c, s) = (cos, sin) of half the angle, signed with the axis. The eight products with
/// the zero components are left out; the rest are summed in quat_mul's order, so the result is
/// quat_mul's to the bit.
inline Quat quat_mul_axis(const Quat& q, int k, double c, double s) {
  switch (k) {
    case 0:
      return Quat(q[0] * c - q[1] * s, q[0] * s + q[1] * c, q[2] * c + q[3] * s,
                  -(q[2] * s) + q[3] * c);
    case 1:
      return Quat(q[0] * c - q[2] * s, q[1] * c - q[3] * s, q[0] * s + q[2] * c,
                  q[1] * s + q[3] * c);
    default:
      return Quat(q[0] * c - q[3] * s, q[1] * c + q[2] * s, -(q[1] * s) + q[2] * c,
                  q[0] * s + q[3] * c);
  }
}

/// The rotation matrix of a unit quaternion (maps local to parent coordinates).
inline Eigen::Matrix3d quat_to_mat(const Quat& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Eigen::Matrix3d R;
  R << w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y), 2 * (x * y + w * z),
      w * w - x * x + y * y - z * z, 2 * (y * z - w * x), 2 * (x * z - w * y), 2 * (y * z + w * x),
      w * w - x * x - y * y + z * z;
  return R;
}

/// q / |q|, or the identity for a (near) zero quaternion.
inline Quat quat_normalized(const Quat& q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (n < 1e-15) return Quat(1, 0, 0, 0);
  const double inv = 1.0 / n;
  return Quat(q[0] * inv, q[1] * inv, q[2] * inv, q[3] * inv);
}

/// q / |q| for a q whose norm is already 1 to within rounding (a product of unit quaternions):
/// one Newton step for 1/sqrt(|q|^2) about 1, exact to rounding there and free of sqrt and
/// division. Use quat_normalized() for an arbitrary quaternion.
inline Quat quat_renormalized(const Quat& q) {
  const double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  const double inv = 1.5 - 0.5 * n2;
  return Quat(q[0] * inv, q[1] * inv, q[2] * inv, q[3] * inv);
}

/// Rotation by angle (rad) about a unit axis.
Quat quat_from_axis_angle(const Eigen::Vector3d& axis, double angle);

/// A unit quaternion for a proper rotation matrix.
Quat quat_from_mat(const Eigen::Matrix3d& R);

}  // namespace lever
