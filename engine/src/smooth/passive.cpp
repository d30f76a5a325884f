// Passive forces: joint springs about springref and viscous damping, the tendons' spring-dampers
// (tendon.cpp), and the fluid's drag (fluid.cpp), in MuJoCo 2.2.2's mj_passive's order.
#include <lever/dynamics.hpp>

#include <cmath>

#include "basics/basics.hpp"
#include "model/model_room.hpp"
#include "smooth/smooth.hpp"

namespace lever {

namespace {

// A ball's spring: a torque -k r about the body's axes, r the rotation vector that turns the
// spring's reference quaternion into the joint's (MuJoCo's mju_subQuat), subtracted from zero as
// MuJoCo subtracts it. Without stiffness, at a finite quaternion (r is finite then), the torque is
// 0 - 0 r = +0 and r is not computed; at a bad one it is, so that its NaN reaches the force as in
// MuJoCo.
void ball_spring(double k, const double* quat, const double* reference, double* torque) {
  if (k == 0 && std::isfinite(quat[0] + quat[1] + quat[2] + quat[3])) {
    for (int c = 0; c < 3; ++c) torque[c] = 0.0;
    return;
  }
  const Eigen::Vector3d r = detail::quat_difference(quat, reference);
  for (int c = 0; c < 3; ++c) torque[c] = 0.0 - k * r[c];
}

}  // namespace

void unchecked::passive(const Model& model, Data& data) {
  double* const qfrc = data.qfrc_passive.data();
  if (model.opt.disabled(kDisablePassive)) {
    for (int i = 0; i < model.nv; ++i) qfrc[i] = 0.0;
    return;
  }
  const double* const qpos = data.qpos.data();
  const double* const spring = model.qpos_spring.data();
  const int* const qposadr = model.jnt_qposadr.data();
  const int* const dofadr = model.jnt_dofadr.data();
  const JointKind* const kind = model.jnt_kind.data();
  for (int j = 0; j < model.njnt; ++j) {
    const double k = model.jnt_stiffness[j];
    const int q = qposadr[j];
    const int d = dofadr[j];
    switch (kind[j]) {
      case JointKind::kFree:  // a spring on the position, then one on the orientation
        for (int c = 0; c < 3; ++c) qfrc[d + c] = 0.0 - k * (qpos[q + c] - spring[q + c]);
        ball_spring(k, qpos + q + 3, spring + q + 3, qfrc + d + 3);
        break;
      case JointKind::kBall: ball_spring(k, qpos + q, spring + q, qfrc + d); break;
      default: qfrc[d] = 0.0 - k * (qpos[q] - spring[q]);
    }
  }
  const double* const damping = model.dof_damping.data();
  const double* const qvel = data.qvel.data();
  for (int i = 0; i < model.nv; ++i) qfrc[i] -= damping[i] * qvel[i];
  if (model.ntendon > 0) add_tendon_passive(model, data);
  if (has_fluid(model.opt)) detail::add_fluid_forces(model, data);
}

void passive(const Model& model, Data& data) {
  check_entry(model, data, "lever::passive");
  unchecked::passive(model, data);
}

}  // namespace lever
