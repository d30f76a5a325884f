// How a contact's distance, position and frame change when its two geoms move: the narrow phase's
// closed-form pairs (collision/primitive_pairs.hpp and collision/box_pairs.hpp, written once on a
// scalar; here the plane-ellipsoid support point too) and the driver's frame
// completion (MuJoCo's mju_makeFrame), evaluated on dual numbers a + sum_m b_m e_m (e_m e_n = 0)
// with the geoms' poses moving along up to six rigid motions at once (the values computed once, a
// derivative per motion). Every branch is decided on the values, as the collision stage
// decided it, so the result is the exact derivative of the contact the stage found, its case held
// (which face, which corner, which end of a capsule): forward-mode differentiation, no step and no
// truncation. The values are checked against data.contact, so a contact this room does not
// reproduce is an error, not a wrong derivative.
//
// Pairs: every pair MuJoCo collides in closed form: plane against sphere, capsule, box, cylinder,
// ellipsoid and mesh; sphere-sphere, sphere-capsule, capsule-capsule, sphere-box, capsule-box and
// box-box (collision/box_pairs.hpp). Of the pairs MuJoCo collides by MPR, those of two polytopes
// (box-mesh, mesh-mesh) at margin 0: MPR's answer is a closed form of its last portal's vertices,
// the portal its search ended on held (a vertex on a face, an edge across an edge, a face on a
// face). The others (a round geom against a mesh, a cylinder or an ellipsoid against anything but
// a plane, a margin) are refused by name: their support points move with the iteration's
// directions, so the answer is the whole iteration's, not its last portal's (docs/derivatives.md).
#include <lever/collision.hpp>
#include <lever/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "basics/basics.hpp"
#include "basics/dual.hpp"
#include "collision/collision_room.hpp"
#include "collision/box_pairs.hpp"
#include "collision/narrow_phase.hpp"
#include "collision/primitive_pairs.hpp"
#include "transition/transition.hpp"

namespace lever::detail {

namespace {

// the narrow phase runs along kMotions motions at once: the values once, a derivative per motion
constexpr int kMotions = 6;
using Scalar = Duals<kMotions>;
using V = primitive::Vec<Scalar>;
using primitive::cross;
using primitive::dot;
using primitive::normalize;
V constant(const Eigen::Vector3d& x) { return primitive::constant_vec<Scalar>(x); }

// The pairs MuJoCo collides by MPR whose geoms are both polytopes: box-mesh and mesh-mesh.
bool polytope_mpr_pair(GeomType a, GeomType b) {
  const auto polytope = [](GeomType t) { return t == GeomType::kBox || t == GeomType::kMesh; };
  return polytope(a) && polytope(b) && (a == GeomType::kMesh || b == GeomType::kMesh);
}

// A geom's pose moving rigidly along each of the motions (geom 1's or 2's part of each):
// pos' = w x (pos - centre) + v at the centre, mat' = [w] mat; motions past `count` stand still.
using Pose = primitive::Shape<Scalar>;

Pose moving_pose(const Model& model, const Data& data, int g, const GeomPairMotion* motions,
                 int count, bool second) {
  Pose p{model.geom_type[g], model.geom_size[g], {}, {}};
  for (int k = 0; k < 3; ++k) p.pos[k] = Scalar(data.geom_xpos[g][k]);
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 3; ++k) p.axis[c][k] = Scalar(data.geom_xmat[g](k, c));
  }
  for (int m = 0; m < count; ++m) {
    const Eigen::Vector3d& w = second ? motions[m].w2 : motions[m].w1;
    const Eigen::Vector3d& v = second ? motions[m].v2 : motions[m].v1;
    for (int k = 0; k < 3; ++k) p.pos[k].d[m] = v[k];
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d turn = w.cross(data.geom_xmat[g].col(c));
      for (int k = 0; k < 3; ++k) p.axis[c][k].d[m] = turn[k];
    }
  }
  return p;
}

// R x and R^T x for the pose's rotation
V rotate(const Pose& p, const V& x) { return primitive::rotate(p, x); }
V unrotate(const Pose& p, const V& x) {
  return {{dot(p.axis[0], x), dot(p.axis[1], x), dot(p.axis[2], x)}};
}

