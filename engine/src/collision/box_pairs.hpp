// The narrow phase of the pairs with a box: sphere-box, capsule-box and box-box, deciding their
// contacts as MuJoCo 2.2.2 does (engine_collision_box.c), written once on a scalar type S: double
// in the narrow phase (box.cpp), dual numbers where the transition room differentiates a contact's
// geometry (transition/contact_geometry.cpp). Every branch, clamp and tie is decided on value(x),
// so on dual numbers the derivative is that of the case the narrow phase took (which face, edge or
// corner, which clipping), held.
//
// These are not exact closest-point computations but heuristics: a capsule gets a second contact
// only in some orientations, two boxes are clipped against the face or edge pair of least
// penetration found with MuJoCo's tie rule, and so on. Those choices decide how many contacts a
// pair yields and where, so every comparison, threshold and tie rule below is MuJoCo's, and so is
// the order of the arithmetic that feeds one (a near-tie then falls the same way in both). The
// vector helpers spell out their sums for that reason instead of leaving the order to Eigen.
//
// S needs what primitive_pairs.hpp's pairs need, and magnitude(S) (|x|, its sign decided on the
// value), found by argument-dependent lookup (for double: std::abs, below).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <lever/collision.hpp>

#include "basics/basics.hpp"
#include "collision/primitive_pairs.hpp"

