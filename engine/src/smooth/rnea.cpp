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

#include "model/model_room.hpp"
#include "smooth/recursion.hpp"
#include "smooth/smooth.hpp"

namespace lever {

void unchecked::newton_euler(const Model& model, Data& data, const double* qdd, double* tau) {
  const RigidInertia* const I = data.cinert.data();
  Force* const f = data.work.cfrc.data();
  forward_pass(model, data, data.qvel.data(), qdd, true, data.cvel, data.work.cacc, &data.cdof_dot,
               nullptr, [&](int b, const Motion& vb, const Motion& ab) {
                 f[b] = net_force(I[b], vb, ab);  // I a + v x* I v
               });
  backward_pass(model, data, data.work.cfrc, tau);
}

void unchecked::bias(const Model& model, Data& data) {
  unchecked::newton_euler(model, data, nullptr, data.qfrc_bias.data());
}

void bias(const Model& model, Data& data) {
  check_entry(model, data, "lever::bias");
  unchecked::bias(model, data);
}

void rnea(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc,
          Eigen::Ref<Eigen::VectorXd> tau) {
  check_entry(model, data, "lever::rnea");
  check_argument_size(qacc.size(), model.nv, "lever::rnea", "qacc");
  check_argument_size(tau.size(), model.nv, "lever::rnea", "tau");
  unchecked::newton_euler(model, data, qacc.data(), tau.data());
  // armature is part of M (crba adds it), so it is part of M qacc here too
  for (int i = 0; i < model.nv; ++i) tau[i] += model.dof_armature[i] * qacc[i];
}

}  // namespace lever
