// Passive joint forces: springs about springref and viscous damping (MuJoCo's mj_passive).
#include <lever/dynamics.hpp>

#include "internal.hpp"

namespace lever {

namespace {

// A ball's spring: a torque -k r about the body's axes, r the rotation vector that turns the
// spring's reference quaternion into the joint's (MuJoCo's mju_subQuat).
void ball_spring(double k, const double* quat, const double* reference, double* torque) {
  const Eigen::Vector3d r = detail::quat_difference(quat, reference);
  for (int c = 0; c < 3; ++c) torque[c] = -k * r[c];
}

}  // namespace

void passive(const Model& model, Data& data) {
  check_entry(model, data, "lever::passive");
  for (int j = 0; j < model.njnt; ++j) {
    const double k = model.jnt_stiffness[j];
    const int q = model.jnt_qposadr[j];
    const int d = model.jnt_dofadr[j];
    switch (model.jnt_kind[j]) {
      case JointKind::kFree:  // a spring on the position, then one on the orientation
        for (int c = 0; c < 3; ++c) {
          data.qfrc_passive[d + c] = -k * (data.qpos[q + c] - model.qpos_spring[q + c]);
        }
        ball_spring(k, &data.qpos[q + 3], &model.qpos_spring[q + 3], &data.qfrc_passive[d + 3]);
        break;
      case JointKind::kBall:
        ball_spring(k, &data.qpos[q], &model.qpos_spring[q], &data.qfrc_passive[d]);
        break;
      default: data.qfrc_passive[d] = -k * (data.qpos[q] - model.qpos_spring[q]);
    }
  }
  for (int i = 0; i < model.nv; ++i) data.qfrc_passive[i] -= model.dof_damping[i] * data.qvel[i];
}

}  // namespace lever
