// For tests that assert lever's numbers are MuJoCo's to the bit: how many of them are not.
#pragma once

namespace lever::test {

/// How many of n numbers differ in their bits, but for the sign of a zero (a limit row's velocity
/// at rest is sign * 0 in lever, a sum of products that starts from +0 in MuJoCo): == on doubles.
inline int numbers_apart(const double* a, const double* b, int n) {
  int apart = 0;
  for (int i = 0; i < n; ++i) apart += !(a[i] == b[i]);
  return apart;
}

}  // namespace lever::test
