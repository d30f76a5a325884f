// What the narrow-phase files share (engine/src only): the box functions written in
// collision/box.cpp, and the small vector helpers whose rounding and thresholds decide
// MuJoCo 2.2.2's results (engine_util_blas.c).
#pragma once

#include <Eigen/Core>

#include <cmath>

#include <lever/collision.hpp>

#include "basics/basics.hpp"

namespace lever::detail {

/// MuJoCo's mju_normalize3: scale v to unit length by multiplying with 1 / |v| and return |v|;
/// a vector shorter than kMinVal becomes (1, 0, 0).
inline double normalize_or_x(Eigen::Vector3d& v) {
  const double norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (norm < kMinVal) {
    v = Eigen::Vector3d(1, 0, 0);
  } else {
    const double inverse = 1 / norm;
    v *= inverse;
  }
  return norm;
}

/// MuJoCo's mju_dot3, summed left to right.
inline double dot3(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// The pairs with a box (MuJoCo 2.2.2's engine_collision_box.c: mjc_SphereBox, mjc_CapsuleBox,
// mjc_BoxBox), written in collision/box.cpp. Each has collide_shapes()'s contract: g1's type
// comes first in MuJoCo's table (sphere, capsule, box), at most kMaxPairContacts contacts with
// dist, pos and the frame's normal row (the second row zero unless the function sets it; the
// driver completes the frame).
int collide_sphere_box(const GeomShape& sphere, const GeomShape& box, double margin,
                       Contact* contacts);
int collide_capsule_box(const GeomShape& capsule, const GeomShape& box, double margin,
                        Contact* contacts);
int collide_box_box(const GeomShape& box1, const GeomShape& box2, double margin, Contact* contacts);

/// What MuJoCo 2.2.2's driver (mj_collideGeoms) does to a box-box pair's contacts before it keeps
/// them: a contact whose position equals, component by component and exactly, that of a later one
/// is dropped; the survivors keep their order. Returns how many remain in contacts[0, result).
int remove_repeated_positions(Contact* contacts, int count);

}  // namespace lever::detail