namespace lever::detail::box_pairs {

using primitive::value;
inline double magnitude(double x) { return std::abs(x); }

template <class S>
using Vec3 = std::array<S, 3>;
template <class S>
using Mat9 = std::array<S, 9>;  // 3x3, row-major like geom_xmat: m[3 * row + col]

// ---- vector arithmetic, each sum in MuJoCo's order ------------------------------------------

template <class S>
Vec3<S> sub(const Vec3<S>& a, const Vec3<S>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <class S>
Vec3<S> add(const Vec3<S>& a, const Vec3<S>& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
template <class S>
Vec3<S> scale(const Vec3<S>& v, const S& s) {
  return {v[0] * s, v[1] * s, v[2] * s};
}
/// a + v * s
template <class S>
Vec3<S> add_scaled(const Vec3<S>& a, const Vec3<S>& v, const S& s) {
  return {a[0] + v[0] * s, a[1] + v[1] * s, a[2] + v[2] * s};
}
template <class S>
S dot(const Vec3<S>& a, const Vec3<S>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class S>
Vec3<S> abs(const Vec3<S>& v) {
  return {magnitude(v[0]), magnitude(v[1]), magnitude(v[2])};
}
/// std::clamp decided on the values
template <class S>
S clamp(const S& x, const S& lo, const S& hi) {
  return value(x) < value(lo) ? lo : (value(hi) < value(x) ? hi : x);
}
/// std::min decided on the values
template <class S>
S smaller(const S& a, const S& b) {
  return value(b) < value(a) ? b : a;
}

/// m v
template <class S>
Vec3<S> mul(const Mat9<S>& m, const Vec3<S>& v) {
  return {m[0] * v[0] + m[1] * v[1] + m[2] * v[2], m[3] * v[0] + m[4] * v[1] + m[5] * v[2],
          m[6] * v[0] + m[7] * v[1] + m[8] * v[2]};
}
/// m^T v
template <class S>
Vec3<S> mul_t(const Mat9<S>& m, const Vec3<S>& v) {
  return {m[0] * v[0] + m[3] * v[1] + m[6] * v[2], m[1] * v[0] + m[4] * v[1] + m[7] * v[2],
          m[2] * v[0] + m[5] * v[1] + m[8] * v[2]};
}
template <class S>
Vec3<S> row(const Mat9<S>& m, int i) {
  return {m[3 * i], m[3 * i + 1], m[3 * i + 2]};
}
template <class S>
Mat9<S> transpose(const Mat9<S>& m) {
  return {m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8]};
}

/// Scales v to unit length and returns the length it had; a vector shorter than kMinVal becomes
/// (1, 0, 0). Multiplies by the reciprocal of the length, as MuJoCo, so the last bits agree.
template <class S>
S normalize(Vec3<S>& v) {
  using std::sqrt;
  const S length = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (value(length) < kMinVal) {
    v = {S(1), S(0), S(0)};
  } else {
    const S inverse = S(1) / length;
    v = scale(v, inverse);
  }
  return length;
}

/// A contact found: dist, pos and the normal (no tangent: the driver completes the frame).
template <class S>
void found(primitive::Touch<S>& t, const S& dist, const Vec3<S>& pos, const Vec3<S>& normal) {
  primitive::touch(t, dist, primitive::Vec<S>{{pos[0], pos[1], pos[2]}},
                   primitive::Vec<S>{{normal[0], normal[1], normal[2]}});
}

template <class S>
struct Box {
  Vec3<S> pos;   ///< centre, world
  Mat9<S> mat;   ///< axes as columns, world
  Vec3<S> half;  ///< half-sizes
};

/// A geom of primitive_pairs.hpp as a box: its columns as mat's columns, its size as constants.
template <class S>
Box<S> box_of(const primitive::Shape<S>& g) {
  Box<S> b;
  for (int k = 0; k < 3; ++k) {
    b.pos[k] = g.pos[k];
    b.half[k] = S(g.size[k]);
    for (int c = 0; c < 3; ++c) b.mat[3 * k + c] = g.axis[c][k];
  }
  return b;
}

// ---- sphere-box ------------------------------------------------------------------------------

/// A sphere of `radius` centred at `center_world` against `box`: 0 or 1 contact.
template <class S>
int sphere_box(const Vec3<S>& center_world, double radius, const Box<S>& box, double margin,
               primitive::Touch<S>* out) {
  const Vec3<S> center = mul_t(box.mat, sub(center_world, box.pos));  // in the box's frame

  // the box's point nearest the centre: the centre clamped to the box (MuJoCo leaves an axis of
  // size 0 unclamped)
  Vec3<S> nearest = center;
  for (int k = 0; k < 3; ++k) {
    if (value(box.half[k]) > 0) nearest[k] = clamp(center[k], -box.half[k], box.half[k]);
  }
  Vec3<S> toward_box = sub(nearest, center);
  const S center_distance = normalize(toward_box);
  if (value(center_distance) - radius > margin) return 0;

  Vec3<S> local_pos, local_normal;
  if (value(center_distance) <= kMinVal) {
    // The centre is inside the box (or on its surface): the sphere leaves through the nearest
    // face, the first of -x, +x, -y, +y, -z, +z on a tie; the normal points into the box.
    S closest = (box.half[0] + box.half[1] + box.half[2]) * S(2);  // farther than any face
    int face = 0;
    for (int f = 0; f < 6; ++f) {
      const int axis = f / 2;
      const double side = (f % 2) ? 1.0 : -1.0;
      const S gap = magnitude(S(side) * box.half[axis] - center[axis]);
      if (value(gap) < value(closest)) {
        closest = gap;
        face = f;
      }
    }
    local_normal = {S(0), S(0), S(0)};
    local_normal[face / 2] = S((face % 2) ? -1.0 : 1.0);
    local_pos = add_scaled(center, local_normal, (S(radius) - closest) / S(2));
  } else {
    // the sphere's point deepest towards the box; the contact lies midway between it and the box
    const Vec3<S> deepest = add_scaled(center, toward_box, S(radius));
    local_pos = add(scale(nearest, S(0.5)), scale(deepest, S(0.5)));
    local_normal = toward_box;
  }
  found(*out, center_distance - S(radius), add(mul(box.mat, local_pos), box.pos),
        mul(box.mat, local_normal));
  return 1;
}

// ---- capsule-box -----------------------------------------------------------------------------
//
// In the box's frame the capsule is the segment center + t * halfaxis, t in [-1, 1], thickened by
// its radius. MuJoCo finds the box feature nearest the segment (a face under one of its ends, or
// a point of one of the 12 edges), then guesses from the orientation whether the capsule lies
// along the box, and where a second point of the segment is still over it. Each point becomes a
// sphere of the capsule's radius collided with the box.

/// Box corners and axis directions share a bit code: bit k set means + along axis k.
template <class S>
int sign_bits(const Vec3<S>& v) {
  return (value(v[0]) > 0 ? 1 : 0) + (value(v[1]) > 0 ? 2 : 0) + (value(v[2]) > 0 ? 4 : 0);
}

/// The segment's point nearest the box, and which feature of the box it is nearest.
template <class S>
struct NearestFeature {
  enum Kind { kNone, kEndOverFace, kEdge } kind = kNone;
  S segment_t = S(0);  ///< where on the segment, in [-1, 1]
  // kEndOverFace
  int end_face_axis = -1;  ///< the axis of the face the end is over; -1: the end is inside the box
  // kEdge: the edge along axis edge_axis through corner `corner`
  int edge_axis = -1;
  S edge_t = S(0);  ///< where on the edge, in [-1, 1] of its half-length
  /// Whether MuJoCo clamped edge_t to the edge's lower (0) or upper (2) end, else 1. Like MuJoCo's
  /// flag it is not reset when a later step moves edge_t back inside.
  int edge_state = 1;
  int corner = 0;  ///< the edge's corner nearest the segment if edge_state is 2, else its lower one
};

/// MuJoCo's search: each end that lies over a face (beyond the box along one axis at most), then
/// every edge, by squared distance; an edge must beat the best so far by more than kMinVal.
template <class S>
NearestFeature<S> nearest_feature(const Vec3<S>& center, const Vec3<S>& halfaxis,
                                  double halflength, double radius, const Vec3<S>& half,
                                  double margin) {
  NearestFeature<S> best;
  // MuJoCo's starting bound. It has the units of a length but is compared with squared
  // distances: a segment whose squared distance to the box exceeds it finds nothing, and the
  // capsule gets no contact even when it is thick enough to reach the box (radius >~ 2)
  double best_distance2 =
      margin + 2 * (radius + halflength + value(half[0]) + value(half[1]) + value(half[2]));

  for (int end = -1; end <= 1; end += 2) {
    const Vec3<S> end_point = add_scaled(center, halfaxis, S(end));
    Vec3<S> clamped = end_point;
    int clamped_axes = 0, clamped_axis = -1;
    for (int k = 0; k < 3; ++k) {
      if (value(end_point[k]) < -value(half[k]) || value(end_point[k]) > value(half[k])) {
        clamped[k] = clamp(end_point[k], -half[k], half[k]);
        ++clamped_axes;
        clamped_axis = k;
      }
    }
    if (clamped_axes > 1) continue;  // nearest an edge or corner: the edge search covers it
    const Vec3<S> gap = sub(clamped, end_point);
    const double distance2 = value(dot(gap, gap));
    if (distance2 < best_distance2) {
      best_distance2 = distance2;
      best.kind = NearestFeature<S>::kEndOverFace;
      best.segment_t = S(end);
      best.end_face_axis = clamped_axis;
    }
  }

  for (int axis = 0; axis < 3; ++axis) {
    for (int corner = 0; corner < 8; ++corner) {
      if (corner & (1 << axis)) continue;  // each edge once, from its corner at -half[axis]
      // the edge: middle + s * half[axis] * e_axis, s in [-1, 1]
      Vec3<S> middle;
      for (int k = 0; k < 3; ++k) middle[k] = S((corner & (1 << k)) ? 1.0 : -1.0) * half[k];
      middle[axis] = S(0);

      // closest points of the two lines: the 2x2 normal equations in (s, t)
      const Vec3<S> offset = sub(middle, center);
      const S a = half[axis] * half[axis];
      const S b = -half[axis] * halfaxis[axis];
      const S c = S(halflength * halflength);
      const S rhs_s = -half[axis] * offset[axis];
      const S rhs_t = dot(halfaxis, offset);
      const S det = a * c - b * b;
      if (std::abs(value(det)) < kMinVal) continue;  // parallel to this edge
      const S inverse_det = S(1) / det;
      S s = (c * rhs_s - b * rhs_t) * inverse_det;
      S t = (a * rhs_t - b * rhs_s) * inverse_det;

      // clamp to the edge, then to the segment (re-solving the other parameter each time)
      int edge_state = 1;
      if (value(s) > 1 || value(s) < -1) {
        edge_state = value(s) > 1 ? 2 : 0;
        s = S(value(s) > 1 ? 1.0 : -1.0);
        t = (rhs_t - b * s) * (S(1) / c);
      }
      if (value(t) > 1 || value(t) < -1) {
        t = S(value(t) > 1 ? 1.0 : -1.0);
        s = (rhs_s - b * t) * (S(1) / a);
        if (value(s) > 1 || value(s) < -1) {
          edge_state = value(s) > 1 ? 2 : 0;
          s = S(value(s) > 1 ? 1.0 : -1.0);
        }
      }

      Vec3<S> gap = add_scaled(offset, halfaxis, -t);
      gap[axis] = gap[axis] + half[axis] * s;
      const double distance2 = value(dot(gap, gap));
      // kMinVal: an edge numerically parallel to the capsule does not take over from a face
      if (distance2 < best_distance2 - kMinVal) {
        best_distance2 = distance2;
        best.kind = NearestFeature<S>::kEdge;
        best.segment_t = t;
        best.edge_t = s;
        best.edge_state = edge_state;
        best.edge_axis = axis;
        best.corner = corner + (edge_state == 2 ? (1 << axis) : 0);
      }
    }
  }
  return best;
}

/// The two axes other than `axis`, in cyclic order.
inline void cyclic_others(int axis, int& next, int& after) {
  next = (axis + 1) % 3;
  after = (axis + 2) % 3;
}

/// The second point of the segment, as an offset in t from the first, or nothing.
///
/// The relative orientation is read from bit codes: `octant` has bit k set where the capsule's
/// axis points along +k, a corner's bits where it is at +half[k]; their XOR marks the axes along
/// which moving towards +t brings the segment back towards the box's inside.
template <class S>
std::optional<S> second_point(const NearestFeature<S>& nearest, const Vec3<S>& center,
                              const Vec3<S>& axis, const Vec3<S>& halfaxis, const Vec3<S>& half) {
  const int octant = sign_bits(halfaxis);
  const S t0 = nearest.segment_t;

  if (nearest.kind == NearestFeature<S>::kEdge && nearest.edge_state != 1) {
    // Nearest a corner of the box.
    int inward = octant ^ nearest.corner;
    if (inward == 0 || inward == 7) return std::nullopt;  // pointing at or away from the corner
    // `direction` (+1 or -1 along t) moves inward along exactly one axis, `along`
    double direction;
    S room_ahead, room_behind;
    if (inward == 1 || inward == 2 || inward == 4) {
      direction = 1;
      room_ahead = S(1) - t0;
      room_behind = S(1) + t0;
    } else {
      direction = -1;
      inward = 7 - inward;
      room_behind = S(1) - t0;
      room_ahead = S(1) + t0;
    }
    const int along = inward == 1 ? 0 : (inward == 2 ? 1 : 2);
    int side1, side2;
    cyclic_others(along, side1, side2);
    S offset;
    if (value(axis[along]) * value(axis[along]) > 0.5) {
      // within 45 degrees of that edge: the second point follows the edge, at most to its end
      offset = smaller(room_ahead, S(2) * half[along] / magnitude(halfaxis[along]));
      return offset * S(direction);
    }
    // otherwise it crosses the face across the other two axes, at most to its far edges
    offset = room_behind;
    offset = smaller(offset, S(2) * half[side1] / magnitude(halfaxis[side1]));
    offset = smaller(offset, S(2) * half[side2] / magnitude(halfaxis[side2]));
    return offset * S(-direction);
  }

  if (nearest.kind == NearestFeature<S>::kEdge) {
    // Nearest the middle of an edge: only a capsule crossing the edge (an X seen along the
    // normal, one differing bit left besides the edge's own) gets a second point, not a T.
    const int edge = nearest.edge_axis;
    const int inward = (octant ^ nearest.corner) & (7 - (1 << edge));
    if (inward != 1 && inward != 2 && inward != 4) return std::nullopt;
    // of the other two axes, `flat` has the smaller component of the capsule's direction (the
    // capsule lies along that axis's face), `steep` the larger
    int flat, steep;
    cyclic_others(edge, flat, steep);
    if (std::abs(value(axis[flat])) > std::abs(value(axis[steep]))) flat = steep;
    steep = 3 - edge - flat;
    double direction;
    S offset;
    if (inward & (1 << steep)) {
      direction = 1;
      offset = S(1) - t0;
    } else {
      direction = -1;
      offset = S(1) + t0;
    }
    // at most across the face to its far edge, and at most to the end of the edge
    offset = smaller(offset, S(2) * half[steep] / magnitude(halfaxis[steep]));
    const bool same_way = ((octant & (1 << edge)) != 0) == ((inward & (1 << steep)) != 0);
    const S edge_room = same_way ? S(1) - nearest.edge_t : S(1) + nearest.edge_t;
    offset = smaller(offset, half[edge] * edge_room / magnitude(halfaxis[edge]));
    return offset * S(direction);
  }

  // Nearest a face under one end: the second point is the farthest point towards the other end
  // that is still over the box (within its slab along the face's two in-plane axes).
  if (nearest.end_face_axis == -1) return std::nullopt;  // that end is inside the box
  const double direction = value(t0) < 0 ? 1 : -1;       // towards the other end
  const Vec3<S> end_point = add_scaled(center, halfaxis, S(-direction));
  S offset = S(2);  // the whole segment
  for (int k = 0; k < 3; ++k) {
    if (k == nearest.end_face_axis) continue;
    for (const S& bound : {half[k], -half[k]}) {
      const S leaves_at = (bound - end_point[k]) / halfaxis[k] * S(direction);
      if (value(leaves_at) > 0 && value(leaves_at) < value(offset)) offset = leaves_at;
    }
  }
  return offset * S(direction);
}

/// The capsule (its centre, its axis: its frame's z column, its radius and half-length) against
/// the box: up to two contacts.
template <class S>
int capsule_box(const Vec3<S>& capsule_pos, const Vec3<S>& capsule_z, double radius,
                double halflength, const Box<S>& box, double margin, primitive::Touch<S>* out) {
  const Vec3<S> center = mul_t(box.mat, sub(capsule_pos, box.pos));
  const Vec3<S> axis = mul_t(box.mat, capsule_z);
  const Vec3<S> halfaxis = scale(axis, S(halflength));

  const NearestFeature<S> nearest =
      nearest_feature(center, halfaxis, halflength, radius, box.half, margin);
  // nothing found (beyond nearest_feature's starting bound, or a segment of length 0 beside an
  // edge or a corner): MuJoCo gives no contact
  if (nearest.kind == NearestFeature<S>::kNone) return 0;
  const std::optional<S> second = second_point(nearest, center, axis, halfaxis, box.half);

  // a sphere at each point, placed in the world as MuJoCo does (the box frame round trip included)
  const auto sphere_at = [&](const S& t) {
    return add(mul(box.mat, add_scaled(center, halfaxis, t)), box.pos);
  };
  int count = sphere_box(sphere_at(nearest.segment_t), radius, box, margin, out);
  if (second) {
    count += sphere_box(sphere_at(*second + nearest.segment_t), radius, box, margin, out + count);
  }
  return count;
}

// ---- box-box ---------------------------------------------------------------------------------
//
// Separating axes (3 face normals of each box, 9 edge-pair cross products) pick the axis of least
// penetration. For a face, the other (incident) box is clipped against that face's rectangle; for
// an edge pair, a face of box 2 next to its edge is projected along the axis onto a face of box 1
// next to its edge, and clipped there. The clipped polygon's points within the margin are the
// contacts, before the driver drops repeated positions (remove_repeated_positions).

/// Box 2 seen from box 1 and back.
template <class S>
struct BoxPair {
  Vec3<S> center2_in_1;  ///< box 2's centre in box 1's frame
  Vec3<S> center1_in_2;  ///< box 1's centre in box 2's frame
  Mat9<S> rot;           ///< rot(i, j) = axis i of box 1 . axis j of box 2 (columns: box 2 in 1)
  Mat9<S> rot_t;         ///< its transpose (columns: box 1's axes in box 2)
  Mat9<S> abs_rot;       ///< |rot|
};

template <class S>
BoxPair<S> relate(const Box<S>& b1, const Box<S>& b2) {
  BoxPair<S> pair;
  pair.center2_in_1 = mul_t(b1.mat, sub(b2.pos, b1.pos));
  pair.center1_in_2 = mul_t(b2.mat, sub(b1.pos, b2.pos));
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      // MuJoCo accumulates from +0, so an entry never comes out as -0
      pair.rot[3 * i + j] = S(0.0) + b1.mat[i] * b2.mat[j] + b1.mat[3 + i] * b2.mat[3 + j] +
                            b1.mat[6 + i] * b2.mat[6 + j];
    }
  }
  pair.rot_t = transpose(pair.rot);
  for (int k = 0; k < 9; ++k) pair.abs_rot[k] = magnitude(pair.rot[k]);
  return pair;
}

/// The separating axis of least penetration.
template <class S>
struct SeparatingAxis {
  enum Kind { kFace, kEdges } kind = kFace;
  S penetration = S(0);  ///< the overlap along it (negative: a gap within the margin)
  // kFace
  int face = -1;         ///< 0-2: the +x, +y, +z face, 3-5: the -x, -y, -z face
  bool on_box2 = false;  ///< the face is box 2's
  // kEdges: box 1's axis edge1 crossed with box 2's axis edge2
  int edge1 = -1, edge2 = -1;
  Vec3<S> normal{S(0), S(0), S(0)};  ///< the unit cross product, box 1's frame
  bool flipped = false;  ///< box 2 lies on its negative side
  int corner1 = 0;       ///< bits of box 1's corners on its edge nearest box 2 (edge1's bit unused)
  int corner2 = 0;       ///< the same for box 2's edge nearest box 1
};

/// e_axis x v
template <class S>
Vec3<S> axis_cross(int axis, const Vec3<S>& v) {
  switch (axis) {
    case 0: return {S(0), -v[2], v[1]};
    case 1: return {v[2], S(0), -v[0]};
    default: return {-v[1], v[0], S(0)};
  }
}

/// MuJoCo's test of the 15 axes, in its order. Returns nothing when an axis separates the boxes
/// by more than the margin. A face axis must be strictly better to win, an edge axis below
/// penetration * (1 - 1e-12): with an overlap (> 0) that favours the faces in the ties of a box
/// resting flat; with a gap within the margin (< 0) it lets an edge axis win an exact tie.
template <class S>
std::optional<SeparatingAxis<S>> least_penetration(const Box<S>& b1, const Box<S>& b2,
                                                   const BoxPair<S>& pair, double margin) {
  const Vec3<S>& size1 = b1.half;
  const Vec3<S>& size2 = b2.half;
  // each box's extent along the other's axes
  const Vec3<S> extent2_in_1 = mul(pair.abs_rot, size2);
  const Vec3<S> extent1_in_2 = mul_t(pair.abs_rot, size1);

  SeparatingAxis<S> best;
  best.penetration = S(margin);  // start above any real overlap
  for (int i = 0; i < 3; ++i) {
    best.penetration = best.penetration + (size1[i] * S(3) + size2[i] * S(3));
  }
  bool found_one = false;

  for (int i = 0; i < 3; ++i) {
    const S overlap1 = -magnitude(pair.center2_in_1[i]) + size1[i] + extent2_in_1[i];
    const S overlap2 = -magnitude(pair.center1_in_2[i]) + size2[i] + extent1_in_2[i];
    if (value(overlap1) < -margin || value(overlap2) < -margin) return std::nullopt;
    if (value(overlap1) < value(best.penetration)) {
      best.penetration = overlap1;
      best.face = i + (value(pair.center2_in_1[i]) < 0 ? 3 : 0);
      best.on_box2 = false;
      found_one = true;
    }
    if (value(overlap2) < value(best.penetration)) {
      best.penetration = overlap2;
      best.face = i + (value(pair.center1_in_2[i]) < 0 ? 3 : 0);
      best.on_box2 = true;
      found_one = true;
    }
  }

  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      Vec3<S> normal = axis_cross(i, row(pair.rot_t, j));
      const S sine = normalize(normal);
      if (value(sine) < kMinVal) continue;  // parallel edges: covered by the faces
      const S center_offset = dot(pair.center2_in_1, normal);
      // half-widths of both boxes along the axis; box 2's axis k projects as
      // |e1_i . (e2_j x e2_k)| / sine = |rot(i, third)| / sine
      S overlap = S(0);
      for (int k = 0; k < 3; ++k) {
        if (k != i) overlap = overlap + size1[k] * magnitude(normal[k]);
      }
      for (int k = 0; k < 3; ++k) {
        if (k != j) overlap = overlap + size2[k] * pair.abs_rot[3 * i + 3 - k - j] / sine;
      }
      overlap = overlap - magnitude(center_offset);
      if (value(overlap) < -margin) return std::nullopt;
      if (value(overlap) < value(best.penetration) * (1 - 1e-12)) {
        best.kind = SeparatingAxis<S>::kEdges;
        best.penetration = overlap;
        best.edge1 = i;
        best.edge2 = j;
        best.normal = normal;
        best.flipped = value(center_offset) < 0;
        const bool flip = best.flipped;
        // box 1's nearest edge: on the side of each other axis that faces box 2
        best.corner1 = 0;
        for (int k = 0; k < 3; ++k) {
          if (k != i && ((value(normal[k]) > 0) != flip)) best.corner1 += 1 << k;
        }
        // box 2's: normal . e2_k has the sign of rot(i, third), negated when (j, k) is not cyclic
        best.corner2 = 0;
        for (int k = 0; k < 3; ++k) {
          if (k == j) continue;
          const bool cyclic = (k - j + 3) % 3 == 1;
          if (((value(pair.rot[3 * i + 3 - k - j]) > 0) != flip) != cyclic) best.corner2 += 1 << k;
        }
        found_one = true;
      }
    }
  }
  if (!found_one) return std::nullopt;  // only with NaN in the input
  return best;
}

