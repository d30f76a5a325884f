// The closed-form pairs of MuJoCo 2.2.2's engine_collision_primitive.c that need no box (plane
// against sphere, capsule and box; sphere and capsule against each other), written once on a
// scalar type S: double in the narrow phase (primitive.cpp), dual numbers where the transition
// room differentiates a contact's geometry (transition/contact_geometry.cpp). Every branch is
// decided on value(x), so on dual numbers the derivative is that of the case the narrow phase
// took.
//
// The branch tests (margins, clamps, kMinVal) decide which contacts exist, so they are MuJoCo's,
// evaluated on the same sums in the same order: dot products left to right, rotations row by row.
// A pair writes dist, pos and the normal of each contact, and a first tangent where MuJoCo seeds
// one (the capsule's axis for plane-capsule); the driver completes the frame (mju_makeFrame).
//
// S needs +, - (binary and unary), *, / with S and with double, value(S) -> double and sqrt(S),
// found by argument-dependent lookup (for double: value() below and std::sqrt).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <type_traits>

#include <lever/model.hpp>

#include "basics/basics.hpp"

namespace lever::detail::primitive {

inline double value(double x) { return x; }

/// A vector of three S; the arithmetic is component by component.
template <class S>
struct Vec {
  std::array<S, 3> c;
  S& operator[](int k) { return c[static_cast<std::size_t>(k)]; }
  const S& operator[](int k) const { return c[static_cast<std::size_t>(k)]; }
};

template <class S>
Vec<S> operator+(const Vec<S>& a, const Vec<S>& b) {
  return {{a[0] + b[0], a[1] + b[1], a[2] + b[2]}};
}
template <class S>
Vec<S> operator-(const Vec<S>& a, const Vec<S>& b) {
  return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
}
template <class S>
Vec<S> operator*(const Vec<S>& a, const S& s) {
  return {{a[0] * s, a[1] * s, a[2] * s}};
}
template <class S>
Vec<S> operator*(const Vec<S>& a, double s) requires(!std::is_same_v<S, double>) {
  return {{a[0] * s, a[1] * s, a[2] * s}};
}
/// MuJoCo's mju_dot3, summed left to right.
template <class S>
S dot(const Vec<S>& a, const Vec<S>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class S>
Vec<S> cross(const Vec<S>& a, const Vec<S>& b) {
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
template <class S>
Vec<S> constant_vec(const Eigen::Vector3d& x) {
  return {{S(x[0]), S(x[1]), S(x[2])}};
}

/// MuJoCo's mju_normalize3: scale v to unit length by multiplying with 1 / |v| and return |v|;
/// a vector shorter than kMinVal becomes (1, 0, 0).
template <class S>
S normalize(Vec<S>& v) {
  using std::sqrt;
  const S norm = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (value(norm) < kMinVal) {
    v = {{S(1), S(0), S(0)}};
  } else {
    const S inverse = S(1) / norm;
    v = v * inverse;
  }
  return norm;
}

/// A geom as the pairs see it: its type, size, position and the columns of its orientation.
template <class S>
struct Shape {
  GeomType type;
  Eigen::Vector3d size;
  Vec<S> pos;
  std::array<Vec<S>, 3> axis;  // geom_xmat's columns
};

/// R x: each row's products summed left to right (mju_rotVecMat).
template <class S>
Vec<S> rotate(const Shape<S>& g, const Vec<S>& x) {
  return g.axis[0] * x[0] + g.axis[1] * x[1] + g.axis[2] * x[2];
}

/// R^T x: each column's products summed top to bottom (mju_rotVecMatT).
template <class S>
Vec<S> unrotate(const Shape<S>& g, const Vec<S>& x) {
  return {{dot(g.axis[0], x), dot(g.axis[1], x), dot(g.axis[2], x)}};
}

/// A contact as a pair finds it; tangent is zero unless the pair seeds the frame's first tangent.
template <class S>
struct Touch {
  S dist;
  Vec<S> pos, normal, tangent;
};

template <class S>
void touch(Touch<S>& t, const S& dist, const Vec<S>& pos, const Vec<S>& normal) {
  t.dist = dist;
  t.pos = pos;
  t.normal = normal;
  t.tangent = {{S(0), S(0), S(0)}};
}

// ---- plane against a point-like shape ----------------------------------------------------------

/// A sphere of `radius` at `center` against the plane: one contact midway between the plane and
/// the sphere's lowest point, if the centre is within margin + radius of the plane.
template <class S>
int plane_sphere(const Shape<S>& plane, const Vec<S>& center, double radius, double margin,
                 Touch<S>* out) {
  const Vec<S> normal = plane.axis[2];
  const S center_height = dot(center - plane.pos, normal);
  if (value(center_height) > margin + radius) return 0;
  const S dist = center_height - radius;
  touch(out[0], dist, center + normal * (-dist / 2 - radius), normal);
  return 1;
}

/// Two spheres: one contact on the line between the centres, midway between the surfaces. When
/// the centres coincide, the normal is the cross product of the two geoms' z axes (or x).
template <class S>
int sphere_sphere(const Vec<S>& center1, const Shape<S>& g1, double radius1, const Vec<S>& center2,
                  const Shape<S>& g2, double radius2, double margin, Touch<S>* out) {
  using std::sqrt;
  const Vec<S> between = center1 - center2;
  const S center_distance = sqrt(dot(between, between));
  if (value(center_distance) > margin + radius1 + radius2) return 0;
  const S dist = center_distance - radius1 - radius2;
  Vec<S> normal = center2 - center1;
  if (value(normalize(normal)) < kMinVal) {
    normal = cross(g1.axis[2], g2.axis[2]);
    normalize(normal);
  }
  touch(out[0], dist, normal * (radius1 + dist / 2) + center1, normal);
  return 1;
}

/// Clamp a segment parameter to the segment [-1, 1].
template <class S>
S clamp_to_segment(const S& x) {
  if (value(x) > 1) return S(1);
  if (value(x) < -1) return S(-1);
  return x;
}

// ---- the pairs ---------------------------------------------------------------------------------

template <class S>
int plane_capsule(const Shape<S>& plane, const Shape<S>& capsule, double margin, Touch<S>* out) {
  // the two end spheres, each against the plane; the capsule's axis becomes the first tangent
  const Vec<S> axis = capsule.axis[2];
  const Vec<S> segment = axis * capsule.size[1];
  const int n1 = plane_sphere(plane, capsule.pos + segment, capsule.size[0], margin, out);
  const int n2 = plane_sphere(plane, capsule.pos - segment, capsule.size[0], margin, out + n1);
  for (int k = 0; k < n1 + n2; ++k) out[k].tangent = axis;
  return n1 + n2;
}

template <class S>
int plane_box(const Shape<S>& plane, const Shape<S>& box, double margin, Touch<S>* out) {
  const Vec<S> normal = plane.axis[2];
  const S center_height = dot(box.pos - plane.pos, normal);

  // the corners in order (bit 0: +x, bit 1: +y, bit 2: +z), the first four below the centre and
  // within margin of the plane
  int count = 0;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d local((i & 1) ? box.size[0] : -box.size[0],
                                (i & 2) ? box.size[1] : -box.size[1],
                                (i & 4) ? box.size[2] : -box.size[2]);
    const Vec<S> corner = rotate(box, constant_vec<S>(local));
    const S corner_along_normal = dot(normal, corner);
    if (value(center_height) + value(corner_along_normal) > margin ||
        value(corner_along_normal) > 0) {
      continue;
    }
    const S dist = center_height + corner_along_normal;
    touch(out[count], dist, (corner + box.pos) + normal * (-dist / 2), normal);
    if (++count >= 4) return 4;
  }
  return count;
}

template <class S>
int sphere_capsule(const Shape<S>& sphere, const Shape<S>& capsule, double margin, Touch<S>* out) {
  // the point of the capsule's segment nearest the sphere's centre, as a sphere
  const Vec<S> axis = capsule.axis[2] * capsule.size[1];
  const S x = clamp_to_segment(dot(axis, sphere.pos - capsule.pos) / dot(axis, axis));
  return sphere_sphere(sphere.pos, sphere, sphere.size[0], axis * x + capsule.pos, capsule,
                       capsule.size[0], margin, out);
}

template <class S>
int capsule_capsule(const Shape<S>& c1, const Shape<S>& c2, double margin, Touch<S>* out) {
  // segments p1 + x1 a1 and p2 + x2 a2 (x in [-1, 1]); the normal equations of their distance
  const Vec<S> a1 = c1.axis[2] * c1.size[1];
  const Vec<S> a2 = c2.axis[2] * c2.size[1];
  const Vec<S> between = c1.pos - c2.pos;
  const S ma = dot(a1, a1);
  const S mb = -dot(a1, a2);
  const S mc = dot(a2, a2);
  const S u = -dot(a1, between);
  const S v = dot(a2, between);
  const S det = ma * mc - mb * mb;

  // a point of each segment, as two spheres
  const auto spheres_at = [&](const Vec<S>& p1, const Vec<S>& p2, Touch<S>* t) {
    return sphere_sphere(p1, c1, c1.size[0], p2, c2, c2.size[0], margin, t);
  };

  if (std::abs(value(det)) >= kMinVal) {
    // not parallel: the nearest pair of points, clamped to the segments one at a time
    S x1 = (mc * u - mb * v) / det;
    S x2 = (ma * v - mb * u) / det;
    if (value(x1) > 1) {
      x1 = S(1);
      x2 = (v - mb) / mc;
    } else if (value(x1) < -1) {
      x1 = S(-1);
      x2 = (v + mb) / mc;
    }
    if (value(x2) > 1) {
      x2 = S(1);
      x1 = clamp_to_segment((u - mb) / ma);
    } else if (value(x2) < -1) {
      x2 = S(-1);
      x1 = clamp_to_segment((u + mb) / ma);
    }
    return spheres_at(a1 * x1 + c1.pos, a2 * x2 + c2.pos, out);
  }

  // parallel: each end of the first segment against the second, then each end of the second
  // against the first, until two contacts are found
  int count = spheres_at(c1.pos + a1, a2 * clamp_to_segment((v - mb) / mc) + c2.pos, out);
  count += spheres_at(c1.pos - a1, a2 * clamp_to_segment((v + mb) / mc) + c2.pos, out + count);
  if (count >= 2) return count;
  count += spheres_at(a1 * clamp_to_segment((u - mb) / ma) + c1.pos, c2.pos + a2, out + count);
  if (count >= 2) return count;
  count += spheres_at(a1 * clamp_to_segment((u + mb) / ma) + c1.pos, c2.pos - a2, out + count);
  return count;
}

/// A cylinder against the plane: the rim point nearest the plane on the disc facing it, the same
/// rim point on the other disc, and two more points of the near disc a third of the way round
/// either side, each within the margin (MuJoCo's mjc_PlaneCylinder).
template <class S>
int plane_cylinder(const Shape<S>& plane, const Shape<S>& cylinder, double margin, Touch<S>* out) {
  using std::sqrt;
  const Vec<S> normal = plane.axis[2];
  Vec<S> axis = cylinder.axis[2];
  const double radius = cylinder.size[0], half_length = cylinder.size[1];

  // let the axis point towards the plane
  S axis_along_normal = dot(normal, axis);
  if (value(axis_along_normal) > 0) {
    axis = axis * S(-1.0);
    axis_along_normal = -axis_along_normal;
  }
  const S center_height = dot(cylinder.pos - plane.pos, normal);

  // the radius towards the plane: -normal without its component along the axis
  Vec<S> rim = axis * axis_along_normal - normal;
  const S rim_length = sqrt(dot(rim, rim));
  if (value(rim_length) >= kMinVal) {
    rim = rim * (S(radius) / rim_length);
  } else {
    rim = cylinder.axis[0] * S(radius);  // disc parallel to the plane: the cylinder's x axis
  }
  const S rim_along_normal = dot(rim, normal);
  axis = axis * S(half_length);
  axis_along_normal = axis_along_normal * S(half_length);

  int count = 0;
  const auto add = [&](const S& dist, const Vec<S>& point) {
    touch(out[count++], dist, point + normal * (-dist * S(0.5)), normal);
  };

  // the rim point nearest the plane, on the lower disc; none within margin means no contact
  const S lowest = center_height + axis_along_normal + rim_along_normal;
  if (value(lowest) > margin) return 0;
  add(lowest, cylinder.pos + rim + axis);

  // the same rim point on the other disc
  const S other_disc = center_height - axis_along_normal + rim_along_normal;
  if (value(other_disc) <= margin) add(other_disc, cylinder.pos + rim - axis);

  // two more points of the lower disc, a third of the way round either side
  const S side_along_normal = -rim_along_normal * S(0.5);
  const S side = center_height + axis_along_normal + side_along_normal;
  if (value(side) <= margin) {
    Vec<S> sideways = cross(rim, axis);
    normalize(sideways);
    sideways = sideways * S(radius * std::sqrt(3.0) / 2);
    add(side, cylinder.pos + sideways + axis + rim * S(-0.5));
    add(side, cylinder.pos - sideways + axis + rim * S(-0.5));
  }
  return count;
}

}  // namespace lever::detail::primitive
