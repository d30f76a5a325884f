// A spatial tendon wrapped around a sphere or a cylinder (MuJoCo 2.2.2's mju_wrap and its two
// planar solvers, engine_util_misc.c).
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
#include "basics/basics.hpp"
#include "smooth/smooth.hpp"

#include <algorithm>
#include <cmath>

namespace lever::detail {

namespace {

// ---- the planar problem --------------------------------------------------------------------

double dot2(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1]; }

// a 2D vector scaled to unit length (the x axis when it is too short to have a direction)
void normalize2(double* v) {
  const double norm = std::sqrt(dot2(v, v));
  if (norm < kMinVal) {
    v[0] = 1.0;
    v[1] = 0.0;
    return;
  }
  const double inverse = 1.0 / norm;
  v[0] *= inverse;
  v[1] *= inverse;
}

// Whether the segments a0-a1 and b0-b1 of the plane meet (parallel segments never do).
bool segments_meet(const double* a0, const double* a1, const double* b0, const double* b1) {
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
double arc_length(const double* t0, const double* t1, int pair, double r) {
  double u0[2] = {t0[0], t0[1]};
  double u1[2] = {t1[0], t1[1]};
  normalize2(u0);
  normalize2(u1);
  double angle = std::acos(dot2(u0, u1));
  const double turn = t0[1] * t1[0] - t0[0] * t1[1];
  if ((turn > 0 && pair == 1) || (turn < 0 && pair == 0)) angle = 2 * kPi - angle;
  return r * angle;
}

// The wrap around a circle of radius r at the origin, from d[0..1] to d[2..3]: the two tangent
// points in tangent[0..3] and the arc's length, or -1 when the straight segment clears the circle
// (on the side site's side, when there is one: `side` the side site projected onto the circle) or
// the path cannot wrap (an end inside the circle, the ends on top of each other).
double wrap_circle(const double* d, const double* side, double r, double* tangent) {
  const double sq_len0 = d[0] * d[0] + d[1] * d[1];
  const double sq_len1 = d[2] * d[2] + d[3] * d[3];
  const double sq_r = r * r;
  if (sq_len0 < sq_r || sq_len1 < sq_r || r < kMinVal) return -1;
  const double dif[2] = {d[2] - d[0], d[3] - d[1]};
  const double sq_dif = dif[0] * dif[0] + dif[1] * dif[1];
  if (sq_dif < kMinVal) return -1;

  // the segment's point nearest the centre: outside the circle (and, with a side site, on the
  // side site's side of the centre) means the tendon runs straight
  double along = -(dif[0] * d[0] + dif[1] * d[1]) / sq_dif;
  along = along < 0 ? 0 : along > 1 ? 1 : along;
  const double nearest[2] = {along * dif[0] + d[0], along * dif[1] + d[1]};
  if (nearest[0] * nearest[0] + nearest[1] * nearest[1] > sq_r &&
      (side == nullptr || dot2(side, nearest) >= 0)) {
    return -1;
  }

  // the two pairs of tangent points, one going each way round; the better is the one nearer the
  // side site, or without one the one with the shorter chord; a pair whose tangents cross loses
  double pairs[2][4];
  double score[2];
  for (int pair = 0; pair < 2; ++pair) {
    const double root0 = std::sqrt(sq_len0 - sq_r);
    const double root1 = std::sqrt(sq_len1 - sq_r);
    const double sign = pair == 0 ? 1.0 : -1.0;
    double* t = pairs[pair];
    t[0] = (d[0] * sq_r + sign * r * d[1] * root0) / sq_len0;
    t[1] = (d[1] * sq_r - sign * r * d[0] * root0) / sq_len0;
    t[2] = (d[2] * sq_r - sign * r * d[3] * root1) / sq_len1;
    t[3] = (d[3] * sq_r + sign * r * d[2] * root1) / sq_len1;
    if (side != nullptr) {
      double mid[2] = {t[0] + t[2], t[1] + t[3]};
      normalize2(mid);
      score[pair] = dot2(mid, side);
    } else {
      const double chord[2] = {t[0] - t[2], t[1] - t[3]};
      score[pair] = -dot2(chord, chord);
    }
    if (segments_meet(d, t, d + 2, t + 2)) score[pair] = -10000;
  }
  const int best = score[0] > score[1] ? 0 : 1;
  for (int c = 0; c < 4; ++c) tangent[c] = pairs[best][c];
  if (segments_meet(d, tangent, d + 2, tangent + 2)) return -1;
  return arc_length(pairs[best], pairs[best] + 2, best, r);
}

// The wrap through a circle of radius r (a side site inside it): the one point of the circle
// where the path d[0..1] -> point -> d[2..3] makes equal angles with the radius (the shortest such
// path), in tangent[0..1] and again in tangent[2..3]; 0 when it wraps (the arc has no length), -1
// when the straight segment already meets the circle or an end is inside it. Should Newton's
// method fail, the point is the direction of the ends' midpoint, as in MuJoCo.
double wrap_through_circle(const double* d, double r, double* tangent) {
  constexpr int kMaxIterations = 20;
  constexpr double kStart = 1 - 1e-7;
  constexpr double kTolerance = 1e-6;

  const double len0 = std::sqrt(dot2(d, d));
  const double len1 = std::sqrt(dot2(d + 2, d + 2));
  if (len0 <= r || len1 <= r || r < kMinVal || len0 < kMinVal || len1 < kMinVal) return -1;
  const double dif[2] = {d[2] - d[0], d[3] - d[1]};
  const double sq_dif = dif[0] * dif[0] + dif[1] * dif[1];
  if (sq_dif > kMinVal) {
    const double along = -(dif[0] * d[0] + dif[1] * d[1]) / sq_dif;
    if (along > 0 && along < 1) {
      const double nearest[2] = {d[0] + dif[0] * along, d[1] + dif[1] * along};
      if (std::sqrt(dot2(nearest, nearest)) <= r) return -1;
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
  const double A = r / len0;
  const double B = r / len1;
  const double cos_g = (len0 * len0 + len1 * len1 - sq_dif) / (2 * len0 * len1);
  if (cos_g < -1 + kMinVal) return -1;
  if (cos_g > 1 - kMinVal) return 0;
  const double G = std::acos(cos_g);
  auto condition = [&](double z) { return std::asin(A * z) + std::asin(B * z) - 2 * std::asin(z) + G; };
  double z = kStart;
  double f = condition(z);
  if (f > 0) return 0;  // the start is on the wrong side of the root
  int iteration = 0;
  for (; iteration < kMaxIterations && std::abs(f) > kTolerance; ++iteration) {
    const double slope = A / std::max(kMinVal, std::sqrt(1 - z * z * A * A)) +
                         B / std::max(kMinVal, std::sqrt(1 - z * z * B * B)) -
                         2 / std::max(kMinVal, std::sqrt(1 - z * z));
    if (slope > -kMinVal) return 0;  // the condition must fall with z
    const double next = z - f / slope;
    if (next > z) return 0;  // and Newton must move left
    z = next;
    f = condition(z);
    if (f > kTolerance) return 0;  // overshot
  }
  if (iteration >= kMaxIterations) return 0;

  // the point: end 0's direction (or end 1's) turned by the angle the root gives
  double from[2];
  double angle;
  if (d[0] * d[3] - d[1] * d[2] > 0) {
    from[0] = d[0];
    from[1] = d[1];
    angle = std::asin(z) - std::asin(A * z);
  } else {
    from[0] = d[2];
    from[1] = d[3];
    angle = std::asin(z) - std::asin(B * z);
  }
  normalize2(from);
  tangent[0] = r * (std::cos(angle) * from[0] - std::sin(angle) * from[1]);
  tangent[1] = r * (std::sin(angle) * from[0] + std::cos(angle) * from[1]);
  tangent[2] = tangent[0];
  tangent[3] = tangent[1];
  return 0;
}

// ---- 3D helpers, in MuJoCo's order of operations ------------------------------------------------

double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void cross3(const double* a, const double* b, double* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

// scaled to unit length (the x axis when too short); returns the length it had
double normalize3(double* v) {
  const double norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (norm < kMinVal) {
    v[0] = 1.0;
    v[1] = v[2] = 0.0;
  } else {
    const double inverse = 1.0 / norm;
    v[0] *= inverse;
    v[1] *= inverse;
    v[2] *= inverse;
  }
  return norm;
}

// a world point in the geom's frame: R^T (x - centre)
void to_local(const Eigen::Vector3d& x, const Eigen::Vector3d& centre, const Mat3& R, double* out) {
  const double v[3] = {x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]};
  for (int i = 0; i < 3; ++i) out[i] = R(0, i) * v[0] + R(1, i) * v[1] + R(2, i) * v[2];
}

}  // namespace

double wrap_around_geom(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1,
                        const Eigen::Vector3d& centre, const Mat3& R, double radius,
                        bool cylinder, const Eigen::Vector3d* side, Eigen::Vector3d& tangent0,
                        Eigen::Vector3d& tangent1) {
  double p[2][3];
  to_local(x0, centre, R, p[0]);
  to_local(x1, centre, R, p[1]);
  if (std::sqrt(dot3(p[0], p[0])) < kMinVal || std::sqrt(dot3(p[1], p[1])) < kMinVal) return -1;

  // the plane of the circle: axes u, v
  double u[3], v[3];
  if (!cylinder) {
    // a sphere: u towards x0, the plane the one through the centre, x0 and x1
    for (int c = 0; c < 3; ++c) u[c] = p[0][c];
    normalize3(u);
    double normal[3];
    cross3(p[0], p[1], normal);
    if (normalize3(normal) < kMinVal) {
      // x0, the centre and x1 on one line: any plane through them; MuJoCo's choice, a normal
      // away from u's largest component
      int largest = 0;
      if (std::abs(u[1]) > std::abs(u[0]) && std::abs(u[1]) > std::abs(u[2])) largest = 1;
      if (std::abs(u[2]) > std::abs(u[0]) && std::abs(u[2]) > std::abs(u[1])) largest = 2;
      double other[3] = {1.0, 1.0, 1.0};
      other[largest] = 0.0;
      cross3(u, other, normal);
      normalize3(normal);
    }
    cross3(normal, u, v);
    normalize3(v);
  } else {
    // a cylinder: its cross-section, the geom's x and y
    u[0] = 1.0, u[1] = 0.0, u[2] = 0.0;
    v[0] = 0.0, v[1] = 1.0, v[2] = 0.0;
  }

  const double d[4] = {dot3(p[0], u), dot3(p[0], v), dot3(p[1], u), dot3(p[1], v)};
  double side_2d[2] = {0.0, 0.0};
  if (side != nullptr) {
    double s[3];
    to_local(*side, centre, R, s);
    side_2d[0] = dot3(s, u);
    side_2d[1] = dot3(s, v);
    // onto the circle when outside it; (0, 0) when inside: the tendon goes through
    if (std::sqrt(dot2(side_2d, side_2d)) >= radius) {
      normalize2(side_2d);
      side_2d[0] *= radius;
      side_2d[1] *= radius;
    } else {
      side_2d[0] = side_2d[1] = 0.0;
    }
  }

  double tangent_2d[4];
  double length;
  if (side != nullptr && side_2d[0] == 0 && side_2d[1] == 0) {
    length = wrap_through_circle(d, radius, tangent_2d);
  } else {
    length = wrap_circle(d, side != nullptr ? side_2d : nullptr, radius, tangent_2d);
  }
  if (length < 0) return -1;

  // the tangent points in the geom's frame
  double local[2][3];
  for (int i = 0; i < 2; ++i) {
    for (int c = 0; c < 3; ++c) local[i][c] = u[c] * tangent_2d[2 * i];
    for (int c = 0; c < 3; ++c) local[i][c] += v[c] * tangent_2d[2 * i + 1];
  }
  if (cylinder) {
    // the helix: the height changes along the path in proportion to the path's planar length
    const double straight0 = std::sqrt((p[0][0] - local[0][0]) * (p[0][0] - local[0][0]) +
                                       (p[0][1] - local[0][1]) * (p[0][1] - local[0][1]));
    const double straight1 = std::sqrt((p[1][0] - local[1][0]) * (p[1][0] - local[1][0]) +
                                       (p[1][1] - local[1][1]) * (p[1][1] - local[1][1]));
    const double planar = straight0 + length + straight1;
    local[0][2] = p[0][2] + (p[1][2] - p[0][2]) * straight0 / planar;
    local[1][2] = p[0][2] + (p[1][2] - p[0][2]) * (straight0 + length) / planar;
    const double rise = std::abs(local[1][2] - local[0][2]);
    length = std::sqrt(length * length + rise * rise);
  }

  // back to the world
  Eigen::Vector3d* const out[2] = {&tangent0, &tangent1};
  for (int i = 0; i < 2; ++i) {
    for (int r = 0; r < 3; ++r) {
      (*out[i])[r] = R(r, 0) * local[i][0] + R(r, 1) * local[i][1] + R(r, 2) * local[i][2];
    }
    for (int r = 0; r < 3; ++r) (*out[i])[r] += centre[r];
  }
  return length;
}

}  // namespace lever::detail
