// Minkowski portal refinement (MPR): the general convex search MuJoCo 2.2.2 runs for every pair
// without a closed form, as libccd v2.1 writes it (ccdMPRPenetration, the library MuJoCo links),
// here on support functions called directly.
//
// Two convex shapes overlap where their Minkowski difference A - B holds the origin. The search
// walks that difference through its support points (a point of A farthest along d minus a point
// of B farthest along -d):
//
//   discovery    v0 an interior point (the centres' difference), v1 the support towards the
//                origin, v2 across, v3 until the triangle v1 v2 v3 is a portal: the cone from v0
//                through it holds the ray from v0 to the origin
//   refinement   the portal pushed outwards (its face's normal, a new support point replacing a
//                corner) until the origin is behind its face: the shapes overlap; or until the
//                difference ends before the origin: they do not
//   penetration  the portal pushed on until a new support point no longer moves its face by the
//                tolerance: the face is the boundary near the origin; the depth and direction are
//                the origin's nearest point on the face, the point the origin's barycentric
//                coordinates in the tetrahedron v0 v1 v2 v3 applied to each shape's own points
//
// Every operation is libccd's, in libccd's order, with its thresholds (values within DBL_EPSILON
// of zero or of each other count as equal), so that the same support points are asked for and
// the answer is the same bit for bit (tests/diff/collision_mpr_ccd.cpp compares the two).
//
// Written on a scalar S: double for the collision stage (collision/convex.cpp), dual numbers for
// the derivatives, which replay the stage's search on moving poses
// (transition/contact_geometry.cpp): every decision is taken on the values, so both take the
// same path.
#pragma once

#include <cfloat>
#include <cmath>

#include "collision/primitive_pairs.hpp"

namespace lever::detail::mpr {

using primitive::cross;
using primitive::dot;
using primitive::value;
using primitive::Vec;

/// libccd's threshold (CCD_EPS in double precision).
inline constexpr double kEps = DBL_EPSILON;

inline bool near_zero(double x) { return std::fabs(x) < kEps; }

/// Equal within kEps, absolutely or relative to the larger magnitude.
inline bool near_equal(double x, double y) {
  const double gap = std::fabs(x - y);
  if (gap < kEps) return true;
  const double ax = std::fabs(x), ay = std::fabs(y);
  return gap < kEps * (ay > ax ? ay : ax);
}

/// C's fmin as libccd calls it (glibc's): the smaller; of two equal values (-0 and +0) the
/// second; a NaN loses. Written out, not called: fmin is a library call where this is two tests.
inline double smaller(double x, double y) {
  if (x < y) return x;
  if (y <= x) return y;
  return std::fmin(x, y);  // a NaN
}

/// At zero (within kEps) or above.
inline bool not_negative(double x) { return near_zero(x) || x > 0; }
/// At zero (within kEps) or below: a support point that does not pass the origin.
inline bool behind(double x) { return near_zero(x) || x < 0; }

/// Every component within kEps of zero.
template <class S>
bool near_origin(const Vec<S>& v) {
  return near_equal(value(v[0]), 0) && near_equal(value(v[1]), 0) &&
         near_equal(value(v[2]), 0);
}

/// Scaled by the reciprocal of the length (no test: libccd normalizes only non-zero vectors;
/// primitive::normalize tests for a short one).
template <class S>
void make_unit(Vec<S>& d) {
  using std::sqrt;
  const S inverse = S(1) / sqrt(dot(d, d));
  d = d * inverse;
}

/// A point of the Minkowski difference: v = a - b, a of shape A along the direction asked, b of
/// shape B against it.
template <class S>
struct Point {
  Vec<S> v, a, b;
};

/// The two shapes' support functions, each `(const double* dir, double* point)` in the world, as
/// the search asks them (on doubles): A's point along dir, B's along -dir.
template <class SupportA, class SupportB>
struct Supports {
  SupportA& a;
  SupportB& b;
  void operator()(const Vec<double>& dir, Point<double>& p) const {
    Vec<double> d = dir;
    a(d.c.data(), p.a.c.data());
    for (int i = 0; i < 3; ++i) d[i] *= -1.0;
    b(d.c.data(), p.b.c.data());
    p.v = p.a - p.b;
  }
};

/// What the search found where the shapes overlap: the depth, the direction from A into B along
/// which it is measured (zero where the shapes only touch), and the point between them.
template <class S>
struct Answer {
  S depth;
  Vec<S> dir, pos;
};

/// How the search ended: apart (the difference ends before the origin, found in discovery or
/// in refinement), or overlapping: the origin on v1 (a touch), on the segment v0 v1, or inside
/// the refined portal.
enum class Outcome { kApart, kApartRefined, kOnV1, kOnSegment, kPortal };

inline bool overlapping(Outcome o) { return o != Outcome::kApart && o != Outcome::kApartRefined; }

/// `supports(dir, point)` fills a Point along dir.
template <class S, class SupportsT>
class Search {
 public:
  Search(SupportsT& supports, double tolerance, unsigned long max_iterations)
      : supports_(supports), tolerance_(tolerance), max_iterations_(max_iterations) {}

