// Centred differences of a step, lever's step() and MuJoCo 2.2.2's mj_step, in qpos's tangent
// space (qpos moved with integrate_pos / mj_integratePos, the next qpos read with
// differentiate_pos / mj_differentiatePos), against which the derivative tests compare A and B;
// and the states they start from. Shared by contacts.cpp and tendons.cpp.
#pragma once

#include <lever/diff/twin.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>

#include <algorithm>
#include <vector>

namespace lever::test::step_differences {

inline constexpr double kScaleBound = 1e-6;

// the rows that push at the state, and the contacts' geom pairs: what must not change inside a
// difference
inline std::vector<int> active_set(const Model& model, Data& data) {
  forward(model, data);
  std::vector<int> set;
  for (int i = 0; i < data.ncon; ++i) {
    set.push_back(data.contact[i].geom1 * 1000 + data.contact[i].geom2);
  }
  set.push_back(-1);
  for (int r = 0; r < data.nefc; ++r) set.push_back(static_cast<int>(data.efc_state[r]));
  return set;
}

struct Differences {
  Eigen::MatrixXd A, B;
  bool same_active_set = true;  // at every differenced state, as at the state
};

// mj_step (MuJoCo) or step (lever) differenced, centred with step eps, in tangent space: column c
// of A moves qpos by +-eps along dof c (integrate_pos) or qvel_c or act_c by +-eps; B moves ctrl.
// The next qpos is read with differentiate_pos from the minus side to the plus side; the rows are
// [dq'; qvel'; act'] (mjd_transitionFD's layout).
inline Differences mujoco_differences(diff::Twin& twin, const State& s, double eps) {
  const mjModel* m = twin.m.get();
  mjData* d = twin.d.get();
  const int nq = m->nq, nv = m->nv, nu = m->nu, na = m->na;
  const int n = 2 * nv + na;
  Differences out;
  out.A.resize(n, n);
  out.B.resize(n, nu);
  Eigen::VectorXd plus(nq + nv + na), minus(nq + nv + na), column(n), dpos(nv);
  for (int c = 0; c < n + nu; ++c) {
    for (const double delta : {eps, -eps}) {
      diff::set_mujoco_state(m, d, s);
      if (c < nv) {
        dpos.setZero();
        dpos[c] = 1;
        mj_integratePos(m, d->qpos, dpos.data(), delta);
      } else if (c < 2 * nv) {
        d->qvel[c - nv] += delta;
      } else if (c < n) {
        d->act[c - 2 * nv] += delta;
      } else {
        d->ctrl[c - n] += delta;
      }
      mj_step(m, d);
      Eigen::VectorXd& next = delta > 0 ? plus : minus;
      for (int i = 0; i < nq; ++i) next[i] = d->qpos[i];
      for (int i = 0; i < nv; ++i) next[nq + i] = d->qvel[i];
      for (int i = 0; i < na; ++i) next[nq + nv + i] = d->act[i];
    }
    mj_differentiatePos(m, column.data(), 2 * eps, minus.data(), plus.data());
    column.tail(nv + na) = (plus.tail(nv + na) - minus.tail(nv + na)) / (2 * eps);
    if (c < n) {
      out.A.col(c) = column;
    } else {
      out.B.col(c - n) = column;
    }
  }
  diff::set_mujoco_state(m, d, s);
  return out;
}

inline Differences lever_differences(const Model& model, const State& s, double eps) {
  const int nq = model.nq, nv = model.nv, nu = model.nu, na = model.na;
  const int n = 2 * nv + na;
  Data data(model);
  apply(s, data);
  const std::vector<int> at_state = active_set(model, data);
  Differences out;
  out.A.resize(n, n);
  out.B.resize(n, nu);
  Eigen::VectorXd plus_q(nq), minus_q(nq), plus_v(nv + na), minus_v(nv + na), column(n);
  for (int c = 0; c < n + nu; ++c) {
    for (const double delta : {eps, -eps}) {
      apply(s, data);
      if (c < nv) {
        integrate_pos(model, data.qpos, Eigen::VectorXd::Unit(nv, c), delta);
      } else if (c < 2 * nv) {
        data.qvel[c - nv] += delta;
      } else if (c < n) {
        data.act[c - 2 * nv] += delta;
      } else {
        data.ctrl[c - n] += delta;
      }
      out.same_active_set = out.same_active_set && active_set(model, data) == at_state;
      step(model, data);
      (delta > 0 ? plus_q : minus_q) = data.qpos;
      (delta > 0 ? plus_v : minus_v) << data.qvel, data.act;
    }
    differentiate_pos(model, column.head(nv), 2 * eps, minus_q, plus_q);
    column.tail(nv + na) = (plus_v - minus_v) / (2 * eps);
    if (c < n) {
      out.A.col(c) = column;
    } else {
      out.B.col(c - n) = column;
    }
  }
  return out;
}

// max |analytic - differenced| over the bound, kScaleBound * max(1, max |differenced|)
inline double ratio_to_bound(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& differenced) {
  if (analytic.size() == 0) return 0;
  const double scale = std::max(1.0, differenced.cwiseAbs().maxCoeff());
  return (analytic - differenced).cwiseAbs().maxCoeff() / (kScaleBound * scale);
}

// A state after `steps` Euler steps of lever from s with controls ctrl
inline State settle(Model model, State s, int steps) {
  model.opt.integrator = Integrator::kEuler;
  Data data(model);
  apply(s, data);
  for (int k = 0; k < steps; ++k) step(model, data);
  s.time = data.time;
  s.qpos = data.qpos;
  s.qvel = data.qvel;
  s.act = data.act;
  return s;
}

inline State state_of(const Model& model) {
  Data data(model);
  State s;
  s.qpos = data.qpos;
  s.qvel = Eigen::VectorXd::Zero(model.nv);
  s.ctrl = Eigen::VectorXd::Zero(model.nu);
  s.qfrc_applied = Eigen::VectorXd::Zero(model.nv);
  s.act = Eigen::VectorXd::Zero(model.na);
  return s;
}

// MuJoCo's solver run to convergence (tolerance 0), on both sides the same cone and condim
inline void converge(diff::Twin& twin) {
  twin.m->opt.tolerance = 0;
  twin.model.opt.tolerance = 0;
}

}  // namespace lever::test::step_differences
