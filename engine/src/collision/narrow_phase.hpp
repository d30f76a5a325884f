// What the narrow-phase files share (engine/src only): the box functions run in collision/box.cpp
// (written in box_pairs.hpp), the general convex pairs written in collision/convex.cpp, and the small
// vector helpers whose rounding and thresholds decide MuJoCo 2.2.2's results (engine_util_blas.c,
// engine_util_spatial.c).
#pragma once

#include <Eigen/Core>

#include <cmath>

#include <lever/collision.hpp>

#include "basics/basics.hpp"
#include "collision/primitive_pairs.hpp"

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

/// A geom as the code written on a scalar (primitive_pairs.hpp, surface_normal.hpp) sees it, on
/// doubles.
inline primitive::Vec<double> primitive_vec(const Eigen::Vector3d& x) {
  return {{x[0], x[1], x[2]}};
}
inline primitive::Shape<double> primitive_shape(const GeomShape& g) {
  return {g.type, g.size, primitive_vec(g.pos),
          {primitive_vec(g.mat.col(0)), primitive_vec(g.mat.col(1)), primitive_vec(g.mat.col(2))}};
}

/// MuJoCo's mju_dot3, summed left to right.
inline double dot3(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// R v, each row's products summed left to right (mju_rotVecMat).
inline Eigen::Vector3d rotate_rows(const Mat3& R, const Eigen::Vector3d& v) {
  return Eigen::Vector3d(R(0, 0) * v[0] + R(0, 1) * v[1] + R(0, 2) * v[2],
                         R(1, 0) * v[0] + R(1, 1) * v[1] + R(1, 2) * v[2],
                         R(2, 0) * v[0] + R(2, 1) * v[1] + R(2, 2) * v[2]);
}

/// R^T v, each column's products summed top to bottom (mju_rotVecMatT).
inline Eigen::Vector3d rotate_columns(const Mat3& R, const Eigen::Vector3d& v) {
  return Eigen::Vector3d(R(0, 0) * v[0] + R(1, 0) * v[1] + R(2, 0) * v[2],
                         R(0, 1) * v[0] + R(1, 1) * v[1] + R(2, 1) * v[2],
                         R(0, 2) * v[0] + R(1, 2) * v[1] + R(2, 2) * v[2]);
}

/// The contact frame from its normal row (mju_makeFrame): the normal made unit; the first tangent
/// the given second row if it has one (the capsule's axis), else world y or, for a normal near y,
/// world z, made orthogonal to the normal; the second tangent their cross product. Returns false
/// (the frame unchanged) when the normal is shorter than 0.5, which MuJoCo treats as an error.
inline bool complete_frame(Mat3& frame) {
  Eigen::Vector3d normal = frame.row(0).transpose();
  if (normalize_or_x(normal) < 0.5) return false;
  Eigen::Vector3d tangent = frame.row(1).transpose();
  if (std::sqrt(dot3(tangent, tangent)) < 0.5) {
    tangent.setZero();
    if (normal[1] < 0.5 && normal[1] > -0.5) {
      tangent[1] = 1;
    } else {
      tangent[2] = 1;
    }
  }
  tangent -= normal * dot3(normal, tangent);
  normalize_or_x(tangent);
  frame.row(0) = normal.transpose();
  frame.row(1) = tangent.transpose();
  frame.row(2) << normal[1] * tangent[2] - normal[2] * tangent[1],
      normal[2] * tangent[0] - normal[0] * tangent[2],
      normal[0] * tangent[1] - normal[1] * tangent[0];
  return true;
}

// The general convex pairs (MuJoCo 2.2.2's engine_collision_convex.c), written in
// collision/convex.cpp, with collide_shapes()'s contract (g1's type first in MuJoCo's table).
// convex_pair: mjc_Convex, MPR on the two support functions (multiccd: up to four more contacts);
// plane_convex: mjc_PlaneConvex, the support point against the plane, and for a mesh up to two
// more vertices below the margin.
int convex_pair(const GeomShape& g1, const GeomShape& g2, double margin,
                const ConvexOptions& options, Contact* contacts);
int plane_convex(const GeomShape& plane, const GeomShape& convex, double margin,
                 Contact* contacts);
/// The support point MPR asks a geom for (MuJoCo's mjccd_support): its point farthest along the
/// world direction `dir`, grown by margin / 2, in the world.
void convex_support(const GeomShape& g, double margin, const double* dir, double* point);

/// convex_pair's first MPR search (without fix_normal), the support points it asked for written
/// down in order: geom 1's in points1, geom 2's in points2, in the world (those past `capacity`
/// counted, not kept). Returns how many it asked for, -1 if it found no contact; `answer` gets
/// dist, pos and the normal row. For the derivative of MPR's answer, a closed form of its last
/// portal, three of these.
int mpr_search(const GeomShape& g1, const GeomShape& g2, double margin,
               const ConvexOptions& options, Contact& answer, Eigen::Vector3d* points1,
               Eigen::Vector3d* points2, int capacity);

// The pairs with a box (MuJoCo 2.2.2's engine_collision_box.c: mjc_SphereBox, mjc_CapsuleBox,
// mjc_BoxBox), written once on a scalar in collision/box_pairs.hpp and run on doubles by
// collision/box.cpp. Each has collide_shapes()'s contract: g1's type
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