using Found = primitive::Touch<Scalar>;

void set(Found& f, const Scalar& dist, const V& pos, const V& normal) {
  primitive::touch(f, dist, pos, normal);
}

// ---- the pairs the collision room does not write on a scalar: as box.cpp and convex.cpp decide
// them

int plane_ellipsoid(const Pose& plane, const Pose& ellipsoid, double margin, Found* out) {
  const V n = plane.axis[2];
  const V down = unrotate(ellipsoid, n * -1.0);
  V support{down[0] * ellipsoid.size[0], down[1] * ellipsoid.size[1], down[2] * ellipsoid.size[2]};
  normalize(support);
  support = {support[0] * ellipsoid.size[0], support[1] * ellipsoid.size[1],
             support[2] * ellipsoid.size[2]};
  const V deepest = rotate(ellipsoid, support) + ellipsoid.pos;
  const Scalar dist = dot(n, deepest - plane.pos);
  if (dist.v > margin) return 0;
  set(out[0], dist, deepest + n * (dist * -0.5), n);
  return 1;
}

// The box pairs of collision/box_pairs.hpp on the moving poses.
box_pairs::Vec3<Scalar> box_vec(const V& x) { return {x[0], x[1], x[2]}; }

int sphere_box(const Pose& sphere, const Pose& box, double margin, Found* out) {
  return box_pairs::sphere_box(box_vec(sphere.pos), sphere.size[0], box_pairs::box_of(box), margin,
                               out);
}

int capsule_box(const Pose& capsule, const Pose& box, double margin, Found* out) {
  return box_pairs::capsule_box(box_vec(capsule.pos), box_vec(capsule.axis[2]), capsule.size[0],
                                capsule.size[1], box_pairs::box_of(box), margin, out);
}

// The driver drops a box-box contact whose position another later one repeats exactly
// (remove_repeated_positions): the same here, on the values.
int box_box(const Pose& box1, const Pose& box2, double margin, Found* out) {
  const int n =
      box_pairs::box_box(box_pairs::box_of(box1), box_pairs::box_of(box2), margin, out);
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    bool repeated = false;
    for (int j = i + 1; j < n && !repeated; ++j) {
      repeated = out[i].pos[0].v == out[j].pos[0].v && out[i].pos[1].v == out[j].pos[1].v &&
                 out[i].pos[2].v == out[j].pos[2].v;
    }
    if (repeated) continue;
    if (kept < i) out[kept] = out[i];
    ++kept;
  }
  return kept;
}

// Plane-mesh (collision/convex.cpp's plane_convex): each contact is a vertex of the mesh's hull
// against the plane, the lowest and up to two more below the margin. The vertex, rigid in the
// mesh, is where the contact's point and half its distance along the normal put it; held, it moves
// with the mesh's pose. (Which vertices: the case the stage found.)
int plane_mesh(const Pose& plane, const Pose& mesh, const Data& data, int first, int count,
               Found* out) {
  const V n = plane.axis[2];
  const int g = data.contact[static_cast<std::size_t>(first)].geom2;
  for (int k = 0; k < count; ++k) {
    const Contact& c = data.contact[static_cast<std::size_t>(first + k)];
    const Eigen::Vector3d vertex = c.pos + c.frame.row(0).transpose() * (0.5 * c.dist);
    const Eigen::Vector3d local = data.geom_xmat[g].transpose() * (vertex - data.geom_xpos[g]);
    const V point = rotate(mesh, constant(local)) + mesh.pos;
    const Scalar dist = dot(n, point - plane.pos);
    set(out[k], dist, point + n * (dist * -0.5), n);
  }
  return count;
}

