// States at which the dynamics is differentiable, with room for a finite-difference step: every
// joint at least kClearance from each stop's margin (or, on purpose, well past one stop, where its
// limit row is active), and every motor command at least kClearance of its span inside its
// ctrlrange and forcerange, or well outside them (clamped); for a servo (gain and bias depending on
// the joint's position and velocity) the control and the force it gives at the drawn state, each
// kClearance of its range inside or outside it.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <lever/lever.hpp>
#include <lever/model.hpp>
#include <random>
#include <vector>

#include <lever/harness/random_state.hpp>

namespace lever::test {

constexpr double kClearance = 0.02;  // rad, m, or fraction of a motor's span

/// An actuator whose force is not gain-1 ctrl: an affine gain or bias, or a gain other than 1.
/// max |x_ij|, 0 for an empty matrix.
inline double largest(const Eigen::MatrixXd& x) { return x.size() ? x.cwiseAbs().maxCoeff() : 0.0; }

inline bool force_is_not_ctrl(const Model& model, int a) {
  return model.actuator_gaintype[a] != GainType::kFixed ||
         model.actuator_biastype[a] != BiasType::kNone || model.actuator_gainprm[a][0] != 1.0;
}

/// Whether x is at least kClearance * (hi - lo) inside [lo, hi] or that far outside it.
inline bool clear_of_edges(double x, const std::array<double, 2>& range) {
  const double margin = kClearance * std::max(range[1] - range[0], 1e-9);
  return std::abs(x - range[0]) >= margin && std::abs(x - range[1]) >= margin;
}

/// A control for servo a at state s (qpos and qvel already drawn) with both clamps clear of their
/// switches: the clamped control away from the ctrlrange's edges and the force away from the
/// forcerange's. Mostly a force drawn inside the forcerange and the control that produces it,
/// sometimes a control anywhere (clamped by ctrlrange, or a force clamped by forcerange).
template <class Uniform>
double servo_control(const Model& model, int a, const State& s, Uniform& uniform) {
  const int j = model.actuator_trnid[a][0];
  const double gear = model.actuator_gear[a][0];
  const double length = gear * s.qpos[model.jnt_qposadr[j]];
  const double velocity = gear * s.qvel[model.jnt_dofadr[j]];
  const auto& g = model.actuator_gainprm[a];
  const auto& b = model.actuator_biasprm[a];
  const double gain = model.actuator_gaintype[a] == GainType::kAffine
                          ? g[0] + g[1] * length + g[2] * velocity
                          : g[0];
  const double bias =
      model.actuator_biastype[a] == BiasType::kAffine ? b[0] + b[1] * length + b[2] * velocity : 0;
  const std::array<double, 2> span = control_span(model, a);
  const double width = span[1] - span[0];
  for (int attempt = 0; attempt < 1000; ++attempt) {
    double ctrl;
    if (model.actuator_forcelimited[a] && std::abs(gain) > 1e-9 && uniform(0, 1) < 0.8) {
      const auto& f = model.actuator_forcerange[a];
      ctrl = (uniform(f[0], f[1]) - bias) / gain;
    } else {
      ctrl = uniform(span[0] - width, span[1] + width);
    }
    double clamped = ctrl;
    if (model.actuator_ctrllimited[a]) {
      const auto& c = model.actuator_ctrlrange[a];
      if (!clear_of_edges(ctrl, c)) continue;
      clamped = std::clamp(ctrl, c[0], c[1]);
    }
    const double force = gain * clamped + bias;
    if (model.actuator_forcelimited[a] && !clear_of_edges(force, model.actuator_forcerange[a])) {
      continue;
    }
    return ctrl;
  }
  return span[1] + width;  // no clear control found: far out (the state may sit on a switch)
}

/// past_stop: put each limited joint past a stop (by 0.02-0.1) one time in four. Ball and free
/// joints: a uniformly random orientation (a unit quaternion).
inline State smooth_state(const Model& model, std::mt19937_64& rng, bool past_stop) {
  const auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  State s;
  s.qpos = model.qpos0;
  for (int j = 0; j < model.njnt; ++j) {
    double& q = s.qpos[model.jnt_qposadr[j]];
    if (model.jnt_kind[j] == JointKind::kFree || model.jnt_kind[j] == JointKind::kBall) {
      // any orientation (a unit quaternion), a free body within a metre of qpos0's position
      double* quat = &q;
      if (model.jnt_kind[j] == JointKind::kFree) {
        for (int k = 0; k < 3; ++k) (&q)[k] += uniform(-1, 1);
        quat += 3;
      }
      Eigen::Vector4d v;
      for (int k = 0; k < 4; ++k) v[k] = std::normal_distribution<double>(0, 1)(rng);
      v.normalize();
      for (int k = 0; k < 4; ++k) quat[k] = v[k];
      continue;
    }
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
    if (force_is_not_ctrl(model, a)) {
      s.ctrl[a] = servo_control(model, a, s, uniform);
      continue;
    }
    // a motor (force = gain ctrl, gain 1 in every model here):
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

/// The switches of the dynamics at data's last forward(): per limit row, its joint, side and
/// state; per actuator, whether its ctrl is clamped (below or above ctrlrange) and whether its
/// force sits on an edge of its forcerange (a clamped force is the edge itself). Appended to out.
inline void append_switches(const Model& model, const Data& data, std::vector<int>& out) {
  for (int r = 0; r < data.nefc; ++r) {
    out.push_back(4 * data.efc_id[r] + (data.efc_sign[r] > 0 ? 0 : 2) +
                  (data.efc_state[r] == ConstraintState::kActive ? 1 : 0));
  }
  out.push_back(-1);
  for (int a = 0; a < model.nu; ++a) {
    int code = 0;
    if (model.actuator_ctrllimited[a]) {
      const auto& c = model.actuator_ctrlrange[a];
      code = data.ctrl[a] < c[0] ? 1 : data.ctrl[a] > c[1] ? 2 : 0;
    }
    if (model.actuator_forcelimited[a]) {
      const auto& f = model.actuator_forcerange[a];
      code += data.actuator_force[a] == f[0] ? 3 : data.actuator_force[a] == f[1] ? 6 : 0;
    }
    out.push_back(code);
  }
}

/// The switches of every forward() a step from (qpos, qvel, ctrl) evaluates: one for Euler and
/// implicit, RK4's four stages (built as step() builds them). A central difference whose two
/// sides see other switches than the middle straddles a non-differentiable point: the analytic
/// derivative is one-sided there and the difference is not a derivative at all.
inline std::vector<int> step_switches(const Model& model, Data& data, const State& s) {
  apply(s, data);
  forward(model, data);
  std::vector<int> out;
  append_switches(model, data, out);
  if (model.opt.integrator != Integrator::kRK4) return out;
  constexpr double kA[3] = {0.5, 0.5, 1.0};
  const double h = model.opt.timestep;
  for (int i = 1; i < 4; ++i) {
    const Eigen::VectorXd qvel = data.qvel, qacc = data.qacc;
    data.qpos = s.qpos;
    integrate_pos(model, data.qpos, kA[i - 1] * qvel, h);
    data.qvel = s.qvel + (h * kA[i - 1]) * qacc;
    data.time = s.time + kA[i - 1] * h;
    forward(model, data);
    append_switches(model, data, out);
  }
  return out;
}

/// Whether every central difference of the step (each of qpos, qvel and ctrl moved by +-eps)
/// sees the switches that s sees, at every forward() of the step (qpos moved along its tangent).
inline bool differences_see_same_switches(const Model& model, Data& probe, const State& s,
                                          double eps) {
  const std::vector<int> middle = step_switches(model, probe, s);
  const int nv = model.nv;
  for (int c = 0; c < 2 * nv + model.nu; ++c) {
    for (const double delta : {eps, -eps}) {
      State moved = s;
      if (c < nv)  // along the tangent: qpos (+) delta e_c
        integrate_pos(model, moved.qpos, Eigen::VectorXd::Unit(nv, c), delta);
      else if (c < 2 * nv)
        moved.qvel[c - nv] += delta;
      else
        moved.ctrl[c - 2 * nv] += delta;
      if (step_switches(model, probe, moved) != middle) return false;
    }
  }
  return true;
}

}  // namespace lever::test
