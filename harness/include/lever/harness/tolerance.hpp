// The one agreement bound of lever's differential tests, and helpers to report against it.
//
//   |ours - mujoco| <= 1e-12 * max(1, |mujoco|)
//
// applied per quantity and state: for a quantity with several elements (qacc, M, xpos, the limit
// rows' forces, ...), |mujoco| is the quantity's magnitude, its largest element in that state.
// Two engines that round differently cannot agree closer than the rounding error of the
// computation itself, and for accelerations obtained through M^-1 that error is set by the largest
// acceleration and M's conditioning, not by each element: MuJoCo disagrees with itself by more than
// 1e-12 of a small element of a large qacc when the same model is merely moved in space (see
// docs/agreement.md). The element-wise ratio is still measured and reported beside this one.
//
// The bound is never loosened locally: a test that misses it has found a term that differs.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace lever::test {

constexpr double kAgreement = 1e-12;

/// The allowed difference for a quantity of the given magnitude.
inline double allowed(double magnitude) { return kAgreement * std::max(1.0, std::abs(magnitude)); }

/// A quantity's magnitude: its largest finite |element|.
inline double magnitude(const double* values, int n) {
  double m = 0.0;
  for (int i = 0; i < n; ++i) {
    if (std::isfinite(values[i])) m = std::max(m, std::abs(values[i]));
  }
  return m;
}

/// |ours - reference| / allowed(magnitude): <= 1 means the two agree. NaN on either side is
/// infinitely far unless both are NaN.
inline double excess(double ours, double reference, double magnitude) {
  if (std::isnan(ours) || std::isnan(reference)) {
    return (std::isnan(ours) && std::isnan(reference)) ? 0.0
                                                       : std::numeric_limits<double>::infinity();
  }
  return std::abs(ours - reference) / allowed(magnitude);
}

/// The same for a single value, which is its own magnitude.
inline double excess(double ours, double reference) { return excess(ours, reference, reference); }

inline bool agrees(double ours, double reference) { return excess(ours, reference) <= 1.0; }

/// "field[3]: lever 1.0000000000000002 vs mujoco 1 (|diff| 2.2e-16, 0.00022 of the bound)"
inline std::string describe(const std::string& field, int index, double ours, double reference,
                            double magnitude) {
  std::ostringstream s;
  s.precision(17);
  s << field << "[" << index << "]: lever " << ours << " vs mujoco " << reference;
  s.precision(2);
  s << " (|diff| " << std::abs(ours - reference) << ", " << excess(ours, reference, magnitude)
    << " of the bound";
  if (std::abs(magnitude) > std::max(1.0, std::abs(reference))) s << " for magnitude " << magnitude;
  s << ")";
  return s.str();
}

inline std::string describe(const std::string& field, int index, double ours, double reference) {
  return describe(field, index, ours, reference, reference);
}

}  // namespace lever::test
