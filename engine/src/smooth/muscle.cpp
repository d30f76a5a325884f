// MuJoCo 2.2.2's muscle (engine_util_misc.c: mju_muscleGain, mju_muscleBias,
// mju_muscleDynamics; engine_derivative.c: the gain's velocity derivative).
//
// A muscle's parameters (gainprm = biasprm, 9 numbers): the operating range of normalized
// lengths [range0, range1], the peak active force F (if negative, scale / acc0), lmin and lmax
// where the active force-length curve vanishes, vmax (shortening velocity at which it vanishes,
// in optimal lengths per second), fpmax (passive force at lmax, relative to F) and fvmax
// (the force of lengthening, relative to F).
//
// The actuator's length range (actuator_lengthrange, from the compiler) is mapped onto the
// operating range: the optimal length L0 is (lengthrange width) / (range width), and the
// normalized length is L = range0 + (length - lengthrange0) / L0, the normalized velocity
// V = velocity / (L0 vmax).
//
//   FL(L): two half-parabolas up from lmin to 1 through the middle a = (lmin + 1) / 2, two down
//          from 1 to lmax through b = (1 + lmax) / 2; zero beyond lmax. Below lmin MuJoCo
//          2.2.2's branches fall through to the second parabola (negative there): so do these.
//   FV(V): zero below -1, (V + 1)^2 up to 0, then rising to fvmax at V = fvmax - 1.
//   FP(L): zero below 1, a half-parabola to fpmax / 2 at b, then linear with slope fpmax / (b - 1).
//
// The gain is -F FL FV, the bias -F FP (a muscle pulls: its force is negative), and the
// activation follows ctrl (clamped to [0, 1]) with the time constant of Millard et al. (2013):
// tau_act (0.5 + 1.5 act) while activating, tau_deact / (0.5 + 1.5 act) while deactivating.
#include <lever/dynamics.hpp>

#include <algorithm>

#include "basics/basics.hpp"
#include "smooth/smooth.hpp"

