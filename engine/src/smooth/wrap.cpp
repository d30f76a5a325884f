// The tendon's wrap around a geom on double: smooth/wrap_path.hpp says what it computes.
#include "smooth/smooth.hpp"
#include "smooth/wrap_path.hpp"

namespace lever::detail {

double wrap_around_geom(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1,
                        const Eigen::Vector3d& centre, const Mat3& R, double radius,
                        bool cylinder, const Eigen::Vector3d* side, Eigen::Vector3d& tangent0,
                        Eigen::Vector3d& tangent1) {
  const double frame[3][3] = {{R(0, 0), R(0, 1), R(0, 2)},
                              {R(1, 0), R(1, 1), R(1, 2)},
                              {R(2, 0), R(2, 1), R(2, 2)}};
  double t0[3], t1[3];
  const double length = wrap_path::wrap(x0.data(), x1.data(), centre.data(), frame, radius,
                                        cylinder, side != nullptr ? side->data() : nullptr, t0, t1);
  if (length < 0) return -1;
  tangent0 = Eigen::Vector3d(t0[0], t0[1], t0[2]);
  tangent1 = Eigen::Vector3d(t1[0], t1[1], t1[2]);
  return length;
}

}  // namespace lever::detail
