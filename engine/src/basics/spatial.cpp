// Quaternion conversions that are too long to inline.
#include <lever/spatial.hpp>

#include <cmath>

namespace lever {

Quat quat_from_axis_angle(const Eigen::Vector3d& axis, double angle) {
  if (angle == 0.0) return Quat(1, 0, 0, 0);
  const double s = std::sin(0.5 * angle);
  return Quat(std::cos(0.5 * angle), axis.x() * s, axis.y() * s, axis.z() * s);
}

Quat quat_from_mat(const Eigen::Matrix3d& R) {
  // Shepperd's method: pivot on the largest of w, x, y, z to avoid dividing by a small number.
  const double trace = R(0, 0) + R(1, 1) + R(2, 2);
  Quat q;
  if (trace > 0.0) {
    const double s = 0.5 / std::sqrt(trace + 1.0);
    q << 0.25 / s, (R(2, 1) - R(1, 2)) * s, (R(0, 2) - R(2, 0)) * s, (R(1, 0) - R(0, 1)) * s;
  } else if (R(0, 0) > R(1, 1) && R(0, 0) > R(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + R(0, 0) - R(1, 1) - R(2, 2));
    q << (R(2, 1) - R(1, 2)) / s, 0.25 * s, (R(0, 1) + R(1, 0)) / s, (R(0, 2) + R(2, 0)) / s;
  } else if (R(1, 1) > R(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + R(1, 1) - R(0, 0) - R(2, 2));
    q << (R(0, 2) - R(2, 0)) / s, (R(0, 1) + R(1, 0)) / s, 0.25 * s, (R(1, 2) + R(2, 1)) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + R(2, 2) - R(0, 0) - R(1, 1));
    q << (R(1, 0) - R(0, 1)) / s, (R(0, 2) + R(2, 0)) / s, (R(1, 2) + R(2, 1)) / s, 0.25 * s;
  }
  if (q[0] < 0.0) q = -q;
  return quat_normalized(q);
}

}  // namespace lever
