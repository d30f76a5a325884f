// lever/derivatives.hpp: analytic derivatives of inverse dynamics, forward dynamics and the step.
//
// Carpentier and Mansard's recursions ("Analytical derivatives of rigid body dynamics algorithms",
// RSS 2018) in lever's frame (world axes, origin at the tree's centre of mass, see kinematics.cpp),
// then the chain rule through the passive forces, the actuators (motors and affine servos), the
// constraint rows (joint limits and contacts, their active set held; a contact's geometry, its
// Jacobian and its soft parameters differentiated) and the integrators (Euler, RK4 and MuJoCo
// 2.2.2's implicit). docs/derivatives.md derives every formula and lists the points where the
// dynamics is not differentiable (a row appearing, a row changing state, a clamp boundary).
//
// All matrices are column-per-input: dtau_dq(i, j) = d tau_i / d qpos_j, a qpos column being a
// direction of qpos's tangent space (nv of them: a ball's turn about its body's axis j, as
// integrate_pos applies it). MuJoCo 2.2.2 has no analytic counterpart; its mjd_transitionFD
// (finite differences of mj_step) returns A and B in the same layout. Fixed tendons (springs,
// dampers, actuators, limits, friction loss), spatial tendons (straight and wrapping), joint and
// tendon couplings, connects and welds,
// actuators on sites (with or without a reference site), and muscles and every activation
// dynamics (the state then carries act: A is 2nv + na square) are covered. Refused
// (lever::Error): a pushing contact of a pair MuJoCo collides by MPR (meshes, cylinders and
// ellipsoids against anything but a plane), an elliptic cone on its surface, an actuator on a
// slider-crank, a ball or free joint or a body, a ball joint sharing its body with others.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

#include <optional>
#include <vector>

#include <lever/data.hpp>
#include <lever/model.hpp>
#include <lever/spatial.hpp>

namespace lever {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// How a contact's distance, position and frame (rows: normal, tangents) change per unit of a
/// motion of its geoms (the contact geometry's derivative; a workspace type of Derivatives).
struct ContactChange {
  double dist = 0;
  Eigen::Vector3d pos{0, 0, 0};
  Mat3 frame = Mat3::Zero();
};

/// A rigid motion of a contact's two geoms along one direction (a dof's): each geom's angular
/// velocity and its centre's velocity (a workspace type of Derivatives).
struct GeomPairMotion {
  Eigen::Vector3d w1{0, 0, 0}, v1{0, 0, 0}, w2{0, 0, 0}, v2{0, 0, 0};
};

/// Outputs and workspace of the derivative functions, sized once from a Model (one per Data):
/// the functions below allocate nothing.
struct Derivatives {
  explicit Derivatives(const Model& model);

  // ---- inverse dynamics: rnea_derivatives() ---------------------------------------------------
  Eigen::MatrixXd dtau_dq;  ///< (nv x nv) d rnea / d qpos at the given qacc
  Eigen::MatrixXd dtau_dv;  ///< (nv x nv) d rnea / d qvel (d rnea / d qacc is data.M)

  // ---- forward dynamics: forward_derivatives() --------------------------------------------------
  Eigen::MatrixXd dqacc_dq;  ///< (nv x nv) d qacc / d qpos
  Eigen::MatrixXd dqacc_dv;  ///< (nv x nv) d qacc / d qvel
  Eigen::MatrixXd dqacc_du;  ///< (nv x nu) d qacc / d ctrl
  Eigen::MatrixXd dqacc_dact;  ///< (nv x na) d qacc / d act (the stateful actuators' activations)
  /// (nv x nv) d qacc / d qfrc_applied, written by applied_force_derivatives() only
  Eigen::MatrixXd dqacc_dapplied;
  /// d qfrc_constraint / d (qpos, qvel, ctrl, act) with the rows' active set held fixed
  Eigen::MatrixXd dconstraint_dq, dconstraint_dv, dconstraint_du, dconstraint_dact;

