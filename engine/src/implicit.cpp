// MuJoCo 2.2.2's implicit integrator (mjINT_IMPLICIT, engine_forward.c mj_implicit): the step is
// implicit in every velocity-dependent force. With D = d qfrc_smooth / d qvel at the step's start,
//   (M - h D) qacc_implicit = qfrc_smooth + qfrc_constraint,
// then qvel += h qacc_implicit and qpos += h qvel (the new qvel), as in the Euler step.
//
// D is what MuJoCo 2.2.2's mjd_smooth_vel holds, term by term (engine_derivative.c):
//   actuators: each affine bias contributes biasprm[2], each affine gain gainprm[2] * ctrl, times
//              gear^2 on its dof; the raw ctrl is used and the ctrl and force clamps are ignored
//              (so a clamped servo still damps implicitly, exactly as in MuJoCo);
//   passive:   -damping on the diagonal (joint springs do not depend on qvel);
//   bias:      -d qfrc_bias / d qvel: the Coriolis and centrifugal terms, differentiated through
//              the Newton-Euler recursion below (gravity does not depend on qvel).
// The constraint force is taken from the forward solve and held fixed, as MuJoCo does.
#include <lever/dynamics.hpp>
#include <lever/error.hpp>

#include <string>

#include "internal.hpp"

namespace lever {

namespace {

// One column of d qfrc_bias / d qvel: the Newton-Euler recursion of rnea.cpp differentiated with
// respect to qvel_j. cdof and cinert do not depend on qvel; cvel and cdof_dot do:
//   dv_b = dv_parent + S_j [if j is a dof of b]          (within a body, dof by dof)
//   dSdot_i = dv x S_i                 (dv: before dof i's segment, detail::starts_segment)
//   da_b = da_parent + dSdot_i qd_i + Sdot_j [if j is a dof of b]
//   df_b = I_b da_b + dv_b x* I_b v_b + v_b x* I_b dv_b
// then the forces are summed leaves to root and projected on each dof. Only the subtree of dof
// j's body moves with qvel_j: every term of the other bodies is zero, so the recursion runs over
// that subtree alone, and the dofs above it see the subtree's whole force.
void bias_velocity_column(const Model& model, Data& data, int j, Eigen::Ref<Eigen::VectorXd> out) {
  auto& dv = data.work.dcvel;
  auto& da = data.work.dcacc;
  auto& df = data.work.dcfrc;
  auto& in_subtree = data.work.in_subtree;
  const int top = model.dof_bodyid[j];
  for (int b = top; b < model.nbody; ++b) {  // children come after their parents
    const int parent = model.body_parentid[b];
    in_subtree[b] = b == top || (parent >= top && in_subtree[parent]);
    if (!in_subtree[b]) continue;
    Motion dvb = b == top ? Motion::Zero() : dv[parent];
    Motion dab = b == top ? Motion::Zero() : da[parent];
    Motion dv_segment;  // dv before dof i's segment (detail::starts_segment)
    for (int k = 0; k < model.body_dofnum[b]; ++k) {
      const int i = model.body_dofadr[b] + k;
      const Motion& S = data.cdof[i];
      if (detail::starts_segment(model, i)) dv_segment = dvb;
      dab += cross_motion(dv_segment, S) * data.qvel[i];
      if (i == j) {
        dab += data.cdof_dot[i];
        dvb += S;
      }
    }
    dv[b] = dvb;
    da[b] = dab;
    const RigidInertia& I = data.cinert[b];
    df[b] = I * dab + cross_force(dvb, I * data.cvel[b]) + cross_force(data.cvel[b], I * dvb);
  }
  for (int b = model.nbody - 1; b > top; --b) {
    if (in_subtree[b]) df[model.body_parentid[b]] += df[b];
  }
  out.setZero();
  for (int b = top; b < model.nbody; ++b) {
    if (!in_subtree[b]) continue;
    for (int k = 0; k < model.body_dofnum[b]; ++k) {
      const int i = model.body_dofadr[b] + k;
      out[i] = data.cdof[i].dot(df[b]);
    }
  }
  // the dofs above: each carries the subtree's force (no other body's term is non-zero)
  const int first = model.body_dofadr[top];
  for (int i = model.dof_parentid[first]; i >= 0; i = model.dof_parentid[i]) {
    out[i] = data.cdof[i].dot(df[top]);
  }
}

}  // namespace

void smooth_velocity_derivative(const Model& model, Data& data,
                                Eigen::Ref<Eigen::MatrixXd> qDeriv) {
  check_entry(model, data, "lever::smooth_velocity_derivative");
  if (qDeriv.rows() != model.nv || qDeriv.cols() != model.nv) {
    throw StateError("lever::smooth_velocity_derivative: qDeriv is " +
                     std::to_string(qDeriv.rows()) + " x " + std::to_string(qDeriv.cols()) +
                     " but must be nv x nv = " + std::to_string(model.nv) + " x " +
                     std::to_string(model.nv) + ".");
  }
  qDeriv.setZero();

  // actuators: d force / d velocity of the affine bias and gain, carried to the dof by the gear
  for (int a = 0; a < model.nu; ++a) {
    double force_per_velocity = 0.0;
    if (model.actuator_biastype[a] == BiasType::kAffine) {
      force_per_velocity = model.actuator_biasprm[a][2];
    }
    if (model.actuator_gaintype[a] == GainType::kAffine) {
      force_per_velocity += model.actuator_gainprm[a][2] * data.ctrl[a];
    }
    const double gear = model.actuator_gear[a][0];
    const int dof = model.jnt_dofadr[model.actuator_trnid[a]];
    qDeriv(dof, dof) += gear * force_per_velocity * gear;
  }

  // joint damping
  for (int i = 0; i < model.nv; ++i) qDeriv(i, i) -= model.dof_damping[i];

  // minus the velocity derivative of the bias force, one column per dof
  for (int j = 0; j < model.nv; ++j) {
    Eigen::VectorXd& column = data.work.vec3;
    bias_velocity_column(model, data, j, column);
    qDeriv.col(j) -= column;
  }
}

namespace detail {

void implicit_step(const Model& model, Data& data) {
  const double h = model.opt.timestep;
  auto& w = data.work;
  smooth_velocity_derivative(model, data, w.qDeriv);
  w.qDeriv = data.M - h * w.qDeriv;  // M - h D, factored in place of D
  w.qLU.compute(w.qDeriv);
  w.vec1 = data.qfrc_smooth + data.qfrc_constraint;
  w.vec2.noalias() = w.qLU.solve(w.vec1);
  data.qvel += h * w.vec2;
  integrate_positions(model, data.qpos.data(), data.qvel.data(), h);
  data.time += h;
}

}  // namespace detail

}  // namespace lever
