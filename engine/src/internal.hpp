// Engine functions shared between source files but not part of lever's public API.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <vector>

#include <lever/data.hpp>
#include <lever/fields.hpp>
#include <lever/model.hpp>

namespace lever {

/// Factor M + h diag(dof_damping) into data.work.LD2 (the Euler step's implicit damping).
void factor_mass_damped(const Model& model, Data& data, double h);

/// x = (M + h diag(dof_damping))^-1 x with the factor above.
// x <- L^-T x, the first half of solve_mass (M = L^T D L): M^-1 = L^-1 D^-1 L^-T, so that
// J M^-1 J^T = Y^T D^-1 Y with Y = L^-T J^T.
void solve_mass_half(const Model& model, const Data& data, Eigen::Ref<Eigen::VectorXd> x);
void solve_mass_damped(const Model& model, const Data& data, Eigen::Ref<Eigen::VectorXd> x);

/// A joint limit's solref and solimp, sanitized as MuJoCo's getsolparam (constraint.cpp).
void limit_parameters(const Model& model, int jnt, std::array<double, 2>& solref,
                      std::array<double, 5>& solimp);

/// A limit row's impedance at distance pos from the stop (constraint.cpp); with slope !=
/// nullptr, also d imp / d pos.
double impedance(const std::array<double, 5>& solimp, double pos, double margin, double* slope);

// ---- the constraint rows' products (constraint.cpp), shared by the solvers -------------------
// A contact's rows are combinations of its frame's rows over its span of dofs
// (data.work.contact_frame_J, contact_span): the products work on those, a limit row on its dof.

/// out = J x for every row (nefc numbers; x has nv).
void rows_times(const Data& data, const double* x, double* out);

/// out = J x - aref for every row (MuJoCo's jar: where the rows' accelerations stand against
/// their reference; nefc numbers).
void rows_jar(const Data& data, const double* x, double* out);

/// out += J^T f (f has nefc numbers, out nv).
void add_rows_transpose(const Data& data, const double* f, double* out);

/// H += J^T diag(weight) J in H's lower triangle (weight: nefc numbers, zero for a row left
/// out), each contact's part from its frame's rows: a pyramid's pair of edges with one weight
/// adds one product along its tangent, the pairs' normal parts gathered into one, instead of
/// one product per edge.
void add_rows_hessian(Data& data, const double* weight, Eigen::MatrixXd& H);

/// H += C^T W C for contact i in H's lower triangle: C its frame's rows, W (dim x dim, row-major,
/// symmetric) a weight in its frame's coordinates (an elliptic cone's Hessian block).
void add_frame_hessian(Data& data, int i, const double* W, Eigen::MatrixXd& H);

/// x = H^-1 x for H = M + J^T (...) J assembled above (its lower triangle), which becomes its
/// Cholesky factor: the active sets and the Newton solver both solve with it (data's workspace
/// holds where its columns end).
void solve_with_hessian(Data& data, Eigen::MatrixXd& H, Eigen::VectorXd& x);

/// Solve the constraint rows by MuJoCo's Newton method to convergence (solver.cpp): qacc,
/// efc_b, efc_force, efc_state, qfrc_constraint. Returns the Newton steps taken.
/// @pre make_constraint, reference_constraint, qacc_smooth and M are current.
int solve_constraint_newton(const Model& model, Data& data);

/// Solve one-sided rows (limits, frictionless and pyramidal contacts) by principal pivoting on
/// A = J M^-1 J^T + R (constraint.cpp), the fallback of solve_constraint's active sets: qacc,
/// efc_b, efc_force, efc_state, qfrc_constraint. For tests that compare the two.
/// @pre as solve_constraint, and no elliptic cone.
void solve_constraint_pivoting(const Model& model, Data& data);

/// efc_force, efc_state and qfrc_constraint that the rows exert at a given qacc (solver.cpp;
/// MuJoCo's mj_constraintUpdate): what inverse() reports.
void constraint_forces_at(Data& data, const Eigen::VectorXd& qacc);

/// Record a warning of kind w about index info (MuJoCo's mj_warning).
inline void record_warning(Data& data, Warning w, int info) {
  WarningStat& stat = data.warning[static_cast<int>(w)];
  ++stat.number;
  stat.lastinfo = info;
}

/// Whether the arrays a caller assigns (the state and the inputs) still have the model's sizes.
inline bool inputs_fit(const Model& model, const Data& data) {
  return data.qpos.size() == model.nq && data.qvel.size() == model.nv &&
         data.qacc.size() == model.nv && data.ctrl.size() == model.nu &&
         data.qfrc_applied.size() == model.nv;
}

/// The check at the door of every public function. Model and Data are matched where they meet:
/// set_const gives a model a fresh tag, and a Data that passed check_fit against a model keeps its
/// tag. A call then costs a comparison of tags and of the input arrays' sizes; only a Data meeting
/// a model (or a model edition) it has not been checked against walks the whole field table.
/// No guard object: nothing to unwind on the hot path. checked_before: this Data has met this
/// model edition and its inputs kept their sizes.
inline bool checked_before(const Model& model, const Data& data) {
  return model.fit_tag != 0 && data.model_tag == model.fit_tag && inputs_fit(model, data);
}

/// The entry check of a function that writes data: a Data that fits adopts the model's tag.
inline void check_entry(const Model& model, Data& data, const char* where) {
  if (checked_before(model, data)) return;
  check_fit(model, data, where);  // throws, naming the array that does not fit
  data.model_tag = model.fit_tag;
}

/// The same for functions that only read data (Jacobians, solves).
inline void check_entry(const Model& model, const Data& data, const char* where) {
  if (checked_before(model, data)) return;
  check_fit(model, data, where);
}

/// The three stages of forward() (MuJoCo's mj_fwdPosition, mj_fwdVelocity, and mj_fwdActuation +
/// mj_fwdAcceleration + mj_fwdConstraint); step1()/step2() split a step between them. The entry
/// check is the caller's.
void position_stage(const Model& model, Data& data);
void velocity_stage(const Model& model, Data& data);
void acceleration_stage(const Model& model, Data& data);

/// The steps of forward()'s stages: each the public function of the same name (lever/dynamics.hpp,
/// lever/constraint.hpp) without its entry check. forward(), step(), inverse(), step1() and step2()
/// check Model and Data once, at their door, and then run these.
namespace unchecked {
void crba(const Model& model, Data& data);
void factor_mass(const Model& model, Data& data);
void solve_mass(const Model& model, const Data& data, double* x);  // x: nv numbers
void bias(const Model& model, Data& data);
void passive(const Model& model, Data& data);
void transmission(const Model& model, Data& data);
void actuation(const Model& model, Data& data);
void make_constraint(const Model& model, Data& data);
void reference_constraint(const Model& model, Data& data);
void solve_constraint(const Model& model, Data& data);
}  // namespace unchecked

/// Throws StateError unless a vector argument has n elements.
void check_argument_size(long size, long n, const char* where, const char* what);

// ---- the implicit integrator's matrix (implicit.cpp, derivatives.cpp) ---------------------------

/// d qfrc_bias / d qvel into out (nv x nv): Carpentier and Mansard's d rnea / d qd, which does not
/// depend on qacc or gravity, from the bodies' velocities v and the dofs' Sdot at velocity qd
/// (RNEA's forward pass: data.cvel and data.cdof_dot after forward()); IC (nbody) holds each
/// body's subtree inertia (crba()'s composites, data.work.crb after the position stage), CC
/// (nbody) is workspace for the subtree sums of velocity coupling (derivatives.cpp).
void bias_velocity_derivative(const Model& model, const Data& data, const double* qd,
                              const std::vector<Motion>& v, const std::vector<Motion>& Sdot,
                              const std::vector<RigidInertia>& IC,
                              std::vector<VelocityCoupling>& CC, Eigen::Ref<Eigen::MatrixXd> out);

/// D += the actuators' and the dampers' part of d qfrc_smooth / d qvel as MuJoCo's mjd_smooth_vel
/// has it: gear^2 (biasprm[2] + gainprm[2] ctrl) of each affine actuator (raw ctrl, no clamp) on
/// its dof, minus dof_damping on the diagonal (implicit.cpp).
void add_actuator_damping_velocity_terms(const Model& model, const Data& data,
                                         Eigen::Ref<Eigen::MatrixXd> D);

/// K (nv x nv, non-zero only where M is: dofs on one branch) factored in place as MuJoCo's
/// mju_factorLUSparse does, without pivoting, leaves first: K = (U + I) L, U strictly upper
/// (above K's diagonal on return), L lower (on and below it). Eliminating a leaf touches only its
/// ancestors' rows and columns, so nothing fills in (implicit.cpp).
void factor_lu_tree(const Model& model, Eigen::MatrixXd& K);

/// x = K^-1 x with factor_lu_tree()'s factor of K.
void solve_lu_tree(const Model& model, const Eigen::MatrixXd& LU, double* x);

namespace detail {
/// The model evaluated once at qpos0, at rest and without control, into data (model_check.cpp):
/// throws ModelError naming the object whose numbers overflow (set_const's last step, once the
/// constants are computed).
void check_at_qpos0(const Model& model, Data& data);

/// The collision stage's body constants, Model::body_weldid and body_collision
/// (collision_driver.cpp; set_const computes them once, the broad phase reads them every call).
void build_collision_constants(Model& model);

/// Size every array of the field table in data for the model, zero-filled (the Data constructor).
void size_data_arrays(const Model& model, Data& data);

/// MuJoCo 2.2.2's implicit step (implicit.cpp), after forward().
void implicit_step(const Model& model, Data& data);

// ---- the lean step pipeline (issue 18): forward() without the outputs nothing in a step reads
// (xquat, and the geom frames when nothing can collide). After step() they are those of the last
// forward() or kinematics(); everything else is forward()'s to the bit
// (tests/property/lean_step.cpp).

/// kinematics() without xquat, and without the geom frames unless the collision stage runs
/// (kinematics.cpp).
void step_kinematics(const Model& model, Data& data);

/// forward() on step_kinematics(), the entry check left to the caller (forward.cpp).
void step_forward(const Model& model, Data& data);

/// step() after its entry check, each forward() of the step being `forward_fn` (forward() or
/// step_forward(); integrate.cpp).
void step(const Model& model, Data& data, void (*forward_fn)(const Model&, Data&));

/// qpos advanced by velocity qvel for time h, joint by joint (MuJoCo's mj_integratePos): hinge and
/// slide coordinates add h qvel; a ball's or free joint's quaternion turns by the rotation h w
/// about its body axes and is normalized. Used by every integrator.
void integrate_positions(const Model& model, double* qpos, const double* qvel, double h);

/// q (4 numbers) normalized in place, or the identity when its length is below 1e-15 (MuJoCo's
/// mju_normalize4, which scales even a unit quaternion by 1 / |q|: so does this).
inline void normalize_quat(double* q) {
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (norm < 1e-15) {
    q[0] = 1.0;
    q[1] = q[2] = q[3] = 0.0;
    return;
  }
  const double inverse = 1.0 / norm;
  for (int k = 0; k < 4; ++k) q[k] *= inverse;
}

/// Every ball and free joint's quaternion in qpos normalized (MuJoCo's mj_normalizeQuat, which
/// mj_kinematics runs first: an evaluation leaves the state's quaternions unit).
inline void normalize_joint_quats(const Model& model, double* qpos) {
  for (int j = 0; j < model.njnt; ++j) {
    const JointKind kind = model.jnt_kind[j];
    if (kind == JointKind::kBall) normalize_quat(qpos + model.jnt_qposadr[j]);
    if (kind == JointKind::kFree) normalize_quat(qpos + model.jnt_qposadr[j] + 3);
  }
}

/// The rotation vector r (3 numbers, in b's frame) with b * exp(r) = a, for unit quaternions a
/// and b, its angle in [-pi, pi], divided by dt (MuJoCo's mju_subQuat for dt = 1, the
/// orientation's difference in tangent space; mj_differentiatePos's rate for other dt).
inline Eigen::Vector3d quat_difference(const double* a, const double* b, double dt = 1.0) {
  // d = conj(b) * a
  const Quat qa(a[0], a[1], a[2], a[3]);
  const Quat conj_b(b[0], -b[1], -b[2], -b[3]);
  const Quat d = quat_mul(conj_b, qa);
  Eigen::Vector3d axis(d[1], d[2], d[3]);
  const double sin_half = axis.norm();
  if (sin_half < 1e-15) {
    axis = Eigen::Vector3d::UnitX();
  } else {
    axis *= 1.0 / sin_half;
  }
  double angle = 2.0 * std::atan2(sin_half, d[0]);
  if (angle > M_PI) angle -= 2.0 * M_PI;  // the shorter way round
  return axis * (angle / dt);
}

/// Whether dof i starts a new motion segment of its body: its Sdot = v x S uses the body's
/// velocity before the segment. Each hinge or slide is its own segment; a ball's three rotations
/// share one, and so do a free joint's three translations and its three rotations (MuJoCo's
/// mj_comVel).
inline bool starts_segment(const Model& model, int i) {
  const int j = model.dof_jntid[i];
  const int offset = i - model.jnt_dofadr[j];
  return offset == 0 || (offset == 3 && model.jnt_kind[j] == JointKind::kFree);
}
}  // namespace detail

/// MuJoCo's mju_isBad: NaN, or beyond +-1e10.
inline bool is_bad(double x) { return x != x || x > 1e10 || x < -1e10; }

/// The first of n numbers that is_bad, or -1 (|x| <= 1e10 is false for a NaN too).
inline int first_bad(const double* x, int n) {
  for (int i = 0; i < n; ++i) {
    if (!(std::abs(x[i]) <= 1e10)) return i;
  }
  return -1;
}

}  // namespace lever
