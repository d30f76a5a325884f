// How a contact's distance, position and frame change when its two geoms move: the narrow phase's
// closed-form pairs (collision/primitive.cpp, collision/box.cpp's sphere-box) and the driver's
// frame completion (MuJoCo's mju_makeFrame), evaluated once more on dual numbers a + b e (e^2 = 0)
// with the geoms' poses moving along a rigid motion. Every branch is decided on the values, as the
// collision stage decided it, so the result is the exact derivative of the contact the stage found,
// its case held (which face, which corner, which end of a capsule): forward-mode differentiation,
// no step and no truncation. The values are checked against data.contact, so a contact this room
// does not reproduce is an error, not a wrong derivative.
//
// Pairs: plane against sphere, capsule, box and ellipsoid; sphere-sphere, sphere-capsule,
// capsule-capsule, sphere-box. Capsule-box, box-box and plane-cylinder are refused by name.
#include <lever/collision.hpp>
#include <lever/error.hpp>

#include <array>
#include <cmath>
#include <string>

#include "basics/basics.hpp"
#include "transition/transition.hpp"

namespace lever::detail {

namespace {

// ---- dual numbers ---------------------------------------------------------------------------------

struct Dual {
  double v = 0;  // value
  double d = 0;  // derivative along the motion
};

Dual operator+(Dual a, Dual b) { return {a.v + b.v, a.d + b.d}; }
Dual operator-(Dual a, Dual b) { return {a.v - b.v, a.d - b.d}; }
Dual operator-(Dual a) { return {-a.v, -a.d}; }
Dual operator*(Dual a, Dual b) { return {a.v * b.v, a.d * b.v + a.v * b.d}; }
Dual operator*(Dual a, double s) { return {a.v * s, a.d * s}; }
Dual operator/(Dual a, Dual b) { return {a.v / b.v, (a.d * b.v - a.v * b.d) / (b.v * b.v)}; }
Dual sqrt(Dual a) {
  const double r = std::sqrt(a.v);
  return {r, r > 0 ? a.d / (2 * r) : 0.0};
}
Dual constant(double x) { return {x, 0.0}; }

using V = std::array<Dual, 3>;

V operator+(const V& a, const V& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V operator-(const V& a, const V& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V operator*(const V& a, Dual s) { return {a[0] * s, a[1] * s, a[2] * s}; }
V operator*(const V& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
Dual dot(const V& a, const V& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V cross(const V& a, const V& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
V constant(const Eigen::Vector3d& x) { return {constant(x[0]), constant(x[1]), constant(x[2])}; }

// v / |v| and |v|; a vector shorter than kMinVal becomes (1, 0, 0) (mju_normalize3)
Dual normalize(V& v) {
  const Dual norm = sqrt(dot(v, v));
  if (norm.v < kMinVal) {
    v = {constant(1), constant(0), constant(0)};
  } else {
    v = v * (constant(1) / norm);
  }
  return norm;
}

// A geom's pose moving rigidly: pos' = w x (pos - centre) + v at the centre, mat' = [w] mat.
struct Pose {
  GeomType type;
  Eigen::Vector3d size;
  V pos;
  std::array<V, 3> axis;  // mat's columns
};

Pose moving_pose(const Model& model, const Data& data, int g, const Eigen::Vector3d& w,
                 const Eigen::Vector3d& v) {
  Pose p{model.geom_type[g], model.geom_size[g], {}, {}};
  for (int k = 0; k < 3; ++k) p.pos[k] = {data.geom_xpos[g][k], v[k]};
  for (int c = 0; c < 3; ++c) {
    const Eigen::Vector3d a = data.geom_xmat[g].col(c);
    const Eigen::Vector3d turn = w.cross(a);
    for (int k = 0; k < 3; ++k) p.axis[c][k] = {a[k], turn[k]};
  }
  return p;
}

// R x and R^T x for the pose's rotation
V rotate(const Pose& p, const V& x) { return p.axis[0] * x[0] + p.axis[1] * x[1] + p.axis[2] * x[2]; }
V unrotate(const Pose& p, const V& x) { return {dot(p.axis[0], x), dot(p.axis[1], x), dot(p.axis[2], x)}; }

struct Found {
  Dual dist;
  V pos, normal, tangent;  // tangent: the first tangent's seed, zero unless the pair sets one
};

void set(Found& f, Dual dist, const V& pos, const V& normal) {
  f.dist = dist;
  f.pos = pos;
  f.normal = normal;
  f.tangent = constant(Eigen::Vector3d::Zero());
}

// ---- the pairs, as collision/primitive.cpp and box.cpp decide them ------------------------------

int plane_sphere(const Pose& plane, const V& center, double radius, double margin, Found* out) {
  const V n = plane.axis[2];
  const Dual height = dot(center - plane.pos, n);
  if (height.v > margin + radius) return 0;
  const Dual dist = height - constant(radius);
  set(out[0], dist, center + n * (dist * -0.5 - constant(radius)), n);
  return 1;
}

int sphere_sphere(const V& c1, const Pose& p1, double r1, const V& c2, const Pose& p2, double r2,
                  double margin, Found* out) {
  const V between = c1 - c2;
  const Dual distance = sqrt(dot(between, between));
  if (distance.v > margin + r1 + r2) return 0;
  const Dual dist = distance - constant(r1 + r2);
  V n = c2 - c1;
  if (normalize(n).v < kMinVal) {
    n = cross(p1.axis[2], p2.axis[2]);
    normalize(n);
  }
  set(out[0], dist, n * (constant(r1) + dist * 0.5) + c1, n);
  return 1;
}

Dual clamp_to_segment(Dual x) {
  if (x.v > 1) return constant(1);
  if (x.v < -1) return constant(-1);
  return x;
}

int plane_capsule(const Pose& plane, const Pose& capsule, double margin, Found* out) {
  const V axis = capsule.axis[2];
  const V segment = axis * capsule.size[1];
  const int n1 = plane_sphere(plane, capsule.pos + segment, capsule.size[0], margin, out);
  const int n2 = plane_sphere(plane, capsule.pos - segment, capsule.size[0], margin, out + n1);
  for (int k = 0; k < n1 + n2; ++k) out[k].tangent = axis;
  return n1 + n2;
}

int plane_box(const Pose& plane, const Pose& box, double margin, Found* out) {
  const V n = plane.axis[2];
  const Dual height = dot(box.pos - plane.pos, n);
  int count = 0;
  for (int i = 0; i < 8; ++i) {
    const V local = constant(Eigen::Vector3d((i & 1) ? box.size[0] : -box.size[0],
                                             (i & 2) ? box.size[1] : -box.size[1],
                                             (i & 4) ? box.size[2] : -box.size[2]));
    const V corner = rotate(box, local);
    const Dual along = dot(n, corner);
    if (height.v + along.v > margin || along.v > 0) continue;
    const Dual dist = height + along;
    set(out[count], dist, (corner + box.pos) + n * (dist * -0.5), n);
    if (++count >= 4) return 4;
  }
  return count;
}

int plane_ellipsoid(const Pose& plane, const Pose& ellipsoid, double margin, Found* out) {
  const V n = plane.axis[2];
  const V down = unrotate(ellipsoid, n * -1.0);
  V support{down[0] * ellipsoid.size[0], down[1] * ellipsoid.size[1], down[2] * ellipsoid.size[2]};
  normalize(support);
  support = {support[0] * ellipsoid.size[0], support[1] * ellipsoid.size[1],
             support[2] * ellipsoid.size[2]};
  const V deepest = rotate(ellipsoid, support) + ellipsoid.pos;
  const Dual dist = dot(n, deepest - plane.pos);
  if (dist.v > margin) return 0;
  set(out[0], dist, deepest + n * (dist * -0.5), n);
  return 1;
}

int sphere_capsule(const Pose& sphere, const Pose& capsule, double margin, Found* out) {
  const V axis = capsule.axis[2] * capsule.size[1];
  const Dual x = clamp_to_segment(dot(axis, sphere.pos - capsule.pos) / dot(axis, axis));
  return sphere_sphere(sphere.pos, sphere, sphere.size[0], axis * x + capsule.pos, capsule,
                       capsule.size[0], margin, out);
}

int capsule_capsule(const Pose& c1, const Pose& c2, double margin, Found* out) {
  const V a1 = c1.axis[2] * c1.size[1];
  const V a2 = c2.axis[2] * c2.size[1];
  const V between = c1.pos - c2.pos;
  const Dual ma = dot(a1, a1), mb = -dot(a1, a2), mc = dot(a2, a2);
  const Dual u = -dot(a1, between), v = dot(a2, between);
  const Dual det = ma * mc - mb * mb;
  const auto spheres_at = [&](Dual x1, Dual x2, Found* f) {
    return sphere_sphere(a1 * x1 + c1.pos, c1, c1.size[0], a2 * x2 + c2.pos, c2, c2.size[0],
                         margin, f);
  };
  if (std::abs(det.v) >= kMinVal) {
    Dual x1 = (mc * u - mb * v) / det;
    Dual x2 = (ma * v - mb * u) / det;
    if (x1.v > 1) {
      x1 = constant(1);
      x2 = (v - mb) / mc;
    } else if (x1.v < -1) {
      x1 = constant(-1);
      x2 = (v + mb) / mc;
    }
    if (x2.v > 1) {
      x2 = constant(1);
      x1 = clamp_to_segment((u - mb) / ma);
    } else if (x2.v < -1) {
      x2 = constant(-1);
      x1 = clamp_to_segment((u + mb) / ma);
    }
    return spheres_at(x1, x2, out);
  }
  // parallel: the ends of each against the other, until two contacts are found
  int count = sphere_sphere(c1.pos + a1, c1, c1.size[0],
                            a2 * clamp_to_segment((v - mb) / mc) + c2.pos, c2, c2.size[0], margin,
                            out);
  count += sphere_sphere(c1.pos - a1, c1, c1.size[0], a2 * clamp_to_segment((v + mb) / mc) + c2.pos,
                         c2, c2.size[0], margin, out + count);
  if (count >= 2) return count;
  count += sphere_sphere(a1 * clamp_to_segment((u - mb) / ma) + c1.pos, c1, c1.size[0], c2.pos + a2,
                         c2, c2.size[0], margin, out + count);
  if (count >= 2) return count;
  count += sphere_sphere(a1 * clamp_to_segment((u + mb) / ma) + c1.pos, c1, c1.size[0], c2.pos - a2,
                         c2, c2.size[0], margin, out + count);
  return count;
}

int sphere_box(const Pose& sphere, const Pose& box, double margin, Found* out) {
  const double radius = sphere.size[0];
  const V center = unrotate(box, sphere.pos - box.pos);  // in the box's frame
  V nearest = center;
  for (int k = 0; k < 3; ++k) {
    const double half = box.size[k];
    if (half > 0 && center[k].v < -half) nearest[k] = constant(-half);
    if (half > 0 && center[k].v > half) nearest[k] = constant(half);
  }
  V toward = nearest - center;
  const Dual distance = normalize(toward);
  if (distance.v - radius > margin) return 0;
  V local_pos, local_normal;
  if (distance.v <= kMinVal) {
    // the centre inside the box: out through the nearest face (first of -x, +x, ..., +z on a tie)
    double closest = (box.size[0] + box.size[1] + box.size[2]) * 2;
    int face = 0;
    Dual gap_of_face;
    for (int f = 0; f < 6; ++f) {
      const int axis = f / 2;
      const double side = (f % 2) ? 1.0 : -1.0;
      const Dual signed_gap = constant(side * box.size[axis]) - center[axis];
      const Dual gap = signed_gap.v < 0 ? -signed_gap : signed_gap;
      if (gap.v < closest) {
        closest = gap.v;
        gap_of_face = gap;
        face = f;
      }
    }
    local_normal = constant(Eigen::Vector3d::Zero());
    local_normal[face / 2] = constant((face % 2) ? -1.0 : 1.0);
    local_pos = center + local_normal * ((constant(radius) - gap_of_face) * 0.5);
  } else {
    const V deepest = center + toward * radius;
    local_pos = nearest * 0.5 + deepest * 0.5;
    local_normal = toward;
  }
  set(out[0], distance - constant(radius), rotate(box, local_pos) + box.pos,
      rotate(box, local_normal));
  return 1;
}

const char* shape_name(GeomType t) {
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

int collide_moving(const Pose& g1, const Pose& g2, double margin, Found* out) {
  using T = GeomType;
  if (g1.type == T::kPlane) {
    switch (g2.type) {
      case T::kSphere: return plane_sphere(g1, g2.pos, g2.size[0], margin, out);
      case T::kCapsule: return plane_capsule(g1, g2, margin, out);
      case T::kBox: return plane_box(g1, g2, margin, out);
      case T::kEllipsoid: return plane_ellipsoid(g1, g2, margin, out);
      default: break;
    }
  } else if (g1.type == T::kSphere) {
    switch (g2.type) {
      case T::kSphere: return sphere_sphere(g1.pos, g1, g1.size[0], g2.pos, g2, g2.size[0], margin, out);
      case T::kCapsule: return sphere_capsule(g1, g2, margin, out);
      case T::kBox: return sphere_box(g1, g2, margin, out);
      default: break;
    }
  } else if (g1.type == T::kCapsule && g2.type == T::kCapsule) {
    return capsule_capsule(g1, g2, margin, out);
  }
  throw Error(std::string("derivatives: a ") + shape_name(g1.type) + "-" + shape_name(g2.type) +
              " contact is active; lever differentiates the contact geometry of plane against "
              "sphere, capsule, box and ellipsoid, and of sphere and capsule pairs, so far.");
}

// The frame the driver completes from the normal and the first tangent's seed (mju_makeFrame).
std::array<V, 3> complete_frame(V normal, V tangent) {
  normalize(normal);
  if (std::sqrt(dot(tangent, tangent).v) < 0.5) {
    const bool near_y = !(normal[1].v < 0.5 && normal[1].v > -0.5);
    tangent = constant(near_y ? Eigen::Vector3d(0, 0, 1) : Eigen::Vector3d(0, 1, 0));
  }
  tangent = tangent - normal * dot(normal, tangent);
  normalize(tangent);
  return {normal, tangent, cross(normal, tangent)};
}

}  // namespace

bool contact_geometry_supported(GeomType a, GeomType b) {
  using T = GeomType;
  if (a == T::kPlane) return b == T::kSphere || b == T::kCapsule || b == T::kBox || b == T::kEllipsoid;
  if (a == T::kSphere) return b == T::kSphere || b == T::kCapsule || b == T::kBox;
  return a == T::kCapsule && b == T::kCapsule;
}

int pair_first_contact(const Data& data, int i, int& count) {
  const Contact& con = data.contact[static_cast<std::size_t>(i)];
  const auto same_pair = [&](int k) {
    const Contact& other = data.contact[static_cast<std::size_t>(k)];
    return other.geom1 == con.geom1 && other.geom2 == con.geom2;
  };
  int first = i;
  while (first > 0 && same_pair(first - 1)) --first;
  int last = i;
  while (last + 1 < data.ncon && same_pair(last + 1)) ++last;
  count = last - first + 1;
  return first;
}

void pair_contact_changes(const Model& model, const Data& data, int first, int count,
                          const Eigen::Vector3d& w1, const Eigen::Vector3d& v1,
                          const Eigen::Vector3d& w2, const Eigen::Vector3d& v2,
                          ContactChange* changes) {
  const Contact& con = data.contact[static_cast<std::size_t>(first)];
  const Pose g1 = moving_pose(model, data, con.geom1, w1, v1);
  const Pose g2 = moving_pose(model, data, con.geom2, w2, v2);
  // the pair's margin as the driver mixed it: includemargin is margin - gap
  double margin;
  int pair = -1;
  for (int p = 0; p < model.npair; ++p) {
    if ((model.pair_geom1[p] == con.geom1 && model.pair_geom2[p] == con.geom2) ||
        (model.pair_geom1[p] == con.geom2 && model.pair_geom2[p] == con.geom1)) {
      pair = p;
    }
  }
  margin = pair >= 0 ? model.pair_margin[pair]
                     : std::max(model.geom_margin[con.geom1], model.geom_margin[con.geom2]);
  std::array<Found, kMaxPairContacts> found;
  const int n = collide_moving(g1, g2, margin, found.data());
  for (int k = 0; k < count; ++k) {
    const int i = first + k;
    const Contact& ck = data.contact[static_cast<std::size_t>(i)];
    if (n == 0) throw Error("derivatives: contact " + std::to_string(i) + " is not reproduced.");
    const Found& f = found[static_cast<std::size_t>(k % n)];
    const std::array<V, 3> frame = complete_frame(f.normal, f.tangent);

    // the values are the collision stage's: else this is not the contact it found
    double gap = std::abs(f.dist.v - ck.dist);
    for (int a = 0; a < 3; ++a) {
      gap = std::max(gap, std::abs(f.pos[a].v - ck.pos[a]));
      for (int r = 0; r < 3; ++r) gap = std::max(gap, std::abs(frame[r][a].v - ck.frame(r, a)));
    }
    if (!(gap <= 1e-9 * (1 + ck.pos.cwiseAbs().maxCoeff()))) {
      throw Error("derivatives: contact " + std::to_string(i) +
                  " is not reproduced by the contact geometry's derivative (off by " +
                  std::to_string(gap) + ").");
    }
    ContactChange& change = changes[k];
    change.dist = f.dist.d;
    for (int a = 0; a < 3; ++a) {
      change.pos[a] = f.pos[a].d;
      for (int r = 0; r < 3; ++r) change.frame(r, a) = frame[r][a].d;
    }
  }
}

void contact_change(const Model& model, const Data& data, int i, const Eigen::Vector3d& w1,
                    const Eigen::Vector3d& v1, const Eigen::Vector3d& w2,
                    const Eigen::Vector3d& v2, ContactChange& change) {
  int count = 0;
  const int first = pair_first_contact(data, i, count);
  std::array<ContactChange, kMaxPairContacts> changes;
  pair_contact_changes(model, data, first, count, w1, v1, w2, v2, changes.data());
  change = changes[static_cast<std::size_t>(i - first)];
}

}  // namespace lever::detail
