// MuJoCo 2.2.2's step (engine_forward.c): state checks, forward, then the integrator.
//
// Euler is semi-implicit (qvel first, then qpos with the new qvel) and, whenever any joint has
// damping, treats damping implicitly: (M + h B) (v' - v) / h = f_smooth + f_constraint, where
// f_smooth already holds the explicit -B v. So the state advances with an acceleration that is
// stored nowhere; data.qacc keeps the forward (solver) acceleration, as in MuJoCo.
// RK4 is the classical four-stage method on (qpos, qvel), without implicit damping. The implicit
// integrator (MuJoCo 2.2.2's mjINT_IMPLICIT) is in implicit.cpp.
#include <lever/dynamics.hpp>
#include <lever/forward.hpp>

#include "internal.hpp"

namespace lever {

namespace {

// MuJoCo's mj_checkPos / mj_checkVel / mj_checkAcc: a bad value resets the state.
bool check_and_reset(const Model& model, Data& data, const Eigen::VectorXd& x, Warning kind) {
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (is_bad(x[i])) {
      reset(model, data);
      record_warning(data, kind, static_cast<int>(i));
      return true;
    }
  }
  return false;
}

void euler(const Model& model, Data& data) {
  const double h = model.opt.timestep;
  Eigen::VectorXd& qacc = data.work.vec2;
  qacc = data.qacc;

  bool damped = false;
  for (int i = 0; i < model.nv; ++i) damped = damped || model.dof_damping[i] > 0;
  if (damped) {
    factor_mass_damped(model, data, h);
    qacc = data.qfrc_smooth + data.qfrc_constraint;
    solve_mass_damped(model, data, qacc);
  }

  data.qvel += h * qacc;
  data.qpos += h * data.qvel;
  data.time += h;
}

void rk4(const Model& model, Data& data) {
  // Butcher tableau of the classical method
  constexpr double kA[3] = {0.5, 0.5, 1.0};  // a_{i,i-1}; the rest of the lower triangle is 0
  constexpr double kB[4] = {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0};
  const double h = model.opt.timestep;
  auto& w = data.work;
  const double t0 = data.time;
  w.rk_qpos0 = data.qpos;
  w.rk_qvel0 = data.qvel;
  w.rk_qvel[0] = data.qvel;
  w.rk_qacc[0] = data.qacc;  // stage 0 is the forward() step() already ran

  for (int i = 1; i < 4; ++i) {
    data.qpos = w.rk_qpos0 + (h * kA[i - 1]) * w.rk_qvel[i - 1];
    data.qvel = w.rk_qvel0 + (h * kA[i - 1]) * w.rk_qacc[i - 1];
    data.time = t0 + kA[i - 1] * h;
    forward(model, data);
    w.rk_qvel[i] = data.qvel;
    w.rk_qacc[i] = data.qacc;
  }

  w.rk_dq.setZero();
  w.rk_dv.setZero();
  for (int i = 0; i < 4; ++i) {
    w.rk_dq += kB[i] * w.rk_qvel[i];
    w.rk_dv += kB[i] * w.rk_qacc[i];
  }
  data.qvel = w.rk_qvel0 + h * w.rk_dv;
  data.qpos = w.rk_qpos0 + h * w.rk_dq;
  data.time = t0 + h;
}

}  // namespace

void step(const Model& model, Data& data) {
  check_entry(model, data, "lever::step");
  if (!check_and_reset(model, data, data.qpos, Warning::kBadQpos)) {
    check_and_reset(model, data, data.qvel, Warning::kBadQvel);
  }
  forward(model, data);
  if (check_and_reset(model, data, data.qacc, Warning::kBadQacc)) forward(model, data);

  switch (model.opt.integrator) {
    case Integrator::kEuler: euler(model, data); break;
    case Integrator::kRK4: rk4(model, data); break;
    case Integrator::kImplicit: detail::implicit_step(model, data); break;
  }
}

void step1(const Model& model, Data& data) {
  check_entry(model, data, "lever::step1");
  if (!check_and_reset(model, data, data.qpos, Warning::kBadQpos)) {
    check_and_reset(model, data, data.qvel, Warning::kBadQvel);
  }
  position_stage(model, data);
  velocity_stage(model, data);
}

void step2(const Model& model, Data& data) {
  check_entry(model, data, "lever::step2");
  acceleration_stage(model, data);
  if (check_and_reset(model, data, data.qacc, Warning::kBadQacc)) forward(model, data);
  // as in MuJoCo 2.2.2, the split step integrates RK4 models with Euler: RK4 needs forward() at
  // states in the middle of the step, which the caller's control is not part of. Implicit stays
  // implicit (it needs only the start of the step).
  if (model.opt.integrator == Integrator::kImplicit) {
    detail::implicit_step(model, data);
  } else {
    euler(model, data);
  }
}

}  // namespace lever
