// Recursive Newton-Euler inverse dynamics: Featherstone's recursion (RBDA 2008, section 5.3) with
// every quantity in absolute coordinates (see kinematics.cpp), where no transforms are needed:
//   v_b = v_parent + S_i qd_i                       velocity, over the dofs i of body b
//   a_b = a_parent + Sdot_i qd_i + S_i qdd_i        Sdot_i = v x S_i, v the velocity before dof i
//   f_b = I_b a_b + v_b x* I_b v_b                  net force on body b
//   f_parent += f_b  (leaves to root);  tau_i = S_i . f_body(i)
// Gravity enters as a fictitious upward acceleration of the world, a_0 = -a_g, so the result
// includes the gravity torques (MuJoCo's qfrc_bias does too).
#include <lever/data.hpp>
#include <lever/dynamics.hpp>

#include "internal.hpp"

namespace lever {

namespace {

// tau = ID(q, qd, qdd) without armature; qdd == nullptr means zero acceleration. Also leaves the
// body velocities and the derivatives of the motion subspaces in data (cvel, cdof_dot).
void newton_euler(const Model& model, Data& data, const double* qdd,
                  Eigen::Ref<Eigen::VectorXd> tau) {
  auto& v = data.cvel;
  auto& a = data.work.cacc;
  auto& f = data.work.cfrc;
  v[0].setZero();
  a[0] << 0.0, 0.0, 0.0, -model.opt.gravity;

  // forward pass: velocity, acceleration and the net force each body needs, root to leaves
  for (int b = 1; b < model.nbody; ++b) {
    const int parent = model.body_parentid[b];
    Motion vb = v[parent];
    Motion ab = a[parent];
    bool moving = parent > 0;  // the world does not move: its children's first Sdot is zero
    for (int k = 0; k < model.body_dofnum[b]; ++k) {
      const int i = model.body_dofadr[b] + k;
      const Motion& S = data.cdof[i];
      if (moving) {
        data.cdof_dot[i] = cross_motion(vb, S);  // S moves with the body carrying it
        ab += data.cdof_dot[i] * data.qvel[i];
      } else {
        data.cdof_dot[i].setZero();
        moving = true;
      }
      vb += S * data.qvel[i];
      if (qdd != nullptr) ab += S * qdd[i];
    }
    v[b] = vb;
    a[b] = ab;
    const RigidInertia& I = data.cinert[b];
    f[b] = I * ab + cross_force(vb, I * vb);
  }

  // backward pass: each joint transmits the force of its whole subtree
  for (int b = model.nbody - 1; b > 0; --b) {
    const int parent = model.body_parentid[b];
    if (parent > 0) f[parent] += f[b];
  }
  for (int i = 0; i < model.nv; ++i) tau[i] = data.cdof[i].dot(f[model.dof_bodyid[i]]);
}

}  // namespace

void bias(const Model& model, Data& data) {
  check_entry(model, data, "lever::bias");
  newton_euler(model, data, nullptr, data.qfrc_bias);
}

void rnea(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc,
          Eigen::Ref<Eigen::VectorXd> tau) {
  check_entry(model, data, "lever::rnea");
  check_argument_size(qacc.size(), model.nv, "lever::rnea", "qacc");
  check_argument_size(tau.size(), model.nv, "lever::rnea", "tau");
  newton_euler(model, data, qacc.data(), tau);
  // armature is part of M (crba adds it), so it is part of M qacc here too
  for (int i = 0; i < model.nv; ++i) tau[i] += model.dof_armature[i] * qacc[i];
}

}  // namespace lever
