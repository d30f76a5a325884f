// The two passes of the recursive Newton-Euler algorithm (Featherstone, RBDA 2008, table 5.1),
// written once for every algorithm that runs them: inverse dynamics and the bias forces (rnea.cpp),
// the inverse-dynamics derivatives (derivatives.cpp) and the inertial-parameter regressor
// (regressor.cpp). Every quantity is in lever's absolute coordinates (see kinematics.cpp), where
// the passes need no coordinate transforms. Inline, so that each caller's copy drops the outputs
// it does not ask for.
#pragma once

#include <vector>

#include <lever/data.hpp>
#include <lever/model.hpp>
#include <lever/spatial.hpp>

#include "internal.hpp"

namespace lever {

/// RNEA's forward pass: every body's velocity v and acceleration a from its parent's, root to
/// leaves, dof by dof:
///   v = v_parent + S_i qd_i,   a = a_parent + Sdot_i qd_i + S_i qdd_i,   Sdot_i = v_seg x S_i
/// (v, a before dof i; v_seg the velocity before dof i's segment: the dof itself for a hinge or
/// a slide, a ball's three rotations together, see detail::starts_segment). qdd == nullptr: zero.
/// gravity: the world accelerates upward at -g, so the forces found from a include the weights.
/// Sdot and Sddot (nv each, or nullptr) receive each dof's Sdot_i and its derivative a x S_i + v x
/// Sdot_i (the inverse-dynamics derivatives' Psi).
inline void forward_pass(const Model& model, const Data& data, const double* qd, const double* qdd,
                         bool gravity, std::vector<Motion>& v, std::vector<Motion>& a,
                         std::vector<Motion>* Sdot, std::vector<Motion>* Sddot) {
  v[0].setZero();
  a[0].setZero();
  if (gravity) a[0].tail<3>() = -model.opt.gravity;  // the world accelerates upward: weights

  for (int b = 1; b < model.nbody; ++b) {
    const int parent = model.body_parentid[b];
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
  }
}

/// Each body's value x[b] replaced by its sum over the body's subtree, leaves to root (the world,
/// body 0, is left out). T has +=: a force, a RigidInertia, the derivatives' couplings.
template <class T>
inline void sum_over_subtrees(const Model& model, std::vector<T>& x) {
  for (int b = model.nbody - 1; b > 0; --b) {
    const int parent = model.body_parentid[b];
    if (parent > 0) x[parent] += x[b];
  }
}

/// RNEA's backward pass: each body's net force f summed into its parent's, leaves to root (f is
/// overwritten with the force each body's joint transmits), then tau_i = S_i . f of dof i's body.
inline void backward_pass(const Model& model, const Data& data, std::vector<Force>& f,
                          double* tau) {
  sum_over_subtrees(model, f);  // a joint carries the force of its whole subtree
  for (int i = 0; i < model.nv; ++i) tau[i] = data.cdof[i].dot(f[model.dof_bodyid[i]]);
}

}  // namespace lever
