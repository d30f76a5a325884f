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

/// The net force I a + v x* I v a body of inertia I = (m, h, I_o) needs to move with velocity
/// v = (w, v_o) and acceleration a = (dw, a_o) (Featherstone eq. 5.9), written as Newton and
/// Euler's equations about the frame origin o with its classical acceleration a_c = a_o + w x v_o:
///   moment = I_o dw + w x I_o w + h x a_c,   force = m a_c - h x dw - w x (h x w)
/// (57 products where the spatial form takes 66).
inline Force net_force(const RigidInertia& I, const Motion& v, const Motion& a) {
  const double w0 = v[0], w1 = v[1], w2 = v[2];
  const double d0 = a[0], d1 = a[1], d2 = a[2];
  // the origin's classical acceleration
  const double c0 = a[3] + (w1 * v[5] - w2 * v[4]);
  const double c1 = a[4] + (w2 * v[3] - w0 * v[5]);
  const double c2 = a[5] + (w0 * v[4] - w1 * v[3]);
  const Eigen::Matrix3d& J = I.I;
  const double h0 = I.h[0], h1 = I.h[1], h2 = I.h[2], m = I.m;
  const double Jw0 = J(0, 0) * w0 + J(0, 1) * w1 + J(0, 2) * w2;
  const double Jw1 = J(1, 0) * w0 + J(1, 1) * w1 + J(1, 2) * w2;
  const double Jw2 = J(2, 0) * w0 + J(2, 1) * w1 + J(2, 2) * w2;
  const double hw0 = h1 * w2 - h2 * w1, hw1 = h2 * w0 - h0 * w2, hw2 = h0 * w1 - h1 * w0;
  Force f;
  f[0] = (J(0, 0) * d0 + J(0, 1) * d1 + J(0, 2) * d2) + (w1 * Jw2 - w2 * Jw1) + (h1 * c2 - h2 * c1);
  f[1] = (J(1, 0) * d0 + J(1, 1) * d1 + J(1, 2) * d2) + (w2 * Jw0 - w0 * Jw2) + (h2 * c0 - h0 * c2);
  f[2] = (J(2, 0) * d0 + J(2, 1) * d1 + J(2, 2) * d2) + (w0 * Jw1 - w1 * Jw0) + (h0 * c1 - h1 * c0);
  f[3] = m * c0 - (h1 * d2 - h2 * d1) - (w1 * hw2 - w2 * hw1);
  f[4] = m * c1 - (h2 * d0 - h0 * d2) - (w2 * hw0 - w0 * hw2);
  f[5] = m * c2 - (h0 * d1 - h1 * d0) - (w0 * hw1 - w1 * hw0);
  return f;
}

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
    Motion vb = v[parent];
    Motion ab = a[parent];
    Motion v_segment;  // the velocity the current segment's Sdot uses
    bool moving = false;
    for (int k = 0; k < model.body_dofnum[b]; ++k) {
      const int i = model.body_dofadr[b] + k;
      const Motion& S = data.cdof[i];
      if (detail::starts_segment(model, i)) {
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
      if (Sddot != nullptr) (*Sddot)[i] = cross_motion(ab, S) + cross_motion(v_segment, S_dot);
      if (moving) ab += S_dot * qd[i];
      if (qdd != nullptr) ab += S * qdd[i];
      vb += S * qd[i];
    }
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
  for (int i = 0; i < model.nv; ++i) tau[i] = data.cdof[i].dot(f[model.dof_bodyid[i]]);
}

}  // namespace lever
