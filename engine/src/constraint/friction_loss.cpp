// Dry friction on a dof as MuJoCo 2.2.2's friction-loss rows (mj_instantiateFriction, and the
// friction case of mj_diagApprox and mj_makeImpedance).
//
// A dof with dof_frictionloss = f > 0 gets one row, J = e_dof, after the equality rows and before
// the limits. It has no position (pos = margin = 0, so its impedance is solimp's d0 and its
// stiffness K is zero): its reference acceleration is -B v, a damper that stops the dof. Its force
// is boxed, |force| <= f. In the primal problem Newton's method solves (newton.cpp) the row's cost
// is Huber's: quadratic 1/2 D jar^2 while |jar| < R f (the force -D jar inside the box), linear
// f |jar| - 1/2 R f^2 beyond (the force +-f at the box's side).
//
// A tendon with tendon_frictionloss > 0 gets such a row too, after every dof's: its Jacobian is
// the tendon's (ten_J), its diagApprox tendon_invweight0, its solref and solimp the tendon's
// friction ones.
#include "constraint/constraint_room.hpp"

namespace lever {

int add_friction_loss_rows(const Model& model, Data& data, int n) {
  for (int dof = 0; dof < model.nv; ++dof) {
    const double loss = model.dof_frictionloss[dof];
    if (!(loss > 0)) continue;
    data.efc_type[n] = ConstraintType::kFrictionDof;
    data.efc_id[n] = dof;
    data.efc_dof[n] = dof;
    data.efc_sign[n] = 1.0;
    data.efc_J.row(n).setZero();
    data.efc_J(n, dof) = 1.0;
    data.efc_pos[n] = 0.0;
    data.efc_margin[n] = 0.0;
    data.efc_frictionloss[n] = loss;

    std::array<double, 2> solref = model.dof_solref[dof];
    std::array<double, 5> solimp = model.dof_solimp[dof];
    sanitize(model, solref, solimp);
    const SoftParameters soft = soft_parameters(solref, solimp, 0.0, 0.0);
    set_soft_row(data, n, soft, 0.0, regularizer(soft, model.dof_invweight0[dof]));
    ++n;
  }
  const int nv = model.nv;
  for (int t = 0; t < model.ntendon; ++t) {
    const double loss = model.tendon_frictionloss[t];
    if (!(loss > 0)) continue;
    data.efc_type[n] = ConstraintType::kFrictionTendon;
    data.efc_id[n] = t;
    data.efc_dof[n] = -1;
    data.efc_sign[n] = 0.0;
    const double* const J = data.ten_J.data() + static_cast<std::ptrdiff_t>(t) * nv;
    for (int j = 0; j < nv; ++j) data.efc_J(n, j) = J[j];
    data.efc_pos[n] = 0.0;
    data.efc_margin[n] = 0.0;
    data.efc_frictionloss[n] = loss;

    std::array<double, 2> solref = model.tendon_solref_fri[t];
    std::array<double, 5> solimp = model.tendon_solimp_fri[t];
    sanitize(model, solref, solimp);
    const SoftParameters soft = soft_parameters(solref, solimp, 0.0, 0.0);
    set_soft_row(data, n, soft, 0.0, regularizer(soft, model.tendon_invweight0[t]));
    ++n;
  }
  return n;
}

}  // namespace lever