  /// The search from the centres a and b (interior points); `answer` is set where overlapping().
  Outcome penetration(const Vec<S>& centre_a, const Vec<S>& centre_b, Answer<S>& answer) {
    const Outcome found = discover(centre_a, centre_b);
    switch (found) {
      case Outcome::kOnV1: touch(answer); return found;
      case Outcome::kOnSegment: on_segment(answer); return found;
      case Outcome::kPortal: break;
      default: return found;
    }
    if (!refine()) return Outcome::kApartRefined;
    penetrate(answer);
    return found;
  }

 private:
  using V = Vec<S>;

  /// Whether a support point found along dir reaches past the origin (is not behind it).
  static bool reaches(const Point<S>& p, const V& dir) {
    return not_negative(value(dot(p.v, dir)));
  }

  /// The normal of the portal's face v1 v2 v3, away from v0.
  V face_normal() const {
    V dir = cross(p_[2].v - p_[1].v, p_[3].v - p_[1].v);
    make_unit(dir);
    return dir;
  }

  /// The normal of the triangle v0 v1 v2 (the direction v3 is sought in).
  V wedge_normal() const {
    V dir = cross(p_[1].v - p_[0].v, p_[2].v - p_[0].v);
    make_unit(dir);
    return dir;
  }

  /// Whether the origin lies outside the plane through v0, x and y (on the side opposite to
  /// the cross product x × y), clearly, not within kEps.
  bool outside(const V& x, const V& y) const {
    const double side = value(dot(cross(x, y), p_[0].v));
    return side < 0 && !near_zero(side);
  }

