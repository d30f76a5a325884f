// Dual numbers a + b e (e^2 = 0): forward-mode differentiation of a computation written once on a
// scalar type. The transition room evaluates the narrow phase's closed-form pairs
// (transition/contact_geometry.cpp) and a tendon's wrap around a geom (smooth/wrap_path.hpp,
// transition/spatial_tendons.cpp) on them, with the geoms' and sites' poses moving along one
// direction: every branch decided on value(x), so the result is the exact derivative of the case
// the double evaluation took. Duals<K> carries K directions at once (the narrow phase along the
// dofs that move a geom pair).
#pragma once

#include <array>
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

// Dual numbers along K directions at once, a + sum_m b_m e_m (e_m e_n = 0): one evaluation gives
// the derivative along each of K motions, the value computed once. The same operations as Dual.
// Default-initialised it is left unset, as a double is (arrays of them are scratch, written before
// they are read); Duals{} is zero.
template <int K>
struct Duals {
  double v;                 // value
  std::array<double, K> d;  // derivative along each motion
  Duals() = default;
  explicit constexpr Duals(double value) : v(value), d{} {}  // a constant
};

template <int K>
Duals<K> combine(double value, const Duals<K>& a, double sa, const Duals<K>& b, double sb) {
  Duals<K> r(value);  // value, and sa a.d + sb b.d
  for (int m = 0; m < K; ++m) r.d[m] = sa * a.d[m] + sb * b.d[m];
  return r;
}
template <int K>
Duals<K> scaled(double value, const Duals<K>& a, double s) {
  Duals<K> r(value);  // value, and s a.d
  for (int m = 0; m < K; ++m) r.d[m] = s * a.d[m];
  return r;
}
template <int K>
Duals<K> operator+(const Duals<K>& a, const Duals<K>& b) {
  return combine(a.v + b.v, a, 1.0, b, 1.0);
}
template <int K>
Duals<K> operator+(double a, Duals<K> b) {
  b.v += a;
  return b;
}
template <int K>
Duals<K> operator+(Duals<K> a, double b) {
  a.v += b;
  return a;
}
template <int K>
Duals<K> operator-(const Duals<K>& a, const Duals<K>& b) {
  return combine(a.v - b.v, a, 1.0, b, -1.0);
}
template <int K>
Duals<K> operator-(Duals<K> a, double b) {
  a.v -= b;
  return a;
}
template <int K>
Duals<K> operator-(double a, const Duals<K>& b) {
  return scaled(a - b.v, b, -1.0);
}
template <int K>
Duals<K> operator-(const Duals<K>& a) {
  return scaled(-a.v, a, -1.0);
}
template <int K>
Duals<K> operator*(const Duals<K>& a, const Duals<K>& b) {
  return combine(a.v * b.v, a, b.v, b, a.v);
}
template <int K>
Duals<K> operator*(const Duals<K>& a, double s) {
  return scaled(a.v * s, a, s);
}
template <int K>
Duals<K> operator*(double s, const Duals<K>& a) {
  return scaled(s * a.v, a, s);
}
template <int K>
Duals<K> operator/(const Duals<K>& a, const Duals<K>& b) {
  const double inverse = 1 / b.v;
  return combine(a.v / b.v, a, inverse, b, -a.v * inverse * inverse);
}
template <int K>
Duals<K> operator/(const Duals<K>& a, double s) {
  return scaled(a.v / s, a, 1 / s);
}
template <int K>
Duals<K> operator/(double s, const Duals<K>& b) {
  return scaled(s / b.v, b, -s / (b.v * b.v));
}
template <int K>
Duals<K>& operator+=(Duals<K>& a, const Duals<K>& b) {
  return a = a + b;
}
template <int K>
Duals<K>& operator-=(Duals<K>& a, const Duals<K>& b) {
  return a = a - b;
}
template <int K>
Duals<K>& operator*=(Duals<K>& a, const Duals<K>& b) {
  return a = a * b;
}
template <int K>
Duals<K>& operator*=(Duals<K>& a, double s) {
  return a = a * s;
}
template <int K>
Duals<K> sqrt(const Duals<K>& a) {
  const double r = std::sqrt(a.v);
  return scaled(r, a, r > 0 ? 1 / (2 * r) : 0.0);
}
template <int K>
Duals<K> sin(const Duals<K>& a) {
  return scaled(std::sin(a.v), a, std::cos(a.v));
}
template <int K>
Duals<K> cos(const Duals<K>& a) {
  return scaled(std::cos(a.v), a, -std::sin(a.v));
}
template <int K>
Duals<K> asin(const Duals<K>& a) {
  return scaled(std::asin(a.v), a, 1 / std::sqrt(1 - a.v * a.v));
}
template <int K>
Duals<K> acos(const Duals<K>& a) {
  return scaled(std::acos(a.v), a, -1 / std::sqrt(1 - a.v * a.v));
}
template <int K>
double value(const Duals<K>& a) {
  return a.v;
}
template <int K>
Duals<K> magnitude(const Duals<K>& a) {
  return a.v < 0 ? -a : a;
}

}  // namespace lever::detail
