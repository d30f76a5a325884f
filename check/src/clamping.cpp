// (6) Commands beyond ctrlrange are clamped, silently: command every motor well beyond its range
// (+-100 alternating in sign, as the lesson does, or 4 times the bound where 100 is inside it),
// run forward(), and read actuator_force and the engine's warnings.
#include <algorithm>
#include <cmath>

#include <lever/data.hpp>
#include <lever/forward.hpp>

#include <lever/check.hpp>
#include "util.hpp"

namespace lever::check {

namespace {

double overdrive(const Model& model, int a) {
  const double sign = a % 2 == 0 ? 1.0 : -1.0;
  if (!model.actuator_ctrllimited[a]) return 100.0 * sign;
  const double bound = model.actuator_ctrlrange[a][sign > 0 ? 1 : 0];
  return std::abs(bound) < 100.0 ? 100.0 * sign : 4.0 * bound;
}

}  // namespace

Clamping check_clamping(const Model& model) {
  Clamping result;
  Data data(model);
  for (int a = 0; a < model.nu; ++a) {
    data.ctrl[a] = overdrive(model, a);
    if (!model.actuator_ctrllimited[a]) result.unbounded.push_back(motor_label(model, a));
  }
  result.newton_metres = model.nu > 0;
  for (int a = 0; a < model.nu; ++a) {
    const bool plain = actuator_scalar_dof(model, a) >= 0 &&
                       is_hinge(model, model.actuator_trnid[a][0]) &&
                       std::abs(model.actuator_gear[a][0]) == 1.0;
    result.newton_metres = result.newton_metres && plain;
  }
  forward(model, data);
  result.qpos = data.qpos;
  result.target = data.ctrl;
  result.raw_force = Eigen::VectorXd::Zero(model.nu);
  for (int a = 0; a < model.nu; ++a) {
    result.servo.push_back(is_servo(model.actuator_kind[a]) ? 1 : 0);
    if (model.actuator_ctrllimited[a]) {
      const auto& r = model.actuator_ctrlrange[a];
      result.target[a] = std::clamp(data.ctrl[a], r[0], r[1]);
    }
    // the force before forcerange, from the model's law (not the engine's): gain target + bias
    const double len = data.actuator_length[a], vel = data.actuator_velocity[a];
    result.raw_force[a] =
        actuator_gain(model, a, len, vel) * result.target[a] + actuator_bias(model, a, len, vel);
  }
  result.ctrl = data.ctrl;
  result.actuator_force = data.actuator_force;
  for (const WarningStat& w : data.warning) result.warnings += w.number;
  return result;
}

bool Clamping::any_servo() const {
  return std::any_of(servo.begin(), servo.end(), [](uint8_t s) { return s != 0; });
}

}  // namespace lever::check