/// The signed permutation of axes that turns a box face's outward normal into +z (faces 0-5 as
/// in SeparatingAxis). Products with it are exact: picking and negating entries.
struct FaceTurn {
  std::array<int, 3> from;  ///< component k of a turned vector is sign[k] * v[from[k]]
  std::array<double, 3> sign;

  template <class S>
  Vec3<S> apply(const Vec3<S>& v) const {
    return {v[from[0]] * S(sign[0]), v[from[1]] * S(sign[1]), v[from[2]] * S(sign[2])};
  }
  /// turn * m: m's rows turned
  template <class S>
  Mat9<S> apply_rows(const Mat9<S>& m) const {
    Mat9<S> r;
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) r[3 * k + c] = m[3 * from[k] + c] * S(sign[k]);
    }
    return r;
  }
  /// mat * turn^T: the turned frame's axes in the world, for a box whose axes are mat's columns
  template <class S>
  Mat9<S> world(const Mat9<S>& mat) const {
    Mat9<S> r;
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) r[3 * i + k] = mat[3 * i + from[k]] * S(sign[k]);
    }
    return r;
  }
};

inline FaceTurn face_turn(int face) {
  switch (face) {
    case 0: return {{2, 1, 0}, {-1, 1, 1}};    // +x
    case 1: return {{0, 2, 1}, {1, -1, 1}};    // +y
    case 2: return {{0, 1, 2}, {1, 1, 1}};     // +z
    case 3: return {{2, 1, 0}, {1, 1, -1}};    // -x
    case 4: return {{0, 2, 1}, {1, 1, -1}};    // -y
    default: return {{0, 1, 2}, {-1, 1, -1}};  // -z
  }
}

