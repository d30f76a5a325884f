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
// ellipsoid and mesh (a box on a plane that stands still by its corners' motions, not the dual
// numbers: still_plane_box_changes()); sphere-sphere, sphere-capsule, capsule-capsule,
// sphere-box, capsule-box and box-box (collision/box_pairs.hpp). And every pair MuJoCo collides
// by MPR (libccd's search, run again here with its support points written down): two polytopes
// at margin 0 by a closed form of the last portal the search ended on (a vertex on a face, an
// edge across an edge, a face on a face), the others (a round geom, a margin) by the whole search
// replayed on the dual numbers, its decisions held; multiccd's extra contacts by the turned
// searches replayed. Where the portal or the search's path flips with the direction of a motion,
// or a closed form's answer turns faster than its first order (an upright cylinder's disc flat on
// a plane), the answer jumps and is refused by name (docs/derivatives.md).
#include <lever/collision.hpp>
#include <lever/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>

#include <Eigen/Geometry>

#include "basics/basics.hpp"
#include "basics/dual.hpp"
#include "collision/collision_room.hpp"
#include "collision/box_pairs.hpp"
#include "collision/mpr.hpp"
#include "collision/narrow_phase.hpp"
#include "collision/primitive_pairs.hpp"
#include "collision/surface_normal.hpp"
#include "transition/transition.hpp"

namespace lever::detail {

namespace {

// the narrow phase runs along kMotions motions at once: the values once, a derivative per motion.
// Where a pair is not a replayed search, up to kMostMotions at once, and a pair's last few motions
// (up to kFewMotions) on Duals<kFewMotions>: each motion's derivative the same numbers (no
// operation mixes motions; whether a contact's frame moves is decided per group of kMotions, see
// frame_moving_groups).
constexpr int kMotions = 6;
constexpr int kFewMotions = 2;
constexpr int kMostMotions = 8;
using Scalar = Duals<kMotions>;
using V = primitive::Vec<Scalar>;
using primitive::cross;
using primitive::dot;
using primitive::normalize;
using primitive::value;
V constant(const Eigen::Vector3d& x) { return primitive::constant_vec<Scalar>(x); }
template <class S>
primitive::Vec<double> values(const primitive::Vec<S>& x) {
  return {{value(x[0]), value(x[1]), value(x[2])}};
}

// Geoms and contacts on any scalar S (double, or dual numbers along some motions).
template <class S>
using ShapeOf = primitive::Shape<S>;
template <class S>
using TouchOf = primitive::Touch<S>;

// The pairs MuJoCo collides by MPR whose geoms are both polytopes: box-mesh and mesh-mesh.
bool polytope_mpr_pair(GeomType a, GeomType b) {
  const auto polytope = [](GeomType t) { return t == GeomType::kBox || t == GeomType::kMesh; };
  return polytope(a) && polytope(b) && (a == GeomType::kMesh || b == GeomType::kMesh);
}

// A geom's pose moving rigidly along each of the motions (geom 1's or 2's part of each):
// pos' = w x (pos - centre) + v at the centre, mat' = [w] mat; motions past `count` stand still.
using Pose = ShapeOf<Scalar>;

// (Inlined: called twice a batch, its pose built in place.)
template <int K>
[[gnu::always_inline]] inline ShapeOf<Duals<K>> moving_pose(const Model& model, const Data& data,
                                                            int g, const GeomPairMotion* motions,
                                                            int count, bool second) {
  using S = Duals<K>;
  ShapeOf<S> p;  // each number set once below
  p.type = model.geom_type[g];
  p.size = model.geom_size[g];
  // the values, and zero derivatives where motions past `count` leave them unset
  const auto start = [count](S& x, double value) {
    if (count < K) {
      x = S(value);
    } else {
      x.v = value;
    }
  };
  for (int k = 0; k < 3; ++k) start(p.pos[k], data.geom_xpos[g][k]);
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 3; ++k) start(p.axis[c][k], data.geom_xmat[g](k, c));
  }
  // a motion that turns the geom as the last one turned did, bit for bit (the world standing
  // still, one translation after another), turns its columns the same: not made again
  std::array<Eigen::Vector3d, 3> turn;
  const Eigen::Vector3d* turned_by = nullptr;
  for (int m = 0; m < count; ++m) {
    const Eigen::Vector3d& w = second ? motions[m].w2 : motions[m].w1;
    const Eigen::Vector3d& v = second ? motions[m].v2 : motions[m].v1;
    for (int k = 0; k < 3; ++k) p.pos[k].d[m] = v[k];
    if (!turned_by || std::memcmp(turned_by->data(), w.data(), sizeof(double) * 3) != 0) {
      for (int c = 0; c < 3; ++c) turn[c] = w.cross(data.geom_xmat[g].col(c));
      turned_by = &w;
    }
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) p.axis[c][k].d[m] = turn[c][k];
    }
  }
  return p;
}

// R x and R^T x for the pose's rotation
V rotate(const Pose& p, const V& x) { return primitive::rotate(p, x); }
V unrotate(const Pose& p, const V& x) { return primitive::unrotate(p, x); }

using Found = TouchOf<Scalar>;

void set(Found& f, const Scalar& dist, const V& pos, const V& normal) {
  primitive::touch(f, dist, pos, normal);
}

// ---- the pairs the collision room does not write on a scalar: as box.cpp and convex.cpp decide
// them

// The pairs below run on any scalar S, as the collision room's closed forms do: the derivative on
// Scalar (or Duals<kFewMotions>), the probes of whether a case holds on double and on two
// motions' duals.

template <class S>
int plane_ellipsoid(const ShapeOf<S>& plane, const ShapeOf<S>& ellipsoid, double margin,
                    TouchOf<S>* out) {
  using W = primitive::Vec<S>;
  const W n = plane.axis[2];
  const W up_along_axes = {dot(ellipsoid.axis[0], n), dot(ellipsoid.axis[1], n),
                           dot(ellipsoid.axis[2], n)};
  const W down = up_along_axes * S(-1.0);
  W support{down[0] * ellipsoid.size[0], down[1] * ellipsoid.size[1], down[2] * ellipsoid.size[2]};
  normalize(support);
  support = {support[0] * ellipsoid.size[0], support[1] * ellipsoid.size[1],
             support[2] * ellipsoid.size[2]};
  const W deepest = primitive::rotate(ellipsoid, support) + ellipsoid.pos;
  const S dist = dot(n, deepest - plane.pos);
  if (value(dist) > margin) return 0;
  primitive::touch(out[0], dist, deepest + n * (dist * S(-0.5)), n);
  return 1;
}

// The box pairs of collision/box_pairs.hpp on the moving poses.
template <class S>
box_pairs::Vec3<S> box_vec(const primitive::Vec<S>& x) {
  return {x[0], x[1], x[2]};
}

template <class S>
int sphere_box(const ShapeOf<S>& sphere, const ShapeOf<S>& box, double margin, TouchOf<S>* out) {
  return box_pairs::sphere_box(box_vec(sphere.pos), sphere.size[0], box_pairs::box_of(box), margin,
                               out);
}