  Outcome discover(const V& centre_a, const V& centre_b) {
    Point<S>& v0 = p_[0];
    v0.a = centre_a;
    v0.b = centre_b;
    v0.v = v0.a - v0.b;
    // the centres coincide: the shapes overlap, but the search needs a direction; moved a
    // little (libccd adds the vector (kEps * 10, 0, 0): a zero's sign made +)
    if (near_origin(v0.v)) {
      v0.v[0] = v0.v[0] + kEps * 10.0;
      v0.v[1] = v0.v[1] + 0.0;
      v0.v[2] = v0.v[2] + 0.0;
    }

    // v1: the support towards the origin
    V dir = v0.v * -1.0;
    make_unit(dir);
    supports_(dir, p_[1]);
    if (behind(value(dot(p_[1].v, dir)))) return Outcome::kApart;

    // v2: across the line v0 v1, unless the origin is on it
    dir = cross(v0.v, p_[1].v);
    if (near_zero(value(dot(dir, dir)))) {
      return near_origin(p_[1].v) ? Outcome::kOnV1 : Outcome::kOnSegment;
    }
    make_unit(dir);
    supports_(dir, p_[2]);
    if (behind(value(dot(p_[2].v, dir)))) return Outcome::kApart;

    // v3 along the normal of v0 v1 v2 on the origin's side (v1 and v2 swapped to face outwards)
    dir = wedge_normal();
    if (value(dot(dir, v0.v)) > 0) {
      const Point<S> swapped = p_[1];
      p_[1] = p_[2];
      p_[2] = swapped;
      dir = dir * -1.0;
    }
    for (;;) {
      supports_(dir, p_[3]);
      if (behind(value(dot(p_[3].v, dir)))) return Outcome::kApart;
      // the origin outside the side v0 v1 v3: v3 replaces v2; outside v0 v3 v2: v3 replaces v1;
      // else the cone through v1 v2 v3 holds it
      if (outside(p_[1].v, p_[3].v)) {
        p_[2] = p_[3];
      } else if (outside(p_[3].v, p_[2].v)) {
        p_[1] = p_[3];
      } else {
        return Outcome::kPortal;
      }
      dir = wedge_normal();
    }
  }

  /// The side of the portal's new tetrahedra (v0, v4 and a corner) the origin is on decides
  /// which corner v4 replaces, so that the portal keeps holding the origin's ray.
  void expand(const Point<S>& v4) {
    const V split = cross(v4.v, p_[0].v);
    if (value(dot(p_[1].v, split)) > 0) {
      p_[value(dot(p_[2].v, split)) > 0 ? 1 : 3] = v4;
    } else {
      p_[value(dot(p_[3].v, split)) > 0 ? 2 : 1] = v4;
    }
  }

  /// Whether v4 (found along dir) moves the portal's face by no more than the tolerance: the
  /// smallest of its reach past each corner.
  bool within_tolerance(const Point<S>& v4, const V& dir) const {
    const double d1 = value(dot(p_[1].v, dir)), d2 = value(dot(p_[2].v, dir));
    const double d3 = value(dot(p_[3].v, dir)), d4 = value(dot(v4.v, dir));
    const double gain = smaller(smaller(d4 - d1, d4 - d2), d4 - d3);
    return near_equal(gain, tolerance_) || gain < tolerance_;
  }

  /// Until the origin is behind the portal's face (overlap: true) or the difference ends first.
  bool refine() {
    Point<S> v4;
    for (;;) {
      const V dir = face_normal();
      if (not_negative(value(dot(dir, p_[1].v)))) return true;
      supports_(dir, v4);
      if (!reaches(v4, dir) || within_tolerance(v4, dir)) return false;
      expand(v4);
    }
  }

  void penetrate(Answer<S>& answer) {
    V dir;
    Point<S> v4;
    for (unsigned long iterations = 0;; ++iterations) {
      dir = face_normal();
      supports_(dir, v4);
      if (within_tolerance(v4, dir) || iterations > max_iterations_) break;
      expand(v4);
    }
    // the origin's nearest point on the face: its distance the depth, its direction the normal
    using std::sqrt;
    answer.depth = sqrt(nearest_on_triangle(p_[1].v, p_[2].v, p_[3].v, answer.dir));
    if (near_zero(value(answer.depth))) {
      answer.dir = {{S(0), S(0), S(0)}};  // touching: no direction
    } else {
      make_unit(answer.dir);
    }
    answer.pos = position(dir);
  }

  /// The origin on v1: touching, no depth, no direction, the point between v1's two points.
  void touch(Answer<S>& answer) const {
    answer.depth = S(0);
    answer.dir = {{S(0), S(0), S(0)}};
    answer.pos = (p_[1].a + p_[1].b) * 0.5;
  }

  /// The origin on segment v0 v1: v1 gives the depth and direction.
  void on_segment(Answer<S>& answer) const {
    using std::sqrt;
    answer.pos = (p_[1].a + p_[1].b) * 0.5;
    answer.dir = p_[1].v;
    answer.depth = sqrt(dot(answer.dir, answer.dir));
    make_unit(answer.dir);
  }