namespace lever {

namespace {

using detail::kMinVal;

double at_least_tiny(double x) { return std::max(kMinVal, x); }

double clamped(double x, double low, double high) {
  if (x < low) return low;
  if (x > high) return high;
  return x;
}

// The numbers the curves share, from the parameters, the length range and acc0.
struct MuscleScales {
  double force;           ///< peak active force F
  double optimal_length;  ///< L0
  double L;               ///< normalized length
};

MuscleScales scales(double length, const std::array<double, 2>& lengthrange, double acc0,
                    const double* prm) {
  MuscleScales s{};
  s.force = prm[2] < 0 ? prm[3] / at_least_tiny(acc0) : prm[2];
  s.optimal_length = (lengthrange[1] - lengthrange[0]) / at_least_tiny(prm[1] - prm[0]);
  s.L = prm[0] + (length - lengthrange[0]) / at_least_tiny(s.optimal_length);
  return s;
}

// FL: the active force-length curve
double force_length(double L, double lmin, double lmax) {
  const double a = 0.5 * (lmin + 1), b = 0.5 * (1 + lmax);
  if (L >= lmin && L <= a) {
    const double x = (L - lmin) / at_least_tiny(a - lmin);
    return 0.5 * x * x;
  }
  if (L <= 1) {
    const double x = (1 - L) / at_least_tiny(1 - a);
    return 1 - 0.5 * x * x;
  }
  if (L <= b) {
    const double x = (L - 1) / at_least_tiny(b - 1);
    return 1 - 0.5 * x * x;
  }
  if (L <= lmax) {
    const double x = (lmax - L) / at_least_tiny(lmax - b);
    return 0.5 * x * x;
  }
  return 0;  // beyond lmax (below lmin, MuJoCo's second branch above applies, as here)
}

// d FL / d L, on force_length's branches
double force_length_slope(double L, double lmin, double lmax) {
  const double a = 0.5 * (lmin + 1), b = 0.5 * (1 + lmax);
  if (L >= lmin && L <= a) {
    const double width = at_least_tiny(a - lmin);
    return (L - lmin) / width / width;
  }
  if (L <= 1) {
    const double width = at_least_tiny(1 - a);
    return (1 - L) / width / width;
  }
  if (L <= b) {
    const double width = at_least_tiny(b - 1);
    return -(L - 1) / width / width;
  }
  if (L <= lmax) {
    const double width = at_least_tiny(lmax - b);
    return -(lmax - L) / width / width;
  }
  return 0;
}

}  // namespace

MusclePartials muscle_partials(double length, double velocity,
                               const std::array<double, 2>& lengthrange, double acc0,
                               const double* gainprm, const double* biasprm) {
  MusclePartials p;
  // the gain: -F FL(L) FV(V), L = range0 + (length - lengthrange0) / L0, V = velocity / (L0 vmax)
  const MuscleScales s = scales(length, lengthrange, acc0, gainprm);
  const double per_length = 1 / at_least_tiny(s.optimal_length);
  const double velocity_scale = at_least_tiny(s.optimal_length * gainprm[6]);
  const double V = velocity / velocity_scale;
  const double fvmax = gainprm[8], y = fvmax - 1;
  double FV = fvmax, dFV = 0, ddFV = 0;  // FV and its first two derivatives in V
  if (V <= -1) {
    FV = 0;
  } else if (V <= 0) {
    FV = (V + 1) * (V + 1);
    dFV = 2 * V + 2;
    ddFV = 2;
  } else if (V <= y) {
    FV = fvmax - (y - V) * (y - V) / at_least_tiny(y);
    dFV = (-2 * V + 2 * y) / at_least_tiny(y);
    ddFV = -2 / at_least_tiny(y);
  }
  const double FL = force_length(s.L, gainprm[4], gainprm[5]);
  const double dFL = force_length_slope(s.L, gainprm[4], gainprm[5]) * per_length;
  p.gain = -s.force * FL * FV;
  p.gain_per_length = -s.force * dFL * FV;
  p.gain_per_velocity = -s.force * FL * dFV / velocity_scale;
  p.gain_per_velocity_per_length = -s.force * dFL * dFV / velocity_scale;
  p.gain_per_velocity_per_velocity = -s.force * FL * ddFV / (velocity_scale * velocity_scale);
  // the bias: -F fpmax FP(L), with biasprm's own numbers
  const MuscleScales sb = scales(length, lengthrange, acc0, biasprm);
  const double b = 0.5 * (1 + biasprm[5]), width = at_least_tiny(b - 1);
  double dFP = 0;  // d FP / d L
  if (sb.L > 1) dFP = sb.L <= b ? (sb.L - 1) / width / width : 1 / width;
  p.bias_per_length = -sb.force * biasprm[7] * dFP / at_least_tiny(sb.optimal_length);
  return p;
}

void muscle_activation_rate_partials(double ctrl, double act, const double* dynprm,
                                     double& per_ctrl, double& per_act) {
  const double target = clamped(ctrl, 0, 1);
  const double a = clamped(act, 0, 1);
  const double per_target = ctrl > 0 && ctrl < 1 ? 1.0 : 0.0;  // d target / d ctrl
  const double a_per_act = act > 0 && act < 1 ? 1.0 : 0.0;     // d a / d act
  // the branch is held (at target = act both give rate 0, and the rate is continuous there)
  const bool activating = target > act;
  const double shape = 0.5 + 1.5 * a;
  const double tau = activating ? dynprm[0] * shape : dynprm[1] / shape;
  const double dtau_dact =
      tau < kMinVal ? 0.0
                    : (activating ? dynprm[0] * 1.5 : -dynprm[1] * 1.5 / (shape * shape)) *
                          a_per_act;
  const double t = at_least_tiny(tau);
  per_ctrl = per_target / t;
  per_act = -1 / t - (target - act) / (t * t) * dtau_dact;
}

double muscle_gain(double length, double velocity, const std::array<double, 2>& lengthrange,
                   double acc0, const double* prm) {
  const MuscleScales s = scales(length, lengthrange, acc0, prm);
  const double V = velocity / at_least_tiny(s.optimal_length * prm[6]);
  const double fvmax = prm[8], y = fvmax - 1;
  double FV;
  if (V <= -1) {
    FV = 0;
  } else if (V <= 0) {
    FV = (V + 1) * (V + 1);
  } else if (V <= y) {
    FV = fvmax - (y - V) * (y - V) / at_least_tiny(y);
  } else {
    FV = fvmax;
  }
  return -s.force * force_length(s.L, prm[4], prm[5]) * FV;
}

double muscle_gain_per_velocity(double length, double velocity,
                                const std::array<double, 2>& lengthrange, double acc0,
                                const double* prm) {
  const MuscleScales s = scales(length, lengthrange, acc0, prm);
  const double V = velocity / at_least_tiny(s.optimal_length * prm[6]);
  const double y = prm[8] - 1;
  double dFV = 0;  // d FV / d V; zero where FV is flat
  if (V > -1 && V <= 0) {
    dFV = 2 * V + 2;
  } else if (V > 0 && V <= y) {
    dFV = (-2 * V + 2 * y) / at_least_tiny(y);
  }
  return -s.force * force_length(s.L, prm[4], prm[5]) * dFV /
         at_least_tiny(s.optimal_length * prm[6]);
}

double muscle_bias(double length, const std::array<double, 2>& lengthrange, double acc0,
                   const double* prm) {
  const MuscleScales s = scales(length, lengthrange, acc0, prm);
  const double fpmax = prm[7], b = 0.5 * (1 + prm[5]);
  if (s.L <= 1) return 0;
  if (s.L <= b) {
    const double x = (s.L - 1) / at_least_tiny(b - 1);
    return -s.force * fpmax * 0.5 * x * x;
  }
  const double x = (s.L - b) / at_least_tiny(b - 1);
  return -s.force * fpmax * (0.5 + x);
}

double muscle_activation_rate(double ctrl, double act, const double* dynprm) {
  const double target = clamped(ctrl, 0, 1);
  const double a = clamped(act, 0, 1);
  // compared with the unclamped activation, as MuJoCo does
  const double tau = target > act ? dynprm[0] * (0.5 + 1.5 * a) : dynprm[1] / (0.5 + 1.5 * a);
  return (target - act) / at_least_tiny(tau);
}

}  // namespace lever
