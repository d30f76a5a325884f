// Potential and kinetic energy (MuJoCo's mj_energyPos and mj_energyVel).
#include <lever/dynamics.hpp>

#include "internal.hpp"

namespace lever {

void compute_energy(const Model& model, Data& data) {
  check_entry(model, data, "lever::compute_energy");
  // gravity: -m g . x_com for every body; springs: k (q - q_spring)^2 / 2
  double potential = 0.0;
  for (int b = 1; b < model.nbody; ++b) {
    potential -= model.body_mass[b] * model.opt.gravity.dot(data.xipos[b]);
  }
  for (int j = 0; j < model.njnt; ++j) {
    const int q = model.jnt_qposadr[j];
    const double stretch = data.qpos[q] - model.qpos_spring[q];
    potential += 0.5 * model.jnt_stiffness[j] * stretch * stretch;
  }
  data.energy[0] = potential;
  Eigen::VectorXd& momentum = data.work.vec1;  // preallocated: no heap use here
  momentum.noalias() = data.M * data.qvel;
  data.energy[1] = 0.5 * data.qvel.dot(momentum);
}

}  // namespace lever
