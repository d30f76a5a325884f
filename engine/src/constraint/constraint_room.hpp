// The constraint room: MuJoCo 2.2.2's soft constraints. The rows in MuJoCo's order: equality
// constraints (equality.cpp), friction loss (friction_loss.cpp), joint limits and contacts
// (rows.cpp); their impedance and reference acceleration, and the products with their Jacobian
// (rows.cpp); the solvers: the active sets and principal pivoting for one-sided rows (rows.cpp)
// and, on MuJoCo's primal problem (primal.cpp), Newton's method for every kind (newton.cpp) and
// MuJoCo's conjugate gradients (cg.cpp, for opt.solver CG); on the dual problem, MuJoCo's
// projected Gauss-Seidel (pgs.cpp, for opt.solver PGS); a contact's force in its frame
// (contact_force.cpp); the body transmission, which acts along the contacts' normals
// (body_transmission.cpp).
#pragma once

#include <Eigen/Core>

#include <array>

#include <lever/data.hpp>
#include <lever/model.hpp>

#include "basics/basics.hpp"

namespace lever {

/// A joint limit's solref and solimp, sanitized as MuJoCo's getsolparam (rows.cpp).
void limit_parameters(const Model& model, int jnt, std::array<double, 2>& solref,
                      std::array<double, 5>& solimp);

/// A limit row's impedance at distance pos from the stop (rows.cpp); with slope !=
/// nullptr, also d imp / d pos.
double impedance(const std::array<double, 5>& solimp, double pos, double margin, double* slope);

/// solimp within the bounds MuJoCo's getsolparam clamps it to (rows.cpp).
void bound_solimp(std::array<double, 5>& solimp);

/// solref and solimp sanitized as MuJoCo's getsolparam (rows.cpp): the standard and direct
/// forms not mixed, a time constant of at least two steps, solimp within its bounds.
void sanitize(const Model& model, std::array<double, 2>& solref, std::array<double, 5>& solimp);

/// A row's impedance at its distance, and the stiffness and damping of its reference
/// acceleration (K and B use dmax, not the current impedance).
struct SoftParameters {
  double imp, K, B;
};

/// The soft parameters of a row at distance pos with margin (rows.cpp; sanitized solref, solimp).
SoftParameters soft_parameters(const std::array<double, 2>& solref,
                               const std::array<double, 5>& solimp, double pos, double margin);

/// The regularizer R = (1 - imp) / imp * diag of a row whose approximate inverse inertia is diag
/// (MuJoCo's mj_diagApprox, frozen at qpos0), at least mjMINVAL (rows.cpp).
double regularizer(const SoftParameters& soft, double diag);

/// Row r's efc_imp, efc_K (K: 0 for friction), efc_B, efc_R, efc_D and efc_diagApprox (rows.cpp).
void set_soft_row(Data& data, int r, const SoftParameters& soft, double K, double R);
/// set_soft_row for `count` rows from `first` that share their parameters (D and diagApprox
/// computed once).
void set_soft_rows(Data& data, int first, int count, const SoftParameters& soft, double K,
                   double R);

/// The active equality constraints' rows from row n, with their soft parameters (equality.cpp).
/// Returns the rows made so far.
int add_equality_rows(const Model& model, Data& data, int n);

/// What mj_setConst completes in eq_data from the bodies' poses in data (kinematics at qpos0):
/// a connect's anchor in body 2's frame; a weld's anchor in body 1's frame and body 2's
/// orientation in body 1's when its relpose quaternion is zero, else that quaternion normalized
/// (equality.cpp).
void complete_equality_data(Model& model, const Data& data);

/// One row per dof with friction loss, then per tendon with friction loss, from row n, with their
/// soft parameters (friction_loss.cpp).
/// Returns the rows made so far.
int add_friction_loss_rows(const Model& model, Data& data, int n);

/// The rows' matrix in row space, A = J M^-1 J^T + R (MuJoCo's efc_AR), into the lower triangle
/// of work.A's top-left nefc x nefc corner, as MuJoCo forms it: Y = D^-1/2 L^-T J^T (work.halfJ)
/// with M = L^T D L, then A = Y^T Y, each coefficient summed over the dofs in order (rows.cpp).
/// Shared by the principal pivoting and the PGS solver. @pre M factored, rows made.
void row_space_matrix(const Model& model, Data& data);

/// Whether a row's Jacobian is a dense row of efc_J that the products read whole (an equality
/// row, a tendon's friction-loss or limit row) rather than sign e_dof or a contact's frame rows.
inline bool dense_row(ConstraintType type) {
  return type == ConstraintType::kEquality || type == ConstraintType::kFrictionTendon ||
         type == ConstraintType::kLimitTendon;
}

/// Whether a row is a friction-loss row (its force boxed by efc_frictionloss).
inline bool friction_loss_row(ConstraintType type) {
  return type == ConstraintType::kFrictionDof || type == ConstraintType::kFrictionTendon;
}

// ---- the constraint rows' products (rows.cpp), shared by the solvers -------------------
// A contact's rows are nonzero only over its span of dofs (data.work.contact_span): J x and
// J^T f read efc_J's rows there (a pyramid's edges n +- mu t as efc_J holds them), each summed as
// MuJoCo's products sum efc_J's; a limit row reads its dof. J^T D J works on the contact
// frame's rows (data.work.contact_frame_J), a pyramid's pairs of edges gathered.

/// out = J x for every row (nefc numbers; x has nv), each row's product summed as MuJoCo sums
/// efc_J's: mju_mulMatVec's dot_as_mujoco, or in order when its Jacobian is sparse
/// (data.work.sparse_row_sums).
void rows_times(const Data& data, const double* x, double* out);

/// out = J x - aref for every row (MuJoCo's jar: where the rows' accelerations stand against
/// their reference; nefc numbers).
void rows_jar(const Data& data, const double* x, double* out);

/// out += J^T f (f has nefc numbers, out nv): the rows added one after another, each row's
/// products row_j f_r, as MuJoCo's mju_mulMatTVec adds them (and, sparse, its products with the
/// columns of efc_J, each over its rows in order: the same sums).
void add_rows_transpose(const Data& data, const double* f, double* out);

/// H += J^T diag(weight) J in H's lower triangle (weight: nefc numbers, zero for a row left
/// out), each contact's part from its frame's rows: a pyramid's pair of edges with one weight
/// adds one product along its tangent, the pairs' normal parts gathered into one, instead of
/// one product per edge.
void add_rows_hessian(Data& data, const double* weight, Eigen::Ref<Eigen::MatrixXd> H);

/// H += C^T W C for contact i in H's lower triangle: C its frame's rows, W (dim x dim, row-major,
/// symmetric) a weight in its frame's coordinates (an elliptic cone's Hessian block).
void add_frame_hessian(Data& data, int i, const double* W, Eigen::Ref<Eigen::MatrixXd> H);

/// One round of the active-set solve with the rows `active` (nefc flags) pushing: a = (M + J_S^T
/// D_S J_S)^-1 (qfrc_smooth + J_S^T D_S aref_S) into work.newton_dir, each row's jar at it into
/// work.newton_jar. True if the rows that push at a, {r : jar_r < 0}, are `active` again: then a
/// is the one-sided rows' unique solution.
bool active_set_round(Data& data, const int* active);

/// Whether solve_constraint() solves data's rows by active sets (solve_rows' choice): one-sided
/// rows only, more of them than dofs, and an exact solve asked for (not PGS, nor CG stopped at
/// a tolerance). Where the rounds do not settle, the pivoting finishes instead.
bool solved_by_active_sets(const Model& model, const Data& data);

/// Whether data.work.newton_H holds, after forward(), the Cholesky factor L of M + J_S^T D_S J_S
/// for the rows S its solve left active (L in the lower triangle, column j's nonzeros ending
/// before data.work.hessian_envelope[j]): the active-set solve's last round settled on S (not
/// the pivoting after rounds that did not).
bool settled_active_set_factor(const Model& model, const Data& data);

/// x = H^-1 x for H = M + J^T (...) J assembled above (its lower triangle), which becomes its
/// Cholesky factor: the active sets and the Newton solver both solve with it (data's workspace
/// holds where its columns end).
void solve_with_hessian(Data& data, Eigen::Ref<Eigen::MatrixXd> H, Eigen::Ref<Eigen::VectorXd> x);

// ---- MuJoCo's primal problem (primal.cpp), shared by the Newton and CG solvers -------------
// The unknown is qacc; the cost is the Gauss term plus a convex function s of each block's
// jar = J qacc - aref (a block: an elliptic cone's dim rows, else one row). The line quantities
// below read work.newton_jar (jar at the current qacc) and work.newton_jv (J dir).

/// MuJoCo's scale of costs and gradients, meaninertia max(1, nv): meaninertia the mean of M's
/// diagonal at qpos0 (dof_M0, summed in dof order as mj_setConst's setStat does). The CG and PGS
/// solvers' tolerances are on costs divided by it.
double cost_scale(const Model& model);

/// A block's Hessian d^2 s / d jar^2 (its top-left size x size corner).
using BlockHessian = Eigen::Matrix<double, 6, 6>;

/// The rows of the block starting at row r: an elliptic cone's dim rows, else one row.
int block_size(const Data& data, int r);

/// Cost, gradient (d s / d jar, into grad[0..size)) and, with hess != nullptr, Hessian of the
/// block starting at row r, at the rows' values x[0..size). Returns the block's state.
ConstraintState block_cost(const Data& data, int r, int size, const double* x, double& cost,
                           double* grad, BlockHessian* hess);

/// Gauss term and constraint cost at qacc (work.newton_Merr, newton_x and newton_grad_x hold
/// M (qacc - qacc_smooth), the rows' jar and their gradient there afterwards).
double primal_cost(Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc);

/// The Gauss term along qacc + alpha dir, cost + alpha slope + alpha^2 curvature:
/// 1/2 |qacc - qacc_smooth|_M^2, dir^T M (qacc - qacc_smooth), 1/2 dir^T M dir.
struct LineGauss {
  double cost, slope, curvature;
};

/// A point of the line qacc + alpha dir: the cost there, its slope and curvature in alpha.
struct LinePoint {
  double alpha = 0, cost = 0, slope = 0, curvature = 0;
};

/// p's cost, slope and curvature at p.alpha: the Gauss term's plus each block's, from
/// jar + alpha J dir.
void evaluate_line(Data& data, const LineGauss& gauss, LinePoint& p);

/// The step length that minimizes the cost along dir, to rounding (Newton's method on the slope,
/// kept inside a bracket around its zero).
double exact_line_search(Data& data, const LineGauss& gauss);

/// efc_force, efc_state and qfrc_constraint at the rows' values x (forces -d s / d jar).
void record_primal_forces(Data& data, const Eigen::Ref<const Eigen::VectorXd>& x);

/// Solve the constraint rows by MuJoCo's Newton method to convergence (newton.cpp): qacc,
/// efc_b, efc_force, efc_state, qfrc_constraint. Returns the Newton steps taken.
/// @pre make_constraint, reference_constraint, qacc_smooth and M are current.
int solve_constraint_newton(const Model& model, Data& data);

/// Solve the constraint rows by MuJoCo's conjugate gradients (cg.cpp), stopped as MuJoCo stops
/// them by opt.tolerance and opt.iterations: qacc, efc_b, efc_force, efc_state,
/// qfrc_constraint. Returns the iterations taken (MuJoCo's solver_iter).
/// @pre as solve_constraint_newton.
int solve_constraint_cg(const Model& model, Data& data);

/// Solve the constraint rows by MuJoCo's projected Gauss-Seidel on the dual problem (pgs.cpp),
/// opt.iterations sweeps at most, stopped as MuJoCo stops them by opt.tolerance, from the warm
/// start (the forces at qacc_warmstart, or zero): efc_b, efc_force, efc_state (the dual states),
/// qfrc_constraint, qacc. Returns the
/// sweeps taken (MuJoCo's solver_iter). @pre as solve_constraint_newton.
int solve_constraint_pgs(const Model& model, Data& data);

/// Solve one-sided rows (limits, frictionless and pyramidal contacts) by principal pivoting on
/// A = J M^-1 J^T + R (rows.cpp), the fallback of solve_constraint's active sets: qacc,
/// efc_b, efc_force, efc_state, qfrc_constraint. For tests that compare the two.
/// @pre as solve_constraint, and no elliptic cone.
void solve_constraint_pivoting(const Model& model, Data& data);

/// efc_force, efc_state and qfrc_constraint that the rows exert at a given qacc (newton.cpp;
/// MuJoCo's mj_constraintUpdate): what inverse() reports.
void constraint_forces_at(Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc);

/// Row (nv numbers) = n^T (J_2 - J_1) at contact i's point, n its normal: the normal row of a
/// contact that has no constraint rows (one in the gap beyond margin - gap), as its rows would
/// have it (rows.cpp).
void contact_normal_row(const Model& model, Data& data, int i, double* row);

namespace unchecked {
void make_constraint(const Model& model, Data& data);
/// The body transmissions' (adhesion's) moments and velocities, from the contacts touching each
/// body and their rows (body_transmission.cpp). @pre make_constraint and transmission are current.
void body_transmission(const Model& model, Data& data);
void reference_constraint(const Model& model, Data& data);
void solve_constraint(const Model& model, Data& data);
}  // namespace unchecked

}  // namespace lever