  /// The point of segment x0 b nearest the origin (`witness`), and its squared distance.
  static S nearest_on_segment(const V& x0, const V& b, V& witness) {
    const V d = b - x0;
    S t = dot(x0, d) * -1.0;  // x0 - origin, as x0
    t = t / dot(d, d);
    if (value(t) < 0 || near_zero(value(t))) {
      witness = x0;
    } else if (value(t) > 1 || near_equal(value(t), 1)) {
      witness = b;
    } else {
      witness = d * t + x0;
    }
    return dot(witness, witness);
  }

  /// The point of triangle x0 b c nearest the origin (`witness`), and its squared distance: the
  /// plane's nearest point where it lies in the triangle (within kEps), else the nearest of the
  /// three edges'.
  static S nearest_on_triangle(const V& x0, const V& b, const V& c, V& witness) {
    const V d1 = b - x0, d2 = c - x0;
    const S v = dot(d1, d1), w = dot(d2, d2);
    const S p = dot(x0, d1), q = dot(x0, d2), r = dot(d1, d2);
    const S det = w * v - r * r;
    S s(-1.0), t(-1.0);  // a triangle without area: its edges
    if (!near_zero(value(det))) {
      s = (q * r - w * p) / det;
      t = (s * r * -1.0 - q) / w;
    }
    const double sv = value(s), tv = value(t);
    if (not_negative(sv) && (near_equal(sv, 1) || sv < 1) && not_negative(tv) &&
        (near_equal(tv, 1) || tv < 1) && (near_equal(tv + sv, 1) || tv + sv < 1)) {
      witness = x0 + d1 * s + d2 * t;
      return dot(witness, witness);
    }
    S best = nearest_on_segment(x0, b, witness);
    V other;
    S next = nearest_on_segment(x0, c, other);
    if (value(next) < value(best)) {
      best = next;
      witness = other;
    }
    next = nearest_on_segment(b, c, other);
    if (value(next) < value(best)) {
      best = next;
      witness = other;
    }
    return best;
  }

  /// The point between the shapes: the origin's barycentric coordinates (six times the volumes)
  /// in the tetrahedron v0 v1 v2 v3, or, where they do not sum to a positive volume, in the face
  /// v1 v2 v3 (projected along its normal `dir`, the portal's last face_normal), applied to each
  /// shape's own points; their midpoint.
  V position(const V& dir) const {
    S weight[4] = {dot(cross(p_[1].v, p_[2].v), p_[3].v), dot(cross(p_[3].v, p_[2].v), p_[0].v),
                   dot(cross(p_[0].v, p_[1].v), p_[3].v), dot(cross(p_[2].v, p_[1].v), p_[0].v)};
    S sum = weight[0] + weight[1] + weight[2] + weight[3];
    if (near_zero(value(sum)) || value(sum) < 0) {
      weight[0] = S(0);
      weight[1] = dot(cross(p_[2].v, p_[3].v), dir);
      weight[2] = dot(cross(p_[3].v, p_[1].v), dir);
      weight[3] = dot(cross(p_[1].v, p_[2].v), dir);
      sum = weight[1] + weight[2] + weight[3];
    }
    const S inverse = S(1) / sum;
    V on_a = {{S(0), S(0), S(0)}}, on_b = on_a;
    for (int k = 0; k < 4; ++k) {
      on_a = on_a + p_[k].a * weight[k];
      on_b = on_b + p_[k].b * weight[k];
    }
    return (on_a * inverse + on_b * inverse) * 0.5;
  }

  SupportsT& supports_;
  double tolerance_;
  unsigned long max_iterations_;
  Point<S> p_[4];  // the portal: v0 the interior point, v1 v2 v3 the face
};

}  // namespace lever::detail::mpr
