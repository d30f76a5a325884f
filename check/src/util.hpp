// Small helpers shared by the sections of `lever check`.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <limits>
#include <string>

#include <lever/model.hpp>

namespace lever::check {

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

/// The joint force interval one motor can produce: gear x (ctrlrange intersected with forcerange),
/// as actuation() clamps the command and then the force; unbounded sides are infinite.
inline std::array<double, 2> motor_torque_range(const Model& model, int a) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  double lo = -inf, hi = inf;
  if (model.actuator_ctrllimited[a]) {
    lo = model.actuator_ctrlrange[a][0];
    hi = model.actuator_ctrlrange[a][1];
  }
  if (model.actuator_forcelimited[a]) {
    lo = std::max(lo, model.actuator_forcerange[a][0]);
    hi = std::min(hi, model.actuator_forcerange[a][1]);
  }
  const double gear = model.actuator_gear[a][0];
  if (gear == 0.0) return {0.0, 0.0};
  const double x = gear * lo, y = gear * hi;
  return {std::min(x, y), std::max(x, y)};
}

inline bool is_hinge(const Model& m, int j) { return m.jnt_type[j] == JointType::kHinge; }

}  // namespace lever::check
