// The two passes of the recursive Newton-Euler algorithm (Featherstone, RBDA 2008, table 5.1),
// written once for every algorithm that runs them: inverse dynamics and the bias forces (rnea.cpp),
// the inverse-dynamics derivatives (derivatives/inverse_dynamics.cpp) and the inertial-parameter
// regressor (regressor.cpp). Every quantity is in lever's absolute coordinates (see
// kinematics.cpp), where the passes need no coordinate transforms. Inline, so that each caller's
// copy drops the outputs it does not ask for.
#pragma once

#include <span>
#include <type_traits>
#include <vector>

#include <lever/data.hpp>
#include <lever/model.hpp>
#include <lever/spatial.hpp>

#include "smooth/smooth.hpp"

namespace lever {

/// The net force I a + v x* I v a body of inertia I needs to move with velocity v and
/// acceleration a (Featherstone eq. 5.9), summed as MuJoCo's mj_rne sums it: the two momenta by
/// RigidInertia * Motion (mju_mulInertVec's order), then v x* (I v) added term by term. Where
/// the forces of a long chain cancel, another order (Newton and Euler's equations about the
/// origin, 57 products rather than 66) rounds to other last bits.
inline Force net_force(const RigidInertia& I, const Motion& v, const Motion& a) {
  // I a and I v side by side, a's element first in each pair: the two lanes do the same
  // arithmetic (RigidInertia * Motion's, term by term), so one SSE2 instruction does both
  using Pair = Eigen::Array2d;
  const Pair x0(a[0], v[0]), x1(a[1], v[1]), x2(a[2], v[2]);
  const Pair x3(a[3], v[3]), x4(a[4], v[4]), x5(a[5], v[5]);
  const Eigen::Matrix3d& J = I.I;
  const double h0 = I.h[0], h1 = I.h[1], h2 = I.h[2], m = I.m;
  const Pair r0 = J(0, 0) * x0 + J(0, 1) * x1 + J(0, 2) * x2 - h2 * x4 + h1 * x5;
  const Pair r1 = J(1, 0) * x0 + J(1, 1) * x1 + J(1, 2) * x2 + h2 * x3 - h0 * x5;
  const Pair r2 = J(2, 0) * x0 + J(2, 1) * x1 + J(2, 2) * x2 - h1 * x3 + h0 * x4;
  const Pair r3 = m * x3 - (h1 * x2 - h2 * x1);
  const Pair r4 = m * x4 - (h2 * x0 - h0 * x2);
  const Pair r5 = m * x5 - (h0 * x1 - h1 * x0);
  // the momentum p = I v, and v x* p added to I a (cross_force's terms)
  const double p0 = r0[1], p1 = r1[1], p2 = r2[1], p3 = r3[1], p4 = r4[1], p5 = r5[1];
  Force f;
  f[0] = r0[0] + ((v[1] * p2 - v[2] * p1) + (v[4] * p5 - v[5] * p4));
  f[1] = r1[0] + ((v[2] * p0 - v[0] * p2) + (v[5] * p3 - v[3] * p5));
  f[2] = r2[0] + ((v[0] * p1 - v[1] * p0) + (v[3] * p4 - v[4] * p3));
  f[3] = r3[0] + (v[1] * p5 - v[2] * p4);
  f[4] = r4[0] + (v[2] * p3 - v[0] * p5);
  f[5] = r5[0] + (v[0] * p4 - v[1] * p3);
  return f;
}

/// A body of several dofs in RNEA's forward pass, summed in MuJoCo's order (mj_comVel, mj_rne):
/// a segment's S qd before it joins the body's velocity, and the body's Sdot qd terms, then its
/// S qdd terms (qdd == nullptr: none), before they join the parent's acceleration. add() takes
/// the body's k-th dof i, which starts a segment or not.
struct BodyDofSums {
  Motion segment_velocity = Motion::Zero();  // the current segment's S qd summed
  Motion turning = Motion::Zero();           // the body's Sdot qd summed
  Motion driven = Motion::Zero();            // the body's S qdd summed