  // ---- step: step_derivatives() ---------------------------------------------------------------
  /// (2nv + na)^2 d [dq'; qvel'; act'] / d [dq; qvel; act] (mjd_transitionFD's A)
  Eigen::MatrixXd A;
  Eigen::MatrixXd B;  ///< (2nv + na x nu) d [dq'; qvel'; act'] / d ctrl (mjd_transitionFD's B)
  /// step_derivatives(): the constraint rows' active set (which contacts exist, which rows push)
  /// is not the same at the step's end, or at an RK4 stage, as at its start: A and B are the
  /// derivative of the start's piece, held, and differences across the step are not smooth
  bool active_set_changes = false;

  // ---- workspace (contents meaningless between calls) ---------------------------------------
  struct Workspace {
    // per body: velocity, acceleration, and the subtree (composite) sums of the net force, the
    // inertia and the velocity coupling C (derivatives/inverse_dynamics.cpp); v and Sdot (below)
    // are rnea_derivatives()'s own, the step's derivatives read forward()'s cvel and cdof_dot
    std::vector<Motion> v, a;
    /// (nbody, nv) implicit: v and Sdot at a second velocity (the velocity product's polar form)
    std::vector<Motion> v2, Sdot2;
    std::vector<Force> F;              ///< net force of the body's whole subtree
    std::vector<RigidInertia> IC;      ///< inertia of the body's whole subtree
    std::vector<VelocityCoupling> CC;  ///< C = v x* I - I v x + (I v) xbar* summed over the subtree
    // per dof: the motion subspace's time derivative and Carpentier and Mansard's Psi_ddot
    std::vector<Motion> Sdot, Sddot;
    /// (nv x nv / nv / nu + na) right-hand sides before M^-1; rhs_u's columns: ctrl, then act
    Eigen::MatrixXd rhs_q, rhs_v, rhs_u;
    /// (nv x 2nv + nu + na) [rhs_q rhs_v rhs_u] side by side, solved in place; after
    /// step_derivatives() (implicit, or Euler with damping): d a / d (qpos, qvel, ctrl, act) of
    /// the step's acceleration a
    RowMatrix right_hand_sides;
    Eigen::MatrixXd MinvJ;           ///< (nv x 2 njnt) M^-1 J^T of the active limit rows
    Eigen::MatrixXd AR;              ///< (2 njnt)^2 Cholesky factor of (J M^-1 J^T + R)_SS
    Eigen::VectorXd col;             ///< (max(nv, nefc_max)) scratch
    Eigen::VectorXd drhs_q, drhs_v;  ///< (nefc_max) d (aref - R f) / d q_c, d qd_c per row
    std::vector<int> rows;           ///< (nefc_max) the active rows
    Eigen::VectorXd qacc_step;       ///< (nv) the acceleration the Euler step advances with
    Eigen::VectorXd qpos0, qvel0;    ///< (nq, nv) the state step_derivatives() started from
    Eigen::VectorXd qvel_next;       ///< (nv) the velocity the step's qpos is integrated with
    Eigen::VectorXd stage_dq;        ///< (nv) RK4: a_i qvel_{i-1}, a stage's qpos velocity
    Eigen::MatrixXd Jx, Ju;          ///< (2nv + na x 2nv + na / nu) RK4: d stage state / d (x0, u)
    Eigen::MatrixXd Kx, Ku;          ///< (2nv + na x 2nv + na / nu) RK4: d stage slope / d (x0, u)
    /// (na) d act_dot / d act and d act_dot / d ctrl of each stateful actuator (its own ctrl), at
    /// the last forward (transition/step_derivatives.cpp)
    Eigen::VectorXd act_rate_per_act, act_rate_per_ctrl;
    Eigen::VectorXd act0;            ///< (na) RK4: the activations the step started from
    Eigen::VectorXd act_dot_sum;     ///< (na) RK4: sum_i b_i act_dot_i
    Eigen::VectorXd moment_times_a;  ///< (nv) implicit: an actuator's m m^T a, where M is non-zero
    /// (nv x nv) implicit: M - h D, D = d qfrc_smooth / d qvel (made in this buffer first)
    Eigen::MatrixXd K;
    Eigen::MatrixXd K_lu;            ///< (nv x nv) implicit: K's factor (U + I) L (implicit.cpp)
    Eigen::VectorXd qvel_change;     ///< (nv) implicit: h a, the step's change of qvel
    Eigen::VectorXd qacc_change;     ///< (nv) implicit: a - qacc
    int active_rows = 0;             ///< the limit rows active at the last forward (limit_rows)
    std::vector<Force> IC_S;         ///< (nv) IC S_i, IC dof i's subtree inertia (derivatives/inverse_dynamics.cpp)
    std::vector<VelocityCoupling> CC2;  ///< (nbody) implicit: CC at a second velocity
    /// (nbody) I v of each body alone at RNEA's velocity, before CC's subtree sums: the polar
    /// form's net force reads it again (derivatives/inverse_dynamics.cpp)
    std::vector<Force> momentum;
    /// (nv) the angular part of CC^T S_i (CC of dof i's body) at RNEA's velocity, which the
    /// polar form's columns read again (derivatives/inverse_dynamics.cpp)
    std::vector<Eigen::Vector3d> CCt_S;
    // contacts' rows with their active set held (transition/contact_rows.cpp)
    RowMatrix contact_Y;          ///< (nefc_max x nv) per active row: D (d aref - dR f - dJ qacc)
    /// (nv x nv) dJ^T f, one column per qpos direction, and the contact rows' J^T Y; after the
    /// held rows' solve, the step's rnea (or polar form) derivative in qpos (step_derivatives.cpp)
    Eigen::MatrixXd contact_E;
    Eigen::MatrixXd contact_H;    ///< (nv x nv) M + J^T D J over the active rows, then its factor
    /// (nv x nv) J^T D J over the active rows; after the held rows' solve, the step's rnea (or
    /// polar form) derivative in qvel (one buffer for both: they are never live together)
    Eigen::MatrixXd contact_G;
    std::vector<int> contact_H_first;  ///< (nv) the first column of each of its rows not zero
    std::vector<char> moves1, moves2;  ///< (nv) the dofs that move a contact's two bodies
    std::vector<char> carries;  ///< (nv x nv) [c * nv + i]: moving dof c turns dof i's axis
    /// (nv + 1, and M's possible non-zeros) the dofs on one branch with dof i, ascending, are
    /// branch_dofs[branch_first[i] .. branch_first[i + 1]) (transition/contact_rows.cpp)
    std::vector<int> branch_first, branch_dofs;
    /// (nv x kMaxPairContacts) [m * count + k]: the change of one geom pair's contact k (of its
    /// count) along the m-th dof that moves the pair, the narrow phase run once per dof for all of
    /// the pair's contacts
    std::vector<ContactChange> pair_changes;
    std::vector<GeomPairMotion> pair_motions;  ///< (nv) the pair's motion along each such dof
    std::vector<Eigen::Vector3d> contact_point_velocity;  ///< (nv) each dof's at the world origin
    /// Sums over the dofs on a geom pair's paths of their velocities at the world origin and
    /// their axes, weighted by the motion qacc + B qvel (contact_rows.cpp)
    struct PathSums {
      Eigen::Vector3d V = Eigen::Vector3d::Zero(), W = Eigen::Vector3d::Zero();
    };
    /// One column of dJ^T f and J^T Y summed over a geom pair's contacts (contact_rows.cpp)
    struct ColumnWrench {
      Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
      Eigen::Vector3d carried_force = Eigen::Vector3d::Zero();
      Eigen::Vector3d carried_torque = Eigen::Vector3d::Zero();
    };
    std::vector<int> pair_dofs;  ///< (nv) the dofs that move a geom pair, in order
    std::vector<PathSums> pair_turned;  ///< (nv) per such dof c: the sums over the dofs c turns
    std::vector<ColumnWrench> pair_columns;  ///< (nv) per such dof c: dJ^T f's column c
    /// (2nv) a connect's or weld's two anchors: each dof's velocity at body 1's anchor, then at
    /// body 2's (transition/equality_rows.cpp)
    std::vector<Eigen::Vector3d> equality_point_velocity;
    /// (nv x nv) a site actuator's moment's change: (i, c) = d moment_i / d q_c
    /// (transition/step_derivatives.cpp)
    Eigen::MatrixXd moment_change;
    Eigen::VectorXd length_gradient;  ///< (nv) a site actuator's d length / d qpos
    /// (nv x nv) a spatial tendon's (i, c) = d ten_J_i / d q_c (transition/spatial_tendons.cpp)
    Eigen::MatrixXd tendon_change;
    /// (2nv) a tendon segment's two ends' motions per dof, and a wrap's two tangent points'
    std::vector<Eigen::Vector3d> segment_motion, tangent_motion;
    // the active set's check (step_derivatives)
    /// the contacts' geom pairs, the rows' states and the spatial tendons' wraps at the start
    std::vector<int> active_set;
    Eigen::VectorXd qacc_sum;     ///< (nv) RK4: sum_i b_i qacc_i
    std::optional<Data> next;     ///< forward() at the step's end
  } work;

