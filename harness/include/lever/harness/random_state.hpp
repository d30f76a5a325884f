// Seeded random states for the property and differential tests, and the smooth control of the
// trajectory tests. MuJoCo-free: lever's Model is all it reads.
//
// The states lean towards the joint stops on purpose: a good fraction of joints sit just past a
// stop (up to 10 mrad, or 5 mm on a slide: 10 mrad at a 0.5 m lever arm) or inside a limit's
// margin, so that limit rows exist; some sit exactly on a stop, where a row must *not* appear.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <lever/data.hpp>
#include <lever/model.hpp>
#include <numbers>
#include <random>

namespace lever::test {

/// Everything forward() reads besides the model.
struct State {
  double time = 0.0;
  Eigen::VectorXd qpos, qvel, ctrl, qfrc_applied;
  Eigen::VectorXd act;  ///< (na) activations, drawn only when the model has any
};

/// How far a "just past the stop" sample goes.
constexpr double kPastStopHinge = 0.010;  // rad
constexpr double kPastStopSlide = 0.005;  // m

/// The span a motor's command is drawn from and swept across: its ctrlrange if limited, else
/// its forcerange (divided by the gear's size, so the force can reach it) if force-limited, else
/// [-1, 1].
inline std::array<double, 2> control_span(const Model& model, int a) {
  if (model.actuator_ctrllimited[a]) return model.actuator_ctrlrange[a];
  if (model.actuator_forcelimited[a]) {
    const double gear = std::max(std::abs(model.actuator_gear[a][0]), 1e-9);
    const auto& f = model.actuator_forcerange[a];
    return {f[0] / gear, f[1] / gear};
  }
  return {-1.0, 1.0};
}

namespace detail {

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// One joint's coordinate: inside its range, past a stop, inside the margin, or exactly on a stop.
inline double random_joint_position(const Model& model, int j, std::mt19937_64& rng) {
  const int adr = model.jnt_qposadr[j];
  const bool hinge = model.jnt_type[j] == JointType::kHinge;
  if (!model.jnt_limited[j]) {
    const double reach = hinge ? std::numbers::pi : 0.1;
    return model.qpos0[adr] + uniform(rng, -reach, reach);
  }
  const double lo = model.jnt_range[j][0], hi = model.jnt_range[j][1];
  const double margin = model.jnt_margin[j];
  const bool lower = uniform(rng, 0, 1) < 0.5;
  const double stop = lower ? lo : hi;
  const double inward = lower ? 1.0 : -1.0;  // direction from the stop into the range
  const double u = uniform(rng, 0, 1);
  if (u < 0.55) return uniform(rng, lo, hi);
  if (u < 0.80) return stop - inward * uniform(rng, 0, hinge ? kPastStopHinge : kPastStopSlide);
  if (u < 0.92) {
    // inside the margin band, where a row exists before contact (or, with no margin, just
    // inside the stop, where none may exist)
    const double band = margin > 0 ? margin : 0.001;
    return stop + inward * uniform(rng, 0, band);
  }
  return stop;  // exactly on the stop: the row test is strict
}

// A ball's (or a free joint's) orientation: a uniformly random rotation, given a length off one
// one time in four (the evaluation normalizes it, as MuJoCo's does).
inline void random_joint_quat(double* q, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Vector4d v;
  for (int k = 0; k < 4; ++k) v[k] = normal(rng);
  v.normalize();
  if (uniform(rng, 0, 1) < 0.25) v *= uniform(rng, 0.5, 2.0);
  for (int k = 0; k < 4; ++k) q[k] = v[k];
}

inline double random_control(const Model& model, int a, std::mt19937_64& rng) {
  const auto span = control_span(model, a);
  const double u = uniform(rng, 0, 1);
  if (u < 0.5) return uniform(rng, span[0], span[1]);
  if (u < 0.9) return uniform(rng, 3 * span[0], 3 * span[1]);  // clamped by ctrlrange
  return u < 0.95 ? span[0] : span[1];
}

}  // namespace detail

/// A random state: qpos as above (ball and free joints: random orientations, not always unit), qvel
/// ~ U(-2, 2) (at rest one time in ten), ctrl inside and beyond the span (up to 3x), qfrc_applied ~
/// U(-2, 2) one time in three, time ~ U(0, 10).
inline State random_state(const Model& model, std::mt19937_64& rng) {
  State s;
  s.time = detail::uniform(rng, 0, 10);
  s.qpos = model.qpos0;
  for (int j = 0; j < model.njnt; ++j) {
    const int adr = model.jnt_qposadr[j];
    switch (model.jnt_type[j]) {
      case JointType::kFree:  // a position within a metre of qpos0's, any orientation
        for (int k = 0; k < 3; ++k)
          s.qpos[adr + k] = model.qpos0[adr + k] + detail::uniform(rng, -1, 1);
        detail::random_joint_quat(&s.qpos[adr + 3], rng);
        break;
      case JointType::kBall: detail::random_joint_quat(&s.qpos[adr], rng); break;
      default: s.qpos[adr] = detail::random_joint_position(model, j, rng);
    }
  }
  s.qvel = Eigen::VectorXd::Zero(model.nv);
  if (detail::uniform(rng, 0, 1) >= 0.1) {
    for (int i = 0; i < model.nv; ++i) s.qvel[i] = detail::uniform(rng, -2, 2);
  }
  s.ctrl = Eigen::VectorXd::Zero(model.nu);
  for (int a = 0; a < model.nu; ++a) s.ctrl[a] = detail::random_control(model, a, rng);
  s.qfrc_applied = Eigen::VectorXd::Zero(model.nv);
  if (detail::uniform(rng, 0, 1) < 1.0 / 3.0) {
    for (int i = 0; i < model.nv; ++i) s.qfrc_applied[i] = detail::uniform(rng, -2, 2);
  }
  // a little outside [0, 1] too: a muscle clamps its activation there
  s.act = Eigen::VectorXd::Zero(model.na);
  for (int i = 0; i < model.na; ++i) s.act[i] = detail::uniform(rng, -0.2, 1.2);
  return s;
}

/// A random joint acceleration, for inverse dynamics.
inline Eigen::VectorXd random_qacc(const Model& model, std::mt19937_64& rng) {
  Eigen::VectorXd qacc(model.nv);
  for (int i = 0; i < model.nv; ++i) qacc[i] = detail::uniform(rng, -20, 20);
  return qacc;
}

/// Write a state into lever's Data.
inline void apply(const State& s, Data& data) {
  data.time = s.time;
  data.qpos = s.qpos;
  data.qvel = s.qvel;
  data.ctrl = s.ctrl;
  if (s.act.size() == data.act.size()) data.act = s.act;
  data.qfrc_applied = s.qfrc_applied;
}

/// The smooth control of the trajectory tests: motor a sweeps its whole span (control_span) as a
/// sinusoid, each motor at its own frequency (0.35 Hz + 0.13 Hz per index) and phase, so the
/// joints are driven into their stops. A function of time only: two engines that run on their
/// own compute the same commands.
inline void smooth_control(const Model& model, double time, Eigen::Ref<Eigen::VectorXd> ctrl) {
  for (int a = 0; a < model.nu; ++a) {
    const auto span = control_span(model, a);
    const double centre = 0.5 * (span[0] + span[1]), half = 0.5 * (span[1] - span[0]);
    const double frequency = 0.35 + 0.13 * a;
    ctrl[a] = centre + half * std::sin(2 * std::numbers::pi * frequency * time + 1.7 * a);
  }
}

}  // namespace lever::test
