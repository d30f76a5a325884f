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
#pragma once

#include <cfloat>
#include <cmath>

namespace lever::detail::mpr {

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

// three-vectors as plain arrays, each sum in libccd's order
inline double dot(const double* a, const double* b) {
  double sum = a[0] * b[0];
  sum += a[1] * b[1];
  sum += a[2] * b[2];
  return sum;
}
inline void cross(double* out, const double* a, const double* b) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}
inline void subtract(double* out, const double* a, const double* b) {
  for (int i = 0; i < 3; ++i) out[i] = a[i] - b[i];
}
inline void copy(double* out, const double* a) {
  for (int i = 0; i < 3; ++i) out[i] = a[i];
}
/// Scaled by the reciprocal of the length (no test: libccd normalizes only non-zero vectors).
inline void normalize(double* d) {
  const double inverse = 1.0 / std::sqrt(dot(d, d));
  for (int i = 0; i < 3; ++i) d[i] *= inverse;
}
/// Every component within kEps of zero.
inline bool near_origin(const double* v) {
  return near_equal(v[0], 0) && near_equal(v[1], 0) && near_equal(v[2], 0);
}

/// A point of the Minkowski difference: v = a - b, a of shape A along the direction asked, b of
/// shape B against it.
struct Point {
  double v[3];
  double a[3];
  double b[3];
};

/// What the search found where the shapes overlap: the depth, the direction from A into B along
/// which it is measured (zero where the shapes only touch), and the point between them.
struct Answer {
  double depth;
  double dir[3];
  double pos[3];
};

/// The two shapes' support functions, each `(const double* dir, double* point)` in the world.
template <class SupportA, class SupportB>
class Search {
 public:
  Search(SupportA& a, SupportB& b, double tolerance, unsigned long max_iterations)
      : a_(a), b_(b), tolerance_(tolerance), max_iterations_(max_iterations) {}

  /// Whether the shapes overlap (then `answer` is set), centres a and b their interior points.
  bool penetration(const double* centre_a, const double* centre_b, Answer& answer) {
    switch (discover(centre_a, centre_b)) {
      case Discovery::kApart: return false;
      case Discovery::kOnV1: touch(answer); return true;
      case Discovery::kOnSegment: on_segment(answer); return true;
      case Discovery::kPortal: break;
    }
    if (!refine()) return false;
    penetrate(answer);
    return true;
  }

 private:
  enum class Discovery { kApart, kOnV1, kOnSegment, kPortal };

  /// The support point along dir: A's along dir, B's along -dir.
  void support(const double* dir, Point& p) {
    double d[3];
    copy(d, dir);
    a_(d, p.a);
    for (int i = 0; i < 3; ++i) d[i] *= -1.0;
    b_(d, p.b);
    subtract(p.v, p.a, p.b);
  }

  /// Whether a support point found along dir reaches past the origin (is not behind it).
  static bool reaches(const Point& p, const double* dir) { return not_negative(dot(p.v, dir)); }

  /// The normal of the portal's face v1 v2 v3, away from v0.
  void face_normal(double* dir) const {
    double e2[3], e3[3];
    subtract(e2, p_[2].v, p_[1].v);
    subtract(e3, p_[3].v, p_[1].v);
    cross(dir, e2, e3);
    normalize(dir);
  }

  /// The normal of the triangle v0 v1 v2 (the direction v3 is sought in).
  void wedge_normal(double* dir) const {
    double e1[3], e2[3];
    subtract(e1, p_[1].v, p_[0].v);
    subtract(e2, p_[2].v, p_[0].v);
    cross(dir, e1, e2);
    normalize(dir);
  }

  /// Whether the origin lies outside the plane through v0, x and y (on the side opposite to
  /// the cross product x × y), clearly, not within kEps.
  bool outside(const double* x, const double* y) const {
    double n[3];
    cross(n, x, y);
    const double side = dot(n, p_[0].v);
    return side < 0 && !near_zero(side);
  }

