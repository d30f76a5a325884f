// Fixed tendons (MuJoCo 2.2.2's mj_tendon for a path of joints, the tendon part of mj_fwdVelocity
// and of mj_passive).
//
// A fixed tendon's length is a weighted sum of its joints' coordinates, L = sum_k c_k q_k (qpos
// itself, not its offset from qpos0), so its Jacobian is the constant row with c_k at each
// joint's dof, and its velocity J qvel. Along it acts a spring-damper,
// f = -stiffness (L - lengthspring) - damping v, carried to the dofs as J^T f. The Jacobian is
// dense, as MuJoCo's ten_J for models it keeps dense (nv < 60): a joint named twice keeps its
// last coefficient, as MuJoCo writes it.
#include <lever/dynamics.hpp>

#include "model/model_room.hpp"
#include "smooth/smooth.hpp"

namespace lever {

void unchecked::tendon(const Model& model, Data& data) {
  const int nv = model.nv;
  for (int t = 0; t < model.ntendon; ++t) {
    double* const J = data.ten_J.data() + static_cast<std::ptrdiff_t>(t) * nv;
    for (int j = 0; j < nv; ++j) J[j] = 0.0;
    double length = 0.0;
    const int first = model.tendon_adr[t], end = first + model.tendon_num[t];
    for (int w = first; w < end; ++w) {  // validate() admits fixed tendons only
      const int joint = model.wrap_objid[w];
      const double coef = model.wrap_prm[w];
      length += coef * data.qpos[model.jnt_qposadr[joint]];
      J[model.jnt_dofadr[joint]] = coef;
    }
    data.ten_length[t] = length;
  }
}

void unchecked::tendon_velocity(const Model& model, Data& data) {
  const int nv = model.nv;
  const double* const qvel = data.qvel.data();
  for (int t = 0; t < model.ntendon; ++t) {
    const double* const J = data.ten_J.data() + static_cast<std::ptrdiff_t>(t) * nv;
    double v = 0.0;
    for (int j = 0; j < nv; ++j) v += J[j] * qvel[j];
    data.ten_velocity[t] = v;
  }
}

void add_tendon_passive(const Model& model, Data& data) {
  const int nv = model.nv;
  double* const qfrc = data.qfrc_passive.data();
  for (int t = 0; t < model.ntendon; ++t) {
    const double f = -model.tendon_stiffness[t] * (data.ten_length[t] - model.tendon_lengthspring[t]) -
                     model.tendon_damping[t] * data.ten_velocity[t];
    const double* const J = data.ten_J.data() + static_cast<std::ptrdiff_t>(t) * nv;
    for (int j = 0; j < nv; ++j) qfrc[j] += J[j] * f;
  }
}

void tendon(const Model& model, Data& data) {
  check_entry(model, data, "lever::tendon");
  unchecked::tendon(model, data);
  unchecked::tendon_velocity(model, data);
}

}  // namespace lever