/// Where segment start + c * dir, c in [0, 1], crosses the lines x = +-half_x (q = 0) and
/// y = +-half_y (q = 1) within the rectangle [-half_x, half_x] x [-half_y, half_y]: calls
/// on_crossing(c, q, bound, other) for each crossing, in MuJoCo's order (q, then -bound before
/// +bound), `other` being the crossing's other in-plane coordinate.
template <class S, class Found>
void rectangle_crossings(const Vec3<S>& start, const Vec3<S>& dir, const S& half_x,
                         const S& half_y, Found&& on_crossing) {
  const S half[2] = {half_x, half_y};
  for (int q = 0; q < 2; ++q) {
    const S a = start[q], b = dir[q], c = start[1 - q], d = dir[1 - q];
    if (!(std::abs(value(b)) > kMinVal)) continue;  // runs along those lines
    for (int side = -1; side <= 1; side += 2) {
      const S bound = half[q] * S(side);
      const S at = (bound - a) * (S(1) / b);
      if (value(at) < 0 || value(at) > 1) continue;
      const S other = c + d * at;
      if (std::abs(value(other)) > value(half[1 - q])) continue;
      on_crossing(at, q, bound, other);
    }
  }
}

template <class S>
struct Point {
  Vec3<S> pos;
  S depth;
};

