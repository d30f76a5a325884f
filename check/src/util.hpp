// Small helpers shared by the sections of `lever check`.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <limits>
#include <string>

#include <lever/dynamics.hpp>
#include <lever/model.hpp>

namespace lever::check {

/// Gravity torque (N m, or N on a slide) below this does not load a joint or a stop.
constexpr double kUnloaded = 1e-9;

/// Principal moments in ascending order (as the lesson prints them, np.sort).
inline Eigen::Vector3d sorted_moments(Eigen::Vector3d v) {
  std::sort(v.data(), v.data() + 3);
  return v;
}

/// An element's name, or "<kind> <index>" when it has none.
inline std::string label(const std::string& name, const char* kind, int index) {
  return name.empty() ? std::string(kind) + " " + std::to_string(index) : name;
}
inline std::string joint_label(const Model& m, int j) { return label(m.jnt_name[j], "joint", j); }
inline std::string body_label(const Model& m, int b) { return label(m.body_name[b], "body", b); }
inline std::string site_label(const Model& m, int s) { return label(m.site_name[s], "site", s); }
inline std::string geom_label(const Model& m, int g) { return label(m.geom_name[g], "geom", g); }
inline std::string motor_label(const Model& m, int a) {
  return label(m.actuator_name[a], "motor", a);
}

/// The force interval of one actuator at actuator length `length` and velocity `velocity`:
/// gain x ctrlrange + bias, intersected with forcerange, as actuation() clamps the command and then
/// the force; unbounded sides are infinite.
inline std::array<double, 2> actuator_force_range(const Model& model, int a, double length,
                                                  double velocity) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double gain = actuator_gain(model, a, length, velocity);
  const double bias = actuator_bias(model, a, length, velocity);
  double lo = -inf, hi = inf;
  if (gain == 0.0) {
    lo = hi = bias;
  } else if (model.actuator_ctrllimited[a]) {
    const double x = gain * model.actuator_ctrlrange[a][0],
                 y = gain * model.actuator_ctrlrange[a][1];
    lo = std::min(x, y) + bias;
    hi = std::max(x, y) + bias;
  }
  if (model.actuator_forcelimited[a]) {
    lo = std::max(lo, model.actuator_forcerange[a][0]);
    hi = std::min(hi, model.actuator_forcerange[a][1]);
  }
  return {lo, hi};
}

/// gear x a force interval, ordered.
inline std::array<double, 2> geared(const Model& model, int a, const std::array<double, 2>& force) {
  const double gear = model.actuator_gear[a][0];
  if (gear == 0.0) return {0.0, 0.0};
  const double x = gear * force[0], y = gear * force[1];
  return {std::min(x, y), std::max(x, y)};
}

/// The joint force interval one actuator can produce. A motor: gear x (gain x ctrlrange
/// intersected with forcerange). A servo: gear x forcerange, what it can push with whatever target
/// it is given (without a forcerange, its interval at qpos0 and rest, from the ctrlrange).
inline std::array<double, 2> motor_torque_range(const Model& model, int a) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (is_servo(model.actuator_kind[a])) {
    if (model.actuator_forcelimited[a]) return geared(model, a, model.actuator_forcerange[a]);
    const double length = model.actuator_length0[a];
    const auto range = actuator_force_range(model, a, length, 0.0);
    if (!model.actuator_ctrllimited[a]) return {-inf, inf};
    return geared(model, a, range);
  }
  return geared(model, a, actuator_force_range(model, a, 0.0, 0.0));
}

inline bool is_hinge(const Model& m, int j) { return m.jnt_type[j] == JointType::kHinge; }

}  // namespace lever::check