// ---- the MPR pairs of two polytopes (box-mesh, mesh-mesh) -------------------------------------
// MuJoCo collides them by libccd's MPR, whose answer is read off its last portal: a triangle
// (v1, v2, v3) of the Minkowski difference's support points v = a - b (a a point of geom 1, b of
// geom 2, each a vertex of its polytope) and the interior point v0 = c1 - c2 (the geoms' centres).
// The normal is the triangle's, pointing away from the origin, the depth the origin's distance to
// it (dist = margin - depth: margin 0 here, where support points are vertices), and the point
// half the sum of a and b weighted by the origin's barycentric coordinates in the tetrahedron
// (v0, v1, v2, v3). Held (the vertices stay the portal's), all three are closed forms of the two
// poses: differentiated here. Which vertices: the search is run again on the same shapes
// (collision/convex.cpp's mpr_search, which writes down the support points it asks for), and of
// those the triple whose closed form gives its answer is its last portal. Where two faces meet,
// the point depends on which triangle of their Minkowski face that is, so it must be the
// search's own; where the portal flips with the direction of a motion, there is no derivative.

// The geom as the collision stage hands it to the narrow phase (its pose at the state).
GeomShape shape_at_state(const Model& model, const Data& data, int g) {
  GeomShape s{model.geom_type[g], model.geom_size[g], data.geom_xpos[g], data.geom_xmat[g],
              model.geom_rbound[g]};
  const int mesh = model.geom_dataid[g];
  if (mesh >= 0 && model.mesh_vertnum[mesh] > 0) {
    s.mesh_vert = model.mesh_vert[static_cast<std::size_t>(model.mesh_vertadr[mesh])].data();
    s.mesh_vertnum = model.mesh_vertnum[mesh];
    const int graph = model.mesh_graphadr[mesh];
    s.mesh_graph = graph >= 0 ? model.mesh_graph.data() + graph : nullptr;
  }
  return s;
}

// The answer of a portal whose support points are a[i] - b[i], the centres c1, c2.
template <class S>
primitive::Touch<S> portal_answer(const primitive::Vec<S> (&a)[3], const primitive::Vec<S> (&b)[3],
                                  const primitive::Vec<S>& c1, const primitive::Vec<S>& c2,
                                  double margin) {
  using W = primitive::Vec<S>;
  using primitive::value;
  const W v0 = c1 - c2;
  const W v[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  W normal = cross(v[1] - v[0], v[2] - v[0]);
  normalize(normal);
  if (value(dot(normal, v[0])) < 0) normal = normal * S(-1.0);
  const S depth = dot(normal, v[0]);
  // barycentric weights (six times the volumes) of v0, v1, v2, v3, as libccd's findPos sums them;
  // the triangle's orientation flips all four
  const auto det = [](const W& x, const W& y, const W& z) { return dot(cross(x, y), z); };
  const S w[4] = {det(v[0], v[1], v[2]), det(v[2], v[1], v0), det(v0, v[0], v[2]),
                  det(v[1], v[0], v0)};
  const S sum = w[0] + w[1] + w[2] + w[3];
  W p1 = c1 * w[0], p2 = c2 * w[0];
  for (int i = 0; i < 3; ++i) {
    p1 = p1 + a[i] * w[i + 1];
    p2 = p2 + b[i] * w[i + 1];
  }
  const S half = S(0.5) / sum;
  primitive::Touch<S> f;
  primitive::touch(f, S(margin) - depth, (p1 + p2) * half, normal);
  return f;
}

// MPR's last portal: three of the support points its search asked for (a of geom 1, b of geom 2,
// in the world), found as the triple whose answer is the search's; gap is how far that triple's
// answer is from the search's (dist, pos and normal, the largest difference).
struct Portal {
  Eigen::Vector3d a[3], b[3];
  double gap = 1e300;
};

using Point = primitive::Vec<double>;
Point point(const Eigen::Vector3d& x) { return {{x[0], x[1], x[2]}}; }

constexpr int kMostSupportPoints = 256;

bool last_portal(const GeomShape& s1, const GeomShape& s2, double margin,
                 const ConvexOptions& options, Portal& portal) {
  std::array<Eigen::Vector3d, kMostSupportPoints> a_all, b_all;
  Contact answer;
  const int asked =
      mpr_search(s1, s2, margin, options, answer, a_all.data(), b_all.data(), kMostSupportPoints);
  if (asked < 0 || asked > kMostSupportPoints) return false;
  // each pair of support points once, and of those the ones on the answer's plane (a portal that
  // the ray from v0 through the origin meets inside lies on it); all if fewer than three are
  std::array<std::size_t, kMostSupportPoints> unique{}, on_plane{};
  int n_unique = 0, n_on_plane = 0;
  const Eigen::Vector3d normal = answer.frame.row(0).transpose();
  const double depth = margin - answer.dist;
  for (std::size_t i = 0; i < static_cast<std::size_t>(asked); ++i) {
    bool seen = false;
    for (int k = 0; k < n_unique && !seen; ++k) {
      const std::size_t j = unique[static_cast<std::size_t>(k)];
      seen = a_all[j] == a_all[i] && b_all[j] == b_all[i];
    }
    if (seen) continue;
    unique[static_cast<std::size_t>(n_unique++)] = i;
    const Eigen::Vector3d v = a_all[i] - b_all[i];
    if (std::abs(normal.dot(v) - depth) <= 1e-9 * (1 + v.norm())) {
      on_plane[static_cast<std::size_t>(n_on_plane++)] = i;
    }
  }
  const bool plane = n_on_plane >= 3;
  const std::array<std::size_t, kMostSupportPoints>& pool = plane ? on_plane : unique;
  const std::size_t n = static_cast<std::size_t>(plane ? n_on_plane : n_unique);
  const Point c1 = point(s1.pos), c2 = point(s2.pos);
  portal.gap = 1e300;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      for (std::size_t k = j + 1; k < n; ++k) {
        const std::size_t I = pool[i], J = pool[j], K = pool[k];
        const Point a[3] = {point(a_all[I]), point(a_all[J]), point(a_all[K])};
        const Point b[3] = {point(b_all[I]), point(b_all[J]), point(b_all[K])};
        const primitive::Touch<double> f = portal_answer(a, b, c1, c2, margin);
        double gap = std::abs(f.dist - answer.dist);
        for (int c = 0; c < 3; ++c) {
          gap = std::max(gap, std::abs(f.pos[c] - answer.pos[c]));
          gap = std::max(gap, std::abs(f.normal[c] - answer.frame(0, c)));
        }
        if (gap < portal.gap) {
          portal.gap = gap;
          portal.a[0] = a_all[I], portal.a[1] = a_all[J], portal.a[2] = a_all[K];
          portal.b[0] = b_all[I], portal.b[1] = b_all[J], portal.b[2] = b_all[K];
        }
      }
    }
  }
  return portal.gap < 1e300;
}

