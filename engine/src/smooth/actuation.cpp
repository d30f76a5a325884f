// Actuators on joints and tendons: transmission, clamping and the joint forces they produce
// (MuJoCo 2.2.2's mj_transmission and mj_fwdActuation for stateless actuators: motors, position
// and velocity servos, and <general> with fixed or affine gain and bias). A joint transmission's
// length is gear[0] qpos, its moment gear[0] at the joint's dof; a tendon transmission's length is
// gear[0] times the tendon's length, its moment gear[0] ten_J. actuator_moment holds every row.
//
// Order, as MuJoCo: ctrl clamped to ctrlrange (on a copy; data.ctrl is never changed), force =
// gain * ctrl + bias, force clamped to forcerange, then the gear carries it to the joint. A
// position servo is gain kp and bias -kp length - kv velocity, so it pulls length to ctrl.
// Clamping is silent here; `lever check` reports it.
#include <lever/dynamics.hpp>

#include <algorithm>

#include "basics/basics.hpp"
#include "model/model_room.hpp"
#include "smooth/smooth.hpp"

namespace lever {

namespace {
double clamp(double x, const std::array<double, 2>& range) {
  if (x < range[0]) return range[0];
  if (x > range[1]) return range[1];
  return x;  // NaN passes through, as mju_clip
}
}  // namespace

void unchecked::transmission(const Model& model, Data& data) {
  const int* const id = model.actuator_trnid.data();
  const auto* const gear = model.actuator_gear.data();
  const int* const qposadr = model.jnt_qposadr.data();
  const int* const dofadr = model.jnt_dofadr.data();
  const int nv = model.nv;
  for (int a = 0; a < model.nu; ++a) {
    const double g = gear[a][0];  // joint and tendon transmissions use gear[0] only
    double* const moment = data.actuator_moment.data() + static_cast<std::ptrdiff_t>(a) * nv;
    if (model.actuator_trntype[a] == TransmissionType::kTendon) {
      const int t = id[a];
      const double* const J = data.ten_J.data() + static_cast<std::ptrdiff_t>(t) * nv;
      data.actuator_length[a] = data.ten_length[t] * g;
      double velocity = 0.0;
      for (int j = 0; j < nv; ++j) {
        moment[j] = J[j] * g;
        velocity += moment[j] * data.qvel[j];
      }
      data.actuator_velocity[a] = velocity;
      continue;
    }
    const int j = id[a];
    for (int k = 0; k < nv; ++k) moment[k] = 0.0;
    moment[dofadr[j]] = g;
    data.actuator_length[a] = g * data.qpos[qposadr[j]];
    data.actuator_velocity[a] = g * data.qvel[dofadr[j]];
  }
}

void transmission(const Model& model, Data& data) {
  check_entry(model, data, "lever::transmission");
  unchecked::transmission(model, data);
}

void unchecked::actuation(const Model& model, Data& data) {
  double* const qfrc = data.qfrc_actuator.data();
  for (int i = 0; i < model.nv; ++i) qfrc[i] = 0.0;
  if (model.nu == 0) return;
  double* const force = data.actuator_force.data();
  if (model.opt.disabled(kDisableActuation)) {
    for (int a = 0; a < model.nu; ++a) force[a] = 0.0;
    return;
  }

  // the clamped controls; one bad control zeroes them all (MuJoCo's mjWARN_BADCTRL)
  const double* const ctrl = data.ctrl.data();
  const bool clamp_ctrl = !model.opt.disabled(kDisableClampctrl);
  for (int a = 0; a < model.nu; ++a) {
    force[a] = clamp_ctrl && model.actuator_ctrllimited[a]
                   ? clamp(ctrl[a], model.actuator_ctrlrange[a])
                   : ctrl[a];
  }
  const int bad = first_bad(force, model.nu);
  if (bad >= 0) {
    record_warning(data, Warning::kBadCtrl, bad);
    for (int a = 0; a < model.nu; ++a) force[a] = 0.0;
  }

  const double* const length = data.actuator_length.data();
  const double* const velocity = data.actuator_velocity.data();
  const int* const joint = model.actuator_trnid.data();
  const auto* const gear = model.actuator_gear.data();
  const int* const dofadr = model.jnt_dofadr.data();
  const int nv = model.nv;
  for (int a = 0; a < model.nu; ++a) {
    double f = force[a] * actuator_gain(model, a, length[a], velocity[a]);
    f += actuator_bias(model, a, length[a], velocity[a]);
    if (model.actuator_forcelimited[a]) f = clamp(f, model.actuator_forcerange[a]);
    force[a] = f;
    if (model.actuator_trntype[a] == TransmissionType::kTendon) {  // moment^T f
      const double* const moment = data.actuator_moment.data() + static_cast<std::ptrdiff_t>(a) * nv;
      for (int j = 0; j < nv; ++j) qfrc[j] += moment[j] * f;
      continue;
    }
    qfrc[dofadr[joint[a]]] += gear[a][0] * f;
  }
}

void actuation(const Model& model, Data& data) {
  check_entry(model, data, "lever::actuation");
  unchecked::actuation(model, data);
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
