// The one agreement bound of lever's differential tests, and helpers to report against it.
//
//   |ours - mujoco| <= 1e-12 * max(1, |mujoco|)
//
// It is never loosened locally: a test that misses it has found a term that differs.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace lever::test {

constexpr double kAgreement = 1e-12;

/// The allowed difference for a reference value.
inline double allowed(double reference) { return kAgreement * std::max(1.0, std::abs(reference)); }

/// |ours - reference| / allowed(reference): <= 1 means the two agree. NaN on either side is
/// infinitely far unless both are NaN.
inline double excess(double ours, double reference) {
  if (std::isnan(ours) || std::isnan(reference)) {
    return (std::isnan(ours) && std::isnan(reference)) ? 0.0 : std::numeric_limits<double>::infinity();
  }
  return std::abs(ours - reference) / allowed(reference);
}

inline bool agrees(double ours, double reference) { return excess(ours, reference) <= 1.0; }

/// "field[3]: lever 1.0000000000000002 vs mujoco 1 (|diff| 2.2e-16, 0.00022 of the bound)"
inline std::string describe(const std::string& field, int index, double ours, double reference) {
  std::ostringstream s;
  s.precision(17);
  s << field << "[" << index << "]: lever " << ours << " vs mujoco " << reference;
  s.precision(2);
  s << " (|diff| " << std::abs(ours - reference) << ", " << excess(ours, reference)
    << " of the bound)";
  return s.str();
}

}  // namespace lever::test