/// Contacts of the incident box against the reference box's face `axis.face`: the face is the
/// rectangle [-lx, lx] x [-ly, ly] at z = 0 of the turned reference frame.
template <class S>
int face_contacts(const Box<S>& b1, const Box<S>& b2, const BoxPair<S>& pair,
                  const SeparatingAxis<S>& axis, double margin, primitive::Touch<S>* out) {
  const bool on_box2 = axis.on_box2;
  const Box<S>& reference = on_box2 ? b2 : b1;
  const FaceTurn turn = face_turn(axis.face);
  // incident box: its axes (rows of rt), centre and half-sizes in the turned reference frame
  const Mat9<S> r = turn.apply_rows(on_box2 ? pair.rot_t : pair.rot);
  const Mat9<S> rt = transpose(r);
  Vec3<S> center = turn.apply(on_box2 ? pair.center1_in_2 : pair.center2_in_1);
  const Vec3<S> reference_half = abs(turn.apply(reference.half));
  const Vec3<S>& incident_half = on_box2 ? b1.half : b2.half;
  const S lx = reference_half[0], ly = reference_half[1], hz = reference_half[2];
  center[2] = center[2] - hz;  // heights above the face

  // the incident box's lowest corner: + along each axis that points down
  int low_corner = 0;
  for (int i = 0; i < 3; ++i) {
    if (value(r[6 + i]) < 0) low_corner += 1 << i;
  }
  Vec3<S> lowest = center;
  for (int i = 0; i < 3; ++i) {
    lowest = add_scaled(lowest, row(rt, i),
                        incident_half[i] * S((low_corner & (1 << i)) ? 1.0 : -1.0));
  }
  // the edges from that corner within 60 degrees of the face's plane (|cos| < 0.5 to the normal)
  std::array<Vec3<S>, 6> pts;  // corner, edge 1, edge 2, corner + edge 1, corner + edge 2, all
  int corners_and_edges = 0;
  pts[corners_and_edges++] = lowest;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(value(r[6 + i])) < 0.5) {
      pts[corners_and_edges++] =
          scale(row(rt, i), incident_half[i] * S((low_corner & (1 << i)) ? -2.0 : 2.0));
    }
  }
  const int edges = corners_and_edges - 1;
  if (edges >= 1) pts[3] = add(pts[0], pts[1]);
  if (edges == 2) {
    pts[4] = add(pts[0], pts[2]);
    pts[5] = add(pts[3], pts[2]);
  }

  std::array<Point<S>, kMaxPairContacts> points;
  int n = 0;
  // 1. where the low edge (or the parallelogram of the two low edges) crosses the rectangle
  std::array<std::array<Vec3<S>, 2>, 4> lines;  // start, direction
  int nlines = 0;
  if (edges >= 1) lines[nlines++] = {pts[0], pts[1]};
  if (edges == 2) {
    lines[nlines++] = {pts[0], pts[2]};
    lines[nlines++] = {pts[3], pts[2]};
    lines[nlines++] = {pts[4], pts[1]};
  }
  for (int i = 0; i < nlines; ++i) {
    const Vec3<S>& start = lines[i][0];
    const Vec3<S>& dir = lines[i][1];
    rectangle_crossings(start, dir, lx, ly, [&](const S& at, int, const S&, const S&) {
      points[n++].pos = add_scaled(start, dir, at);
    });
  }
  // 2. the rectangle's corners strictly inside the parallelogram, at its height there
  if (edges == 2) {
    const S a = pts[1][0], b = pts[2][0], c = pts[1][1], d = pts[2][1];
    const S det = a * d - b * c;
    for (int i = 0; i < 4; ++i) {
      const S llx = i / 2 ? lx : -lx;
      const S lly = i % 2 ? ly : -ly;
      const S x = llx - pts[0][0], y = lly - pts[0][1];
      const S u = (x * d - y * b) * (S(1) / det);
      const S v = (y * a - x * c) * (S(1) / det);
      if (value(u) <= 0 || value(v) <= 0 || value(u) >= 1 || value(v) >= 1) continue;
      points[n++].pos = {llx, lly, pts[0][2] + u * pts[1][2] + v * pts[2][2]};
    }
  }
  // 3. the lowest corner always, even outside the rectangle; the other corners of the edges only
  // strictly over it
  const int ncorners = 1 << edges;
  for (int i = 0; i < ncorners; ++i) {
    const Vec3<S>& corner = pts[i == 0 ? 0 : i + 2];
    if (i > 0 && (value(corner[0]) <= -value(lx) || value(corner[0]) >= value(lx))) continue;
    if (i > 0 && (value(corner[1]) <= -value(ly) || value(corner[1]) >= value(ly))) continue;
    points[n++].pos = corner;
  }

  // within the margin; the contact is halfway down to the face, and MuJoCo 2.2.2's dist is that
  // half height too (its full depth is computed but not used): a box pressed 1 mm into a face
  // reports dist -0.5 mm, where the edge path reports full distances
  const Mat9<S> to_world = turn.world(reference.mat);
  const Vec3<S> column_z = {to_world[2], to_world[5], to_world[8]};
  const Vec3<S> normal = scale(column_z, S(on_box2 ? -1.0 : 1.0));  // from box 1 into box 2
  int count = 0;
  for (int i = 0; i < n; ++i) {
    Vec3<S> p = points[i].pos;
    if (value(p[2]) > margin) continue;
    p[2] = p[2] * S(0.5);
    const S dist = p[2];
    p[2] = p[2] + hz;
    found(out[count++], dist, add(mul(to_world, p), reference.pos), normal);
  }
  return count;
}

