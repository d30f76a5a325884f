// Analytic derivatives of inverse dynamics (Carpentier and Mansard, RSS 2018): d tau / d q and
// d tau / d qd of RNEA, and d qfrc_bias / d qvel, which the implicit integrator and the step's
// Jacobians (transition/) read; and the same recursion for the polar form 2 Q(v1, v2) of RNEA's
// velocity product, which the implicit step's Jacobian reads. docs/derivatives.md derives each
// formula.
//
// Every spatial quantity is in lever's frame (world axes, origin at the tree's centre of mass c,
// see kinematics.cpp). tau is a sum of dot products S_i . F, which do not depend on the frame, so
// the derivatives may be taken with c held where it is: a frame fixed in the world. In such a
// frame moving dof j by dq_j moves everything it carries rigidly with the spatial velocity S_j:
//   d S_i / d q_j = S_j x S_i            (j a strict ancestor of i; 0 otherwise)
//   d I_b / d q_j = S_j x* I_b - I_b S_j x   (j supports body b)
// With Sdot_j = v_lambda(j) x S_j and Psi_ddot_j = a_lambda(j) x S_j + v_lambda(j) x Sdot_j (the
// velocity and acceleration just before dof j), the net force f_b = I_b a_b + v_b x* I_b v_b of a
// body b that dof j supports changes as
//   d f_b / d q_j  = S_j x* f_b + I_b Psi_ddot_j + C_b Sdot_j
//   d f_b / d qd_j = 2 I_b Sdot_j + C_b S_j,      C_b = v_b x* I_b - I_b v_b x + (I_b v_b) xbar*
// where (f xbar*) m = m x* f. Summed over a subtree (composites IC, CC, F) and dotted with S_i,
// the S_j x* F term cancels d S_i / d q_j when j is an ancestor of i, and for a pair (i, j) on one
// branch, with d the deeper of the two and b(d) its body (the paper's table, in this frame):
//   d tau_i / d q_j  = S_i . (IC Psi_ddot_j + CC Sdot_j)       + [i strictly above j] S_i . (S_j x*
//   F) d tau_i / d qd_j = S_i . (2 IC Sdot_j + CC S_j)
// (IC, CC, F of b(d)); pairs on different branches are zero.
//
// Ball and free joints, in qpos's tangent space (q -> q exp(dq)): a ball's dq_j turns its body
// about S_j, and with it all three of the ball's axes, so for i above j within one segment (a
// ball's dofs, a free joint's rotations or its translations) the S_j x* F term is cancelled too;
// Psi_ddot_j uses the acceleration before the segment, and d / d qd_j's 2 Sdot_j becomes
// Sdot_j + v' x S_j, v' the velocity after the segment. The step's position update
// qpos (+) h w contributes exp(-h [w]) and SO(3)'s right Jacobian Jr(h w) on a turn's rows, and a
// ball's spring -k log(ref^-1 q) the inverse right Jacobian. docs/derivatives.md derives each.
#include <lever/derivatives.hpp>
#include <lever/error.hpp>

#include <array>
#include <span>
#include <string>

#include "derivatives/derivatives_room.hpp"
#include "smooth/recursion.hpp"

