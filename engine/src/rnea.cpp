// Recursive Newton-Euler inverse dynamics: Featherstone's Table 5.1, symbol for symbol.
//
//   lambda(i) = model.dof_parentid[i] (-1: the world), S_i = model.link_S[i],
//   Xup[i] = ^i X_lambda(i) from kinematics(), I_i = model.link_inertia[i] (link coordinates).
// Gravity enters as a fictitious upward acceleration of the world, a_0 = -a_g, so the result
// includes the gravity torques (MuJoCo's qfrc_bias does too).
#include <lever/data.hpp>
#include <lever/dynamics.hpp>

namespace lever {

namespace {

// tau = ID(q, qd, qdd) without armature; qdd == nullptr means zero acceleration.
void newton_euler(const Model& model, Data& data, const double* qdd, Eigen::Ref<Eigen::VectorXd> tau) {
  auto& v = data.work.v;
  auto& a = data.work.a;
  auto& f = data.work.f;
  Motion a_world;
  a_world << 0.0, 0.0, 0.0, -model.opt.gravity;

  // forward pass: velocity, acceleration and the net force each link needs, root to leaves
  for (int i = 0; i < model.nv; ++i) {
    const int lambda = model.dof_parentid[i];
    const Motion& S = model.link_S[i];
    const Transform& X = data.Xup[i];
    const Motion vJ = S * data.qvel[i];
    if (lambda < 0) {
      v[i] = vJ;
      a[i] = X.apply(a_world);
    } else {
      v[i] = X.apply(v[lambda]) + vJ;
      a[i] = X.apply(a[lambda]) + cross_motion(v[i], vJ);
    }
    if (qdd != nullptr) a[i] += S * qdd[i];
    const RigidInertia& I = model.link_inertia[i];
    f[i] = I * a[i] + cross_force(v[i], I * v[i]);
  }

  // backward pass: each joint transmits the force of its whole subtree
  for (int i = model.nv - 1; i >= 0; --i) {
    tau[i] = model.link_S[i].dot(f[i]);
    const int lambda = model.dof_parentid[i];
    if (lambda >= 0) f[lambda] += data.Xup[i].apply_transpose(f[i]);
  }
}

}  // namespace

void bias(const Model& model, Data& data) { newton_euler(model, data, nullptr, data.qfrc_bias); }

void rnea(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc,
          Eigen::Ref<Eigen::VectorXd> tau) {
  newton_euler(model, data, qacc.data(), tau);
  // armature is part of M (crba adds it), so it is part of M qacc here too
  for (int i = 0; i < model.nv; ++i) tau[i] += model.dof_armature[i] * qacc[i];
}

}  // namespace lever
