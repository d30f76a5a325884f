// A spatial tendon wrapped around a sphere or a cylinder (MuJoCo 2.2.2's mju_wrap and its two
// planar solvers, engine_util_misc.c), written once on a scalar type (below): wrap.cpp evaluates
// it on double, the transition room on dual numbers.
//
// Between two sites x0 and x1 the tendon runs straight unless the straight segment would pass
// through the geom; then it runs along a tangent from x0 to the geom, an arc on the surface and a
// tangent to x1. Both geoms reduce to a circle in a plane through the geom's centre: a sphere's
// great circle in the plane of the centre and the two sites, a cylinder's cross-section (the arc
// then rises along the axis in proportion to the path's length: a helix).
//
// A side site chooses the side the tendon passes on. When it lies inside the circle, the tendon
// is taken to pass through the geom (MuJoCo's "inside" wrap): the point on the circle where the
// path from x0 to x1 through it is shortest, found by Newton's method on the angle condition.
//
// The arithmetic keeps MuJoCo's order of operations where a branch depends on it (which tangent
// pair is chosen, whether the segment crosses the circle), so that both engines take the same
// branch on the same state.
#pragma once

#include <algorithm>
#include <cmath>

#include "basics/basics.hpp"

// Written once on a scalar type S (double, or the transition room's dual numbers, basics/dual.hpp,
// which differentiate the wrap along a motion of the sites and the geom): S needs +, -, *, / with
// S and double, compound assignment, and sqrt, acos, asin, cos, sin, value(S) -> double and
// magnitude(S) = |S| by argument-dependent lookup (for double: std's and the two below). Every
// branch is decided on value(x), so both scalars take the same branch on the same state.
namespace lever::detail::wrap_path {

inline double value(double x) { return x; }
inline double magnitude(double x) { return std::abs(x); }

// ---- the planar problem --------------------------------------------------------------------

template <class S>
S dot2(const S* a, const S* b) { return a[0] * b[0] + a[1] * b[1]; }

// a 2D vector scaled to unit length (the x axis when it is too short to have a direction)
template <class S>
void normalize2(S* v) {
  using std::sqrt;
  const S norm = sqrt(dot2(v, v));
  if (value(norm) < kMinVal) {
    v[0] = S(1.0);
    v[1] = S(0.0);
    return;
  }
  const S inverse = 1.0 / norm;
  v[0] *= inverse;
  v[1] *= inverse;
}

// Whether the segments a0-a1 and b0-b1 of the plane meet (parallel segments never do): decided on
// the values.
template <class S>
bool segments_meet(const S* A0, const S* A1, const S* B0, const S* B1) {
  const double a0[2] = {value(A0[0]), value(A0[1])}, a1[2] = {value(A1[0]), value(A1[1])};
  const double b0[2] = {value(B0[0]), value(B0[1])}, b1[2] = {value(B1[0]), value(B1[1])};
  const double det = (b1[1] - b0[1]) * (a1[0] - a0[0]) - (b1[0] - b0[0]) * (a1[1] - a0[1]);
  if (std::abs(det) < kMinVal) return false;
  // where the crossing lies along each segment, 0 at its start and 1 at its end
  const double along_a = ((b1[0] - b0[0]) * (a0[1] - b0[1]) - (b1[1] - b0[1]) * (a0[0] - b0[0])) / det;
  const double along_b = ((a1[0] - a0[0]) * (a0[1] - b0[1]) - (a1[1] - a0[1]) * (a0[0] - b0[0])) / det;
  return along_a >= 0 && along_a <= 1 && along_b >= 0 && along_b <= 1;
}

// The length of the arc of radius r from tangent point t0 to t1, going the way tangent pair
// `pair` (0 or 1) turns: the angle between them, or its complement to a full turn when the pair
// goes round the long way.
template <class S>
S arc_length(const S* t0, const S* t1, int pair, double r) {
  using std::acos;
  S u0[2] = {t0[0], t0[1]};
  S u1[2] = {t1[0], t1[1]};
  normalize2(u0);
  normalize2(u1);
  S angle = acos(dot2(u0, u1));
  const double turn = value(t0[1] * t1[0] - t0[0] * t1[1]);
  if ((turn > 0 && pair == 1) || (turn < 0 && pair == 0)) angle = 2 * kPi - angle;
  return r * angle;
}

// The wrap around a circle of radius r at the origin, from d[0..1] to d[2..3]: the two tangent
// points in tangent[0..3] and the arc's length, or -1 when the straight segment clears the circle
// (on the side site's side, when there is one: `side` the side site projected onto the circle) or
// the path cannot wrap (an end inside the circle, the ends on top of each other).
template <class S>
S wrap_circle(const S* d, const S* side, double r, S* tangent) {
  using std::sqrt;
  const S sq_len0 = d[0] * d[0] + d[1] * d[1];
  const S sq_len1 = d[2] * d[2] + d[3] * d[3];
  const double sq_r = r * r;
  if (value(sq_len0) < sq_r || value(sq_len1) < sq_r || r < kMinVal) return S(-1.0);
  const S dif[2] = {d[2] - d[0], d[3] - d[1]};
  const S sq_dif = dif[0] * dif[0] + dif[1] * dif[1];
  if (value(sq_dif) < kMinVal) return S(-1.0);

  // the segment's point nearest the centre: outside the circle (and, with a side site, on the
  // side site's side of the centre) means the tendon runs straight
  S along = -(dif[0] * d[0] + dif[1] * d[1]) / sq_dif;
  along = value(along) < 0 ? S(0.0) : value(along) > 1 ? S(1.0) : along;
  const S nearest[2] = {along * dif[0] + d[0], along * dif[1] + d[1]};
  if (value(nearest[0] * nearest[0] + nearest[1] * nearest[1]) > sq_r &&
      (side == nullptr || value(dot2(side, nearest)) >= 0)) {
    return S(-1.0);
  }

  // the two pairs of tangent points, one going each way round; the better is the one nearer the
  // side site, or without one the one with the shorter chord; a pair whose tangents cross loses
  S pairs[2][4];
  double score[2];
  for (int pair = 0; pair < 2; ++pair) {
    const S root0 = sqrt(sq_len0 - sq_r);
    const S root1 = sqrt(sq_len1 - sq_r);
    const double sign = pair == 0 ? 1.0 : -1.0;
    S* t = pairs[pair];
    t[0] = (d[0] * sq_r + sign * r * d[1] * root0) / sq_len0;
    t[1] = (d[1] * sq_r - sign * r * d[0] * root0) / sq_len0;
    t[2] = (d[2] * sq_r - sign * r * d[3] * root1) / sq_len1;
    t[3] = (d[3] * sq_r + sign * r * d[2] * root1) / sq_len1;
    if (side != nullptr) {
      S mid[2] = {t[0] + t[2], t[1] + t[3]};
      normalize2(mid);
      score[pair] = value(dot2(mid, side));
    } else {
      const S chord[2] = {t[0] - t[2], t[1] - t[3]};
      score[pair] = -value(dot2(chord, chord));
    }
    if (segments_meet(d, t, d + 2, t + 2)) score[pair] = -10000;
  }
  const int best = score[0] > score[1] ? 0 : 1;
  for (int c = 0; c < 4; ++c) tangent[c] = pairs[best][c];
  if (segments_meet(d, tangent, d + 2, tangent + 2)) return S(-1.0);
  return arc_length(pairs[best], pairs[best] + 2, best, r);
}

// at least lo (std::max's answer for double)
template <class S>
S at_least(double lo, S x) {
  return value(x) < lo ? S(lo) : x;
}

// The wrap through a circle of radius r (a side site inside it): the one point of the circle
// where the path d[0..1] -> point -> d[2..3] makes equal angles with the radius (the shortest such
// path), in tangent[0..1] and again in tangent[2..3]; 0 when it wraps (the arc has no length), -1
// when the straight segment already meets the circle or an end is inside it. Should Newton's
// method fail, the point is the direction of the ends' midpoint, as in MuJoCo. (On dual numbers
// the derivative is that of the iterations taken, their number held.)
template <class S>
S wrap_through_circle(const S* d, double r, S* tangent) {
  using std::acos;
  using std::asin;
  using std::cos;
  using std::sin;
  using std::sqrt;
  constexpr int kMaxIterations = 20;
  constexpr double kStart = 1 - 1e-7;
  constexpr double kTolerance = 1e-6;

  const S len0 = sqrt(dot2(d, d));
  const S len1 = sqrt(dot2(d + 2, d + 2));
  if (value(len0) <= r || value(len1) <= r || r < kMinVal || value(len0) < kMinVal ||
      value(len1) < kMinVal) {
    return S(-1.0);
  }
  const S dif[2] = {d[2] - d[0], d[3] - d[1]};
  const S sq_dif = dif[0] * dif[0] + dif[1] * dif[1];
  if (value(sq_dif) > kMinVal) {
    const S along = -(dif[0] * d[0] + dif[1] * d[1]) / sq_dif;
    if (value(along) > 0 && value(along) < 1) {
      const S nearest[2] = {d[0] + dif[0] * along, d[1] + dif[1] * along};
      if (value(sqrt(dot2(nearest, nearest))) <= r) return S(-1.0);
    }
  }

  // the fallback: the midpoint's direction on the circle
  tangent[0] = 0.5 * (d[0] + d[2]);
  tangent[1] = 0.5 * (d[1] + d[3]);
  normalize2(tangent);
  tangent[0] *= r;
  tangent[1] *= r;
  tangent[2] = tangent[0];
  tangent[3] = tangent[1];

  // with z = sin of the angle at the point, solve asin(A z) + asin(B z) - 2 asin(z) + G = 0
  const S A = r / len0;
  const S B = r / len1;
  const S cos_g = (len0 * len0 + len1 * len1 - sq_dif) / (2 * len0 * len1);
  if (value(cos_g) < -1 + kMinVal) return S(-1.0);
  if (value(cos_g) > 1 - kMinVal) return S(0.0);
  const S G = acos(cos_g);
  auto condition = [&](const S& z) { return asin(A * z) + asin(B * z) - 2 * asin(z) + G; };
  S z(kStart);
  S f = condition(z);
  if (value(f) > 0) return S(0.0);  // the start is on the wrong side of the root
  int iteration = 0;
  for (; iteration < kMaxIterations && std::abs(value(f)) > kTolerance; ++iteration) {
    const S slope = A / at_least(kMinVal, sqrt(1 - z * z * A * A)) +
                    B / at_least(kMinVal, sqrt(1 - z * z * B * B)) -
                    2 / at_least(kMinVal, sqrt(1 - z * z));
    if (value(slope) > -kMinVal) return S(0.0);  // the condition must fall with z
    const S next = z - f / slope;
    if (value(next) > value(z)) return S(0.0);  // and Newton must move left
    z = next;
    f = condition(z);
    if (value(f) > kTolerance) return S(0.0);  // overshot
  }
  if (iteration >= kMaxIterations) return S(0.0);

  // the point: end 0's direction (or end 1's) turned by the angle the root gives
  S from[2];
  S angle;
  if (value(d[0] * d[3] - d[1] * d[2]) > 0) {
    from[0] = d[0];
    from[1] = d[1];
    angle = asin(z) - asin(A * z);
  } else {
    from[0] = d[2];
    from[1] = d[3];
    angle = asin(z) - asin(B * z);
  }
  normalize2(from);
  tangent[0] = r * (cos(angle) * from[0] - sin(angle) * from[1]);
  tangent[1] = r * (sin(angle) * from[0] + cos(angle) * from[1]);
  tangent[2] = tangent[0];
  tangent[3] = tangent[1];
  return S(0.0);
}

// ---- 3D helpers, in MuJoCo's order of operations ------------------------------------------------

template <class S>
S dot3(const S* a, const S* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

template <class S>
void cross3(const S* a, const S* b, S* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

// scaled to unit length (the x axis when too short); returns the length it had
template <class S>
S normalize3(S* v) {
  using std::sqrt;
  const S norm = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (value(norm) < kMinVal) {
    v[0] = S(1.0);
    v[1] = v[2] = S(0.0);
  } else {
    const S inverse = 1.0 / norm;
    v[0] *= inverse;
    v[1] *= inverse;
    v[2] *= inverse;
  }
  return norm;
}

// a world point in the geom's frame: R^T (x - centre), R[r][c] the frame's matrix
template <class S>
void to_local(const S* x, const S* centre, const S (*R)[3], S* out) {
  const S v[3] = {x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]};
  for (int i = 0; i < 3; ++i) out[i] = R[0][i] * v[0] + R[1][i] * v[1] + R[2][i] * v[2];
}

/// The wrap of the path x0 -> x1 around a sphere (great circle) or a cylinder (helix) of `radius`
/// at `centre` with frame R (R[r][c]): -1 when the path runs straight, else the wrapped part's
/// length (the arc, or the helix) with the tangent points in tangent0 and tangent1 (world); `side`
/// the side site's position or nullptr.
template <class S>
S wrap(const S* x0, const S* x1, const S* centre, const S (*R)[3], double radius, bool cylinder,
       const S* side, S* tangent0, S* tangent1) {
  using std::sqrt;
  S p[2][3];
  to_local(x0, centre, R, p[0]);
  to_local(x1, centre, R, p[1]);
  if (value(sqrt(dot3(p[0], p[0]))) < kMinVal || value(sqrt(dot3(p[1], p[1]))) < kMinVal) {
    return S(-1.0);
  }

  // the plane of the circle: axes u, v
  S u[3], v[3];
  if (!cylinder) {
    // a sphere: u towards x0, the plane the one through the centre, x0 and x1
    for (int c = 0; c < 3; ++c) u[c] = p[0][c];
    normalize3(u);
    S normal[3];
    cross3(p[0], p[1], normal);
    if (value(normalize3(normal)) < kMinVal) {
      // x0, the centre and x1 on one line: any plane through them; MuJoCo's choice, a normal
      // away from u's largest component
      const double a[3] = {std::abs(value(u[0])), std::abs(value(u[1])), std::abs(value(u[2]))};
      int largest = 0;
      if (a[1] > a[0] && a[1] > a[2]) largest = 1;
      if (a[2] > a[0] && a[2] > a[1]) largest = 2;
      S other[3] = {S(1.0), S(1.0), S(1.0)};
      other[largest] = S(0.0);
      cross3(u, other, normal);
      normalize3(normal);
    }
    cross3(normal, u, v);
    normalize3(v);
  } else {
    // a cylinder: its cross-section, the geom's x and y
    u[0] = S(1.0), u[1] = S(0.0), u[2] = S(0.0);
    v[0] = S(0.0), v[1] = S(1.0), v[2] = S(0.0);
  }

  const S d[4] = {dot3(p[0], u), dot3(p[0], v), dot3(p[1], u), dot3(p[1], v)};
  S side_2d[2] = {S(0.0), S(0.0)};
  if (side != nullptr) {
    S s[3];
    to_local(side, centre, R, s);
    side_2d[0] = dot3(s, u);
    side_2d[1] = dot3(s, v);
    // onto the circle when outside it; (0, 0) when inside: the tendon goes through
    if (value(sqrt(dot2(side_2d, side_2d))) >= radius) {
      normalize2(side_2d);
      side_2d[0] *= radius;
      side_2d[1] *= radius;
    } else {
      side_2d[0] = side_2d[1] = S(0.0);
    }
  }

  S tangent_2d[4];
  S length;
  if (side != nullptr && value(side_2d[0]) == 0 && value(side_2d[1]) == 0) {
    length = wrap_through_circle(d, radius, tangent_2d);
  } else {
    length = wrap_circle(d, side != nullptr ? side_2d : nullptr, radius, tangent_2d);
  }
  if (value(length) < 0) return S(-1.0);

  // the tangent points in the geom's frame
  S local[2][3];
  for (int i = 0; i < 2; ++i) {
    for (int c = 0; c < 3; ++c) local[i][c] = u[c] * tangent_2d[2 * i];
    for (int c = 0; c < 3; ++c) local[i][c] += v[c] * tangent_2d[2 * i + 1];
  }
  if (cylinder) {
    // the helix: the height changes along the path in proportion to the path's planar length
    const S straight0 = sqrt((p[0][0] - local[0][0]) * (p[0][0] - local[0][0]) +
                             (p[0][1] - local[0][1]) * (p[0][1] - local[0][1]));
    const S straight1 = sqrt((p[1][0] - local[1][0]) * (p[1][0] - local[1][0]) +
                             (p[1][1] - local[1][1]) * (p[1][1] - local[1][1]));
    const S planar = straight0 + length + straight1;
    local[0][2] = p[0][2] + (p[1][2] - p[0][2]) * straight0 / planar;
    local[1][2] = p[0][2] + (p[1][2] - p[0][2]) * (straight0 + length) / planar;
    const S rise = magnitude(local[1][2] - local[0][2]);
    length = sqrt(length * length + rise * rise);
  }

  // back to the world
  S* const out[2] = {tangent0, tangent1};
  for (int i = 0; i < 2; ++i) {
    for (int r = 0; r < 3; ++r) {
      out[i][r] = R[r][0] * local[i][0] + R[r][1] * local[i][1] + R[r][2] * local[i][2];
    }
    for (int r = 0; r < 3; ++r) out[i][r] += centre[r];
  }
  return length;
}

}  // namespace lever::detail::wrap_path
