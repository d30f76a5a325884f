// The narrow phase's closed-form pairs without a box: MuJoCo 2.2.2's
// engine_collision_primitive.c (plane against sphere, capsule, box and cylinder; sphere and
// capsule against each other), and collide_shapes(), the table that dispatches to them and to
// the box pairs (box.cpp) and the general convex pairs (convex.cpp).
//
// The branch tests (margins, clamps, kMinVal) decide which contacts exist, so they are MuJoCo's,
// evaluated on the same sums in the same order: dot products left to right (dot3), rotations row
// by row (rotate_rows). Each function writes dist, pos and the frame's normal row; the second row
// stays zero (the capsule's axis for plane-capsule, which MuJoCo uses as the first tangent) and the
// driver completes the frame, as mj_collideGeoms does with mju_makeFrame.
#include <cmath>
#include <string>
#include <utility>

#include <lever/collision.hpp>
#include <lever/error.hpp>

#include "collision/narrow_phase.hpp"

namespace lever {

namespace {

using detail::dot3;
using detail::kMinVal;
using detail::normalize_or_x;
using detail::rotate_rows;
using Vec3 = Eigen::Vector3d;

Vec3 cross3(const Vec3& a, const Vec3& b) {
  return Vec3(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
}

/// A geom's z axis: a plane's normal, a capsule's or cylinder's axis.
Vec3 z_axis(const Mat3& R) { return R.col(2); }

/// Start a contact: its normal, no tangent yet.
void set_normal(Contact& c, const Vec3& normal) {
  c.frame.row(0) = normal.transpose();
  c.frame.row(1).setZero();
  c.frame.row(2).setZero();
}

// ---- plane against a point-like shape ----------------------------------------------------------

/// A sphere of `radius` at `center` against the plane: one contact midway between the plane and
/// the sphere's lowest point, if the centre is within margin + radius of the plane.
int plane_sphere(const GeomShape& plane, const Vec3& center, double radius, double margin,
                 Contact* contacts) {
  const Vec3 normal = z_axis(plane.mat);
  const double center_height = dot3(center - plane.pos, normal);
  if (center_height > margin + radius) return 0;
  Contact& c = contacts[0];
  c.dist = center_height - radius;
  c.pos = center + normal * (-c.dist / 2 - radius);
  set_normal(c, normal);
  return 1;
}

/// Two spheres: one contact on the line between the centres, midway between the surfaces. When
/// the centres coincide, the normal is the cross product of the two geoms' z axes (or x).
int sphere_sphere(const Vec3& center1, const Mat3& mat1, double radius1, const Vec3& center2,
                  const Mat3& mat2, double radius2, double margin, Contact* contacts) {
  const Vec3 between = center1 - center2;
  const double center_distance = std::sqrt(dot3(between, between));
  if (center_distance > margin + radius1 + radius2) return 0;
  Contact& c = contacts[0];
  c.dist = center_distance - radius1 - radius2;
  Vec3 normal = center2 - center1;
  if (normalize_or_x(normal) < kMinVal) {
    normal = cross3(z_axis(mat1), z_axis(mat2));
    normalize_or_x(normal);
  }
  c.pos = normal * (radius1 + c.dist / 2) + center1;
  set_normal(c, normal);
  return 1;
}

/// Clamp a segment parameter to the segment [-1, 1].
double clamp_to_segment(double x) {
  if (x > 1) return 1;
  if (x < -1) return -1;
  return x;
}

// ---- the pairs ---------------------------------------------------------------------------------

int plane_capsule(const GeomShape& plane, const GeomShape& capsule, double margin,
                  Contact* contacts) {
  // the two end spheres, each against the plane; the capsule's axis becomes the first tangent
  const Vec3 axis = z_axis(capsule.mat);
  const Vec3 segment = axis * capsule.size[1];
  const int n1 = plane_sphere(plane, capsule.pos + segment, capsule.size[0], margin, contacts);
  const int n2 = plane_sphere(plane, capsule.pos - segment, capsule.size[0], margin, contacts + n1);
  for (int k = 0; k < n1 + n2; ++k) contacts[k].frame.row(1) = axis.transpose();
  return n1 + n2;
}

int plane_cylinder(const GeomShape& plane, const GeomShape& cylinder, double margin,
                   Contact* contacts) {
  const Vec3 normal = z_axis(plane.mat);
  Vec3 axis = z_axis(cylinder.mat);
  const double radius = cylinder.size[0], half_length = cylinder.size[1];

  // let the axis point towards the plane
  double axis_along_normal = dot3(normal, axis);
  if (axis_along_normal > 0) {
    axis = axis * -1.0;
    axis_along_normal = -axis_along_normal;
  }
  const double center_height = dot3(cylinder.pos - plane.pos, normal);

  // the radius towards the plane: -normal without its component along the axis
  Vec3 rim = axis * axis_along_normal - normal;
  const double rim_length = std::sqrt(dot3(rim, rim));
  if (rim_length >= kMinVal) {
    rim = rim * (radius / rim_length);
  } else {
    rim = cylinder.mat.col(0) * radius;  // disc parallel to the plane: the cylinder's x axis
  }
  const double rim_along_normal = dot3(rim, normal);
  axis = axis * half_length;
  axis_along_normal *= half_length;

  auto add = [&](int k, double dist, const Vec3& point) {
    contacts[k].dist = dist;
    contacts[k].pos = point + normal * (-dist * 0.5);
    set_normal(contacts[k], normal);
  };

  // the rim point nearest the plane, on the lower disc; none within margin means no contact
  int count = 0;
  const double lowest = center_height + axis_along_normal + rim_along_normal;
  if (lowest > margin) return 0;
  add(count++, lowest, cylinder.pos + rim + axis);

  // the same rim point on the other disc
  const double other_disc = center_height - axis_along_normal + rim_along_normal;
  if (other_disc <= margin) add(count++, other_disc, cylinder.pos + rim - axis);

  // two more points of the lower disc, a third of the way round either side
  const double side_along_normal = -rim_along_normal * 0.5;
  const double side = center_height + axis_along_normal + side_along_normal;
  if (side <= margin) {
    Vec3 sideways = cross3(rim, axis);
    normalize_or_x(sideways);
    sideways = sideways * (radius * std::sqrt(3.0) / 2);
    add(count++, side, cylinder.pos + sideways + axis + rim * -0.5);
    add(count++, side, cylinder.pos - sideways + axis + rim * -0.5);
  }
  return count;
}

int plane_box(const GeomShape& plane, const GeomShape& box, double margin, Contact* contacts) {
  const Vec3 normal = z_axis(plane.mat);
  const double center_height = dot3(box.pos - plane.pos, normal);

  // the corners in order (bit 0: +x, bit 1: +y, bit 2: +z), the first four below the centre and
  // within margin of the plane
  int count = 0;
  for (int i = 0; i < 8; ++i) {
    const Vec3 local((i & 1) ? box.size[0] : -box.size[0], (i & 2) ? box.size[1] : -box.size[1],
                     (i & 4) ? box.size[2] : -box.size[2]);
    const Vec3 corner = rotate_rows(box.mat, local);
    const double corner_along_normal = dot3(normal, corner);
    if (center_height + corner_along_normal > margin || corner_along_normal > 0) continue;
    Contact& c = contacts[count];
    c.dist = center_height + corner_along_normal;
    set_normal(c, normal);
    c.pos = (corner + box.pos) + normal * (-c.dist / 2);
    if (++count >= 4) return 4;
  }
  return count;
}

int sphere_capsule(const GeomShape& sphere, const GeomShape& capsule, double margin,
                   Contact* contacts) {
  // the point of the capsule's segment nearest the sphere's centre, as a sphere
  const Vec3 axis = z_axis(capsule.mat) * capsule.size[1];
  const double x = clamp_to_segment(dot3(axis, sphere.pos - capsule.pos) / dot3(axis, axis));
  return sphere_sphere(sphere.pos, sphere.mat, sphere.size[0], axis * x + capsule.pos, capsule.mat,
                       capsule.size[0], margin, contacts);
}

int capsule_capsule(const GeomShape& c1, const GeomShape& c2, double margin, Contact* contacts) {
  // segments p1 + x1 a1 and p2 + x2 a2 (x in [-1, 1]); the normal equations of their distance
  const Vec3 a1 = z_axis(c1.mat) * c1.size[1];
  const Vec3 a2 = z_axis(c2.mat) * c2.size[1];
  const Vec3 between = c1.pos - c2.pos;
  const double ma = dot3(a1, a1);
  const double mb = -dot3(a1, a2);
  const double mc = dot3(a2, a2);
  const double u = -dot3(a1, between);
  const double v = dot3(a2, between);
  const double det = ma * mc - mb * mb;

  auto spheres_at = [&](double x1, double x2, Contact* out) {
    return sphere_sphere(a1 * x1 + c1.pos, c1.mat, c1.size[0], a2 * x2 + c2.pos, c2.mat, c2.size[0],
                         margin, out);
  };

  if (std::abs(det) >= kMinVal) {
    // not parallel: the nearest pair of points, clamped to the segments one at a time
    double x1 = (mc * u - mb * v) / det;
    double x2 = (ma * v - mb * u) / det;
    if (x1 > 1) {
      x1 = 1;
      x2 = (v - mb) / mc;
    } else if (x1 < -1) {
      x1 = -1;
      x2 = (v + mb) / mc;
    }
    if (x2 > 1) {
      x2 = 1;
      x1 = clamp_to_segment((u - mb) / ma);
    } else if (x2 < -1) {
      x2 = -1;
      x1 = clamp_to_segment((u + mb) / ma);
    }
    return spheres_at(x1, x2, contacts);
  }

  // parallel: each end of the first segment against the second, then each end of the second
  // against the first, until two contacts are found
  auto end_sphere = [&](const Vec3& end, const Mat3& end_mat, double end_radius, const Vec3& other,
                        const Mat3& other_mat, double other_radius, bool end_is_first,
                        Contact* out) {
    return end_is_first ? sphere_sphere(end, end_mat, end_radius, other, other_mat, other_radius,
                                        margin, out)
                        : sphere_sphere(other, other_mat, other_radius, end, end_mat, end_radius,
                                        margin, out);
  };
  int count =
      end_sphere(c1.pos + a1, c1.mat, c1.size[0], a2 * clamp_to_segment((v - mb) / mc) + c2.pos,
                 c2.mat, c2.size[0], true, contacts);
  count +=
      end_sphere(c1.pos - a1, c1.mat, c1.size[0], a2 * clamp_to_segment((v + mb) / mc) + c2.pos,
                 c2.mat, c2.size[0], true, contacts + count);
  if (count >= 2) return count;
  count +=
      end_sphere(c2.pos + a2, c2.mat, c2.size[0], a1 * clamp_to_segment((u - mb) / ma) + c1.pos,
                 c1.mat, c1.size[0], false, contacts + count);
  if (count >= 2) return count;
  count +=
      end_sphere(c2.pos - a2, c2.mat, c2.size[0], a1 * clamp_to_segment((u + mb) / ma) + c1.pos,
                 c1.mat, c1.size[0], false, contacts + count);
  return count;
}

using PairFunction = int (*)(const GeomShape&, const GeomShape&, double, Contact*);

int sphere_sphere_shapes(const GeomShape& s1, const GeomShape& s2, double margin,
                         Contact* contacts) {
  return sphere_sphere(s1.pos, s1.mat, s1.size[0], s2.pos, s2.mat, s2.size[0], margin, contacts);
}

int plane_sphere_shapes(const GeomShape& plane, const GeomShape& sphere, double margin,
                        Contact* contacts) {
  return plane_sphere(plane, sphere.pos, sphere.size[0], margin, contacts);
}

/// lever's closed-form part of MuJoCo's mjCOLLISIONFUNC, indexed by (type1, type2) with
/// type1 <= type2; null where MuJoCo runs MPR (is_convex_pair) or has no function.
PairFunction pair_function(GeomType a, GeomType b) {
  using T = GeomType;
  switch (a) {
    case T::kPlane:
      switch (b) {
        case T::kSphere: return plane_sphere_shapes;
        case T::kCapsule: return plane_capsule;
        case T::kEllipsoid:
        case T::kMesh: return detail::plane_convex;
        case T::kCylinder: return plane_cylinder;
        case T::kBox: return plane_box;
        default: return nullptr;
      }
    case T::kSphere:
      switch (b) {
        case T::kSphere: return sphere_sphere_shapes;
        case T::kCapsule: return sphere_capsule;
        case T::kBox: return detail::collide_sphere_box;
        default: return nullptr;
      }
    case T::kCapsule:
      switch (b) {
        case T::kCapsule: return capsule_capsule;
        case T::kBox: return detail::collide_capsule_box;
        default: return nullptr;
      }
    case T::kBox: return b == T::kBox ? detail::collide_box_box : nullptr;
    default: return nullptr;
  }
}

/// The pairs MuJoCo 2.2.2 gives mjc_Convex (type1 <= type2): every pair of two solids (neither a
/// plane nor a height field) without a closed form, i.e. any with an ellipsoid, a cylinder or a
/// mesh, except plane-ellipsoid and plane-mesh (mjc_PlaneConvex, in the table above).
bool is_convex_pair(GeomType a, GeomType b) {
  const auto solid = [](GeomType t) { return t != GeomType::kPlane && t != GeomType::kHfield; };
  return solid(a) && solid(b) && pair_function(a, b) == nullptr;
}

const char* type_name(GeomType t) {
  switch (t) {
    case GeomType::kPlane: return "plane";
    case GeomType::kHfield: return "hfield";
    case GeomType::kSphere: return "sphere";
    case GeomType::kCapsule: return "capsule";
    case GeomType::kEllipsoid: return "ellipsoid";
    case GeomType::kCylinder: return "cylinder";
    case GeomType::kBox: return "box";
    case GeomType::kMesh: return "mesh";
  }
  return "unknown";
}

}  // namespace

bool has_collision_function(GeomType a, GeomType b) {
  if (static_cast<int>(a) > static_cast<int>(b)) std::swap(a, b);
  if (pair_function(a, b)) {
    // plane-mesh runs the support function only; this build has it whenever it has meshes
    return true;
  }
  return is_convex_pair(a, b) && detail::has_convex_pairs();
}

int collide_shapes(const GeomShape& g1, const GeomShape& g2, double margin, Contact* contacts,
                   const ConvexOptions& convex) {
  if (static_cast<int>(g1.type) > static_cast<int>(g2.type)) {
    throw ModelError(std::string("collide_shapes: a ") + type_name(g1.type) +
                     " must come after a " + type_name(g2.type) +
                     " (pass the geoms in MuJoCo's type order)");
  }
  if (is_convex_pair(g1.type, g2.type) && detail::has_convex_pairs()) {
    return detail::convex_pair(g1, g2, margin, convex, contacts);
  }
  const PairFunction f = pair_function(g1.type, g2.type);
  if (!f) {
    throw ModelError(std::string("lever has no collision function for a ") + type_name(g1.type) +
                     " against a " + type_name(g2.type));
  }
  return f(g1, g2, margin, contacts);
}

}  // namespace lever
