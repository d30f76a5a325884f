// lever/dynamics.hpp: joint-space dynamics. M(q) qacc + qfrc_bias(q, qvel) = tau.
//
// crba() and rnea() are Featherstone's composite-rigid-body and recursive Newton-Euler
// algorithms (Rigid Body Dynamics Algorithms, tables 6.2 and 5.1); factor_mass() is his
// LTDL factorization exploiting branch-induced sparsity (section 6.5).
#pragma once

#include <Eigen/Core>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

/// Joint-space inertia M(q) into data.M, full and symmetric, with dof_armature added on the
/// diagonal (as MuJoCo's mj_crb). @pre kinematics().
void crba(const Model& model, Data& data);

/// Factor M = L^T D L into data.qLD / data.qLDiagInv (MuJoCo's mj_factorM). @pre crba().
void factor_mass(const Model& model, Data& data);

/// x = M^-1 x in place, with the factor from factor_mass() (MuJoCo's mj_solveM).
void solve_mass(const Model& model, const Data& data, Eigen::Ref<Eigen::VectorXd> x);

/// tau = M(q) qacc + C(q, qvel) qvel + g(q) by recursive Newton-Euler, at data.qpos/data.qvel.
/// M here includes armature, so tau = data.M * qacc + data.qfrc_bias exactly in exact arithmetic.
/// Passive, actuator and constraint forces are not included. @pre kinematics().
void rnea(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc,
          Eigen::Ref<Eigen::VectorXd> tau);

/// qfrc_bias = C(q, qvel) qvel + g(q) (MuJoCo's mj_rne with flg_acc = 0). @pre kinematics().
void bias(const Model& model, Data& data);

/// Joint springs and damping into qfrc_passive (MuJoCo's mj_passive).
void passive(const Model& model, Data& data);

/// Tendon lengths, Jacobians (ten_J) and velocities (MuJoCo's mj_tendon and the tendon part of
/// its velocity stage); after kinematics().
void tendon(const Model& model, Data& data);

/// Motor transmission lengths and velocities (MuJoCo's mj_transmission and the velocity stage).
void transmission(const Model& model, Data& data);

/// Actuator forces (MuJoCo's mj_fwdActuation): ctrl clamped to ctrlrange where ctrllimited
/// (data.ctrl itself is not changed), force = gain * ctrl + bias (gain fixed, affine or a
/// muscle's, bias none, affine or a muscle's, in the actuator's length and velocity; act instead
/// of ctrl for an actuator with dynamics), clamped to forcerange where forcelimited, then
/// qfrc_actuator = moment^T actuator_force, and act_dot from the clamped controls.
void actuation(const Model& model, Data& data);

/// Actuator a's gain at actuator length and velocity: gainprm[0], plus gainprm[1] length +
/// gainprm[2] velocity when the gain is affine, a muscle's muscle_gain(). Its force is gain *
/// (clamped ctrl, or its activation if it has dynamics) + bias.
double actuator_gain(const Model& model, int a, double length, double velocity);

/// Actuator a's bias at actuator length and velocity: 0, or biasprm[0] + biasprm[1] length +
/// biasprm[2] velocity when the bias is affine, a muscle's muscle_bias().
double actuator_bias(const Model& model, int a, double length, double velocity);

/// A muscle's active force per unit activation (MuJoCo 2.2.2's mju_muscleGain: -F FL(L) FV(V),
/// muscle.cpp says what the parameters prm = gainprm and the curves are), at this length and
/// velocity, for the actuator's lengthrange and acc0.
double muscle_gain(double length, double velocity, const std::array<double, 2>& lengthrange,
                   double acc0, const double* prm);

/// d muscle_gain / d velocity (MuJoCo 2.2.2's mjd_muscleGain_vel, the implicit step's term).
double muscle_gain_per_velocity(double length, double velocity,
                                const std::array<double, 2>& lengthrange, double acc0,
                                const double* prm);

/// A muscle's passive force (MuJoCo 2.2.2's mju_muscleBias: -F FP(L)); prm = biasprm.
double muscle_bias(double length, const std::array<double, 2>& lengthrange, double acc0,
                   const double* prm);

/// A muscle's activation rate d act / dt at this control and activation (MuJoCo 2.2.2's
/// mju_muscleDynamics; dynprm[0], dynprm[1]: the activation and deactivation time constants).
double muscle_activation_rate(double ctrl, double act, const double* dynprm);

/// Whether actuator a's last actuation() clamped something: ctrl outside a limited ctrlrange, or
/// the force at a limited forcerange's end (then the force no longer follows gain and bias).
bool actuator_clamped(const Model& model, const Data& data, int a);

/// D = d (qfrc_actuator + qfrc_passive - qfrc_bias) / d qvel into qDeriv (nv x nv), the matrix
/// MuJoCo 2.2.2's implicit integrator uses (mjd_smooth_vel): affine actuator bias and gain
/// velocity terms (with the raw ctrl; clamps ignored), joint damping, and the Coriolis and
/// centrifugal terms of the bias force. @pre forward()'s position and velocity stages, as after
/// forward(): crba's composite inertias, cvel and cdof_dot.
void smooth_velocity_derivative(const Model& model, Data& data, Eigen::Ref<Eigen::MatrixXd> qDeriv);

/// qpos (nq) advanced by the velocity qvel (nv) for time h, in place, as MuJoCo's
/// mj_integratePos: hinge and slide coordinates add h qvel; a ball's or free joint's quaternion
/// turns by h w (w about the body's axes) and is normalized. Every integrator steps qpos with it.
/// Throws StateError when the sizes do not fit the model.
void integrate_pos(const Model& model, Eigen::Ref<Eigen::VectorXd> qpos,
                   const Eigen::Ref<const Eigen::VectorXd>& qvel, double h);

/// The velocity that takes qpos1 to qpos2 in time h (nv numbers into qvel), as MuJoCo's
/// mj_differentiatePos: the inverse of integrate_pos. A ball's or free joint's turn is the
/// rotation vector from qpos1's quaternion to qpos2's, about the body's axes, the short way round
/// (both quaternions unit). Throws StateError when the sizes do not fit the model.
void differentiate_pos(const Model& model, Eigen::Ref<Eigen::VectorXd> qvel, double h,
                       const Eigen::Ref<const Eigen::VectorXd>& qpos1,
                       const Eigen::Ref<const Eigen::VectorXd>& qpos2);

/// Potential (gravity and joint springs) and kinetic energy into data.energy.
/// @pre kinematics() and crba().
void compute_energy(const Model& model, Data& data);

}  // namespace lever