// Whether the held portal's closed form is still MPR's answer with geom 1 turned by kPortalProbe
// rad about each world axis through its centre, or moved by kPortalProbe along it, either way
// (another triangle of the same plane whose answer is the same counts as held): where it is not
// (two faces whose edges line up, say), the portal flips with the direction of the motion and
// the answer has no derivative.
constexpr double kPortalProbe = 1e-8;

bool portal_holds(const GeomShape& s1, const GeomShape& s2, double margin,
                  const ConvexOptions& options, const Portal& portal) {
  std::array<Eigen::Vector3d, kMostSupportPoints> scratch1, scratch2;
  Eigen::Vector3d local[3];
  for (int i = 0; i < 3; ++i) local[i] = s1.mat.transpose() * (portal.a[i] - s1.pos);
  const Point b[3] = {point(portal.b[0]), point(portal.b[1]), point(portal.b[2])};
  for (int axis = 0; axis < 3; ++axis) {
    for (const double step : {-kPortalProbe, kPortalProbe}) {
      for (const bool turn : {true, false}) {
        GeomShape moved = s1;
        if (turn) {
          moved.mat = Eigen::AngleAxisd(step, Eigen::Vector3d::Unit(axis)).toRotationMatrix() *
                      s1.mat;
        } else {
          moved.pos[axis] += step;
        }
        Contact answer;
        if (mpr_search(moved, s2, margin, options, answer, scratch1.data(), scratch2.data(),
                       kMostSupportPoints) < 0) {
          return false;
        }
        const Point a[3] = {point(moved.mat * local[0] + moved.pos),
                            point(moved.mat * local[1] + moved.pos),
                            point(moved.mat * local[2] + moved.pos)};
        const primitive::Touch<double> f =
            portal_answer(a, b, point(moved.pos), point(s2.pos), margin);
        double gap = std::abs(f.dist - answer.dist);
        for (int c = 0; c < 3; ++c) {
          gap = std::max(gap, std::abs(f.pos[c] - answer.pos[c]));
          gap = std::max(gap, std::abs(f.normal[c] - answer.frame(0, c)));
        }
        if (!(gap <= 1e-10 * (1 + answer.pos.cwiseAbs().maxCoeff()))) return false;
      }
    }
  }
  return true;
}

