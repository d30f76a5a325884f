// The pipeline: forward() and inverse() stage by stage (forward.cpp), the step and its
// integrators (integrate.cpp, implicit.cpp) and the batch of states (batch.cpp). It calls the
// smooth, collision and constraint rooms in MuJoCo's order.
#pragma once

#include <Eigen/Core>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

/// The three stages of forward() (MuJoCo's mj_fwdPosition, mj_fwdVelocity, and mj_fwdActuation +
/// mj_fwdAcceleration + mj_fwdConstraint); step1()/step2() split a step between them. The entry
/// check is the caller's.
void position_stage(const Model& model, Data& data);
void velocity_stage(const Model& model, Data& data);
void acceleration_stage(const Model& model, Data& data);

// ---- the implicit integrator's matrix (implicit.cpp; the step's Jacobians read it too) -------

/// D += the actuators' and the dampers' part of d qfrc_smooth / d qvel as MuJoCo's mjd_smooth_vel
/// has it: gear^2 (biasprm[2] + gainprm[2] ctrl) of each affine actuator (raw ctrl, no clamp) on
/// its dof, minus dof_damping on the diagonal (implicit.cpp).
void add_actuator_damping_velocity_terms(const Model& model, const Data& data,
                                         Eigen::Ref<Eigen::MatrixXd> D);

/// K (nv x nv, non-zero only where M is: dofs on one branch) factored in place as MuJoCo's
/// mju_factorLUSparse does, without pivoting, leaves first: K = (U + I) L, U strictly upper
/// (above K's diagonal on return), L lower (on and below it). Eliminating a leaf touches only its
/// ancestors' rows and columns, so nothing fills in (implicit.cpp).
void factor_lu_tree(const Model& model, Eigen::Ref<Eigen::MatrixXd> K);

/// x = K^-1 x with factor_lu_tree()'s factor of K, summed in mju_solveLUSparse's order;
/// `ancestors` is scratch room for nv ints (a Data's work.dof_chain).
void solve_lu_tree(const Model& model, const Eigen::Ref<const Eigen::MatrixXd>& LU, double* x,
                   int* ancestors);

namespace detail {
/// MuJoCo 2.2.2's implicit step (implicit.cpp), after forward().
void implicit_step(const Model& model, Data& data);
/// MuJoCo 3's implicitfast step (implicit.cpp), after forward().
void implicit_fast_step(const Model& model, Data& data);

/// forward() on step_kinematics() (on kinematics() when the model has sensors), the entry check
/// left to the caller (forward.cpp).
void step_forward(const Model& model, Data& data);

/// forward() and step_forward() without the sensors, for the RK4 step's later stages (MuJoCo
/// skips them there, so that sensordata stays that of the step's start).
void forward_without_sensors(const Model& model, Data& data);
void step_forward_without_sensors(const Model& model, Data& data);

/// forward()'s stages for a caller that reads the rows' active set alone and solves as it needs
/// (step_derivatives' check at the step's end; nothing else of that Data is read):
/// forward_until_solve() runs them up to the constraint solve on step_kinematics() whatever
/// sensors the model has, without sensors, energy or the input check, and leaves out what only
/// the solve reads (M's factor, qacc_smooth: it holds qfrc_smooth); forward_solve() then adds
/// those and the solve: forward()'s rows, forces and acceleration to the bit.
void forward_until_solve(const Model& model, Data& data);
void forward_solve(const Model& model, Data& data);

/// data.solver_fwdinv after forward(), for <flag fwdinv="enable"> (MuJoCo's mj_compareFwdInv):
/// inverse dynamics at forward()'s qacc, the constraint force and the applied force it implies
/// compared with forward()'s; forward()'s efc_force and qfrc_constraint are kept, inverse()'s
/// qfrc_inverse and efc_state are left (forward.cpp).
void compare_forward_inverse(const Model& model, Data& data);

/// step() after its entry check, the step's forward() being `forward_fn` (forward() or
/// step_forward(); integrate.cpp) and the RK4 stages' `stage_fn` (the same without sensors).
void step(const Model& model, Data& data, void (*forward_fn)(const Model&, Data&),
          void (*stage_fn)(const Model&, Data&));

/// qpos advanced by velocity qvel for time h, joint by joint (MuJoCo's mj_integratePos): hinge and
/// slide coordinates add h qvel; a ball's or free joint's quaternion turns by the rotation h w
/// about its body axes and is normalized. Used by every integrator.
void integrate_positions(const Model& model, double* qpos, const double* qvel, double h);

/// act += h act_dot (na numbers), then each limited activation clamped to its actrange (MuJoCo's
/// mj_advance: every integrator's last step on the activations).
void advance_activations(const Model& model, Data& data, const double* act_dot, double h);
}  // namespace detail

}  // namespace lever