namespace lever {

namespace detail {

void check_derivative_sizes(const Model& model, const Data& data, const Derivatives& deriv) {
  // a ball's dofs turn about its body's final axes (MuJoCo's cdof): a joint after it in the same
  // body would turn them too, a case the derivation below leaves out (docs/derivatives.md)
  for (int j = 0; model.nq != model.nv && j < model.njnt; ++j) {
    const int b = model.jnt_bodyid[j];
    if (model.jnt_kind[j] == JointKind::kBall && model.body_jntnum[b] > 1) {
      throw ModelError("derivatives: ball joint '" + model.jnt_name[j] +
                       "' shares its body with other joints; lever's analytic derivatives cover a "
                       "ball joint alone in its body so far.");
    }
  }
  if (data.nv != model.nv || data.nu != model.nu || deriv.nv != model.nv || deriv.nu != model.nu ||
      deriv.na != model.na ||
      static_cast<int>(deriv.work.qpos0.size()) != model.nq) {
    throw StateError("derivatives: Data or Derivatives was built for another model (nv " +
                     std::to_string(model.nv) + ", nu " + std::to_string(model.nu) + ").");
  }
}

Velocities bias_stage_velocities(const Data& data) {
  return {{data.cvel.data(), data.cvel.size()}, {data.cdof_dot.data(), data.cdof_dot.size()}};
}

// The inertia of each body's subtree, summed into w.IC by crba()'s composite_inertias(), for
// rnea_derivatives(), whose caller may have run kinematics() alone; after forward(),
// data.work.crb holds the same numbers and is read instead.
std::span<const RigidInertia> subtree_inertias(const Model& model, const Data& data,
                                               Derivatives::Workspace& w) {
  composite_inertias(model, data, w.IC);
  return w.IC;
}

// IC S_i of each dof i (IC its body's subtree inertia): the column force crba() finds, which every
// RNEA-derivative pass at this qpos reads (columns(), segment_velocity_columns()), so the step's
// passes share it.
void inertia_columns(const Model& model, const Data& data, std::span<const RigidInertia> IC,
                     Derivatives::Workspace& w) {
  for (int i = 0; i < model.nv; ++i) w.IC_S[i] = IC[model.dof_bodyid[i]] * data.cdof[i];
}

}  // namespace detail

namespace {

using detail::rotation_block;

// ---- inverse-dynamics derivatives, one function per pass ---------------------------------------

// The velocity coupling C = v x* I - I (v x) + (I v) xbar* of a body with inertia I = (m, h, J)
// (h = m c, J about the frame's origin) moving with v = (w, u), whose momentum is
// I v = (n, p) = (J w + h x u, m u - h x w). Writing [a] for the matrix of a x, the three terms are
//   v x* I      = [[ [w]J - [u][h],  [w][h] + m[u] ], [ -[w][h],          m[w] ]]
//   I (v x)     = [[ J[w] + [h][u],  [h][w]        ], [ -[h][w] + m[u],   m[w] ]]
//   (I v) xbar* = [[ -[n],           -[p]          ], [ -[p],             0    ]]
// and [p] = m[u] - [h][w] + [w][h] (as [a x b] = [a][b] - [b][a]) cancels the right column, so
//   C = [[S - [n], 0], [-2[p], 0]],   S = [w]J - J[w] - [u][h] - [h][u].
// S is symmetric: with P = [w]J, J[w] = -P^T; and [a][b] = b a^T - (a.b) 1.
// (Inlined into both of its callers, RNEA's and the polar form's body passes: a call returns C
// through memory.)
[[gnu::always_inline]] inline VelocityCoupling velocity_coupling(const RigidInertia& I,
                                                                 const Motion& v,
                                                                 const Force& momentum) {
  const Eigen::Vector3d w = v.head<3>(), u = v.tail<3>();
  const Eigen::Matrix3d& J = I.I;
  const Eigen::Vector3d& h = I.h;
  // P = [w] J, column by column: P(., c) = w x J(., c)
  double P[3][3];
  for (int c = 0; c < 3; ++c) {
    P[0][c] = w[1] * J(2, c) - w[2] * J(1, c);
    P[1][c] = w[2] * J(0, c) - w[0] * J(2, c);
    P[2][c] = w[0] * J(1, c) - w[1] * J(0, c);
  }
  const double uh = 2 * (u[0] * h[0] + u[1] * h[1] + u[2] * h[2]);
  VelocityCoupling C;
  // S(r, c) = P(r, c) + P(c, r) - h_r u_c - u_r h_c, + 2 u.h on the diagonal: the upper
  // triangle, mirrored
  const double s01 = (P[0][1] + P[1][0]) - (h[0] * u[1] + u[0] * h[1]);
  const double s02 = (P[0][2] + P[2][0]) - (h[0] * u[2] + u[0] * h[2]);
  const double s12 = (P[1][2] + P[2][1]) - (h[1] * u[2] + u[1] * h[2]);
  C.S(0, 0) = 2 * (P[0][0] - h[0] * u[0]) + uh;
  C.S(1, 1) = 2 * (P[1][1] - h[1] * u[1]) + uh;
  C.S(2, 2) = 2 * (P[2][2] - h[2] * u[2]) + uh;
  C.S(0, 1) = C.S(1, 0) = s01;
  C.S(0, 2) = C.S(2, 0) = s02;
  C.S(1, 2) = C.S(2, 1) = s12;
  C.momentum = momentum;
  return C;
}

// The body pass, after the forward pass gave each body's v: its momentum I v into `momentum` (the
// polar form's net force reads it again) and its velocity coupling C into CC (their subtree sums
// come next). The net force is the forward pass's (net_force, recursion.hpp); the subtree
// inertias IC do not depend on the velocity: crba()'s composites (subtree_inertias()).
void body_couplings(const Model& model, const Data& data, std::span<const Motion> v,
                    std::span<Force> momentum, std::span<VelocityCoupling> CC) {
  for (int b = 1; b < model.nbody; ++b) {
    const RigidInertia& I = data.cinert[b];
    const Force p = I * v[b];
    CC[b] = velocity_coupling(I, v[b], p);
    momentum[b] = p;  // after C: a store before it would have it read I again
  }
}

// RNEA's forward pass (forward_pass(), recursion.hpp) where each body's velocity v and each dof's
// Sdot at qd are given: each body's acceleration w.a and each dof's Psi_ddot w.Sddot, with
// forward_pass()'s sums term by term. A body of several segments (a free joint's
// translations, then its rotations) forms the velocity before each later segment again, which v
// does not hold.
void acceleration_pass(const Model& model, const Data& data, std::span<const Motion> v,
                       std::span<const Motion> Sdot, const double* qd, const double* qdd,
                       bool gravity, Derivatives::Workspace& w) {
  w.a[0].setZero();
  // the world accelerates upward: weights
  if (gravity && !model.opt.disabled(kDisableGravity)) w.a[0].tail<3>() = -model.opt.gravity;
  for (int b = 1; b < model.nbody; ++b) {
    const int parent = model.body_parentid[b];
    const Motion& a_parent = w.a[parent];
    Motion a;
    if (model.body_dofnum[b] == 1) {  // a hinge or a slide alone in its body
      const int i = model.body_dofadr[b];
      const Motion &S = data.cdof[i], &S_dot = Sdot[i];
      w.Sddot[i] = cross_motion(a_parent, S) + cross_motion(v[parent], S_dot);
      if (parent > 0 && qdd != nullptr) {
        a = a_parent + S_dot * qd[i] + S * qdd[i];
      } else if (parent > 0) {
        a = a_parent + S_dot * qd[i];
      } else if (qdd != nullptr) {
        a = a_parent + S * qdd[i];
      } else {
        a = a_parent;
      }
    } else {
      Motion vb = v[parent];
      Motion v_segment;  // the velocity the current segment's Sdot used
      BodyDofSums sums;
      Motion a_before = a_parent;  // the acceleration before dof i
      bool moving = false;
      for (int k = 0; k < model.body_dofnum[b]; ++k) {
        const int i = model.body_dofadr[b] + k;
        const Motion &S = data.cdof[i], &S_dot = Sdot[i];
        const bool starts = detail::starts_segment(model, i);
        if (starts) {
          if (k > 0) vb += sums.segment_velocity;
          v_segment = vb;
          moving = parent > 0 || k > 0;  // the world does not move: nothing before it turns S
        }
        w.Sddot[i] = cross_motion(a_before, S) + cross_motion(v_segment, S_dot);
        if (moving) a_before += S_dot * qd[i];
        if (qdd != nullptr) a_before += S * qdd[i];
        sums.add(starts, k, S, S_dot, qd, qdd, i);
      }
      a = a_parent + sums.turning;
      if (qdd != nullptr) a += sums.driven;
    }
    w.a[b] = a;
  }
}

// Each body's net force I a + v x* I v (net_force(), recursion.hpp) into w.F, after the forward
// pass (one call of it in this file, which the compiler inlines).
void net_forces(const Model& model, const Data& data, std::span<const Motion> v,
                Derivatives::Workspace& w) {
  for (int b = 1; b < model.nbody; ++b) w.F[b] = net_force(data.cinert[b], v[b], w.a[b]);
}

// The columns, from the subtree sums IC and CC, for each dof i: the pairs (i, j) with j = i or
// above it (d = i), then the pairs (k, i) with k strictly above i (d = i again, now the deeper).
// IC_S: inertia_columns() at this qpos.

// A velocity coupling's term: the subtree sums CC of C at one velocity, with the Sdot of each dof
// at a velocity (the same one for RNEA; the other for the polar form below), and S_i . CC x of
// each dof i (x's angular part: C's linear columns are zero), which every pair of dof i reads:
// CCt_S where one pass formed them for another (the polar form's CC at v1 is RNEA's), or empty:
// formed in columns().
struct CouplingTerm {
  std::span<const VelocityCoupling> CC;
  std::span<const Motion> Sdot;
  std::span<const Eigen::Vector3d> CCt_S = {};
};

// d tau / d q, from Psi_ddot (Sddot), the subtree net forces F and the coupling terms (one for
// RNEA, two for the polar form), and d tau / d qd from the coupling term `velocity` (Sdot and CC
// at one velocity, one of the terms' CC), one dof i at a time: both read S_i . CC x. The first
// term's S_i . CC x is kept in keep_CCt_S unless it is empty.
template <std::size_t Terms>
void columns(const Model& model, const Data& data, std::span<const Motion> Sddot,
             std::span<const Force> F, std::span<const RigidInertia> ICs,
             std::span<const Force> IC_S, const std::array<CouplingTerm, Terms>& couplings,
             Eigen::MatrixXd& dtau_dq, const CouplingTerm& velocity, Eigen::MatrixXd& dtau_dv,
             std::span<Eigen::Vector3d> keep_CCt_S) {
  std::size_t velocity_term = 0;  // the term whose CC the velocity's is
  while (velocity_term + 1 < Terms &&
         couplings[velocity_term].CC.data() != velocity.CC.data()) {
    ++velocity_term;
  }
  dtau_dq.setZero();
  dtau_dv.setZero();
  const std::span<const Motion> Sdot = velocity.Sdot;
  for (int i = 0; i < model.nv; ++i) {
    const int b = model.dof_bodyid[i];
    const Motion& Si = data.cdof[i];
    const RigidInertia& IC = ICs[b];
    const Force& IC_Si = IC_S[i];  // IC symmetric: S_i . IC x
    std::array<Eigen::Vector3d, Terms> CCt_Si;  // S_i . CC x (x's angular part)
    for (std::size_t t = 0; t < Terms; ++t) {
      const CouplingTerm& term = couplings[t];
      CCt_Si[t] = term.CCt_S.empty() ? term.CC[b].transpose_times(Si) : term.CCt_S[i];
    }
    if (!keep_CCt_S.empty()) keep_CCt_S[i] = CCt_Si[0];
    // the pairs (i, j), j = i or above it: d / d q, then d / d qd
    for (int j = i; j >= 0; j = model.dof_parentid[j]) {
      double sum = IC_Si.dot(Sddot[j]);
      for (std::size_t t = 0; t < Terms; ++t) {
        const Motion& Sdot_j = couplings[t].Sdot[j];
        sum += CCt_Si[t].dot(Sdot_j.head<3>());
      }
      dtau_dq(i, j) = sum;
    }
    for (int j = i; j >= 0; j = model.dof_parentid[j]) {
      dtau_dv(i, j) = 2 * IC_Si.dot(Sdot[j]) + CCt_Si[velocity_term].dot(data.cdof[j].head<3>());
    }
    // the pairs (k, i), k strictly above i, read S_k . X: none where i hangs from the world (a
    // root's first dof), whose X is not formed
    if (model.dof_parentid[i] < 0) continue;
    Force Xq = IC * Sddot[i];
    for (std::size_t t = 0; t < Terms; ++t) Xq += couplings[t].CC[b] * couplings[t].Sdot[i];
    Xq += cross_force(Si, F[b]);
    for (int k = model.dof_parentid[i]; k >= 0; k = model.dof_parentid[k]) {
      dtau_dq(k, i) = data.cdof[k].dot(Xq);
    }
    const Force Xv = 2 * (IC * Sdot[i]) + velocity.CC[b] * Si;
    for (int k = model.dof_parentid[i]; k >= 0; k = model.dof_parentid[k]) {
      dtau_dv(k, i) = data.cdof[k].dot(Xv);
    }
  }
}

// ---- what a ball (or a free joint's rotation) changes: its three dofs turn together
// --------------

// Psi_ddot of a segment's second and third dofs with the acceleration before the segment, not
// before the dof: the forward pass gave a_i x S_i + v_seg x Sdot_i, where a_i adds the segment's
// earlier dofs' accelerations (add(k, sum) adds dof k's: RNEA's Sdot_k qd_k + S_k qdd_k), which
// turn with dof i (docs/derivatives.md). A free joint's translations need nothing (linear x
// linear = 0).
template <class AddDof>
void segment_accelerations(const Model& model, const Data& data, AddDof&& add,
                           std::span<Motion> Sddot) {
  for (int j = 0; j < model.njnt; ++j) {
    const int r = rotation_block(model, j);
    if (r < 0) continue;
    Motion added = Motion::Zero();  // what the segment's dofs before i add to the acceleration
    for (int i = r + 1; i < r + 3; ++i) {
      add(i - 1, added);
      Sddot[i] -= cross_motion(added, data.cdof[i]);
    }
  }
}

// d tau_k / d q_i of a segment's dofs, corrected after columns(): for k before i in the
// segment, turning about S_i turns S_k too, and d S_k / d q_i . F = (S_i x S_k) . F cancels the
// S_i x* F term the hinge formula adds.
void segment_position_columns(const Model& model, const Data& data, std::span<const Force> F,
                              Eigen::MatrixXd& dtau_dq) {
  for (int j = 0; j < model.njnt; ++j) {
    const int r = rotation_block(model, j);
    if (r < 0) continue;
    const int b = model.jnt_bodyid[j];
    for (int i = r + 1; i < r + 3; ++i) {  // the block's first dof has no k before it
      const Force S_cross_F = cross_force(data.cdof[i], F[b]);
      for (int k = r; k < i; ++k) dtau_dq(k, i) -= data.cdof[k].dot(S_cross_F);
    }
  }
}

// d tau / d qd_i of a segment's dofs, corrected after columns(): d a_c / d qd_i =
// Sdot_i + v' x S_i + S_i x v_c, v' the velocity after the segment, where a hinge has 2 Sdot_i;
// the difference E = v' x S_i - Sdot_i enters as IC E wherever 2 IC Sdot_i did. (v' is the
// body's velocity less the dofs after the segment in the same body: none for a free joint or a
// ball alone in its body.)
void segment_velocity_columns(const Model& model, const Data& data, const double* qd,
                              std::span<const Motion> v, std::span<const Motion> Sdot,
                              std::span<const RigidInertia> IC, std::span<const Force> IC_S,
                              Eigen::Ref<Eigen::MatrixXd> dtau_dv) {
  for (int j = 0; j < model.njnt; ++j) {
    const int r = rotation_block(model, j);
    if (r < 0) continue;
    const int b = model.jnt_bodyid[j];
    Motion v_after = v[b];
    for (int k = r + 3; k < model.body_dofadr[b] + model.body_dofnum[b]; ++k) {
      v_after -= data.cdof[k] * qd[k];
    }
    for (int i = r; i < r + 3; ++i) {
      const Motion& Si = data.cdof[i];
      const Motion E = cross_motion(v_after, Si) - Sdot[i];
      // rows at or below i (the row's dof the deeper: its body's composite inertia)
      for (int row = i; row < model.nv; ++row) {
        int up = row;
        while (up > i) up = model.dof_parentid[up];
        if (up != i) continue;  // i is not on row's path to the world
        dtau_dv(row, i) += IC_S[row].dot(E);  // IC S_row, inertia_columns()'s
      }
      // rows above i (i the deeper dof)
      const Force IC_E = IC[b] * E;
      for (int k = model.dof_parentid[i]; k >= 0; k = model.dof_parentid[k]) {
        dtau_dv(k, i) += data.cdof[k].dot(IC_E);
      }
    }
  }
}

// ---- the polar form of the velocity product -----------------------------------------------------
// rnea = Q(qd, qd) + L(qdd, gravity), Q quadratic in the velocity and L linear. The polar form
// P(v1, v2) = Q(v1 + v2) - Q(v1) - Q(v2) = 2 Q(v1, v2) follows RNEA's quantities term by term:
// each product of two velocity-linear factors (v x S, v x* I v, C(v) Sdot(v)) becomes the sum of
// its two cross products, one factor at each velocity:
//   Sdot_i^k = v_seg^k x S_i                       (k = 1, 2: each velocity's own, linear)
//   a_b      = a_parent + sum_i (Sdot_i^1 v2_i + Sdot_i^2 v1_i + S_i qdd_i)
//   Psi_ddot_i = a_before_i x S_i + v_seg^1 x Sdot_i^2 + v_seg^2 x Sdot_i^1
//   f_b      = I_b a_b + v_b^1 x* I_b v_b^2 + v_b^2 x* I_b v_b^1
// and d tau / d q's coupling term C Sdot becomes C(v1) Sdot^2 + C(v2) Sdot^1. Its derivative in
// v1 is RNEA's d tau / d qd at v2 (d Q(v1) / d v1 = 2 Q(v1, .)).

// Body b's net force I a + v1 x* I v2 + v2 x* I v1 (the polar form of net_force()'s v x* I v,
// with I a beside it) into w.F and its velocity coupling at v2 into w.CC2, once the forward pass
// has its velocities and a: I v2 formed once for both, I v1 RNEA's (w.momentum, body_couplings()).
void polar_body(const Data& data, int b, const Motion& v1, const Motion& a,
                Derivatives::Workspace& w) {
  const RigidInertia& I = data.cinert[b];
  const Force momentum2 = I * w.v2[b];
  Force f = I * a;
  f += cross_force(v1, momentum2);
  f += cross_force(w.v2[b], w.momentum[b]);
  w.F[b] = f;
  w.CC2[b] = velocity_coupling(I, w.v2[b], momentum2);
}

// The forward pass of the polar form, root to leaves, dof by dof as forward_pass() (recursion.hpp)
// walks a body's segments: each body's velocity w.v2, its acceleration w.a, net force w.F and
// velocity coupling at v2 w.CC2 (polar_body()), each dof's Sdot at v2 (w.Sdot2) and its Psi_ddot
// (w.Sddot). The velocities at v1 and their Sdot are RNEA's (at_v1: forward_pass()'s sums, which
// rnea_derivatives_into() at v1 read): the same sums, bit for bit (a segment's sum here starts
// from +0, which changes only a -0, and no body's velocity is -0: the world's is +0, and a sum is
// -0 only where both of its terms are). A later segment's velocity at v1 is summed here, as
// at_v1 holds none.
// No gravity: it belongs to Q(v1 + v2) and Q(v1), cancelling in P. qdd == nullptr: zero.
void polar_forward_pass(const Model& model, const Data& data, const detail::Velocities& at_v1,
                        const double* v1, const double* v2, const double* qdd,
                        Derivatives::Workspace& w) {
  const std::span<const Motion> V1 = at_v1.v, Sdot1 = at_v1.Sdot;
  w.v2[0].setZero();
  w.a[0].setZero();
  for (int b = 1; b < model.nbody; ++b) {
    const int parent = model.body_parentid[b];
    if (model.body_dofnum[b] == 1) {
      // a hinge or a slide alone in its body: one segment, which the parent's velocities turn;
      // the loop below's arithmetic without its bookkeeping
      const int i = model.body_dofadr[b];
      const Motion& S = data.cdof[i];
      const Motion &v1_parent = V1[parent], &v2_parent = w.v2[parent];
      if (parent > 0) {
        w.Sdot2[i] = cross_motion(v2_parent, S);
      } else {
        w.Sdot2[i].setZero();
      }
      const Motion& a_parent = w.a[parent];
      w.Sddot[i] = cross_motion(a_parent, S) + cross_motion(v1_parent, w.Sdot2[i]) +
                   cross_motion(v2_parent, Sdot1[i]);
      Motion a = a_parent + (Sdot1[i] * v2[i] + w.Sdot2[i] * v1[i]);
      if (qdd != nullptr) a += S * qdd[i];
      w.v2[b] = v2_parent + S * v2[i];
      w.a[b] = a;
      polar_body(data, b, V1[b], a, w);
      continue;
    }
    Motion vb1 = V1[parent], vb2 = w.v2[parent];
    Motion seg1 = Motion::Zero(), seg2 = Motion::Zero();  // the current segment's S v summed
    Motion v1_seg, v2_seg;  // the velocities the current segment's Sdot uses
    Motion a = w.a[parent];  // the acceleration before dof i
    bool moving = false;
    for (int k = 0; k < model.body_dofnum[b]; ++k) {
      const int i = model.body_dofadr[b] + k;
      const Motion& S = data.cdof[i];
      if (detail::starts_segment(model, i)) {
        if (k > 0) {
          vb1 += seg1;
          vb2 += seg2;
          seg1.setZero();
          seg2.setZero();
        }
        v1_seg = vb1;
        v2_seg = vb2;
        moving = parent > 0 || k > 0;  // the world does not move: nothing before it turns S
      }
      if (moving) {
        w.Sdot2[i] = cross_motion(v2_seg, S);
      } else {
        w.Sdot2[i].setZero();
      }
      w.Sddot[i] = cross_motion(a, S) + cross_motion(v1_seg, w.Sdot2[i]) +
                   cross_motion(v2_seg, Sdot1[i]);
      a += Sdot1[i] * v2[i] + w.Sdot2[i] * v1[i];
      if (qdd != nullptr) a += S * qdd[i];
      seg1 += S * v1[i];
      seg2 += S * v2[i];
    }
    w.v2[b] = vb2 + seg2;
    w.a[b] = a;
    polar_body(data, b, V1[b], a, w);
  }
}

}  // namespace

namespace detail {

// Carpentier and Mansard's first-order RNEA derivatives at (data.qpos, qd, qdd), into dtau_dq
// and dtau_dv, given the subtree inertias IC at data.qpos (data.work.crb after forward()) and
// w.IC_S (inertia_columns()) from them, and the velocities at qd where forward() left them; the
// subtree sums of C at qd are left in w.CC (with w.CCt_S and w.momentum, which the polar form
// reads). Armature adds armature * qdd, which depends on neither.
void rnea_derivatives_into(const Model& model, const Data& data, const double* qd,
                           const double* qdd, bool gravity, std::span<const RigidInertia> IC,
                           Derivatives::Workspace& w, Eigen::MatrixXd& dtau_dq,
                           Eigen::MatrixXd& dtau_dv, const Velocities* at_qd) {
  // root to leaves: v and a of every body, Sdot and Psi_ddot of every dof, each body's net force
  // (RNEA's forward pass); v and Sdot read where they are given
  std::span<const Motion> v = w.v, Sdot = w.Sdot;
  if (at_qd != nullptr) {
    v = at_qd->v;
    Sdot = at_qd->Sdot;
    acceleration_pass(model, data, v, Sdot, qd, qdd, gravity, w);
  } else {
    forward_pass(model, data, qd, qdd, gravity, w.v, w.a, &w.Sdot, &w.Sddot);
  }
  net_forces(model, data, v, w);
  if (model.nq != model.nv) {
    segment_accelerations(
        model, data,
        [&](int k, Motion& added) {
          added += Sdot[k] * qd[k];
          if (qdd != nullptr) added += data.cdof[k] * qdd[k];
        },
        std::span<Motion>(w.Sddot));
  }
  // leaves to root: the composites of f and C over each subtree (RNEA's backward pass)
  sum_over_subtrees<Force>(model, w.F);
  body_couplings(model, data, v, w.momentum, w.CC);
  sum_over_subtrees<VelocityCoupling>(model, w.CC);
  const CouplingTerm coupling{w.CC, Sdot};
  columns<1>(model, data, w.Sddot, w.F, IC, w.IC_S, {coupling}, dtau_dq, coupling, dtau_dv,
             w.CCt_S);  // kept for the polar form
  if (model.nq != model.nv) {
    segment_position_columns(model, data, w.F, dtau_dq);
    segment_velocity_columns(model, data, qd, v, Sdot, IC, w.IC_S, dtau_dv);
  }
}

// The derivatives of 2 Q(v1, v2) + L(qdd) (polar_forward_pass()'s quantities, then RNEA's
// backward sums and columns on them), reading w.CC at v1 (derivatives_room.hpp).
void polar_derivatives_into(const Model& model, const Data& data, const Velocities& at_v1,
                            const double* v1, const double* v2, const double* qdd,
                            std::span<const RigidInertia> IC, Derivatives::Workspace& w,
                            Eigen::MatrixXd& dtau_dq, Eigen::MatrixXd& dtau_dv2) {
  const std::span<const Motion> Sdot1 = at_v1.Sdot;
  polar_forward_pass(model, data, at_v1, v1, v2, qdd, w);
  if (model.nq != model.nv) {
    segment_accelerations(
        model, data,
        [&](int k, Motion& added) {
          added += Sdot1[k] * v2[k] + w.Sdot2[k] * v1[k];
          if (qdd != nullptr) added += data.cdof[k] * qdd[k];
        },
        std::span<Motion>(w.Sddot));
  }
  sum_over_subtrees<Force>(model, w.F);
  sum_over_subtrees<VelocityCoupling>(model, w.CC2);  // w.CC: C at v1, the caller's
  const CouplingTerm at_v1_term{w.CC, w.Sdot2, w.CCt_S}, at_v2_term{w.CC2, Sdot1};
  columns<2>(model, data, w.Sddot, w.F, IC, w.IC_S, {at_v1_term, at_v2_term}, dtau_dq,
             {w.CC2, w.Sdot2}, dtau_dv2, {});
  if (model.nq != model.nv) {
    segment_position_columns(model, data, w.F, dtau_dq);
    segment_velocity_columns(model, data, v2, w.v2, w.Sdot2, IC, w.IC_S, dtau_dv2);
  }
}

}  // namespace detail

void rnea_derivatives(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc,
                      Derivatives& deriv) {
  detail::check_derivative_sizes(model, data, deriv);
  if (qacc.size() != model.nv) {
    throw StateError("rnea_derivatives: qacc has " + std::to_string(qacc.size()) +
                     " elements, the model has nv = " + std::to_string(model.nv) + ".");
  }
  const std::span<const RigidInertia> IC = detail::subtree_inertias(model, data, deriv.work);
  detail::inertia_columns(model, data, IC, deriv.work);
  detail::rnea_derivatives_into(model, data, data.qvel.data(), qacc.data(), true, IC, deriv.work,
                                deriv.dtau_dq, deriv.dtau_dv);
}

}  // namespace lever
