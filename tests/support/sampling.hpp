// How many random samples (states, seconds of a run) a test draws.
//
// make test draws every sample and holds the numbers. The sanitized build (make test-asan) runs
// each sample 5-20x slower and looks for something else: a read out of bounds, a leak, undefined
// behaviour, which a quarter of the samples reach along the same code paths. So there it draws a
// quarter, and .ci/run keeps within its time.
#pragma once

namespace lever::test {

#ifdef LEVER_SANITIZED
inline constexpr int kSampleDivisor = 4;
#else
inline constexpr int kSampleDivisor = 1;
#endif

/// n samples in make test, n / 4 (at least one) under the sanitizers.
constexpr int samples(int n) { return n / kSampleDivisor > 0 ? n / kSampleDivisor : 1; }

/// A run of `seconds` in make test, a quarter of it under the sanitizers.
constexpr double run_seconds(double seconds) { return seconds / kSampleDivisor; }

}  // namespace lever::test