  Discovery discover(const double* centre_a, const double* centre_b) {
    Point& v0 = p_[0];
    copy(v0.a, centre_a);
    copy(v0.b, centre_b);
    subtract(v0.v, v0.a, v0.b);
    // the centres coincide: the shapes overlap, but the search needs a direction; moved a little
    if (near_origin(v0.v)) {
      v0.v[0] += kEps * 10.0;
      v0.v[1] += 0.0;  // as libccd adds the vector (kEps * 10, 0, 0): a zero's sign made +
      v0.v[2] += 0.0;
    }

    // v1: the support towards the origin
    double dir[3];
    copy(dir, v0.v);
    for (int i = 0; i < 3; ++i) dir[i] *= -1.0;
    normalize(dir);
    support(dir, p_[1]);
    if (behind(dot(p_[1].v, dir))) return Discovery::kApart;

    // v2: across the line v0 v1, unless the origin is on it
    cross(dir, v0.v, p_[1].v);
    if (near_zero(dot(dir, dir))) {
      return near_origin(p_[1].v) ? Discovery::kOnV1 : Discovery::kOnSegment;
    }
    normalize(dir);
    support(dir, p_[2]);
    if (behind(dot(p_[2].v, dir))) return Discovery::kApart;

    // v3 along the normal of v0 v1 v2 on the origin's side (v1 and v2 swapped to face outwards)
    wedge_normal(dir);
    if (dot(dir, v0.v) > 0) {
      const Point swapped = p_[1];
      p_[1] = p_[2];
      p_[2] = swapped;
      for (int i = 0; i < 3; ++i) dir[i] *= -1.0;
    }
    for (;;) {
      support(dir, p_[3]);
      if (behind(dot(p_[3].v, dir))) return Discovery::kApart;
      // the origin outside the side v0 v1 v3: v3 replaces v2; outside v0 v3 v2: v3 replaces v1;
      // else the cone through v1 v2 v3 holds it
      if (outside(p_[1].v, p_[3].v)) {
        p_[2] = p_[3];
      } else if (outside(p_[3].v, p_[2].v)) {
        p_[1] = p_[3];
      } else {
        return Discovery::kPortal;
      }
      wedge_normal(dir);
    }
  }

  /// The side of the portal's new tetrahedra (v0, v4 and a corner) the origin is on decides
  /// which corner v4 replaces, so that the portal keeps holding the origin's ray.
  void expand(const Point& v4) {
    double split[3];
    cross(split, v4.v, p_[0].v);
    if (dot(p_[1].v, split) > 0) {
      p_[dot(p_[2].v, split) > 0 ? 1 : 3] = v4;
    } else {
      p_[dot(p_[3].v, split) > 0 ? 2 : 1] = v4;
    }
  }

  /// Whether v4 (found along dir) moves the portal's face by no more than the tolerance: the
  /// smallest of its reach past each corner.
  bool within_tolerance(const Point& v4, const double* dir) const {
    const double d1 = dot(p_[1].v, dir), d2 = dot(p_[2].v, dir), d3 = dot(p_[3].v, dir);
    const double d4 = dot(v4.v, dir);
    const double gain = smaller(smaller(d4 - d1, d4 - d2), d4 - d3);
    return near_equal(gain, tolerance_) || gain < tolerance_;
  }

  /// Until the origin is behind the portal's face (overlap: true) or the difference ends first.
  bool refine() {
    double dir[3];
    Point v4;
    for (;;) {
      face_normal(dir);
      if (not_negative(dot(dir, p_[1].v))) return true;
      support(dir, v4);
      if (!reaches(v4, dir) || within_tolerance(v4, dir)) return false;
      expand(v4);
    }
  }

  void penetrate(Answer& answer) {
    double dir[3];
    Point v4;
    for (unsigned long iterations = 0;; ++iterations) {
      face_normal(dir);
      support(dir, v4);
      if (within_tolerance(v4, dir) || iterations > max_iterations_) break;
      expand(v4);
    }
    // the origin's nearest point on the face: its distance the depth, its direction the normal
    answer.depth = std::sqrt(nearest_on_triangle(p_[1].v, p_[2].v, p_[3].v, answer.dir));
    if (near_zero(answer.depth)) {
      for (double& x : answer.dir) x = 0;  // touching: no direction
    } else {
      normalize(answer.dir);
    }
    position(dir, answer.pos);
  }

  /// The origin on v1: touching, no depth, no direction, the point between v1's two points.
  void touch(Answer& answer) const {
    answer.depth = 0;
    for (double& x : answer.dir) x = 0;
    midpoint(p_[1], answer.pos);
  }

  /// The origin on segment v0 v1: v1 gives the depth and direction.
  void on_segment(Answer& answer) const {
    midpoint(p_[1], answer.pos);
    copy(answer.dir, p_[1].v);
    answer.depth = std::sqrt(dot(answer.dir, answer.dir));
    normalize(answer.dir);
  }