// The last portal of a polytope pair's search at the state, checked to hold (else refused).
Portal polytope_portal(const Model& model, const Data& data, double margin, int first, int count) {
  const Contact& con = data.contact[static_cast<std::size_t>(first)];
  const GeomType t1 = model.geom_type[con.geom1], t2 = model.geom_type[con.geom2];
  if (margin != 0.0 || count != 1) {
    throw Error(std::string("derivatives: a ") + geom_type_name(t1) + "-" + geom_type_name(t2) +
                " contact (MPR) is active with a margin or multiccd's extra contacts; lever "
                "differentiates MPR's answer for two polytopes at margin 0, one contact per pair.");
  }
  // the search again, on the same shapes, its support points written down: of them, the portal
  const GeomShape s1 = shape_at_state(model, data, con.geom1);
  const GeomShape s2 = shape_at_state(model, data, con.geom2);
  const ConvexOptions options{model.opt.mpr_tolerance, model.opt.mpr_iterations, false};
  Portal portal;
  if (!last_portal(s1, s2, margin, options, portal)) {
    throw Error("derivatives: contact " + std::to_string(first) +
                " is not reproduced (MPR's search found no portal).");
  }
  if (!portal_holds(s1, s2, margin, options, portal)) {
    throw Error("derivatives: contact " + std::to_string(first) + " (" + geom_type_name(t1) +
                "-" + geom_type_name(t2) +
                ", MPR) ends on a portal that changes when a geom turns or moves by " +
                "1e-8 (faces whose edges line up, say): its answer has no derivative there.");
  }
  // the support points in their geoms' frames: each a vertex, rigid in its geom
  for (int i = 0; i < 3; ++i) {
    portal.a[i] = s1.mat.transpose() * (portal.a[i] - s1.pos);
    portal.b[i] = s2.mat.transpose() * (portal.b[i] - s2.pos);
  }
  return portal;
}

// The portal's answer on the moving poses (its vertices given in their geoms' frames).
int polytope_pair(const Portal& local, const Pose& g1, const Pose& g2, double margin,
                  Found* out) {
  V a[3], b[3];
  for (int i = 0; i < 3; ++i) {
    a[i] = rotate(g1, constant(local.a[i])) + g1.pos;
    b[i] = rotate(g2, constant(local.b[i])) + g2.pos;
  }
  out[0] = portal_answer(a, b, g1.pos, g2.pos, margin);
  return 1;
}