template <class S>
int capsule_box(const ShapeOf<S>& capsule, const ShapeOf<S>& box, double margin,
                TouchOf<S>* out) {
  return box_pairs::capsule_box(box_vec(capsule.pos), box_vec(capsule.axis[2]), capsule.size[0],
                                capsule.size[1], box_pairs::box_of(box), margin, out);
}

// The driver drops a box-box contact whose position another later one repeats exactly
// (remove_repeated_positions): the same here, on the values.
template <class S>
int box_box(const ShapeOf<S>& box1, const ShapeOf<S>& box2, double margin, TouchOf<S>* out) {
  const int n =
      box_pairs::box_box(box_pairs::box_of(box1), box_pairs::box_of(box2), margin, out);
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    bool repeated = false;
    for (int j = i + 1; j < n && !repeated; ++j) {
      repeated = value(out[i].pos[0]) == value(out[j].pos[0]) &&
                 value(out[i].pos[1]) == value(out[j].pos[1]) &&
                 value(out[i].pos[2]) == value(out[j].pos[2]);
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
template <class S>
int plane_mesh(const ShapeOf<S>& plane, const ShapeOf<S>& mesh, const Data& data, int first,
               int count, TouchOf<S>* out) {
  using W = primitive::Vec<S>;
  const W n = plane.axis[2];
  const int g = data.contact[static_cast<std::size_t>(first)].geom2;
  for (int k = 0; k < count; ++k) {
    const Contact& c = data.contact[static_cast<std::size_t>(first + k)];
    const Eigen::Vector3d vertex = c.pos + c.frame.row(0).transpose() * (0.5 * c.dist);
    const Eigen::Vector3d local = data.geom_xmat[g].transpose() * (vertex - data.geom_xpos[g]);
    const W point = primitive::rotate(mesh, primitive::constant_vec<S>(local)) + mesh.pos;
    const S dist = dot(n, point - plane.pos);
    primitive::touch(out[k], dist, point + n * (dist * -0.5), n);
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
  std::array<std::size_t, kMostSupportPoints> unique, on_plane;  // their first n_ are set
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

// The probes of whether a portal or a search's path holds about the state: geom 1 moved by
// kPortalProbe (rad and m) along each of two fixed motions, either way, each a turn about an axis
// through its centre and a shift, in directions that line up with no frame a scene is built in
// (so a flip at the state, which a motion across it shows on one side, is not missed along a
// motion that keeps two faces parallel or an edge level).
constexpr double kPortalProbe = 1e-8;
constexpr int kProbeMotions = 2;

struct ProbeMotion {
  Eigen::Vector3d turn, shift;  // unit
  // the turns by -kPortalProbe and kPortalProbe about `turn`, the only steps the probes take:
  // made once
  Eigen::Matrix3d back, forth;

  ProbeMotion(const Eigen::Vector3d& turn_axis, const Eigen::Vector3d& shift_direction)
      : turn(turn_axis.normalized()), shift(shift_direction.normalized()),
        back(Eigen::AngleAxisd(-kPortalProbe, turn).toRotationMatrix()),
        forth(Eigen::AngleAxisd(kPortalProbe, turn).toRotationMatrix()) {}
};

const std::array<ProbeMotion, kProbeMotions>& probe_motions() {
  static const std::array<ProbeMotion, kProbeMotions> motions = {
      ProbeMotion{Eigen::Vector3d(0.58, -0.38, 0.72), Eigen::Vector3d(0.41, 0.77, -0.49)},
      ProbeMotion{Eigen::Vector3d(-0.27, 0.81, 0.52), Eigen::Vector3d(0.69, -0.19, 0.70)}};
  return motions;
}

// geom 1 moved along a probe's motion by step, -kPortalProbe or kPortalProbe
GeomShape probe_moved(const GeomShape& s, int motion, double step) {
  const ProbeMotion& m = probe_motions()[static_cast<std::size_t>(motion)];
  GeomShape moved = s;
  moved.mat = (step < 0 ? m.back : m.forth) * s.mat;
  moved.pos = s.pos + m.shift * step;
  return moved;
}

// Whether MPR's answer at every probe is, to 1e-10 of its point's size, what gap_at(motion, step,
// moved geom 1, answer) measures it against (a held portal's closed form, a replay's first
// order); false too where the search at a probe finds no contact.
template <class Gap>
bool search_holds_at_probes(const GeomShape& s1, const GeomShape& s2, double margin,
                            const ConvexOptions& options, Gap&& gap_at) {
  std::array<Eigen::Vector3d, kMostSupportPoints> scratch1, scratch2;
  for (int motion = 0; motion < kProbeMotions; ++motion) {
    for (const double step : {-kPortalProbe, kPortalProbe}) {
      const GeomShape moved = probe_moved(s1, motion, step);
      Contact answer;
      if (mpr_search(moved, s2, margin, options, answer, scratch1.data(), scratch2.data(),
                     kMostSupportPoints) < 0) {
        return false;
      }
      const double gap = gap_at(motion, step, moved, answer);
      if (!(gap <= 1e-10 * (1 + answer.pos.cwiseAbs().maxCoeff()))) return false;
    }
  }
  return true;
}

// Geom 1's shape at the state with its derivative along each probe's motion (its turn about the
// geom's centre, its shift) in the first kProbeMotions lanes.
template <class S>
void along_probe_motions(const GeomShape& s1, primitive::Shape<S>& shape) {
  for (int m = 0; m < kProbeMotions; ++m) {
    const ProbeMotion& motion = probe_motions()[static_cast<std::size_t>(m)];
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d turn = motion.turn.cross(s1.mat.col(c));
      for (int k = 0; k < 3; ++k) shape.axis[c][k].d[m] = turn[k];
    }
    for (int k = 0; k < 3; ++k) shape.pos[k].d[m] = motion.shift[k];
  }
}

// Whether the held portal's closed form is still MPR's answer at the probes (another triangle of
// the same plane whose answer is the same counts as held): where it is not (two faces whose
// edges line up, say), the portal flips with the direction of the motion and the answer has no
// derivative.
bool portal_holds(const GeomShape& s1, const GeomShape& s2, double margin,
                  const ConvexOptions& options, const Portal& portal) {
  Eigen::Vector3d local[3];
  for (int i = 0; i < 3; ++i) local[i] = s1.mat.transpose() * (portal.a[i] - s1.pos);
  const Point b[3] = {point(portal.b[0]), point(portal.b[1]), point(portal.b[2])};
  return search_holds_at_probes(
      s1, s2, margin, options,
      [&](int, double, const GeomShape& moved, const Contact& answer) {
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
        return gap;
      });
}

// The last portal of a polytope pair's search at the state, checked to hold (else refused);
// false where no triangle of its support points gives its answer (the origin's nearest point of
// the portal on an edge of it: then the whole search is replayed).
bool polytope_portal(const Model& model, const Data& data, double margin, int first,
                     Portal& portal) {
  const Contact& con = data.contact[static_cast<std::size_t>(first)];
  const GeomType t1 = model.geom_type[con.geom1], t2 = model.geom_type[con.geom2];
  // the search again, on the same shapes, its support points written down: of them, the portal
  const GeomShape s1 = geom_shape(model, data, con.geom1);
  const GeomShape s2 = geom_shape(model, data, con.geom2);
  const ConvexOptions options{model.opt.mpr_tolerance, model.opt.mpr_iterations, false};
  if (!last_portal(s1, s2, margin, options, portal) ||
      !(portal.gap <= 1e-9 * (1 + con.pos.cwiseAbs().maxCoeff()))) {
    return false;
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
  return true;
}

// The portal's answer on the moving poses (its vertices given in their geoms' frames).
template <class S>
int polytope_pair(const Portal& local, const ShapeOf<S>& g1, const ShapeOf<S>& g2, double margin,
                  TouchOf<S>* out) {
  primitive::Vec<S> a[3], b[3];
  for (int i = 0; i < 3; ++i) {
    a[i] = primitive::rotate(g1, primitive::constant_vec<S>(local.a[i])) + g1.pos;
    b[i] = primitive::rotate(g2, primitive::constant_vec<S>(local.b[i])) + g2.pos;
  }
  out[0] = portal_answer(a, b, g1.pos, g2.pos, margin);
  return 1;
}

// ---- MPR's whole search on the moving poses (a round geom, or a margin) ------------------------
// Where a support point is not a vertex (a sphere's, capsule's, cylinder's or ellipsoid's, or any
// geom's grown by margin / 2 along the search's direction), it moves with the direction it was
// asked for, and each direction is made of the earlier support points: the answer is the whole
// search's, not a closed form of its last portal. Held are the search's decisions (how many support
// points it asks for, which portal vertex each replaces, when it stops; a polytope's vertex; a
// capsule's end, a cylinder's disc), taken on the values as libccd (v2.1, the library MuJoCo runs)
// takes them; along that path the search is a smooth function of the two poses, run here on dual
// numbers: the stage's own search (collision/mpr.hpp) on them. The support points it asks for are
// checked against those the collision stage's search asked for (collision/convex.cpp's mpr_search),
// so a path that is not the stage's is an error, not a wrong derivative; and MuJoCo's normal
// correction where a geom's surface gives it (mjc_fixNormal) follows, on the same numbers.

// -1, 0 or 1: the side of a half-extent `half` that the coordinate x (-half, 0 or half, and a
// rounding) is on.
double held_side(double x, double half) {
  if (!(half > 0)) return 0;
  const double r = x / half;
  return r > 0.5 ? 1.0 : (r < -0.5 ? -1.0 : 0.0);
}

using SupportPair = mpr::Point<Scalar>;  // v = a - b

// The two geoms' support functions (MuJoCo's mjccd_support) on the moving poses, replaying the
// stage's search: call k must give the stage's k-th support points.
class SearchReplay {
 public:
  SearchReplay(int contact, const GeomShape& s1, const GeomShape& s2, const Pose& g1,
               const Pose& g2, double margin, const Eigen::Vector3d* recorded1,
               const Eigen::Vector3d* recorded2, int recorded)
      : contact_(contact), s_{&s1, &s2}, g_{&g1, &g2}, margin_(margin),
        recorded_{recorded1, recorded2}, count_(recorded) {}

  // An error naming the contact and its pair.
  Error error(const char* why) const {
    return Error("derivatives: contact " + std::to_string(contact_) + " (" +
                 geom_type_name(s_[0]->type) + "-" + geom_type_name(s_[1]->type) + ", MPR) " +
                 why);
  }
  Error not_reproduced() const {
    return error("is not reproduced by MPR's search on the moving poses.");
  }

  // MPR's support point along dir (collision/mpr.hpp's search asks for it so)
  void operator()(const V& dir, SupportPair& p) {
    if (calls_ >= count_) throw not_reproduced();
    p.a = geom_support(0, dir);
    p.b = geom_support(1, dir * -1.0);
    p.v = p.a - p.b;
    ++calls_;
  }

 private:
  V geom_support(int which, const V& world_dir) const {
    const GeomShape& s = *s_[which];
    const Pose& g = *g_[which];
    const Eigen::Vector3d& recorded = recorded_[which][calls_];
    const V d = unrotate(g, world_dir);
    const Eigen::Vector3d& size = s.size;
    // the recorded point in the geom's frame: where a support point's case is a side (a box's
    // corner, a capsule's end, a cylinder's disc), the side the stage's search took
    const Eigen::Vector3d local = s.mat.transpose() * (recorded - s.pos);
    V res;
    switch (s.type) {
      case GeomType::kSphere:
        res = d * size[0];
        break;
      case GeomType::kCapsule:
        // which end: the stage's (its recorded point's, less the sphere's part)
        res = d * size[0];
        res[2] = res[2] + held_side(local[2] - value(d[2]) * (size[0] + margin_ / 2), size[1]) *
                              size[1];
        break;
      case GeomType::kEllipsoid:
        res = {{d[0] * size[0], d[1] * size[1], d[2] * size[2]}};
        normalize(res);
        res = {{res[0] * size[0], res[1] * size[1], res[2] * size[2]}};
        break;
      case GeomType::kCylinder: {
        const Scalar horizontal = sqrt(d[0] * d[0] + d[1] * d[1]);
        if (value(horizontal) > kMinVal) {
          res[0] = d[0] / horizontal * size[0];
          res[1] = d[1] / horizontal * size[0];
        } else {
          res[0] = res[1] = Scalar(0);
        }
        res[2] = Scalar(held_side(local[2] - value(d[2]) * margin_ / 2, size[1]) * size[1]);
        break;
      }
      case GeomType::kBox:
        // the stage's corner (or a face's or an edge's middle, where a direction was level)
        for (int i = 0; i < 3; ++i) {
          res[i] = Scalar(held_side(local[i] - value(d[i]) * margin_ / 2, size[i]) * size[i]);
        }
        break;
      case GeomType::kMesh: {
        // the stage's vertex: the mesh's nearest to its recorded point, less the growth
        Eigen::Vector3d grow;
        for (int i = 0; i < 3; ++i) grow[i] = value(d[i]) * margin_ / 2;
        const Eigen::Vector3d vertex = local - grow;
        int best = 0;
        double nearest = 1e300;
        for (int k = 0; k < s.mesh_vertnum; ++k) {
          const Eigen::Vector3d x(s.mesh_vert[3 * k], s.mesh_vert[3 * k + 1],
                                  s.mesh_vert[3 * k + 2]);
          const double gap = (x - vertex).squaredNorm();
          if (gap < nearest) nearest = gap, best = k;
        }
        res = constant(Eigen::Vector3d(s.mesh_vert[3 * best], s.mesh_vert[3 * best + 1],
                                       s.mesh_vert[3 * best + 2]));
        break;
      }
      default:
        throw not_reproduced();
    }
    res = res + d * (margin_ / 2);
    const V world = rotate(g, res) + g.pos;
    double gap = 0;
    for (int i = 0; i < 3; ++i) gap = std::max(gap, std::abs(value(world[i]) - recorded[i]));
    if (!(gap <= 1e-9 * (1 + recorded.cwiseAbs().maxCoeff()))) throw not_reproduced();
    return world;
  }

  int contact_;
  const GeomShape* s_[2];
  const Pose* g_[2];
  double margin_;
  const Eigen::Vector3d* recorded_[2];
  int count_;
  int calls_ = 0;
};

// libccd's ccdMPRPenetration on the moving poses: collision/mpr.hpp's search on the dual numbers,
// each decision taken on the values; depth, direction and point of the last portal.
Found mpr_replay(SearchReplay& search, const Pose& g1, const Pose& g2, double margin,
                 double tolerance, int max_iterations) {
  const auto refused = [&search] {
    return search.error(
        "is where MPR's search ends in a touch or on its first segment (the origin on the line "
        "of the geoms' centres), which any motion leaves: its answer has no derivative there.");
  };
  mpr::Search<Scalar, SearchReplay> replay(search, tolerance,
                                           static_cast<unsigned long>(max_iterations));
  mpr::Answer<Scalar> answer;
  switch (replay.penetration(g1.pos, g2.pos, answer)) {
    case mpr::Outcome::kPortal: break;
    case mpr::Outcome::kApartRefined: throw search.not_reproduced();
    default: throw refused();  // apart in discovery, a touch, the origin on the first segment
  }
  if (mpr::near_zero(value(answer.depth))) throw refused();
  Found f;
  set(f, Scalar(margin) - answer.depth, answer.pos, answer.dir);
  return f;
}

// MuJoCo's normal correction (collision/surface_normal.hpp) on the search's dual numbers.
void fix_normal(const Pose& g1, const Pose& g2, Found& f) {
  primitive::fix_normal(g1, g2, f.pos, f.normal);
}

// The search at the state replayed on poses moving as `g1` and `g2` do, MuJoCo's normal
// correction after it.
Found replay_search(const Model& model, int contact, const GeomShape& s1, const GeomShape& s2,
                    const Pose& g1, const Pose& g2, double margin) {
  const ConvexOptions options{model.opt.mpr_tolerance, model.opt.mpr_iterations, false};
  std::array<Eigen::Vector3d, kMostSupportPoints> recorded1, recorded2;
  Contact answer;
  const int asked = mpr_search(s1, s2, margin, options, answer, recorded1.data(),
                               recorded2.data(), kMostSupportPoints);
  SearchReplay search(contact, s1, s2, g1, g2, margin, recorded1.data(), recorded2.data(),
                      std::min(asked, kMostSupportPoints));
  if (asked < 0 || asked > kMostSupportPoints) throw search.not_reproduced();
  Found f = mpr_replay(search, g1, g2, margin, model.opt.mpr_tolerance, model.opt.mpr_iterations);
  fix_normal(g1, g2, f);
  return f;
}

// A geom standing still at a shape's pose.
Pose still_pose(const GeomShape& s) {
  Pose p{s.type, s.size, constant(s.pos), {}};
  for (int c = 0; c < 3; ++c) p.axis[c] = constant(s.mat.col(c));
  return p;
}

// Whether the search's path holds about the state: at the probes the stage's search (with
// MuJoCo's normal correction) gives what the replay's derivative along the probe's motion
// predicts, to 1e-10 (the second order is 1e-14 of it). Where the path changes there (a support
// point's side, a capsule's end, the search's count of steps), the answer jumps, and has no
// derivative.
bool search_holds(const Model& model, int contact, const GeomShape& s1, const GeomShape& s2,
                  double margin) {
  Pose turning = still_pose(s1);
  along_probe_motions(s1, turning);
  const Pose still2 = still_pose(s2);
  const Found predicted = replay_search(model, contact, s1, s2, turning, still2, margin);
  const ConvexOptions options{model.opt.mpr_tolerance, model.opt.mpr_iterations, false};
  return search_holds_at_probes(
      s1, s2, margin, options,
      [&](int m, double step, const GeomShape& moved, const Contact& answer) {
        Found actual;
        set(actual, Scalar(answer.dist), constant(answer.pos),
            constant(answer.frame.row(0).transpose()));
        fix_normal(still_pose(moved), still2, actual);
        double gap = std::abs(actual.dist.v - (predicted.dist.v + step * predicted.dist.d[m]));
        for (int c = 0; c < 3; ++c) {
          gap = std::max(gap, std::abs(actual.pos[c].v -
                                       (predicted.pos[c].v + step * predicted.pos[c].d[m])));
          gap = std::max(gap, std::abs(actual.normal[c].v - (predicted.normal[c].v +
                                                             step * predicted.normal[c].d[m])));
        }
        return gap;
      });
}

// A pair MuJoCo collides by MPR with a round geom or a margin: its search replayed on the moving
// poses, once checked to hold about the state (else refused).
void check_mpr_pair(const Model& model, const Data& data, double margin, int first) {
  const Contact& con = data.contact[static_cast<std::size_t>(first)];
  const GeomType t1 = model.geom_type[con.geom1], t2 = model.geom_type[con.geom2];
  if (!search_holds(model, first, geom_shape(model, data, con.geom1),
                    geom_shape(model, data, con.geom2), margin)) {
    throw Error("derivatives: contact " + std::to_string(first) + " (" + geom_type_name(t1) +
                "-" + geom_type_name(t2) +
                ", MPR) is where MPR's search changes its path when a geom turns or moves by " +
                "1e-8 (a support point's side, the count of its steps): its answer jumps there "
                "and has no derivative.");
  }
}

int mpr_pair(const Model& model, const Data& data, const Pose& g1, const Pose& g2, double margin,
             int first, Found* out) {
  const Contact& con = data.contact[static_cast<std::size_t>(first)];
  out[0] = replay_search(model, first, geom_shape(model, data, con.geom1),
                         geom_shape(model, data, con.geom2), g1, g2, margin);
  return 1;
}

template <class S>
int collide_moving(const ShapeOf<S>& g1, const ShapeOf<S>& g2, double margin, TouchOf<S>* out) {
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
              "ellipsoid and mesh; sphere, capsule and box pairs) and by MPR (with libccd).");
}

// A shape's pose on the scalar S, standing still.
template <class S>
ShapeOf<S> shape_on(const GeomShape& s) {
  ShapeOf<S> p{s.type, s.size, primitive::constant_vec<S>(s.pos), {}};
  for (int c = 0; c < 3; ++c) p.axis[c] = primitive::constant_vec<S>(s.mat.col(c));
  return p;
}

// Whether a closed-form pair's case holds about the state: at the probes (geom 1 moved by 1e-8
// along each of the two fixed motions, either way) the pair gives what its derivative along the
// probe's motion predicts, to 1e-10 (as search_holds). Each branch is a smooth closed form, but
// one can turn fast where a direction is normalised from a short vector: an upright cylinder's
// disc flat on a plane (MuJoCo's mjc_PlaneCylinder takes the rim point nearest the plane along
// the axis's tilt, which a turn of 1e-8 swings round when the tilt is below about 1.6e-4 rad at
// a radius of 5 cm), so the answer moves by more than its first order within the differences'
// reach, and at no tilt at all jumps with the motion's direction. A probe whose count of
// contacts differs (one at the margin's edge) is the active set's business, not judged here. The
// probes run on doubles, the prediction on the probes' two motions' duals.
bool closed_form_holds(const GeomShape& s1, const GeomShape& s2, double margin) {
  // the derivative along each probe's motion (its turn about geom 1's centre, its shift)
  using Probing = Duals<kProbeMotions>;
  ShapeOf<Probing> turning = shape_on<Probing>(s1);
  along_probe_motions(s1, turning);
  std::array<TouchOf<Probing>, kMaxPairContacts> predicted;
  const int n = collide_moving(turning, shape_on<Probing>(s2), margin, predicted.data());
  double scale = 1;
  for (int k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c) scale = std::max(scale, 1 + std::abs(predicted[k].pos[c].v));
  }
  const ShapeOf<double> still2 = shape_on<double>(s2);
  std::array<TouchOf<double>, kMaxPairContacts> actual;
  for (int m = 0; m < kProbeMotions; ++m) {
    for (const double step : {-kPortalProbe, kPortalProbe}) {
      const ShapeOf<double> moved = shape_on<double>(probe_moved(s1, m, step));
      if (collide_moving(moved, still2, margin, actual.data()) != n) continue;
      // each contact at the probe is one of the predicted ones (in any order: where two are
      // level, a capsule's ends or a lying cylinder's discs, which comes first is a tie)
      for (int k = 0; k < n; ++k) {
        const TouchOf<double>& a = actual[static_cast<std::size_t>(k)];
        double nearest = 1e300;
        for (int j = 0; j < n; ++j) {
          const TouchOf<Probing>& p = predicted[static_cast<std::size_t>(j)];
          double gap = std::abs(a.dist - (p.dist.v + step * p.dist.d[m]));
          for (int c = 0; c < 3; ++c) {
            gap = std::max(gap, std::abs(a.pos[c] - (p.pos[c].v + step * p.pos[c].d[m])));
            gap = std::max(gap,
                           std::abs(a.normal[c] - (p.normal[c].v + step * p.normal[c].d[m])));
          }
          nearest = std::min(nearest, gap);
        }
        if (!(nearest <= 1e-10 * scale)) return false;
      }
    }
  }
  return true;
}

// ---- which closed-form pairs the probes can fail -----------------------------------------------
// The probes move geom 1 by kPortalProbe; within that reach a closed form can miss its first order
// only where a case the stage decided (a threshold, a clamp, a tie) changes, or where a direction
// is normalised from a vector short against the reach (it turns by (reach / length)^2 at second
// order). Every other term is a polynomial of the poses whose second order, at the lever arms of a
// scene, is far below the probes' 1e-10. So a pair whose every decision is clear of its threshold
// by more than the probes move it, and whose every normalised vector is long, passes its probes
// for certain and is not probed: plane against sphere, capsule, box (its corners), ellipsoid and
// cylinder (tilted), sphere-sphere and sphere-capsule (centres apart), sphere-box. Each check
// below is that pair's decisions, in doubles, against the reach. Capsule-capsule (near-parallel
// segments, clamps), capsule-box and box-box (which edge or face, which corners clip) have too
// many decisions to bound cheaply: always probed.

// How far the probes move a point of geom 1 at `lever` from its centre (a turn of kPortalProbe
// about an axis through the centre and a shift of kPortalProbe), doubled for the roundings of the
// numbers it is held against.
double probe_reach(double lever) { return 2 * kPortalProbe * (1 + lever); }

// A threshold the stage decided `x` against holds through the probes.
bool clear_of(double x, double threshold, double reach) { return std::abs(x - threshold) > reach; }

// The probes' own turn moves a point at lever L off its first order by L d^2 / 2: below 1e-12 for
// L up to 1e4, far inside the probes' 1e-10.
constexpr double kLongestLever = 1e4;

// A direction normalised from a vector of `length` that the probes move by at most `moved`, a
// point `arm` out along it: its second order is at most 2 (moved / length)^2 (moved below a tenth
// of length), times max(1, arm); held below 1e-11, a tenth of the probes' tolerance.
bool turns_slowly(double length, double moved, double arm) {
  const double ratio = moved / length;
  return length > 0 && ratio < 0.1 && 2 * ratio * ratio * std::max(1.0, arm) <= 1e-11;
}

// geom 1 a plane: every point of geom 2 moves against it by at most probe_reach(its distance from
// the plane's centre); the plane's normal turns by kPortalProbe.
bool plane_pair_smooth(const GeomShape& plane, const GeomShape& g, double margin) {
  const Eigen::Vector3d n = plane.mat.col(2);
  const double lever = (g.pos - plane.pos).norm() + g.size.norm();
  if (!(lever < kLongestLever)) return false;
  const double reach = probe_reach(lever);
  const double center_height = n.dot(g.pos - plane.pos);
  const Eigen::Vector3d axis = g.mat.col(2);
  switch (g.type) {
    case GeomType::kSphere: return clear_of(center_height, margin + g.size[0], reach);
    case GeomType::kCapsule: {
      // each end a sphere: above or within the margin
      const double along = n.dot(axis) * g.size[1];
      return clear_of(center_height + along, margin + g.size[0], reach) &&
             clear_of(center_height - along, margin + g.size[0], reach);
    }
    case GeomType::kBox:
      // each corner below the centre and within the margin, or not; four of them at most, the
      // first in order, so a fixed set of corners is a fixed answer
      for (int i = 0; i < 8; ++i) {
        const Eigen::Vector3d local((i & 1) ? g.size[0] : -g.size[0],
                                    (i & 2) ? g.size[1] : -g.size[1],
                                    (i & 4) ? g.size[2] : -g.size[2]);
        const double along = n.dot(g.mat * local);
        if (!clear_of(along, 0, reach) || !clear_of(center_height + along, margin, reach)) {
          return false;
        }
      }
      return true;
    case GeomType::kEllipsoid: {
      // the support point normalised from -R^T n scaled by the sizes: at least the smallest size
      // long, moved by at most the largest times the normal's turn
      const Eigen::Vector3d scaled = -(g.mat.transpose() * n).cwiseProduct(g.size);
      const double largest = g.size.maxCoeff();
      if (!turns_slowly(scaled.norm(), 2 * kPortalProbe * largest, largest)) return false;
      const Eigen::Vector3d support = scaled.normalized().cwiseProduct(g.size);
      return clear_of(center_height + n.dot(g.mat * support), margin, reach);
    }
    case GeomType::kCylinder: {
      // which disc faces the plane (the axis's sign), and the rim point towards the plane,
      // normalised from the tilt's sine (the vector axis (axis . n) - n, minus n's part across
      // the axis, so moved by at most the normal's turn): an upright cylinder's rim points follow
      // the tilt's direction
      const double axis_along_normal = -std::abs(n.dot(axis));  // the axis towards the plane
      if (!clear_of(axis_along_normal, 0, 2 * kPortalProbe)) return false;
      const double radius = g.size[0], half_length = g.size[1];
      const double tilt = (axis * n.dot(axis) - n).norm();
      if (!turns_slowly(tilt, 2 * kPortalProbe, radius)) return false;
      // the three heights held against the margin (the rim point's height is -radius tilt)
      const double rim_along_normal = -radius * tilt;
      const double near_disc = center_height + axis_along_normal * half_length;
      const double far_disc = center_height - axis_along_normal * half_length;
      return clear_of(near_disc + rim_along_normal, margin, reach) &&
             clear_of(far_disc + rim_along_normal, margin, reach) &&
             clear_of(near_disc - 0.5 * rim_along_normal, margin, reach);
    }
    default: return false;
  }
}

// geom 1 a sphere: the probes move its centre by kPortalProbe (their turn does not move it).
bool sphere_pair_smooth(const GeomShape& sphere, const GeomShape& g, double margin) {
  const double reach = probe_reach(0);
  const double radius = sphere.size[0];
  // two centres: within the margin or not, and the normal between them normalised
  const auto spheres_smooth = [&](const Eigen::Vector3d& center2, double radius2) {
    const double apart = (sphere.pos - center2).norm();
    return clear_of(apart, margin + radius + radius2, reach) &&
           turns_slowly(apart, reach, radius + apart);
  };
  switch (g.type) {
    case GeomType::kSphere: return spheres_smooth(g.pos, g.size[0]);
    case GeomType::kCapsule: {
      // the segment's point nearest the centre, a clamp of x in [-1, 1] (x moves by at most
      // reach / half-length); unclamped, the point moves with the centre along the axis
      const double half_length = g.size[1];
      if (!(half_length > 0)) return false;
      const Eigen::Vector3d axis = g.mat.col(2);
      const double x = axis.dot(sphere.pos - g.pos) / half_length;
      const double x_reach = reach / half_length;
      if (!clear_of(x, 1, x_reach) || !clear_of(x, -1, x_reach)) return false;
      return spheres_smooth(g.pos + axis * (half_length * std::clamp(x, -1.0, 1.0)), g.size[0]);
    }
    case GeomType::kBox: {
      // the centre in the box's frame (it moves by kPortalProbe there too), clamped to the box
      // axis by axis; the clamps held
      const Eigen::Vector3d center = g.mat.transpose() * (sphere.pos - g.pos);
      Eigen::Vector3d toward_box = Eigen::Vector3d::Zero();
      int clamped = 0;
      for (int k = 0; k < 3; ++k) {
        if (!(g.size[k] > 0)) continue;
        if (!clear_of(std::abs(center[k]), g.size[k], reach)) return false;
        if (std::abs(center[k]) > g.size[k]) {
          toward_box[k] = std::copysign(g.size[k], center[k]) - center[k];
          ++clamped;
        }
      }
      if (clamped == 0) {
        // inside: the nearest face, held where the next is farther by more than the probes move
        // the difference; then the contact is linear in the centre
        double gaps[6];
        for (int f = 0; f < 6; ++f) {
          gaps[f] = std::abs(((f % 2) ? 1.0 : -1.0) * g.size[f / 2] - center[f / 2]);
        }
        std::sort(gaps, gaps + 6);
        return clear_of(gaps[1], gaps[0], 2 * reach) && clear_of(-radius, margin, reach);
      }
      const double apart = toward_box.norm();
      // over a face (one axis clamped) the normal is that face's: linear; over an edge or a
      // corner it is normalised from the centre's offset
      return clear_of(apart - radius, margin, reach) &&
             (clamped == 1 || turns_slowly(apart, reach, radius));
    }
    default: return false;
  }
}

// Whether the closed form's decisions all hold through the probes and its directions are
// normalised from long vectors: then its probes pass for certain and are not run.
bool closed_form_smooth(const GeomShape& s1, const GeomShape& s2, double margin) {
  if (s1.type == GeomType::kPlane) return plane_pair_smooth(s1, s2, margin);
  if (s1.type == GeomType::kSphere) return sphere_pair_smooth(s1, s2, margin);
  return false;
}

// (Out of line: once a pair, its shapes kept out of the caller's frame.)
[[gnu::noinline]] void check_closed_form_pair(const Model& model, const Data& data, double margin,
                                              int first) {
  const Contact& con = data.contact[static_cast<std::size_t>(first)];
  const GeomType t1 = model.geom_type[con.geom1], t2 = model.geom_type[con.geom2];
  const GeomShape s1 = geom_shape(model, data, con.geom1);
  const GeomShape s2 = geom_shape(model, data, con.geom2);
  if (closed_form_smooth(s1, s2, margin) || closed_form_holds(s1, s2, margin)) return;
  const bool flat_disc = t1 == GeomType::kPlane && t2 == GeomType::kCylinder;
  throw Error("derivatives: contact " + std::to_string(first) + " (" + geom_type_name(t1) + "-" +
              geom_type_name(t2) + ") is where the closed form's answer turns faster than its " +
              "first order when a geom turns or moves by 1e-8" +
              (flat_disc ? " (a cylinder's disc flat on the plane: its rim points follow the "
                           "direction of the axis's tilt)"
                         : "") +
              ": its answer jumps within that reach and has no derivative there.");
}

// The frame the driver completes from the normal and the first tangent's seed (mju_makeFrame).
// (Inlined: a contact's frame, in the loop over them.)
template <class S>
[[gnu::always_inline]] inline std::array<primitive::Vec<S>, 3> complete_frame(
    primitive::Vec<S> normal, primitive::Vec<S> tangent) {
  normalize(normal);
  if (std::sqrt(value(dot(tangent, tangent))) < 0.5) {
    const bool near_y = !(value(normal[1]) < 0.5 && value(normal[1]) > -0.5);
    tangent = primitive::constant_vec<S>(near_y ? Eigen::Vector3d(0, 0, 1)
                                                : Eigen::Vector3d(0, 1, 0));
  }
  tangent = tangent - normal * dot(normal, tangent);
  normalize(tangent);
  return {normal, tangent, cross(normal, tangent)};
}

// Along which groups of a batch's motions a contact's normal or tangent seed moves: bit q for
// motions q kMotions .. (q + 1) kMotions - 1 (a batch starts at a multiple of kMotions), set where
// a derivative part is not zero (or NaN). Along a group where neither moves, the frame does not
// either: its derivatives there are written as zero (the dual arithmetic could give -0); the
// group is kMotions wide whatever the batch, so that each motion's numbers are the same in any.
// (Out of line: there the sums go two motions at a time.)
template <int K>
[[gnu::noinline]] unsigned frame_moving_groups(const TouchOf<Duals<K>>& f) {
  std::array<double, K> size{};
  for (int a = 0; a < 3; ++a) {
    for (int m = 0; m < K; ++m) {
      size[m] += std::abs(f.normal[a].d[m]) + std::abs(f.tangent[a].d[m]);
    }
  }
  const auto moves = [&size](int begin, int end) {
    double total = 0;
    for (int m = begin; m < end; ++m) total += size[m];
    return !(total == 0.0);
  };
  if constexpr (K <= kMotions) {
    return moves(0, K) ? 1u : 0u;
  } else {
    unsigned moving = 0;
    for (int q = 0; q * kMotions < K; ++q) {
      if (moves(q * kMotions, std::min(K, (q + 1) * kMotions))) moving |= 1u << q;
    }
    return moving;
  }
}

// ---- multiccd's extra contacts (collision/convex.cpp's convex_pair) ----------------------------
// Each is the search run again with geom 1 turned by -+1e-3 rad about a tangent of the first
// contact's frame, through its point, and geom 2 turned back, kept where its point is farther
// than 1e-3 of the smaller bounding radius from every earlier one, at the first contact's depth.
// The turn's axis and centre are the first contact's, so they move with it: the turned poses on
// the dual numbers, the search replayed on them (its decisions held, checked to hold).

constexpr double kMulticcdTurn = 1e-3;

// The rotation by `angle` about the unit `axis` (mju_axisAngle2Quat, then mju_quat2Mat).
template <class S>
std::array<primitive::Vec<S>, 3> turn_matrix(const primitive::Vec<S>& axis, double angle) {
  const double c = std::cos(angle * 0.5), s = std::sin(angle * 0.5);
  const S q0(c), q1 = axis[0] * s, q2 = axis[1] * s, q3 = axis[2] * s;
  // rows
  return {{{{q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, (q1 * q2 - q0 * q3) * 2.0,
             (q1 * q3 + q0 * q2) * 2.0}},
           {{(q1 * q2 + q0 * q3) * 2.0, q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3,
             (q2 * q3 - q0 * q1) * 2.0}},
           {{(q1 * q3 - q0 * q2) * 2.0, (q2 * q3 + q0 * q1) * 2.0,
             q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3}}}};
}

template <class S>
primitive::Vec<S> apply_rows(const std::array<primitive::Vec<S>, 3>& rows,
                             const primitive::Vec<S>& x, bool transposed) {
  if (transposed) return rows[0] * x[0] + rows[1] * x[1] + rows[2] * x[2];
  return {{dot(rows[0], x), dot(rows[1], x), dot(rows[2], x)}};
}

// A pose turned by the rotation about `origin` (mju_rotateFrame): axes turned, centre moved so
// that origin stays.
Pose turned_pose(const Pose& g, const std::array<V, 3>& rows, bool transposed, const V& origin) {
  Pose t = g;
  for (int c = 0; c < 3; ++c) t.axis[c] = apply_rows(rows, g.axis[c], transposed);
  const V rel = origin - g.pos;
  t.pos = g.pos - (apply_rows(rows, rel, transposed) - rel);
  return t;
}

GeomShape turned_shape(const GeomShape& g, const std::array<Point, 3>& rows, bool transposed,
                       const Eigen::Vector3d& origin) {
  GeomShape t = g;
  for (int c = 0; c < 3; ++c) {
    const Point axis = apply_rows(rows, point(g.mat.col(c)), transposed);
    for (int k = 0; k < 3; ++k) t.mat(k, c) = axis[k];
  }
  const Eigen::Vector3d rel = origin - g.pos;
  const Point moved = apply_rows(rows, point(rel), transposed);
  for (int k = 0; k < 3; ++k) t.pos[k] = g.pos[k] - (moved[k] - rel[k]);
  return t;
}

// The pair's contacts after its first, found[0], on the moving poses; returns how many there are
// with the first (the pair's count, or a divisor of it where an explicit pair repeats a dynamic
// one).
int multiccd_contacts(const Model& model, const Data& data, const Pose& g1, const Pose& g2,
                      double margin, int first, int count, Found* found) {
  const Contact& con = data.contact[static_cast<std::size_t>(first)];
  const GeomShape s1 = geom_shape(model, data, con.geom1);
  const GeomShape s2 = geom_shape(model, data, con.geom2);
  const ConvexOptions options{model.opt.mpr_tolerance, model.opt.mpr_iterations, false};
  const std::array<V, 3> frame = complete_frame(found[0].normal, found[0].tangent);
  const double tolerance = kMulticcdTurn * std::min(model.geom_rbound[con.geom1],
                                                    model.geom_rbound[con.geom2]);
  std::array<Eigen::Vector3d, kMostSupportPoints> scratch1, scratch2;
  std::array<Eigen::Vector3d, kMaxPairContacts> kept;
  kept[0] = con.pos;
  int n = 1;
  for (int axis = 1; axis <= 2; ++axis) {
    for (const double angle : {-kMulticcdTurn, kMulticcdTurn}) {
      Point axis_value;
      for (int k = 0; k < 3; ++k) axis_value[k] = con.frame(axis, k);
      const std::array<Point, 3> rows = turn_matrix(axis_value, angle);
      const GeomShape t1 = turned_shape(s1, rows, false, con.pos);
      const GeomShape t2 = turned_shape(s2, rows, true, con.pos);
      Contact answer;
      if (mpr_search(t1, t2, margin, options, answer, scratch1.data(), scratch2.data(),
                     kMostSupportPoints) < 0) {
        continue;
      }
      if (answer.frame.row(0).cwiseAbs().maxCoeff() == 0) continue;  // no direction
      bool distinct = true;
      for (int i = 0; i < n; ++i) {
        distinct = distinct && (kept[static_cast<std::size_t>(i)] - answer.pos).norm() > tolerance;
      }
      if (!distinct) continue;
      if (n == count || n == kMaxPairContacts) {
        throw Error("derivatives: contact " + std::to_string(first) + " (" +
                    geom_type_name(s1.type) + "-" + geom_type_name(s2.type) +
                    ", multiccd) is not reproduced: more contacts than the stage's.");
      }
      if (!search_holds(model, first, t1, t2, margin)) {
        throw Error("derivatives: contact " + std::to_string(first + n) + " (" +
                    geom_type_name(s1.type) + "-" + geom_type_name(s2.type) +
                    ", multiccd) is where MPR's search changes its path when a geom turns or " +
                    "moves by 1e-8: its answer jumps there and has no derivative.");
      }
      const std::array<V, 3> turn = turn_matrix(frame[static_cast<std::size_t>(axis)], angle);
      const Pose p1 = turned_pose(g1, turn, false, found[0].pos);
      const Pose p2 = turned_pose(g2, turn, true, found[0].pos);
      Found f = replay_search(model, first, t1, t2, p1, p2, margin);
      f.dist = found[0].dist;
      found[n] = f;
      kept[static_cast<std::size_t>(n)] = answer.pos;
      ++n;
    }
  }
  return n;
}

// What pair_contact_changes() decided once for a pair: how it is collided.
struct PairCase {
  double margin;
  bool by_mpr;     // by MPR's search
  bool polytopes;  // by MPR's last portal, held (else the search replayed)
  bool multiccd;   // with multiccd's extra contacts
  const Portal* portal;
};

// The pair's contacts on poses moving along motions m0 .. m0 + now - 1 (now at most K),
// and their changes along each; on the first motions, their values checked against the collision
// stage's. The replayed searches (not a polytope pair's portal, multiccd) run on Scalar alone
// (K = kMotions).
template <int K>
void changes_along(const Model& model, const Data& data, const PairCase& pair_case, int first,
                   int count, const GeomPairMotion* motions, int m0, int now,
                   ContactChange* changes) {
  using S = Duals<K>;
  using W = primitive::Vec<S>;
  const Contact& con = data.contact[static_cast<std::size_t>(first)];
  const double margin = pair_case.margin;
  std::array<TouchOf<S>, kMaxPairContacts> found;
  const ShapeOf<S> g1 = moving_pose<K>(model, data, con.geom1, motions + m0, now, false);
  const ShapeOf<S> g2 = moving_pose<K>(model, data, con.geom2, motions + m0, now, true);
  int n = 0;
  if (g1.type == GeomType::kPlane && g2.type == GeomType::kMesh) {
    n = plane_mesh(g1, g2, data, first, count, found.data());
  } else if (pair_case.polytopes) {
    n = polytope_pair(*pair_case.portal, g1, g2, margin, found.data());
  } else if (pair_case.by_mpr) {
    if constexpr (K == kMotions) {
      n = mpr_pair(model, data, g1, g2, margin, first, found.data());
    }
  } else {
    n = collide_moving(g1, g2, margin, found.data());
  }
  if constexpr (K == kMotions) {
    if (pair_case.multiccd) {
      n = multiccd_contacts(model, data, g1, g2, margin, first, count, found.data());
    }
  }
  for (int k = 0; k < count; ++k) {
    const int i = first + k;
    const Contact& ck = data.contact[static_cast<std::size_t>(i)];
    if (n == 0) throw Error("derivatives: contact " + std::to_string(i) + " is not reproduced.");
    const TouchOf<S>& f = found[static_cast<std::size_t>(k % n)];
    // complete_frame() of the normal and the tangent seed on the dual numbers; where neither
    // moves along any motion of a group (a plane's normal, the plane held still), the frame does
    // not either: its derivatives there zero, and along every motion, its values alone on doubles
    const unsigned moving_groups = frame_moving_groups(f);
    std::array<W, 3> frame;
    std::array<primitive::Vec<double>, 3> frame_value;
    if (moving_groups != 0) {
      frame = complete_frame(f.normal, f.tangent);
      for (int r = 0; r < 3; ++r) frame_value[r] = values(frame[r]);
    } else {
      frame_value = complete_frame(values(f.normal), values(f.tangent));
    }

    // the values are the collision stage's (the same along every motion): else this is not
    // the contact it found
    if (m0 == 0) {
      double gap = std::abs(f.dist.v - ck.dist);
      for (int a = 0; a < 3; ++a) {
        gap = std::max(gap, std::abs(f.pos[a].v - ck.pos[a]));
        for (int r = 0; r < 3; ++r) {
          gap = std::max(gap, std::abs(frame_value[r][a] - ck.frame(r, a)));
        }
      }
      if (!(gap <= 1e-9 * (1 + ck.pos.cwiseAbs().maxCoeff()))) {
        throw Error("derivatives: contact " + std::to_string(i) +
                    " is not reproduced by the contact geometry's derivative (off by " +
                    std::to_string(gap) + ").");
      }
    }
    for (int m = 0; m < now; ++m) {
      ContactChange& change = changes[(m0 + m) * count + k];
      change.dist = f.dist.d[m];
      for (int a = 0; a < 3; ++a) change.pos[a] = f.pos[a].d[m];
      const int group = K <= kMotions ? 0 : m / kMotions;  // (a batch starts a group)
      if (!((moving_groups >> group) & 1u)) {
        change.frame.setZero();
      } else {
        for (int a = 0; a < 3; ++a) {
          for (int r = 0; r < 3; ++r) change.frame(r, a) = frame[r][a].d[m];
        }
      }
    }
  }
}

// A box against a plane that stands still along every motion (the floor, say): each of
// plane_box()'s contacts lies at a corner of the box, r from its centre (dist = n . (corner -
// plane), pos = corner - n dist / 2, frame the plane's), so along a motion (w2, v2 the box's, v1
// the plane's translation) the corner moves by u = v2 + w2 x r, the distance by n . (u - v1), the
// position by u - n (d dist) / 2, and the frame not at all: the derivatives the dual numbers give,
// in closed form (without building the box's eight corners on them).
bool still_plane_box(const Model& model, const Contact& con, const GeomPairMotion* motions,
                     int directions) {
  if (model.geom_type[con.geom1] != GeomType::kPlane ||
      model.geom_type[con.geom2] != GeomType::kBox) {
    return false;
  }
  for (int m = 0; m < directions; ++m) {
    if (!(motions[m].w1.array() == 0.0).all()) return false;
  }
  return true;
}

void still_plane_box_changes(const Data& data, int first, int count,
                             const GeomPairMotion* motions, int directions,
                             ContactChange* changes) {
  for (int k = 0; k < count; ++k) {
    const Contact& ck = data.contact[static_cast<std::size_t>(first + k)];
    const Eigen::Vector3d n = ck.frame.row(0).transpose();
    const Eigen::Vector3d r = ck.pos + n * (ck.dist / 2) - data.geom_xpos[ck.geom2];
    for (int m = 0; m < directions; ++m) {
      const GeomPairMotion& motion = motions[m];
      const Eigen::Vector3d u = motion.v2 + motion.w2.cross(r);
      ContactChange& change = changes[m * count + k];
      change.dist = n.dot(u - motion.v1);
      change.pos = u - n * (change.dist / 2);
      change.frame.setZero();
    }
  }
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
  return (a == T::kBox && b == T::kBox) || collides_by_mpr(a, b);
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
  // MPR's pairs: two polytopes at margin 0 by their last portal, the others by the whole search
  const bool by_mpr = collides_by_mpr(model.geom_type[con.geom1], model.geom_type[con.geom2]);
  Portal portal;
  const bool polytopes =
      by_mpr && margin == 0.0 &&
      polytope_mpr_pair(model.geom_type[con.geom1], model.geom_type[con.geom2]) &&
      polytope_portal(model, data, margin, first, portal);
  if (by_mpr && !polytopes) check_mpr_pair(model, data, margin, first);
  const bool plane_mesh_pair = model.geom_type[con.geom1] == GeomType::kPlane &&
                               model.geom_type[con.geom2] == GeomType::kMesh;
  if (!by_mpr && !plane_mesh_pair) check_closed_form_pair(model, data, margin, first);
  // multiccd's extra contacts: not for a sphere or an ellipsoid (as convex_pair)
  const auto roundish = [&](int g) {
    return model.geom_type[g] == GeomType::kSphere || model.geom_type[g] == GeomType::kEllipsoid;
  };
  const bool multiccd = by_mpr && model.opt.enabled(kEnableMulticcd) && !roundish(con.geom1) &&
                        !roundish(con.geom2);
  if (still_plane_box(model, con, motions, directions)) {
    still_plane_box_changes(data, first, count, motions, directions, changes);
    return;
  }
  const PairCase pair_case{margin, by_mpr, polytopes, multiccd, &portal};
  const bool replayed = (by_mpr && !polytopes) || multiccd;
  if (!replayed && directions > kMotions && directions <= kMostMotions) {
    // one batch for all (a free body's and a finger's motions, say)
    changes_along<kMostMotions>(model, data, pair_case, first, count, motions, 0, directions,
                                changes);
    return;
  }
  for (int m0 = 0; m0 < directions; m0 += kMotions) {  // kMotions motions at a time
    const int motions_now = std::min(kMotions, directions - m0);
    // a pair's last few motions, where it is not a replayed search: on fewer lanes
    if (motions_now <= kFewMotions && !replayed) {
      changes_along<kFewMotions>(model, data, pair_case, first, count, motions, m0, motions_now,
                                 changes);
    } else {
      changes_along<kMotions>(model, data, pair_case, first, count, motions, m0, motions_now,
                              changes);
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
