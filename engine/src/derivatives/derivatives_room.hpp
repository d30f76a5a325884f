// The derivatives of the smooth dynamics: Carpentier and Mansard's RNEA derivatives
// (inverse_dynamics.cpp), which the step's Jacobians (transition/) read, and the bias force's
// velocity derivative as MuJoCo's implicit integrator forms it (bias_velocity_chain.cpp), which
// pipeline/implicit.cpp reads.
#pragma once

#include <Eigen/Core>

#include <span>
#include <vector>

#include <lever/data.hpp>
#include <lever/derivatives.hpp>
#include <lever/model.hpp>
#include <lever/spatial.hpp>

namespace lever {

/// D -= d qfrc_bias / d qvel, summed as MuJoCo 2.2.2's implicit step sums it (mjd_rne_vel's chain
/// rule; bias_velocity_chain.cpp), from the velocity stage's cvel, cdof_dot and the position
/// stage's cinert, cdof. Only the elements of dof pairs on one branch of the tree change.
void subtract_bias_velocity_derivative(const Model& model, Data& data,
                                       Eigen::Ref<Eigen::MatrixXd> D);

namespace detail {

/// Each body's velocity v and each dof's Sdot at one joint velocity, summed as forward_pass()
/// (smooth/recursion.hpp) sums them.
struct Velocities {
  std::span<const Motion> v, Sdot;
};

/// The velocities at data.qvel that forward()'s bias stage left (data.cvel, data.cdof_dot):
/// forward_pass()'s own sums, which the step's derivatives read rather than form again.
Velocities bias_stage_velocities(const Data& data);

/// Throws unless Model, Data and Derivatives were made for one another, and the model is one the
/// analytic derivatives cover.
void check_derivative_sizes(const Model& model, const Data& data, const Derivatives& deriv);

/// The first dof of a joint's rotation block (a ball's three dofs, a free joint's last three), or
/// -1 when the joint has none. A tangent coordinate of the block turns the body about its own
/// axes: qpos' = qpos exp(dq). (Inline: the passes ask it of every joint.)
inline int rotation_block(const Model& model, int j) {
  switch (model.jnt_kind[j]) {
    case JointKind::kBall: return model.jnt_dofadr[j];
    case JointKind::kFree: return model.jnt_dofadr[j] + 3;
    default: return -1;
  }
}

/// The inertia of each body's subtree into w.IC (for a caller that ran kinematics() alone); returns
/// w.IC.
std::span<const RigidInertia> subtree_inertias(const Model& model, const Data& data,
                                               Derivatives::Workspace& w);

/// IC S_i of each dof i into w.IC_S, which every RNEA-derivative pass at this qpos reads.
void inertia_columns(const Model& model, const Data& data, std::span<const RigidInertia> IC,
                     Derivatives::Workspace& w);

/// Carpentier and Mansard's first-order RNEA derivatives at (data.qpos, qd, qdd) into dtau_dq and
/// dtau_dv, given the subtree inertias IC and w.IC_S, and the velocities at qd
/// (bias_stage_velocities() where qd is data.qvel after forward(); nullptr: formed here, into w.v
/// and w.Sdot); leaves the subtree sums of C at qd in w.CC, their S_i . CC in w.CCt_S and each
/// body's momentum at qd in w.momentum.
void rnea_derivatives_into(const Model& model, const Data& data, const double* qd,
                           const double* qdd, bool gravity, std::span<const RigidInertia> IC,
                           Derivatives::Workspace& w, Eigen::MatrixXd& dtau_dq,
                           Eigen::MatrixXd& dtau_dv, const Velocities* at_qd = nullptr);

/// The derivatives of RNEA's velocity product in its polar form, 2 Q(v1, v2) (rnea = Q(qd, qd) +
/// L(qdd, gravity)), plus L(qdd) without gravity (qdd nullptr: none): d / d qpos into dtau_dq and
/// d / d v1 (RNEA's d tau / d qd at v2) into dtau_dv2. Reads w.CC, w.CCt_S and w.momentum, the
/// subtree sums of C at v1, their S_i . CC and the bodies' momenta at v1, that
/// rnea_derivatives_into() at v1 (and this qpos) left, and its velocities at v1 (at_v1: the
/// ones it was given, or w.v and w.Sdot); given IC and w.IC_S as it is. One pass
/// where the polarisation identity 2 Q(v1, v2) = (Q(v1 + s v2) - Q(v1 - s v2)) / (2 s) takes two.
void polar_derivatives_into(const Model& model, const Data& data, const Velocities& at_v1,
                            const double* v1, const double* v2, const double* qdd,
                            std::span<const RigidInertia> IC, Derivatives::Workspace& w,
                            Eigen::MatrixXd& dtau_dq, Eigen::MatrixXd& dtau_dv2);

}  // namespace detail

}  // namespace lever
