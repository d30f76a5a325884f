// Rays against geoms (MuJoCo 2.2.2's engine_ray.c): where a ray p + x v first meets a shape, as
// the number x >= 0, or -1 when it never does. Each shape is intersected in its own frame, where
// it is centred and axis-aligned, so that each surface is a quadratic or a plane in x; a mesh
// triangle by triangle (ray_mesh).
#include <cmath>

#include "basics/basics.hpp"
#include "sensors/sensors.hpp"

namespace lever {

namespace {

using Eigen::Vector3d;
using detail::kMinVal;

// The smaller root x >= 0 of a x^2 + 2 b x + c = 0 (the other if only it is >= 0), -1 if neither
// is or there is no real root; both roots in roots[] (-1, -1 without real ones).
double first_root(double a, double b, double c, double roots[2]) {
  double disc = b * b - a * c;
  if (disc < kMinVal) {
    roots[0] = roots[1] = -1;
    return -1;
  }
  disc = std::sqrt(disc);
  roots[0] = (-b - disc) / a;
  roots[1] = (-b + disc) / a;
  if (roots[0] >= 0) return roots[0];
  if (roots[1] >= 0) return roots[1];
  return -1;
}

// the nearer of a hit so far and a new one (-1: none)
double nearer(double best, double x) { return x >= 0 && (best < 0 || x < best) ? x : best; }

// A sphere of radius r at pos (needs no frame).
double ray_sphere(const Vector3d& pos, double r, const Vector3d& pnt, const Vector3d& vec) {
  const Vector3d d = pnt - pos;
  double roots[2];
  return first_root(vec.dot(vec), vec.dot(d), d.dot(d) - r * r, roots);
}

// An infinite plane (z = 0 of its frame, seen from +z), or the rectangle of half-sizes size[0],
// size[1] where those are positive.
double ray_plane(const Vector3d& size, const Vector3d& p, const Vector3d& v) {
  if (v[2] > -kMinVal) return -1;  // parallel, or coming from behind
  const double x = -p[2] / v[2];
  if (x < 0) return -1;
  const double u = p[0] + x * v[0], w = p[1] + x * v[1];
  const bool inside = (size[0] <= 0 || std::abs(u) <= size[0]) &&
                      (size[1] <= 0 || std::abs(w) <= size[1]);
  return inside ? x : -1;
}

// A cylinder's round side, radius r, between z = -half and +half.
double ray_round_side(double r, double half, const Vector3d& p, const Vector3d& v) {
  double roots[2];
  const double x = first_root(v[0] * v[0] + v[1] * v[1], v[0] * p[0] + v[1] * p[1],
                              p[0] * p[0] + p[1] * p[1] - r * r, roots);
  return x >= 0 && std::abs(p[2] + x * v[2]) <= half ? x : -1;
}

double ray_capsule(const Vector3d& size, const Vector3d& p, const Vector3d& v) {
  const double r = size[0], half = size[1];
  double best = ray_round_side(r, half, p, v);
  // the two caps: spheres at z = +-half, each only on its own side of the cylinder
  const double aa = v.dot(v);
  for (const double side : {1.0, -1.0}) {
    const Vector3d d(p[0], p[1], p[2] - side * half);
    double roots[2];
    first_root(aa, v.dot(d), d.dot(d) - r * r, roots);
    for (const double x : roots) {
      if (x >= 0 && side * (p[2] + x * v[2]) >= half) best = nearer(best, x);
    }
  }
  return best;
}

double ray_ellipsoid(const Vector3d& size, const Vector3d& p, const Vector3d& v) {
  // the unit sphere in coordinates scaled by 1 / size
  const Vector3d s(1 / (size[0] * size[0]), 1 / (size[1] * size[1]), 1 / (size[2] * size[2]));
  double roots[2];
  return first_root(s[0] * v[0] * v[0] + s[1] * v[1] * v[1] + s[2] * v[2] * v[2],
                    s[0] * v[0] * p[0] + s[1] * v[1] * p[1] + s[2] * v[2] * p[2],
                    s[0] * p[0] * p[0] + s[1] * p[1] * p[1] + s[2] * p[2] * p[2] - 1, roots);
}

double ray_cylinder(const Vector3d& size, const Vector3d& p, const Vector3d& v) {
  const double r = size[0], half = size[1];
  double best = -1;
  if (std::abs(v[2]) > kMinVal) {  // the flat ends, z = -half and +half
    for (const double side : {-1.0, 1.0}) {
      const double x = (side * half - p[2]) / v[2];
      if (x < 0) continue;
      const double u = p[0] + x * v[0], w = p[1] + x * v[1];
      if (u * u + w * w <= r * r) best = nearer(best, x);
    }
  }
  return nearer(best, ray_round_side(r, half, p, v));
}

double ray_box(const Vector3d& size, const Vector3d& p, const Vector3d& v) {
  double best = -1;
  for (int axis = 0; axis < 3; ++axis) {  // the two faces across each axis
    if (std::abs(v[axis]) <= kMinVal) continue;
    const int a = axis == 0 ? 1 : 0, b = axis == 2 ? 1 : 2;  // the face's own two axes
    for (const double side : {-1.0, 1.0}) {
      const double x = (side * size[axis] - p[axis]) / v[axis];
      if (x < 0) continue;
      if (std::abs(p[a] + x * v[a]) <= size[a] && std::abs(p[b] + x * v[b]) <= size[b]) {
        best = nearer(best, x);
      }
    }
  }
  return best;
}

// A triangle (corners v, the ray's frame) met by p + x d: projected on the plane across d (axes
// b0, b1), the ray is the origin, and it meets the triangle where the origin is inside the
// projected triangle; then x is where the ray crosses the triangle's plane (MuJoCo's
// ray_triangle).
double ray_triangle(const Vector3d v[3], const Vector3d& p, const Vector3d& d, const Vector3d& b0,
                    const Vector3d& b1) {
  double planar[3][2];
  for (int i = 0; i < 3; ++i) {
    const Vector3d dif = v[i] - p;
    planar[i][0] = b0.dot(dif);
    planar[i][1] = b1.dot(dif);
  }
  // all three corners on one side of an axis: the origin is outside
  for (int axis = 0; axis < 2; ++axis) {
    if ((planar[0][axis] > 0 && planar[1][axis] > 0 && planar[2][axis] > 0) ||
        (planar[0][axis] < 0 && planar[1][axis] < 0 && planar[2][axis] < 0)) {
      return -1;
    }
  }
  // the origin as corner 2 + t0 (corner 0 - corner 2) + t1 (corner 1 - corner 2)
  const double a00 = planar[0][0] - planar[2][0], a01 = planar[1][0] - planar[2][0];
  const double a10 = planar[0][1] - planar[2][1], a11 = planar[1][1] - planar[2][1];
  const double det = a00 * a11 - a01 * a10;
  if (std::abs(det) < kMinVal) return -1;
  const double r0 = -planar[2][0], r1 = -planar[2][1];
  const double t0 = (a11 * r0 - a01 * r1) / det;
  const double t1 = (-a10 * r0 + a00 * r1) / det;
  if (t0 < 0 || t1 < 0 || t0 + t1 > 1) return -1;
  // where the ray crosses the triangle's plane
  const Vector3d normal = (v[0] - v[2]).cross(v[1] - v[2]);
  const double denom = d.dot(normal);
  if (std::abs(denom) < kMinVal) return -1;
  return -(p - v[2]).dot(normal) / denom;
}

}  // namespace

double ray_mesh(const Model& model, const Data& data, int g, const Vector3d& pnt,
                const Vector3d& vec) {
  const Mat3& R = data.geom_xmat[g];
  // the mesh's bounding box first (a mesh geom's size is its half-extents)
  if (ray_shape(data.geom_xpos[g], R, model.geom_size[g], pnt, vec, GeomType::kBox) < 0) return -1;
  const Vector3d p = rotate_back(R, pnt - data.geom_xpos[g]), d = rotate_back(R, vec);
  // axes across d: b1 from the coordinate axis least along d (its (1, 1, 1) without that
  // component), made normal to d; b0 normal to both
  Vector3d b0(1, 1, 1);
  if (std::abs(d[0]) >= std::abs(d[1]) && std::abs(d[0]) >= std::abs(d[2])) {
    b0[0] = 0;
  } else if (std::abs(d[1]) >= std::abs(d[2])) {
    b0[1] = 0;
  } else {
    b0[2] = 0;
  }
  Vector3d b1 = b0 - (d.dot(b0) / d.dot(d)) * d;
  b1 /= b1.norm();
  b0 = b1.cross(d);
  b0 /= b0.norm();

  const int mesh = model.geom_dataid[g];
  const Eigen::Vector3d* vert = model.mesh_vert.data() + model.mesh_vertadr[mesh];
  double best = -1;
  const int first = model.mesh_faceadr[mesh], end = first + model.mesh_facenum[mesh];
  for (int f = first; f < end; ++f) {
    const std::array<int, 3>& corners = model.mesh_face[f];
    const Vector3d v[3] = {vert[corners[0]], vert[corners[1]], vert[corners[2]]};
    best = nearer(best, ray_triangle(v, p, d, b0, b1));
  }
  return best;
}

double ray_shape(const Vector3d& pos, const Mat3& R, const Vector3d& size, const Vector3d& pnt,
                 const Vector3d& vec, GeomType type) {
  // a sphere needs no frame; the finite shapes are first tested against their bounding sphere
  switch (type) {
    case GeomType::kSphere: return ray_sphere(pos, size[0], pnt, vec);
    case GeomType::kCapsule:
      if (ray_sphere(pos, size[0] + size[1], pnt, vec) < 0) return -1;
      break;
    case GeomType::kCylinder:
      if (ray_sphere(pos, std::sqrt(size[0] * size[0] + size[1] * size[1]), pnt, vec) < 0) {
        return -1;
      }
      break;
    case GeomType::kBox:
      if (ray_sphere(pos, size.norm(), pnt, vec) < 0) return -1;
      break;
    default: break;
  }
  // the ray in the shape's frame
  const Vector3d p = rotate_back(R, pnt - pos), v = rotate_back(R, vec);
  switch (type) {
    case GeomType::kPlane: return ray_plane(size, p, v);
    case GeomType::kCapsule: return ray_capsule(size, p, v);
    case GeomType::kEllipsoid: return ray_ellipsoid(size, p, v);
    case GeomType::kCylinder: return ray_cylinder(size, p, v);
    case GeomType::kBox: return ray_box(size, p, v);
    default: return -1;  // meshes (ray_mesh) and height fields (a rangefinder's model has none)
  }
}

double ray(const Model& model, const Data& data, const Vector3d& pnt, const Vector3d& vec,
           int exclude_body, int* geom) {
  double best = -1;
  *geom = -1;
  for (int g = 0; g < model.ngeom; ++g) {
    // MuJoCo's exclusions: the given body, invisible geoms (a geom with a material is visible:
    // lever does not read a material's colour)
    if (model.geom_bodyid[g] == exclude_body) continue;
    if (model.visual.geom_material.size() == static_cast<size_t>(model.ngeom) &&
        !model.visual.geom_material[g].empty()) {
      // visible whatever its own rgba
    } else if (model.geom_rgba[g][3] == 0) {
      continue;
    }
    const double x = model.geom_type[g] == GeomType::kMesh
                         ? ray_mesh(model, data, g, pnt, vec)
                         : ray_shape(data.geom_xpos[g], data.geom_xmat[g], model.geom_size[g],
                                     pnt, vec, model.geom_type[g]);
    if (x >= 0 && (best < 0 || x < best)) {
      best = x;
      *geom = g;
    }
  }
  return best;
}

}  // namespace lever