  int nv = 0, nu = 0, na = 0;  ///< sizes of the model this workspace was built for (checked)
};

/// d tau / d qpos and d tau / d qvel of tau = rnea(qpos, qvel, qacc) (armature included, so
/// d tau / d qacc = data.M) into deriv.dtau_dq and deriv.dtau_dv, at data.qpos, data.qvel and the
/// given qacc. Gravity is included (as in rnea); passive, motor and limit forces are not.
/// @pre kinematics() at data.qpos (forward() or inverse() did it).
void rnea_derivatives(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc,
                      Derivatives& deriv);

/// forward() at data's state, then d qacc / d qpos, d qvel and d ctrl into deriv.dqacc_*:
/// springs and damping, actuators with their gain and bias (d ctrl zero where ctrl is clamped,
/// all of an actuator's terms zero where its force is clamped), qfrc_applied held fixed,
/// and the constraint rows (limits and contacts) with their active set held fixed (their
/// impedance, reference acceleration and, for contacts, Jacobian and geometry differentiated).
/// Also writes deriv.dtau_* (at data.qacc) and deriv.dconstraint_*.
void forward_derivatives(const Model& model, Data& data, Derivatives& deriv);

/// d qacc / d qfrc_applied into deriv.dqacc_dapplied, at the state of data's last forward()
/// (forward_derivatives() ran it): (M + J_S^T R_S^-1 J_S)^-1 over the active rows S (limits and
/// contacts, held fixed as in forward_derivatives()); M^-1 when no row pushes. Throws lever::Error
/// for an elliptic cone on its surface, as forward_derivatives() does.
void applied_force_derivatives(const Model& model, const Data& data, Derivatives& deriv);

/// The transition Jacobians of step() at data's state, in mjd_transitionFD's layout:
/// x = [dq; qvel; act] (2nv + na, dq qpos's tangent, the next qpos read in the tangent space at the
/// next state), A = d x' / d x, B = d x' / d ctrl, into deriv.A and deriv.B. Euler
/// (with its implicit damping), RK4 and implicit (K = M - h D differentiated exactly, D's
/// dependence on qpos, qvel and ctrl included); the derivative of step's bad-state resets is not
/// taken. data's state (time, qpos, qvel, ctrl) is left as it was; its other fields hold forward()
/// at that state (Euler, implicit) or at RK4's last stage, and deriv.dqacc_* are those of that
/// evaluation.
/// Throws lever::Error for an integrator it does not differentiate yet.
void step_derivatives(const Model& model, Data& data, Derivatives& deriv);

}  // namespace lever
