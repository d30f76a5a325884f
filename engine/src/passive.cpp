// Passive joint forces: springs about springref and viscous damping (MuJoCo's mj_passive).
#include <lever/dynamics.hpp>

#include "internal.hpp"

namespace lever {

void passive(const Model& model, Data& data) {
  check_entry(model, data, "lever::passive");
  for (int j = 0; j < model.njnt; ++j) {
    const int q = model.jnt_qposadr[j];
    const int d = model.jnt_dofadr[j];
    data.qfrc_passive[d] = -model.jnt_stiffness[j] * (data.qpos[q] - model.qpos_spring[q]) -
                           model.dof_damping[d] * data.qvel[d];
  }
}

}  // namespace lever
