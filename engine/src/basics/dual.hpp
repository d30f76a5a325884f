// Dual numbers a + b e (e^2 = 0): forward-mode differentiation of a computation written once on a
// scalar type. The transition room evaluates the narrow phase's closed-form pairs
// (transition/contact_geometry.cpp) and a tendon's wrap around a geom (smooth/wrap_path.hpp,
// transition/spatial_tendons.cpp) on them, with the geoms' and sites' poses moving along one
// direction: every branch decided on value(x), so the result is the exact derivative of the case
// the double evaluation took.
#pragma once

#include <cmath>

namespace lever::detail {

struct Dual {
  double v = 0;  // value
  double d = 0;  // derivative along the motion
  Dual() = default;
  constexpr Dual(double value, double derivative) : v(value), d(derivative) {}
  explicit constexpr Dual(double value) : v(value) {}  // a constant
};

inline Dual operator+(Dual a, Dual b) { return {a.v + b.v, a.d + b.d}; }
inline Dual operator+(double a, Dual b) { return {a + b.v, b.d}; }
inline Dual operator+(Dual a, double b) { return {a.v + b, a.d}; }
inline Dual operator-(Dual a, Dual b) { return {a.v - b.v, a.d - b.d}; }
inline Dual operator-(Dual a, double b) { return {a.v - b, a.d}; }
inline Dual operator-(double a, Dual b) { return {a - b.v, -b.d}; }
inline Dual operator-(Dual a) { return {-a.v, -a.d}; }
inline Dual operator*(Dual a, Dual b) { return {a.v * b.v, a.d * b.v + a.v * b.d}; }
inline Dual operator*(Dual a, double s) { return {a.v * s, a.d * s}; }
inline Dual operator*(double s, Dual a) { return {s * a.v, s * a.d}; }
inline Dual operator/(Dual a, Dual b) { return {a.v / b.v, (a.d * b.v - a.v * b.d) / (b.v * b.v)}; }
inline Dual operator/(Dual a, double s) { return {a.v / s, a.d / s}; }
inline Dual operator/(double s, Dual b) { return {s / b.v, -s * b.d / (b.v * b.v)}; }
inline Dual& operator+=(Dual& a, Dual b) { return a = a + b; }
inline Dual& operator-=(Dual& a, Dual b) { return a = a - b; }
inline Dual& operator*=(Dual& a, Dual b) { return a = a * b; }
inline Dual& operator*=(Dual& a, double s) { return a = a * s; }
inline Dual sqrt(Dual a) {
  const double r = std::sqrt(a.v);
  return {r, r > 0 ? a.d / (2 * r) : 0.0};
}
inline Dual sin(Dual a) { return {std::sin(a.v), std::cos(a.v) * a.d}; }
inline Dual cos(Dual a) { return {std::cos(a.v), -std::sin(a.v) * a.d}; }
inline Dual asin(Dual a) { return {std::asin(a.v), a.d / std::sqrt(1 - a.v * a.v)}; }
inline Dual acos(Dual a) { return {std::acos(a.v), -a.d / std::sqrt(1 - a.v * a.v)}; }
inline double value(Dual a) { return a.v; }
inline Dual magnitude(Dual a) { return a.v < 0 ? -a : a; }

}  // namespace lever::detail
