// Potential and kinetic energy (MuJoCo's mj_energyPos and mj_energyVel): forward() computes them
// with <flag energy="enable">, compute_energy() on demand.
#include <lever/dynamics.hpp>

#include "basics/basics.hpp"
#include "model/model_room.hpp"
#include "smooth/smooth.hpp"

namespace lever {

void unchecked::energy_position(const Model& model, Data& data) {
  // gravity: -m g . x_com for every body; springs: k (q - q_spring)^2 / 2, tendons' included
  double potential = 0.0;
  if (!model.opt.disabled(kDisableGravity)) {
    for (int b = 1; b < model.nbody; ++b) {
      potential -= model.body_mass[b] * model.opt.gravity.dot(data.xipos[b]);
    }
  }
  if (model.opt.disabled(kDisablePassive)) {
    data.energy[0] = potential;
    return;
  }
  for (int j = 0; j < model.njnt; ++j) {
    const double k = model.jnt_stiffness[j];
    const int q = model.jnt_qposadr[j];
    switch (model.jnt_kind[j]) {
      case JointKind::kFree: {  // stretch of the position, then turn of the orientation
        const Eigen::Vector3d stretch = data.qpos.segment<3>(q) - model.qpos_spring.segment<3>(q);
        potential += 0.5 * k * stretch.dot(stretch);
        const Eigen::Vector3d turn =
            detail::quat_difference(&data.qpos[q + 3], &model.qpos_spring[q + 3]);
        potential += 0.5 * k * turn.dot(turn);
        break;
      }
      case JointKind::kBall: {
        const Eigen::Vector3d turn = detail::quat_difference(&data.qpos[q], &model.qpos_spring[q]);
        potential += 0.5 * k * turn.dot(turn);
        break;
      }
      default: {
        const double stretch = data.qpos[q] - model.qpos_spring[q];
        potential += 0.5 * k * stretch * stretch;
      }
    }
  }
  // the tendons' springs: k (L - lengthspring)^2 / 2, with L the position stage's ten_length
  for (int t = 0; t < model.ntendon; ++t) {
    const double stretch = data.ten_length[t] - model.tendon_lengthspring[t];
    if (model.tendon_stiffness[t] > 0) potential += 0.5 * model.tendon_stiffness[t] * stretch * stretch;
  }
  data.energy[0] = potential;
}

void unchecked::energy_velocity(const Model& model, Data& data) {
  // M qvel and its product with qvel, each summed in MuJoCo's order (mj_mulM, mju_dot)
  double* const momentum = data.work.vec1.data();  // preallocated: no heap use here
  detail::mass_times(model, data, data.qvel.data(), momentum);
  data.energy[1] = 0.5 * dot_as_mujoco(momentum, data.qvel.data(), 0, model.nv, model.nv);
}

void compute_energy(const Model& model, Data& data) {
  check_entry(model, data, "lever::compute_energy");
  unchecked::energy_position(model, data);
  unchecked::energy_velocity(model, data);
}

}  // namespace lever
