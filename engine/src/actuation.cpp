// Actuators on joints: transmission, clamping and the joint forces they produce
// (MuJoCo 2.2.2's mj_transmission and mj_fwdActuation for stateless actuators: motors, position
// and velocity servos, and <general> with fixed or affine gain and bias).
//
// Order, as MuJoCo: ctrl clamped to ctrlrange (on a copy; data.ctrl is never changed), force =
// gain * ctrl + bias, force clamped to forcerange, then the gear carries it to the joint. A
// position servo is gain kp and bias -kp length - kv velocity, so it pulls length to ctrl.
// Clamping is silent here; `lever check` reports it.
#include <lever/dynamics.hpp>

#include <algorithm>

#include "internal.hpp"

namespace lever {

namespace {
double clamp(double x, const std::array<double, 2>& range) {
  if (x < range[0]) return range[0];
  if (x > range[1]) return range[1];
  return x;  // NaN passes through, as mju_clip
}
}  // namespace

void transmission(const Model& model, Data& data) {
  check_entry(model, data, "lever::transmission");
  for (int a = 0; a < model.nu; ++a) {
    const int j = model.actuator_trnid[a];
    const double gear = model.actuator_gear[a][0];  // a joint transmission uses gear[0] only
    data.actuator_length[a] = gear * data.qpos[model.jnt_qposadr[j]];
    data.actuator_velocity[a] = gear * data.qvel[model.jnt_dofadr[j]];
  }
}

void actuation(const Model& model, Data& data) {
  check_entry(model, data, "lever::actuation");
  data.qfrc_actuator.setZero();
  if (model.nu == 0) return;

  // the clamped controls; one bad control zeroes them all (MuJoCo's mjWARN_BADCTRL)
  Eigen::VectorXd& force = data.actuator_force;
  bool bad = false;
  for (int a = 0; a < model.nu; ++a) {
    force[a] = model.actuator_ctrllimited[a] ? clamp(data.ctrl[a], model.actuator_ctrlrange[a])
                                             : data.ctrl[a];
    if (!bad && is_bad(force[a])) {
      bad = true;
      record_warning(data, Warning::kBadCtrl, a);
    }
  }
  if (bad) force.setZero();

  for (int a = 0; a < model.nu; ++a) {
    const double length = data.actuator_length[a];
    const double velocity = data.actuator_velocity[a];
    force[a] *= actuator_gain(model, a, length, velocity);
    force[a] += actuator_bias(model, a, length, velocity);
    if (model.actuator_forcelimited[a]) force[a] = clamp(force[a], model.actuator_forcerange[a]);
    const int dof = model.jnt_dofadr[model.actuator_trnid[a]];
    data.qfrc_actuator[dof] += model.actuator_gear[a][0] * force[a];
  }
}

bool actuator_clamped(const Model& model, const Data& data, int a) {
  const double ctrl = data.ctrl[a];
  const auto& c = model.actuator_ctrlrange[a];
  if (model.actuator_ctrllimited[a] && (ctrl < c[0] || ctrl > c[1])) return true;
  const auto& f = model.actuator_forcerange[a];
  const double force = data.actuator_force[a];
  return model.actuator_forcelimited[a] && (force == f[0] || force == f[1]);
}

}  // namespace lever