/// Contacts across the edge pair `axis.edge1` x `axis.edge2`: box 2's face that holds its nearest
/// edge and the neighbouring parallel edge, projected along the axis onto box 1's face next to its
/// nearest edge, clipped against that face's rectangle.
template <class S>
int edge_contacts(const Box<S>& b1, const Box<S>& b2, const BoxPair<S>& pair,
                  const SeparatingAxis<S>& axis, double margin, primitive::Touch<S>* out) {
  using std::sqrt;
  const int e1 = axis.edge1, e2 = axis.edge2;
  // the other two axes of each box, in MuJoCo's order (it decides ties), the one more aligned
  // with the other box's edge first
  static constexpr int kOthers[3][2] = {{1, 2}, {0, 2}, {1, 0}};
  int across2 = kOthers[e2][0], beside2 = kOthers[e2][1];  // box 2
  if (value(pair.abs_rot[3 * e1 + across2]) < value(pair.abs_rot[3 * e1 + beside2])) {
    across2 = beside2;
    beside2 = 3 - e2 - across2;
  }
  int across1 = kOthers[e1][0], beside1 = kOthers[e1][1];  // box 1
  if (value(pair.abs_rot[3 * across1 + e2]) < value(pair.abs_rot[3 * beside1 + e2])) {
    across1 = beside1;
    beside1 = 3 - e1 - across1;
  }
  // box 1's face: normal to its axis least aligned with box 2's edge, on the nearest edge's side
  const int face = (axis.corner1 & (1 << beside1)) ? beside1 : beside1 + 3;

  const FaceTurn turn = face_turn(face);
  Vec3<S> center = turn.apply(pair.center2_in_1);
  const Vec3<S> normal = turn.apply(axis.normal);
  const Mat9<S> rt = transpose(turn.apply_rows(pair.rot));  // rows: box 2's axes, turned frame
  // (MuJoCo turns the sizes with the transpose: the same magnitudes, each permutation here being
  // its own inverse)
  const Vec3<S> half1 = abs(turn.apply(b1.half));
  const Vec3<S>& half2 = b2.half;
  const S lx = half1[0], ly = half1[1], hz = half1[2];
  center[2] = center[2] - hz;

  // box 2's face: its nearest edge (corners 0, 1) and the parallel edge across `across2` (2, 3)
  const auto side = [&](int k, bool flip) {
    const bool plus = (axis.corner2 & (1 << k)) != 0;
    return half2[k] * S((plus != flip) ? 1.0 : -1.0);
  };
  std::array<Vec3<S>, 4> corners;
  for (int pairs = 0; pairs < 2; ++pairs) {
    Vec3<S> mid = add_scaled(center, row(rt, across2), side(across2, pairs == 1));
    mid = add_scaled(mid, row(rt, beside2), side(beside2, false));
    corners[2 * pairs] = add_scaled(mid, row(rt, e2), half2[e2]);
    corners[2 * pairs + 1] = add_scaled(mid, row(rt, e2), -half2[e2]);
  }

  if (std::abs(value(normal[2])) < kMinVal) return 0;  // axis in the face's plane: not expected
  // 1 / (normal . z), signed so that depth = height * inverse_normal is negative in penetration
  const S inverse_normal = (S(1) / normal[2]) * S(axis.flipped ? -1.0 : 1.0);

  // the face's corners as they are (raw) and projected along the axis onto z = 0 (flat)
  std::array<Vec3<S>, 4> flat;
  for (int i = 0; i < 4; ++i) {
    const S along = -corners[i][2] * (S(1) / normal[2]);
    flat[i] = add_scaled(corners[i], normal, along);
  }
  const Vec3<S> raw_edge1 = sub(corners[1], corners[0]), raw_edge2 = sub(corners[2], corners[0]);
  const Vec3<S> flat_edge1 = sub(flat[1], flat[0]), flat_edge2 = sub(flat[2], flat[0]);

  std::array<Point<S>, kMaxPairContacts> points;
  int n = 0;
  // 1. the projected parallelogram's sides crossing the rectangle, kept within the margin;
  // the contact is midway between box 2's raw point and its projection's crossing
  struct Side {
    Vec3<S> flat_start, flat_dir, raw_start, raw_dir;
  };
  const std::array<Side, 4> sides = {
      Side{flat[0], flat_edge1, corners[0], raw_edge1},
      Side{flat[0], flat_edge2, corners[0], raw_edge2},
      Side{add(flat[0], flat_edge1), flat_edge2, add(corners[0], raw_edge1), raw_edge2},
      Side{add(flat[0], flat_edge2), flat_edge1, add(corners[0], raw_edge2), raw_edge1}};
  for (const Side& s : sides) {
    rectangle_crossings(s.flat_start, s.flat_dir, lx, ly,
                        [&](const S& at, int q, const S& bound, const S& other) {
                          if (value((s.raw_start[2] + s.raw_dir[2] * at) * inverse_normal) >
                              margin)
                            return;
                          Vec3<S> p = add_scaled(scale(s.raw_start, S(0.5)), s.raw_dir,
                                                 S(0.5) * at);
                          p[q] = p[q] + S(0.5) * bound;
                          p[1 - q] = p[1 - q] + S(0.5) * other;
                          points[n++] = {p, p[2] * inverse_normal * S(2)};
                        });
  }
  const int crossings = n;

  // 2. the rectangle's corners over the parallelogram (clamped onto it), measured to box 2's
  // raw face; with no crossing, a corner need only be within it along one of the two sides
  const S a = flat_edge1[0], b = flat_edge2[0], c = flat_edge1[1], d = flat_edge2[1];
  // MuJoCo stores the squared distance below in the variable that holds this determinant, so the
  // corners after the first that reaches it are tested against that distance instead: kept, for
  // the same decisions.
  S det_or_distance2 = a * d - b * c;
  for (int i = 0; i < 4; ++i) {
    const S llx = i / 2 ? lx : -lx;
    const S lly = i % 2 ? ly : -ly;
    const S x = llx - flat[0][0], y = lly - flat[0][1];
    S u = (x * d - y * b) * (S(1) / det_or_distance2);
    S v = (y * a - x * c) * (S(1) / det_or_distance2);
    const bool u_out = value(u) < 0 || value(u) > 1, v_out = value(v) < 0 || value(v) > 1;
    if (crossings == 0 ? (u_out && v_out) : (u_out || v_out)) continue;
    u = clamp(u, S(0.0), S(1.0));
    v = clamp(v, S(0.0), S(1.0));
    Vec3<S> on_box2 = scale(corners[0], S(1) - u - v);
    on_box2 = add_scaled(on_box2, corners[1], u);
    on_box2 = add_scaled(on_box2, corners[2], v);
    const Vec3<S> corner = {llx, lly, S(0)};
    const Vec3<S> gap = sub(corner, on_box2);
    det_or_distance2 = dot(gap, gap);
    if (value(on_box2[2]) > 0 && value(det_or_distance2) > margin * margin) continue;
    points[n++] = {scale(add(corner, on_box2), S(0.5)),
                   sqrt(det_or_distance2) * S(value(on_box2[2]) < 0 ? -1.0 : 1.0)};
  }
  const int with_corners = n;

  // 3. box 2's face corners whose projection is over the rectangle (with no crossing: over it
  // along one axis, or anywhere when nothing was found yet); distance to the rectangle, the raw
  // height counted along the axis
  for (int i = 0; i < 4; ++i) {
    const double x = value(flat[i][0]), y = value(flat[i][1]);
    const bool x_out = x < -value(lx) || x > value(lx), y_out = y < -value(ly) || y > value(ly);
    if (crossings == 0) {
      if (with_corners != 0 && x_out && y_out) continue;
    } else if (x_out || y_out) {
      continue;
    }
    S distance2 = S(0);
    Vec3<S> p = {flat[i][0] * S(0.5), flat[i][1] * S(0.5), S(0)};
    for (int j = 0; j < 2; ++j) {
      const S limit = half1[j];
      if (value(flat[i][j]) < -value(limit)) {
        distance2 = distance2 + (flat[i][j] + limit) * (flat[i][j] + limit);
        p[j] = -limit * S(0.5);
      } else if (value(flat[i][j]) > value(limit)) {
        distance2 = distance2 + (flat[i][j] - limit) * (flat[i][j] - limit);
        p[j] = limit * S(0.5);
      }
    }
    const S height = corners[i][2];
    distance2 = distance2 + height * inverse_normal * height * inverse_normal;
    if (value(height) > 0 && value(distance2) > margin * margin) continue;
    points[n++] = {add_scaled(p, corners[i], S(0.5)),
                   sqrt(distance2) * S(value(height) < 0 ? -1.0 : 1.0)};
  }

  const Mat9<S> to_world = turn.world(b1.mat);
  const Vec3<S> world_normal = scale(mul(to_world, normal), S(axis.flipped ? -1.0 : 1.0));
  for (int i = 0; i < n; ++i) {
    Vec3<S> p = points[i].pos;
    p[2] = p[2] + hz;
    found(out[i], points[i].depth, add(mul(to_world, p), b1.pos), world_normal);
  }
  return n;
}

/// Two boxes: up to kMaxPairContacts contacts, repeated positions not yet dropped (the driver
/// drops them: remove_repeated_positions).
template <class S>
int box_box(const Box<S>& b1, const Box<S>& b2, double margin, primitive::Touch<S>* out) {
  const BoxPair<S> pair = relate(b1, b2);
  const std::optional<SeparatingAxis<S>> axis = least_penetration(b1, b2, pair, margin);
  if (!axis) return 0;
  return axis->kind == SeparatingAxis<S>::kFace
             ? face_contacts(b1, b2, pair, *axis, margin, out)
             : edge_contacts(b1, b2, pair, *axis, margin, out);
}

}  // namespace lever::detail::box_pairs
