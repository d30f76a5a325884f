// The basics every room of the engine uses (its lowest floor): MuJoCo's numerical thresholds,
// written once, the quaternion operations on raw arrays that the state's quaternions need, the
// test for a bad number, and MuJoCo's orders of summation (sums.hpp). Public types (Motion, Force, Quat, RigidInertia) are lever/spatial.hpp's.
#pragma once

#include <Eigen/Core>

#include <cmath>

#include <lever/model.hpp>
#include <lever/spatial.hpp>

#include "basics/sums.hpp"

namespace lever {

namespace detail {

/// MuJoCo's mjMINVAL: the smallest length, denominator or pivot MuJoCo divides by; below it a
/// vector has no direction and a quaternion is reset.
inline constexpr double kMinVal = 1e-15;

/// MuJoCo's mjMINIMP and mjMAXIMP: the range a constraint's impedance (solimp's d0, dwidth and
/// mid point) is clamped to.
inline constexpr double kMinImp = 0.0001;
inline constexpr double kMaxImp = 0.9999;

/// MuJoCo's mjPI.
inline constexpr double kPi = 3.14159265358979323846;

/// q (4 numbers) normalized in place, or the identity when its length is below kMinVal (MuJoCo's
/// mju_normalize4, which scales even a unit quaternion by 1 / |q|: so does this).
inline void normalize_quat(double* q) {
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (norm < kMinVal) {
    q[0] = 1.0;
    q[1] = q[2] = q[3] = 0.0;
    return;
  }
  const double inverse = 1.0 / norm;
  for (int k = 0; k < 4; ++k) q[k] *= inverse;
}

/// v turned by the unit quaternion q (MuJoCo's mju_rotVecQuat, term for term: t = w v + u x v,
/// then v + 2 u x t for q = (w, u)); the identity copies v.
inline Eigen::Vector3d quat_rotate(const Quat& q, const Eigen::Vector3d& v) {
  if (q[0] == 1.0 && q[1] == 0.0 && q[2] == 0.0 && q[3] == 0.0) return v;
  const double t0 = q[0] * v[0] + q[2] * v[2] - q[3] * v[1];
  const double t1 = q[0] * v[1] + q[3] * v[0] - q[1] * v[2];
  const double t2 = q[0] * v[2] + q[1] * v[1] - q[2] * v[0];
  return Eigen::Vector3d(v[0] + 2 * (q[2] * t2 - q[3] * t1), v[1] + 2 * (q[3] * t0 - q[1] * t2),
                         v[2] + 2 * (q[1] * t1 - q[2] * t0));
}

/// Every ball and free joint's quaternion in qpos normalized (MuJoCo's mj_normalizeQuat, which
/// mj_kinematics runs first: an evaluation leaves the state's quaternions unit).
inline void normalize_joint_quats(const Model& model, double* qpos) {
  for (int j = 0; j < model.njnt; ++j) {
    const JointKind kind = model.jnt_kind[j];
    if (kind == JointKind::kBall) normalize_quat(qpos + model.jnt_qposadr[j]);
    if (kind == JointKind::kFree) normalize_quat(qpos + model.jnt_qposadr[j] + 3);
  }
}

/// The rotation vector r (3 numbers, in b's frame) with b * exp(r) = a, for unit quaternions a
/// and b, its angle in [-pi, pi], divided by dt (MuJoCo's mju_subQuat for dt = 1, the
/// orientation's difference in tangent space; mj_differentiatePos's rate for other dt).
inline Eigen::Vector3d quat_difference(const double* a, const double* b, double dt = 1.0) {
  // d = conj(b) * a
  const Quat qa(a[0], a[1], a[2], a[3]);
  const Quat conj_b(b[0], -b[1], -b[2], -b[3]);
  const Quat d = quat_mul(conj_b, qa);
  Eigen::Vector3d axis(d[1], d[2], d[3]);
  const double sin_half = axis.norm();
  if (sin_half < kMinVal) {
    axis = Eigen::Vector3d::UnitX();
  } else {
    axis *= 1.0 / sin_half;
  }
  double angle = 2.0 * std::atan2(sin_half, d[0]);
  if (angle > M_PI) angle -= 2.0 * M_PI;  // the shorter way round
  return axis * (angle / dt);
}
}  // namespace detail

/// MuJoCo's mju_isBad: NaN, or beyond +-1e10.
inline bool is_bad(double x) { return x != x || x > 1e10 || x < -1e10; }

/// The first of n numbers that is_bad, or -1 (|x| <= 1e10 is false for a NaN too).
inline int first_bad(const double* x, int n) {
  for (int i = 0; i < n; ++i) {
    if (!(std::abs(x[i]) <= 1e10)) return i;
  }
  return -1;
}

}  // namespace lever