int collide_moving(const Pose& g1, const Pose& g2, double margin, Found* out) {
  using T = GeomType;
  if (g1.type == T::kPlane) {
    switch (g2.type) {
      case T::kSphere: return primitive::plane_sphere(g1, g2.pos, g2.size[0], margin, out);
      case T::kCapsule: return primitive::plane_capsule(g1, g2, margin, out);
      case T::kBox: return primitive::plane_box(g1, g2, margin, out);
      case T::kEllipsoid: return plane_ellipsoid(g1, g2, margin, out);
      case T::kCylinder: return primitive::plane_cylinder(g1, g2, margin, out);
      default: break;
    }
  } else if (g1.type == T::kSphere) {
    switch (g2.type) {
      case T::kSphere:
        return primitive::sphere_sphere(g1.pos, g1, g1.size[0], g2.pos, g2, g2.size[0], margin,
                                        out);
      case T::kCapsule: return primitive::sphere_capsule(g1, g2, margin, out);
      case T::kBox: return sphere_box(g1, g2, margin, out);
      default: break;
    }
  } else if (g1.type == T::kCapsule && g2.type == T::kCapsule) {
    return primitive::capsule_capsule(g1, g2, margin, out);
  } else if (g1.type == T::kCapsule && g2.type == T::kBox) {
    return capsule_box(g1, g2, margin, out);
  } else if (g1.type == T::kBox && g2.type == T::kBox) {
    return box_box(g1, g2, margin, out);
  }
  throw Error(std::string("derivatives: a ") + geom_type_name(g1.type) + "-" +
              geom_type_name(g2.type) +
              " contact is active; lever differentiates the contact geometry of the pairs "
              "MuJoCo collides in closed form (plane against sphere, capsule, box, cylinder, "
              "ellipsoid and mesh; sphere, capsule and box pairs) and, of those it collides by "
              "MPR, box-mesh and mesh-mesh, not a round geom's.");
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
  if (a == T::kPlane) {
    return b == T::kSphere || b == T::kCapsule || b == T::kBox || b == T::kEllipsoid ||
           b == T::kCylinder || b == T::kMesh;
  }
  if (a == T::kSphere || a == T::kCapsule) {
    return b == T::kSphere || b == T::kCapsule || b == T::kBox;
  }
  return (a == T::kBox && b == T::kBox) || polytope_mpr_pair(a, b);
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
                          const GeomPairMotion* motions, int directions, ContactChange* changes) {
  const Contact& con = data.contact[static_cast<std::size_t>(first)];
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
  const bool polytopes = polytope_mpr_pair(model.geom_type[con.geom1], model.geom_type[con.geom2]);
  const Portal portal = polytopes ? polytope_portal(model, data, margin, first, count) : Portal{};
  for (int m0 = 0; m0 < directions; m0 += kMotions) {  // kMotions motions at a time
    const int motions_now = std::min(kMotions, directions - m0);
    const Pose g1 = moving_pose(model, data, con.geom1, motions + m0, motions_now, false);
    const Pose g2 = moving_pose(model, data, con.geom2, motions + m0, motions_now, true);
    int n = 0;
    if (g1.type == GeomType::kPlane && g2.type == GeomType::kMesh) {
      n = plane_mesh(g1, g2, data, first, count, found.data());
    } else if (polytopes) {
      n = polytope_pair(portal, g1, g2, margin, found.data());
    } else {
      n = collide_moving(g1, g2, margin, found.data());
    }
    for (int k = 0; k < count; ++k) {
      const int i = first + k;
      const Contact& ck = data.contact[static_cast<std::size_t>(i)];
      if (n == 0) throw Error("derivatives: contact " + std::to_string(i) + " is not reproduced.");
      const Found& f = found[static_cast<std::size_t>(k % n)];
      const std::array<V, 3> frame = complete_frame(f.normal, f.tangent);

      // the values are the collision stage's (the same along every motion): else this is not
      // the contact it found
      if (m0 == 0) {
        double gap = std::abs(f.dist.v - ck.dist);
        for (int a = 0; a < 3; ++a) {
          gap = std::max(gap, std::abs(f.pos[a].v - ck.pos[a]));
          for (int r = 0; r < 3; ++r) {
            gap = std::max(gap, std::abs(frame[r][a].v - ck.frame(r, a)));
          }
        }
        if (!(gap <= 1e-9 * (1 + ck.pos.cwiseAbs().maxCoeff()))) {
          throw Error("derivatives: contact " + std::to_string(i) +
                      " is not reproduced by the contact geometry's derivative (off by " +
                      std::to_string(gap) + ").");
        }
      }
      for (int m = 0; m < motions_now; ++m) {
        ContactChange& change = changes[(m0 + m) * kMaxPairContacts + k];
        change.dist = f.dist.d[m];
        for (int a = 0; a < 3; ++a) {
          change.pos[a] = f.pos[a].d[m];
          for (int r = 0; r < 3; ++r) change.frame(r, a) = frame[r][a].d[m];
        }
      }
    }
  }
}

void contact_change(const Model& model, const Data& data, int i, const Eigen::Vector3d& w1,
                    const Eigen::Vector3d& v1, const Eigen::Vector3d& w2,
                    const Eigen::Vector3d& v2, ContactChange& change) {
  int count = 0;
  const int first = pair_first_contact(data, i, count);
  std::array<ContactChange, kMaxPairContacts> changes;
  const GeomPairMotion motion{w1, v1, w2, v2};
  pair_contact_changes(model, data, first, count, &motion, 1, changes.data());
  change = changes[static_cast<std::size_t>(i - first)];
}

}  // namespace lever::detail
