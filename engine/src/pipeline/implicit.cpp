// MuJoCo 2.2.2's implicit integrator (mjINT_IMPLICIT, engine_forward.c mj_implicit): the step is
// implicit in every velocity-dependent force. With D = d qfrc_smooth / d qvel at the step's start,
//   (M - h D) qacc_implicit = qfrc_smooth + qfrc_constraint,
// then qvel += h qacc_implicit and qpos += h qvel (the new qvel), as in the Euler step.
//
// D is what MuJoCo 2.2.2's mjd_smooth_vel holds, term by term (engine_derivative.c):
//   actuators: each affine bias contributes biasprm[2], each affine gain gainprm[2] * ctrl, times
//              gear^2 on its dof; the raw ctrl is used and the ctrl and force clamps are ignored
//              (so a clamped servo still damps implicitly, exactly as in MuJoCo);
//              a tendon actuator's moment row m adds m^T (d force / d velocity) m;
//   passive:   -damping on the diagonal (joint springs do not depend on qvel), each tendon's
//              -damping J^T J (its Jacobian J), and the fluid's drag as mjd_inertiaBoxFluid takes
//              it (smooth/fluid.cpp);
//   bias:      -d qfrc_bias / d qvel: the Coriolis and centrifugal terms, by mjd_rne_vel's chain
//              rule and rounded as it rounds them (derivatives/bias_velocity_chain.cpp; gravity
//              and qacc do not depend on qvel).
// The constraint force is taken from the forward solve and held fixed, as MuJoCo does.
//
// M - h D is not symmetric, but it is non-zero only where M is (pairs of dofs on one branch), so,
// as MuJoCo, it is factored without pivoting from the leaves up, where nothing fills in.
//
// MuJoCo 3's implicitfast (mjINT_IMPLICITFAST, engine_forward.c mj_implicitSkip) is the same step
// with D holding the actuator and damping terms only (mjd_smooth_vel with flg_bias = 0: no
// Coriolis derivative). That D is symmetric (and kept where M is non-zero), so
// M - h D is factored as M is, LTDL on the tree (MuJoCo 3's mj_factorI), and solved as M is.
#include <lever/dynamics.hpp>
#include <lever/error.hpp>

#include <string>

#include "derivatives/derivatives_room.hpp"
#include "model/model_room.hpp"
#include "pipeline/pipeline.hpp"
#include "smooth/smooth.hpp"

