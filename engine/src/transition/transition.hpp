// The transition room: forward dynamics and the step differentiated (step_derivatives.cpp): the
// chain rule through M^-1, the passive forces, the actuators and the constraint rows, then Euler,
// RK4 and the implicit step, in qpos's tangent space. The rows with their active set held:
// joint limits in step_derivatives.cpp, every row once a contact's is active in contact_rows.cpp,
// on the contact geometry's derivative (contact_geometry.cpp, which reads the collision stage's
// contacts), a connect's and weld's rows in equality_rows.cpp, a spatial tendon's Jacobian's
// change in spatial_tendons.cpp. Its public face is
// lever/derivatives.hpp (forward_derivatives, step_derivatives); it reads the derivatives room's
// RNEA derivatives and runs the pipeline's forward().
#pragma once

#include <Eigen/Core>

#include <vector>

#include <lever/derivatives.hpp>
#include <lever/model.hpp>

namespace lever::detail {

using lever::ContactChange;

/// y += a x over n numbers (x and y apart): a row operation of the side-by-side solves (tens of
/// columns), four numbers a step as two of SSE2's pairs (the x86-64 baseline's), each number's
/// product and sum as a plain loop's, so the same bits; a compiler-vectorised loop's set-up and
/// remainder, or Eigen's on a dynamic row, cost more than the arithmetic on rows this short.
inline void add_scaled_row(double* __restrict y, double a, const double* __restrict x,
                           Eigen::Index n) {
  using Pair = double __attribute__((vector_size(16)));
  const Pair scale = {a, a};
  Eigen::Index c = 0;
  for (; c + 4 <= n; c += 4) {
    Pair x0, x1, y0, y1;
    __builtin_memcpy(&x0, x + c, sizeof(Pair));  // unaligned loads and stores
    __builtin_memcpy(&x1, x + c + 2, sizeof(Pair));
    __builtin_memcpy(&y0, y + c, sizeof(Pair));
    __builtin_memcpy(&y1, y + c + 2, sizeof(Pair));
    y0 += scale * x0;
    y1 += scale * x1;
    __builtin_memcpy(y + c, &y0, sizeof(Pair));
    __builtin_memcpy(y + c + 2, &y1, sizeof(Pair));
  }
  for (; c < n; ++c) y[c] += a * x[c];
}

/// x *= d over n numbers: a solve's diagonal (d its reciprocal), as add_scaled_row() two numbers a
/// pair.
inline void scale_row(double* x, double d, Eigen::Index n) {
  using Pair = double __attribute__((vector_size(16)));
  const Pair scale = {d, d};
  Eigen::Index c = 0;
  for (; c + 2 <= n; c += 2) {
    Pair p;
    __builtin_memcpy(&p, x + c, sizeof(Pair));
    p *= scale;
    __builtin_memcpy(x + c, &p, sizeof(Pair));
  }
  if (c < n) x[c] *= d;
}

/// Whether contact_change() covers a pair of geom types (in MuJoCo's order, a before b).
bool contact_geometry_supported(GeomType a, GeomType b);

/// The change of data.contact[i] when geom1 moves rigidly with angular velocity w1 and its centre
/// with velocity v1, and geom2 with (w2, v2): the narrow phase on dual numbers, its case held
/// (contact_geometry.cpp). Throws lever::Error for a pair it does not cover, or a contact it does
/// not reproduce.
void contact_change(const Model& model, const Data& data, int i, const Eigen::Vector3d& w1,
                    const Eigen::Vector3d& v1, const Eigen::Vector3d& w2,
                    const Eigen::Vector3d& v2, ContactChange& change);

/// The first of the contacts data.contact holds for contact i's geom pair (they come one after
/// another, in the narrow phase's order), and in `count` how many there are.
int pair_first_contact(const Data& data, int i, int& count);

/// contact_change() for each of the `count` contacts of the pair whose first is `first`
/// (pair_first_contact()) along each of the `directions` motions: changes[m * count + k] for
/// contact first + k along motions[m] (packed: one motion's contacts share cache lines). The narrow phase runs once per six motions, and its
/// values are checked against data.contact once.
void pair_contact_changes(const Model& model, const Data& data, int first, int count,
                          const GeomPairMotion* motions, int directions, ContactChange* changes);

/// Whether a row other than a joint limit's exerts a force after forward() (a contact pushing, a
/// friction-loss, tendon-limit or equality row): constraint_rows_held() then takes every row.
bool rows_beyond_joint_limits(const Data& data);

/// moves[c] = 1 for every dof that moves body b (its dof path to the root), 0 for the others.
void dofs_moving(const Model& model, int body, std::vector<char>& moves);

/// The velocity of point p per unit rate of dof c: cdof's linear part moved from its tree's
/// centre of mass to p.
Eigen::Vector3d point_velocity(const Model& model, const Data& data, int c,
                               const Eigen::Vector3d& p);

/// table[c * nv + i] = 1 where moving dof c turns the axis of dof i (c a strict ancestor of i, or
/// both in one ball's or free joint's rotation): the contact rows' Jacobian derivative reads it.
void carry_table(const Model& model, std::vector<char>& table);

/// The dofs on one branch with each dof (its ancestors, itself, its descendants), where M can be
/// non-zero: row i's, ascending, are dofs[first[i] .. first[i + 1]) (first has nv + 1 numbers).
void branch_table(const Model& model, std::vector<int>& first, std::vector<int>& dofs);

/// The rows whose force is linear in the state with the active set held (kActive: limits,
/// pyramids, frictionless, elliptic cones in their quadratic zone) into rows; returns how many.
/// Throws lever::Error for an elliptic cone on its surface (its middle zone).
int held_active_rows(const Data& data, std::vector<int>& rows);

/// The dofs row r's Jacobian can be non-zero on, from lo: a contact's span of dofs
/// (data.work.contact_span), a joint limit's or a dof's friction loss's one dof, else every dof.
struct RowSpan {
  int lo, count;
};
RowSpan row_span(const Data& data, int r);

/// H = M + G, G = J_S^T D_S J_S over the rows rows[0..n) (D = 1 / R, G kept for the caller),
/// factored in place as L L^T (L in its lower triangle): the matrix of forward dynamics linearised
/// with those rows' active set held. first[i] (nv): the first column of row i of H, and of L, that
/// is not zero (its profile).
void factor_held_rows(const Data& data, const int* rows, int n, Eigen::MatrixXd& G,
                      Eigen::MatrixXd& H, std::vector<int>& first);

/// X = H^-1 X, every column, with the forward solve's factor of H where
/// settled_active_set_factor() says it holds one (the constraint room's data.work.newton_H);
/// diagonal_inverse: nv numbers of scratch (the factor's 1 / L(j, j)).
void solve_settled_factor(const Data& data, Eigen::Ref<RowMatrix> X, double* diagonal_inverse);

/// X = H^-1 X, every column, with factor_held_rows()' factor L and profile; diagonal_inverse: nv
/// numbers of scratch (the factor's 1 / L(i, i)).
void solve_held_rows(const Eigen::MatrixXd& L, const std::vector<int>& first,
                     Eigen::Ref<RowMatrix> X, double* diagonal_inverse);

/// A connect's (3) or weld's (6) rows, equality constraint e's, at rows w.rows[first_k ...]:
/// their terms of Y (qpos columns: D (d aref - dR f - dJ qacc)) and of E (dJ^T f), as the
/// contacts' (equality_rows.cpp). Uses w.moves1, w.moves2 and w.equality_point_velocity.
void body_equality_rows(const Model& model, const Data& data, int e, int first_k,
                        Derivatives::Workspace& w);

/// Whether tendon t is spatial (a path of sites), whose Jacobian moves with the pose.
bool is_spatial_tendon(const Model& model, int t);

/// w.tendon_change(i, c) = d ten_J(t, i) / d q_c for spatial tendon t: straight segments, pulleys
/// and wraps around spheres and cylinders (spatial_tendons.cpp). Uses w.moves1, w.moves2,
/// w.equality_point_velocity, w.segment_motion and w.tangent_motion.
void spatial_tendon_change(const Model& model, const Data& data, int t,
                           Derivatives::Workspace& w);

/// out += scale P(x y^T + y x^T) a, P keeping the pairs of dofs on one branch (where M is
/// non-zero, as the implicit step's D keeps its outer products).
void add_pair_product(const Model& model, const double* x, const double* y, const double* a,
                      double scale, Eigen::Ref<Eigen::VectorXd, 0, Eigen::InnerStride<>> out);

/// d qacc and d qfrc_constraint with the active set held, every active row (limits and contacts),
/// from the right-hand sides d f_smooth - d ID in deriv.work.rhs_q, rhs_v, rhs_u (before M^-1;
/// contact_rows.cpp).
/// Throws lever::Error for an elliptic cone in its middle zone.
void constraint_rows_held(const Model& model, Data& data, Derivatives& deriv);

}  // namespace lever::detail