  static void midpoint(const Point& p, double* pos) {
    for (int i = 0; i < 3; ++i) {
      pos[i] = p.a[i] + p.b[i];
      pos[i] *= 0.5;
    }
  }

  /// The point of segment x0 b nearest the origin (`witness`), and its squared distance.
  static double nearest_on_segment(const double* x0, const double* b, double* witness) {
    double d[3];
    subtract(d, b, x0);
    double t = -1.0 * dot(x0, d);  // x0 - origin, as x0
    t /= dot(d, d);
    if (t < 0 || near_zero(t)) {
      copy(witness, x0);
    } else if (t > 1 || near_equal(t, 1)) {
      copy(witness, b);
    } else {
      for (int i = 0; i < 3; ++i) {
        witness[i] = d[i] * t;
        witness[i] += x0[i];
      }
    }
    return dot(witness, witness);
  }

  /// The point of triangle x0 b c nearest the origin (`witness`), and its squared distance: the
  /// plane's nearest point where it lies in the triangle (within kEps), else the nearest of the
  /// three edges'.
  static double nearest_on_triangle(const double* x0, const double* b, const double* c,
                                    double* witness) {
    double d1[3], d2[3];
    subtract(d1, b, x0);
    subtract(d2, c, x0);
    const double v = dot(d1, d1), w = dot(d2, d2);
    const double p = dot(x0, d1), q = dot(x0, d2), r = dot(d1, d2);
    const double det = w * v - r * r;
    double s = -1, t = -1;  // a triangle without area: its edges
    if (!near_zero(det)) {
      s = (q * r - w * p) / det;
      t = (-s * r - q) / w;
    }
    if (not_negative(s) && (near_equal(s, 1) || s < 1) && not_negative(t) &&
        (near_equal(t, 1) || t < 1) && (near_equal(t + s, 1) || t + s < 1)) {
      for (int i = 0; i < 3; ++i) {
        witness[i] = x0[i];
        witness[i] += d1[i] * s;
        witness[i] += d2[i] * t;
      }
      return dot(witness, witness);
    }
    double best = nearest_on_segment(x0, b, witness);
    double other[3];
    double next = nearest_on_segment(x0, c, other);
    if (next < best) {
      best = next;
      copy(witness, other);
    }
    next = nearest_on_segment(b, c, other);
    if (next < best) {
      best = next;
      copy(witness, other);
    }
    return best;
  }

  /// The point between the shapes: the origin's barycentric coordinates (six times the volumes)
  /// in the tetrahedron v0 v1 v2 v3, or, where they do not sum to a positive volume, in the face
  /// v1 v2 v3 (projected along its normal `dir`, the portal's last face_normal), applied to each
  /// shape's own points; their midpoint.
  void position(const double* dir, double* pos) const {
    double n[3], weight[4];
    cross(n, p_[1].v, p_[2].v);
    weight[0] = dot(n, p_[3].v);
    cross(n, p_[3].v, p_[2].v);
    weight[1] = dot(n, p_[0].v);
    cross(n, p_[0].v, p_[1].v);
    weight[2] = dot(n, p_[3].v);
    cross(n, p_[2].v, p_[1].v);
    weight[3] = dot(n, p_[0].v);
    double sum = weight[0] + weight[1] + weight[2] + weight[3];
    if (near_zero(sum) || sum < 0) {
      weight[0] = 0;
      cross(n, p_[2].v, p_[3].v);
      weight[1] = dot(n, dir);
      cross(n, p_[3].v, p_[1].v);
      weight[2] = dot(n, dir);
      cross(n, p_[1].v, p_[2].v);
      weight[3] = dot(n, dir);
      sum = weight[1] + weight[2] + weight[3];
    }
    const double inverse = 1.0 / sum;
    double on_a[3] = {0, 0, 0}, on_b[3] = {0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      for (int i = 0; i < 3; ++i) {
        on_a[i] += p_[k].a[i] * weight[k];
        on_b[i] += p_[k].b[i] * weight[k];
      }
    }
    for (int i = 0; i < 3; ++i) {
      pos[i] = on_a[i] * inverse;
      pos[i] += on_b[i] * inverse;
      pos[i] *= 0.5;
    }
  }

  SupportA& a_;
  SupportB& b_;
  double tolerance_;
  unsigned long max_iterations_;
  Point p_[4];  // the portal: v0 the interior point, v1 v2 v3 the face
};

}  // namespace lever::detail::mpr