  void add(bool starts_segment, int k, const Motion& S, const Motion& S_dot, const double* qd,
           const double* qdd, int i) {
    if (starts_segment) {
      segment_velocity = S * qd[i];
    } else {
      segment_velocity += S * qd[i];
    }
    if (k == 0) {
      turning = S_dot * qd[i];
      if (qdd != nullptr) driven = S * qdd[i];
    } else {
      turning += S_dot * qd[i];
      if (qdd != nullptr) driven += S * qdd[i];
    }
  }
};

/// RNEA's forward pass: every body's velocity v and acceleration a from its parent's, root to
/// leaves, dof by dof:
///   v = v_parent + S_i qd_i,   a = a_parent + Sdot_i qd_i + S_i qdd_i,   Sdot_i = v_seg x S_i
/// (v, a before dof i; v_seg the velocity before dof i's segment: the dof itself for a hinge or
/// a slide, a ball's three rotations together, see detail::starts_segment). qdd == nullptr: zero.
/// gravity: the world accelerates upward at -g, so the forces found from a include the weights.
/// Sdot and Sddot (nv each, or nullptr) receive each dof's Sdot_i and its derivative a x S_i + v x
/// Sdot_i (the inverse-dynamics derivatives' Psi). done(b, v[b], a[b]) runs as each body is
/// finished, while its v and a are at hand (RNEA's net force, rnea.cpp).
/// Motions: a std::vector<Motion> or a Data's ArenaArray<Motion>, taken by reference (as spans
/// the passes cost some 8% more instructions: GCC keeps less of them in registers).
template <class Motions, class BodyDone>
inline void forward_pass(const Model& model, const Data& data, const double* qd, const double* qdd,
                         bool gravity, Motions& v, Motions& a, std::type_identity_t<Motions>* Sdot,
                         std::type_identity_t<Motions>* Sddot, BodyDone&& done) {
  v[0].setZero();
  a[0].setZero();
  // the world accelerates upward: weights
  if (gravity && !model.opt.disabled(kDisableGravity)) a[0].template tail<3>() = -model.opt.gravity;

  for (int b = 1; b < model.nbody; ++b) {
    const int parent = model.body_parentid[b];
    if (model.body_dofnum[b] == 1) {
      // a hinge or a slide, alone in its body (the arms' every joint): one segment, which the
      // parent's velocity turns; the same arithmetic as the loop below, without its bookkeeping,
      // each sum written once into its destination
      const int i = model.body_dofadr[b];
      const Motion& S = data.cdof[i];
      const Motion& v_parent = v[parent];
      const Motion& a_parent = a[parent];
      Motion S_dot_here;
      Motion& S_dot = Sdot != nullptr ? (*Sdot)[i] : S_dot_here;
      if (parent > 0) {
        S_dot = cross_motion(v_parent, S);
      } else {
        S_dot.setZero();
      }
      if (Sddot != nullptr) (*Sddot)[i] = cross_motion(a_parent, S) + cross_motion(v_parent, S_dot);
      if (parent > 0 && qdd != nullptr) {
        a[b] = a_parent + S_dot * qd[i] + S * qdd[i];
      } else if (parent > 0) {
        a[b] = a_parent + S_dot * qd[i];
      } else if (qdd != nullptr) {
        a[b] = a_parent + S * qdd[i];
      } else {
        a[b] = a_parent;
      }
      v[b] = v_parent + S * qd[i];
      done(b, v[b], a[b]);
      continue;
    }
    // MuJoCo's order (mj_comVel, mj_rne): a segment's dofs summed before they join the body's
    // velocity, and the body's Sdot qd terms, then its S qdd terms, before they join the parent's
    // acceleration
    Motion vb = v[parent];
    Motion v_segment;   // the velocity the current segment's Sdot uses
    BodyDofSums sums;
    Motion a_before;  // the acceleration before dof i, dof by dof, for Sddot alone
    if (Sddot != nullptr) a_before = a[parent];
    bool moving = false;
    for (int k = 0; k < model.body_dofnum[b]; ++k) {
      const int i = model.body_dofadr[b] + k;
      const Motion& S = data.cdof[i];
      if (detail::starts_segment(model, i)) {
        if (k > 0) vb += sums.segment_velocity;
        v_segment = vb;
        moving = parent > 0 || k > 0;  // the world does not move: nothing before it turns S
      }
      // S moves with the body that carries it: Sdot = v x S
      Motion S_dot_here;
      Motion& S_dot = Sdot != nullptr ? (*Sdot)[i] : S_dot_here;
      if (moving) {
        S_dot = cross_motion(v_segment, S);
      } else {
        S_dot.setZero();
      }
      if (Sddot != nullptr) {
        (*Sddot)[i] = cross_motion(a_before, S) + cross_motion(v_segment, S_dot);
        if (moving) a_before += S_dot * qd[i];
        if (qdd != nullptr) a_before += S * qdd[i];
      }
      sums.add(detail::starts_segment(model, i), k, S, S_dot, qd, qdd, i);
    }
    if (model.body_dofnum[b] > 0) vb += sums.segment_velocity;
    Motion ab = a[parent] + sums.turning;
    if (qdd != nullptr) ab += sums.driven;
    v[b] = vb;
    a[b] = ab;
    done(b, v[b], a[b]);
  }
}

/// The forward pass alone (the derivatives and the regressor use v and a after it).
template <class Motions>
inline void forward_pass(const Model& model, const Data& data, const double* qd, const double* qdd,
                         bool gravity, Motions& v, Motions& a, std::type_identity_t<Motions>* Sdot,
                         std::type_identity_t<Motions>* Sddot) {
  forward_pass(model, data, qd, qdd, gravity, v, a, Sdot, Sddot,
               [](int, const Motion&, const Motion&) {});
}

/// Each body's value x[b] replaced by its sum over the body's subtree, leaves to root (the world,
/// body 0, is left out). T has +=: a force, a RigidInertia, the derivatives' couplings.
template <class T>
inline void sum_over_subtrees(const Model& model, std::span<T> x) {
  for (int b = model.nbody - 1; b > 0; --b) {
    const int parent = model.body_parentid[b];
    if (parent > 0) x[parent] += x[b];
  }
}

/// CRBA's composite inertias: each body's cinert summed over its subtree, leaves to root, into IC
/// (the world, body 0, left out). crba() keeps them in data.work.crb; the derivatives sum their
/// own where forward() has not run.
inline void composite_inertias(const Model& model, const Data& data, std::span<RigidInertia> IC) {
  for (int b = 1; b < model.nbody; ++b) IC[b] = data.cinert[b];
  sum_over_subtrees<RigidInertia>(model, IC);
}

/// RNEA's backward pass: each body's net force f summed into its parent's, leaves to root (f is
/// overwritten with the force each body's joint transmits), then tau_i = S_i . f of dof i's body.
inline void backward_pass(const Model& model, const Data& data, std::span<Force> f, double* tau) {
  sum_over_subtrees<Force>(model, f);  // a joint carries the force of its whole subtree
  for (int i = 0; i < model.nv; ++i) tau[i] = power(data.cdof[i], f[model.dof_bodyid[i]]);
}

}  // namespace lever
