// The body transmission (MuJoCo 2.2.2's mjTRN_BODY in mj_transmission, which <adhesion> uses): an
// actuator that pulls a body onto whatever it touches. It has no length; its moment is minus the
// mean, over the contacts touching the body's geoms, of each contact's normal Jacobian, so a
// positive force pushes each contact point along -n, into contact. It needs the contacts of the
// current state and their rows, which is why it is computed here, after make_constraint, and not
// with the other transmissions in the smooth room.
//
// A contact with rows contributes J^T w, w marking its rows: the normal row itself when it has one
// row (condim 1) or an elliptic cone (the normal row first); with a pyramidal cone its 2(condim-1)
// edges n +- mu_k t_k, each weighted 1/(2(condim-1)), whose mean is the normal. A contact in the
// gap (beyond margin - gap: no rows, MuJoCo's "exclude 1") still counts, its normal row formed from
// the Jacobians. As MuJoCo sums: the rows' products first, in row order, then the gap contacts',
// then the scale -1/count.
#include "constraint/constraint_room.hpp"
#include "model/model_room.hpp"

namespace lever {

void unchecked::body_transmission(const Model& model, Data& data) {
  const int nv = model.nv;
  const bool elliptic = model.opt.cone == Cone::kElliptic;
  for (int a = 0; a < model.nu; ++a) {
    if (model.actuator_trntype[a] != TransmissionType::kBody) continue;
    const int body = model.actuator_trnid[a][0];
    double* const moment = data.actuator_moment.data() + static_cast<std::ptrdiff_t>(a) * nv;
    // scratch: the gap contacts' sum, and one gap contact's normal row
    auto gap_sum = data.work.transmission_jac.row(0);
    double* const normal = data.work.vec3.data();
    gap_sum.setZero();
    for (int j = 0; j < nv; ++j) moment[j] = 0.0;
    int counted = 0;
    for (int i = 0; i < data.ncon; ++i) {
      const Contact& con = data.contact[i];
      if (model.geom_bodyid[con.geom1] != body && model.geom_bodyid[con.geom2] != body) continue;
      // (a contact whose bodies no dof moves has no rows: MuJoCo does not count it)
      if (con.exclude == 0 && con.efc_address >= 0) {
        ++counted;
        const bool normal_only = con.dim == 1 || elliptic;
        const int rows = normal_only ? 1 : 2 * (con.dim - 1);
        const double weight = normal_only ? 1.0 : 0.5 / (con.dim - 1);
        for (int r = con.efc_address; r < con.efc_address + rows; ++r) {
          const double* const J = data.efc_J.data() + static_cast<std::ptrdiff_t>(r) * nv;
          for (int j = 0; j < nv; ++j) moment[j] += J[j] * weight;
        }
      } else if (con.exclude == 1) {
        ++counted;
        contact_normal_row(model, data, i, normal);
        for (int j = 0; j < nv; ++j) gap_sum[j] += normal[j];
      }
    }
    if (counted > 0) {
      const double scale = -1.0 / counted;
      for (int j = 0; j < nv; ++j) moment[j] = (moment[j] + gap_sum[j]) * scale;
    }
    // MuJoCo's mj_fwdVelocity: moment qvel, a dense row whatever the layout (mju_dot)
    data.actuator_velocity[a] = dot_as_mujoco(moment, data.qvel.data(), 0, nv, nv);
  }
}

}  // namespace lever