namespace lever {

void smooth_velocity_derivative(const Model& model, Data& data,
                                Eigen::Ref<Eigen::MatrixXd> qDeriv) {
  check_entry(model, data, "lever::smooth_velocity_derivative");
  if (qDeriv.rows() != model.nv || qDeriv.cols() != model.nv) {
    throw StateError("lever::smooth_velocity_derivative: qDeriv is " +
                     std::to_string(qDeriv.rows()) + " x " + std::to_string(qDeriv.cols()) +
                     " but must be nv x nv = " + std::to_string(model.nv) + " x " +
                     std::to_string(model.nv) + ".");
  }
  // summed in mjd_smooth_vel's order: the actuators, the passive forces, then minus the bias
  // force's derivative
  qDeriv.setZero();
  add_actuator_damping_velocity_terms(model, data, qDeriv);
  if (has_fluid(model.opt) && !model.opt.disabled(kDisablePassive)) {
    detail::add_fluid_velocity_terms(model, data, qDeriv);
  }
  subtract_bias_velocity_derivative(model, data, qDeriv);
}

namespace {

// D += J^T b J for a row J (nv numbers), where M is non-zero only: at dof pairs on one branch of the
// tree (MuJoCo adds the whole product, then keeps M's sparsity pattern in its qDeriv). Each element
// as MuJoCo's addJTBJ forms it: (J_k b) J_j.
void add_row_outer_product(const Model& model, const double* J, double b,
                           Eigen::Ref<Eigen::MatrixXd> D) {
  for (int k = 0; k < model.nv; ++k) {
    if (J[k] == 0.0) continue;
    for (int j = k; j >= 0; j = model.dof_parentid[j]) {
      if (J[j] == 0.0) continue;
      D(k, j) += J[k] * b * J[j];
      if (j != k) D(j, k) += J[j] * b * J[k];
    }
  }
}

}  // namespace

void add_actuator_damping_velocity_terms(const Model& model, const Data& data,
                                         Eigen::Ref<Eigen::MatrixXd> D) {
  // actuators: d force / d velocity of the affine bias and gain, carried to the dof by the gear
  const int actuators = model.opt.disabled(kDisableActuation) ? 0 : model.nu;
  for (int a = 0; a < actuators; ++a) {
    double force_per_velocity = 0.0;
    if (model.actuator_biastype[a] == BiasType::kAffine) {
      force_per_velocity = model.actuator_biasprm[a][2];
    }
    // the gain's velocity term times what the gain multiplies: the raw ctrl (MuJoCo's, without
    // its clamp), or the activation
    double gain_per_velocity = 0.0;
    if (model.actuator_gaintype[a] == GainType::kAffine) {
      gain_per_velocity = model.actuator_gainprm[a][2];
    } else if (model.actuator_gaintype[a] == GainType::kMuscle) {
      gain_per_velocity = muscle_gain_per_velocity(
          data.actuator_length[a], data.actuator_velocity[a], model.actuator_lengthrange[a],
          model.actuator_acc0[a], model.actuator_gainprm[a].data());
    }
    if (gain_per_velocity != 0.0) {
      const int first_stateful = model.nu - model.na;
      force_per_velocity += gain_per_velocity * (a < first_stateful ? data.ctrl[a]
                                                                    : data.act[a - first_stateful]);
    }
    const int dof = model.actuator_scalar_dof[a];
    if (dof < 0) {  // moment^T (d force / d velocity) moment
      if (force_per_velocity != 0.0) {
        add_row_outer_product(model, data.actuator_moment.row(a).data(), force_per_velocity, D);
      }
      continue;
    }
    const double gear = model.actuator_gear[a][0];
    D(dof, dof) += gear * force_per_velocity * gear;
  }
  if (model.opt.disabled(kDisablePassive)) return;  // no dampers either
  // joint damping
  for (int i = 0; i < model.nv; ++i) D(i, i) -= model.dof_damping[i];
  // tendon damping: -damping J^T J over the tendon's Jacobian
  for (int t = 0; t < model.ntendon; ++t) {
    if (model.tendon_damping[t] > 0) {
      add_row_outer_product(model, data.ten_J.row(t).data(), -model.tendon_damping[t], D);
    }
  }
}

void factor_lu_tree(const Model& model, Eigen::Ref<Eigen::MatrixXd> K) {
  // eliminate dof k from its ancestors' rows, leaves first: row i -= (K(i, k) / K(k, k)) row k
  // for each ancestor i, over the columns where row k is still non-zero (k's ancestors j);
  // K(i, k) keeps the multiplier. Column by column, each column's elements in turn. M - h D is
  // dominated by M; a zero pivot (which MuJoCo stops on) makes qvel non-finite, and the next
  // step's state check resets it with a kBadQvel warning.
  for (int k = model.nv - 1; k >= 0; --k) {
    double* multiplier = &K(0, k);  // column k: K(i, k) for the ancestors i
    for (int i = model.dof_parentid[k]; i >= 0; i = model.dof_parentid[i]) {
      multiplier[i] /= multiplier[k];
    }
    for (int j = model.dof_parentid[k]; j >= 0; j = model.dof_parentid[j]) {
      double* column = &K(0, j);
      const double row_k = column[k];
      for (int i = model.dof_parentid[k]; i >= 0; i = model.dof_parentid[i]) {
        column[i] -= row_k * multiplier[i];
      }
    }
  }
}

void solve_lu_tree(const Model& model, const Eigen::Ref<const Eigen::MatrixXd>& LU, double* x,
                   int* ancestors) {
  // (U + I) y = x, leaves to root: each x[i] takes its descendants' terms, the last dof first
  for (int k = model.nv - 1; k >= 0; --k) {
    for (int i = model.dof_parentid[k]; i >= 0; i = model.dof_parentid[i]) x[i] -= x[k] * LU(i, k);
  }
  // L x = y, root to leaves: each x[k] takes its ancestors' terms, the root first as in
  // mju_solveLUSparse (row k's columns in order), listed in `ancestors` nearest first
  for (int k = 0; k < model.nv; ++k) {
    int n = 0;
    for (int j = model.dof_parentid[k]; j >= 0; j = model.dof_parentid[j]) ancestors[n++] = j;
    while (n > 0) {
      const int j = ancestors[--n];
      x[k] -= x[j] * LU(k, j);
    }
    x[k] /= LU(k, k);
  }
}

namespace detail {

void implicit_step(const Model& model, Data& data) {
  const double h = model.opt.timestep;
  auto& w = data.work;
  smooth_velocity_derivative(model, data, w.qDeriv);
  w.qLU = data.M - h * w.qDeriv;
  factor_lu_tree(model, w.qLU);
  w.vec1 = data.qfrc_smooth + data.qfrc_constraint;
  solve_lu_tree(model, w.qLU, w.vec1.data(), w.dof_chain.data());
  advance_activations(model, data, data.act_dot.data(), h);
  data.qvel += h * w.vec1;
  integrate_positions(model, data.qpos.data(), data.qvel.data(), h);
  data.time += h;
}

void implicit_fast_step(const Model& model, Data& data) {
  const double h = model.opt.timestep;
  auto& w = data.work;
  w.qDeriv.setZero();
  add_actuator_damping_velocity_terms(model, data, w.qDeriv);
  factor_mass_minus(model, data, w.qDeriv, h);
  w.vec1 = data.qfrc_smooth + data.qfrc_constraint;
  solve_mass_damped(model, data, w.vec1);
  advance_activations(model, data, data.act_dot.data(), h);
  data.qvel += h * w.vec1;
  integrate_positions(model, data.qpos.data(), data.qvel.data(), h);
  data.time += h;
}

}  // namespace detail

}  // namespace lever
