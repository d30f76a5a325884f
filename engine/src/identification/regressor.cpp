// The inertial-parameter regressor (see lever/regressor.hpp).
//
// RNEA's net force on body b, f_b = I_b a_b + v_b x* I_b v_b, is linear in the body's spatial
// inertia I_b, and I_b is linear in pi_b when all three are written in the body's own frame (origin
// at the body frame, body axes). So with v, a moved into that frame by the motion transform X_b,
//   f_b(body frame) = sum_k pi_b,k (E_k a + v x* E_k v),   E_k the inertia of unit parameter k,
// and tau_i = S_i . (the forces of the bodies i supports) = sum_b (X_b S_i) . f_b(body frame).
// Column k of body b's block is therefore (X_b S_i) . (E_k a_b + v_b x* E_k v_b) for each dof i
// that supports b, and zero for the others.
#include <lever/error.hpp>
#include <lever/regressor.hpp>
#include <lever/spatial.hpp>


#include "smooth/recursion.hpp"
#include "identification/identification.hpp"

namespace lever {

namespace {

using detail::kPerBody;

// The spatial inertia of unit parameter k (not a physical body: the basis of a linear map).
RigidInertia unit_inertia(int k) {
  InertialParameters unit = InertialParameters::Zero();
  unit[k] = 1;
  return RigidInertia::from_parameters(unit);
}

// A motion vector about c with world axes, moved to the body frame (origin p, rotation R).
Motion to_body_frame(const Motion& m, const Eigen::Vector3d& c, const Eigen::Vector3d& p,
                     const Mat3& R) {
  Motion out;
  out.head<3>() = rotate_back(R, m.head<3>());
  out.tail<3>() = rotate_back(R, m.tail<3>() + cross(m.head<3>(), p - c));
  return out;
}

}  // namespace

void regressor(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc,
               Eigen::Ref<Eigen::MatrixXd> Y) {
  if (qacc.size() != model.nv || Y.rows() != model.nv || Y.cols() != regressor_columns(model) ||
      data.nv != model.nv) {
    throw StateError("regressor: qacc must have nv elements and Y be nv x regressor_columns.");
  }
  if (model.ntendon > 0) {
    throw ModelError("regressor: the model has tendons (tendon '" + model.tendon_name[0] +
                     "'); the regressor does not cover tendon forces or tendon-driven actuators "
                     "yet.");
  }
  require_simple_actuators(model, "regressor");
  Y.setZero();
  // velocities and accelerations of every body (RNEA's forward pass; gravity as a_0 = -g), kept
  // in Data's RNEA workspace
  auto& v = data.cvel;
  auto& a = data.work.cacc;
  forward_pass(model, data, data.qvel.data(), qacc.data(), true, v, a, nullptr, nullptr);
  for (int b = 1; b < model.nbody; ++b) {
    const Motion& vb = v[b];
    const Motion& ab = a[b];

    // body b's block: the dofs that support it, seen in its frame
    const Eigen::Vector3d& c = data.subtree_com[model.body_rootid[b]];
    const Eigen::Vector3d& p = data.xpos[b];
    const Mat3& R = data.xmat[b];
    const Motion vB = to_body_frame(vb, c, p, R), aB = to_body_frame(ab, c, p, R);
    Eigen::Matrix<double, 6, kPerBody> F;  // net force of each unit parameter
    for (int k = 0; k < kPerBody; ++k) F.col(k) = net_force(unit_inertia(k), vB, aB);
    int top = b;  // the nearest body at or above b that has dofs
    while (top > 0 && model.body_dofnum[top] == 0) top = model.body_parentid[top];
    if (top == 0) continue;
    for (int i = model.body_dofadr[top] + model.body_dofnum[top] - 1; i >= 0;
         i = model.dof_parentid[i]) {
      const Motion S = to_body_frame(data.cdof[i], c, p, R);
      Y.block<1, kPerBody>(i, kPerBody * (b - 1)) = S.transpose() * F;
    }
  }
  const int tail = kPerBody * (model.nbody - 1);
  for (int i = 0; i < model.nv; ++i) {
    Y(i, tail + i) = qacc[i];                  // armature: part of M
    Y(i, tail + model.nv + i) = data.qvel[i];  // damping: the motor supplies + b qvel
  }
  // gains: the actuator's gain-scaled torque, moved to the parameter side (hence the sign)
  int column = tail + 2 * model.nv;
  for (int u = 0; u < model.nu; ++u) {
    if (!has_gain_column(model, u)) continue;
    const int j = model.actuator_trnid[u][0];  // a hinge or slide (checked above)
    const int q = model.jnt_qposadr[j], d = model.jnt_dofadr[j];
    Y(d, column++) = -model.actuator_gear[u][0] *
                     actuator_gain_basis(model, u, data.ctrl[u], data.qpos[q], data.qvel[d]);
  }
}

}  // namespace lever
