// States at which the dynamics is differentiable, with room for a finite-difference step: every
// joint at least kClearance from each stop's margin (or, on purpose, well past one stop, where its
// limit row is active), and every motor command at least kClearance of its span inside its
// ctrlrange and forcerange, or well outside them (clamped).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <lever/model.hpp>
#include <random>

#include <lever/harness/random_state.hpp>

namespace lever::test {

constexpr double kClearance = 0.02;  // rad, m, or fraction of a motor's span

/// past_stop: put each limited joint past a stop (by 0.02-0.1) one time in four.
inline State smooth_state(const Model& model, std::mt19937_64& rng, bool past_stop) {
  const auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  State s;
  s.qpos = model.qpos0;
  for (int j = 0; j < model.njnt; ++j) {
    double& q = s.qpos[model.jnt_qposadr[j]];
    if (!model.jnt_limited[j]) {
      q = model.qpos0[model.jnt_qposadr[j]] + uniform(-2.5, 2.5);
      continue;
    }
    const double lo = model.jnt_range[j][0], hi = model.jnt_range[j][1];
    const double inner = model.jnt_margin[j] + kClearance;
    if (past_stop && uniform(0, 1) < 0.25) {
      q = uniform(0, 1) < 0.5 ? lo - uniform(0.02, 0.1) : hi + uniform(0.02, 0.1);
    } else if (hi - lo > 2 * inner) {
      q = uniform(lo + inner, hi - inner);
    } else {
      q = 0.5 * (lo + hi);  // a range narrower than twice its margin: always inside a margin
    }
  }
  s.qvel = Eigen::VectorXd::Zero(model.nv);
  for (int i = 0; i < model.nv; ++i) s.qvel[i] = uniform(-2, 2);
  s.ctrl = Eigen::VectorXd::Zero(model.nu);
  for (int a = 0; a < model.nu; ++a) {
    // inside both ranges with clearance, or (one time in five) far outside the span
    std::array<double, 2> span = control_span(model, a);
    if (model.actuator_ctrllimited[a] && model.actuator_forcelimited[a]) {
      // the force is the clamped control itself (gain 1): inside both ranges
      span[0] = std::max(span[0], model.actuator_forcerange[a][0]);
      span[1] = std::min(span[1], model.actuator_forcerange[a][1]);
    } else if (model.actuator_forcelimited[a]) {
      span = model.actuator_forcerange[a];
    }
    if (span[1] <= span[0]) span = {0.0, 0.0};  // disjoint ranges: the motor is always clamped
    const double width = span[1] - span[0];
    if (uniform(0, 1) < 0.2) {
      s.ctrl[a] = uniform(0, 1) < 0.5 ? span[0] - (0.5 + uniform(0, 1)) * width
                                      : span[1] + (0.5 + uniform(0, 1)) * width;
    } else {
      s.ctrl[a] = uniform(span[0] + kClearance * width, span[1] - kClearance * width);
    }
  }
  s.qfrc_applied = Eigen::VectorXd::Zero(model.nv);
  for (int i = 0; i < model.nv; ++i) s.qfrc_applied[i] = uniform(-1, 1);
  return s;
}

}  // namespace lever::test
