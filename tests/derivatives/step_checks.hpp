// Catch2's side of step_differences.hpp: a step's analytic A and B at one state checked against
// lever's own differences (eps 1e-6) and MuJoCo 2.2.2's (eps 1e-6 and 1e-5). Shared by the
// derivative tests of contacts, tendons, equality constraints and site actuators.
#pragma once

#include <catch2/catch.hpp>

#include <algorithm>

#include "step_differences.hpp"

namespace lever::test::step_differences {

/// A and B (deriv, at s) against lever's own differences and MuJoCo's; the worst ratio to the
/// bound against MuJoCo, each comparison a check. With `curved`, MuJoCo's eps = 1e-5 differences
/// are Richardson-extrapolated with 2e-5: where a constraint's error is within solimp's width the
/// impedance's sigmoid makes aref cubic in it, and eps = 1e-5's truncation can reach the bound.
inline double check_against_differences(diff::Twin& twin, const State& s,
                                        const Derivatives& deriv, bool curved) {
  const Differences own = lever_differences(twin.model, s, 1e-6);
  REQUIRE(own.same_active_set);
  CHECK(ratio_to_bound(deriv.A, own.A) <= 1);
  CHECK(ratio_to_bound(deriv.B, own.B) <= 1);
  double worst = 0;
  for (const double eps : {1e-6, 1e-5}) {
    Differences theirs = mujoco_differences(twin, s, eps);
    if (curved && eps > 1e-6) {
      const Differences wide = mujoco_differences(twin, s, 2 * eps);
      theirs.A = (4 * theirs.A - wide.A) / 3;
      theirs.B = (4 * theirs.B - wide.B) / 3;
    }
    const double a = ratio_to_bound(deriv.A, theirs.A), b = ratio_to_bound(deriv.B, theirs.B);
    INFO("eps " << eps << ": A " << a << ", B " << b << " of the bound");
    CHECK(a <= 1);
    CHECK(b <= 1);
    worst = std::max({worst, a, b});
  }
  return worst;
}

/// step_derivatives at s, its active set held within the step, then check_against_differences.
inline double check_step_derivatives(diff::Twin& twin, const State& s, bool curved = false) {
  const Model& model = twin.model;
  INFO(integrator_name(model.opt.integrator));
  Derivatives deriv(model);
  Data data(model);
  apply(s, data);
  step_derivatives(model, data, deriv);
  CHECK_FALSE(deriv.active_set_changes);
  return check_against_differences(twin, s, deriv, curved);
}

}  // namespace lever::test::step_differences
