// MuJoCo 2.2.2's step (engine_forward.c): state checks, forward, then the integrator.
//
// Euler is semi-implicit (qvel first, then qpos with the new qvel) and, whenever any joint has
// damping, treats damping implicitly: (M + h B) (v' - v) / h = f_smooth + f_constraint, where
// f_smooth already holds the explicit -B v. So the state advances with an acceleration that is
// stored nowhere; data.qacc keeps the forward (solver) acceleration, as in MuJoCo.
// RK4 is the classical four-stage method on (qpos, qvel), without implicit damping. The implicit
// integrators (MuJoCo 2.2.2's mjINT_IMPLICIT, MuJoCo 3's mjINT_IMPLICITFAST) are in implicit.cpp.
#include <lever/dynamics.hpp>
#include <lever/forward.hpp>

#include "basics/basics.hpp"
#include "model/model_room.hpp"
#include "pipeline/pipeline.hpp"
#include "smooth/smooth.hpp"

#include <cmath>

namespace lever {

namespace {

using detail::kMinVal;

// q turned by the rotation vector h w, w in the frame q rotates into (body axes), then normalized:
// the turn is exact for constant w, so only rounding moves q off the unit sphere.
void turn_quat(double* q, const double* w, double h) {
  const double speed = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  Eigen::Vector3d axis(1.0, 0.0, 0.0);  // any axis will do when there is no turn
  if (speed >= kMinVal) {
    const double inverse = 1.0 / speed;
    axis = Eigen::Vector3d(w[0] * inverse, w[1] * inverse, w[2] * inverse);
  }
  const double angle = h * speed;
  Quat turn(1.0, 0.0, 0.0, 0.0);
  if (angle != 0.0) {
    const double s = std::sin(angle * 0.5);
    turn = Quat(std::cos(angle * 0.5), axis[0] * s, axis[1] * s, axis[2] * s);
  }
  Quat turned = quat_mul(Quat(q[0], q[1], q[2], q[3]), turn);
  detail::normalize_quat(turned.data());
  for (int k = 0; k < 4; ++k) q[k] = turned[k];
}

// MuJoCo's mj_checkPos / mj_checkVel / mj_checkAcc: a bad value resets the state.
bool check_and_reset(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& x,
                     Warning kind) {
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
  auto& qacc = data.work.vec2;
  qacc = data.qacc;

  bool damped = false;
  for (int i = 0; i < model.nv; ++i) damped = damped || model.dof_damping[i] > 0;
  if (damped) {
    factor_mass_damped(model, data, h);
    qacc = data.qfrc_smooth + data.qfrc_constraint;
    solve_mass_damped(model, data, qacc);
  }

  detail::advance_activations(model, data, data.act_dot.data(), h);
  data.qvel += h * qacc;
  detail::integrate_positions(model, data.qpos.data(), data.qvel.data(), h);
  data.time += h;
}

void rk4(const Model& model, Data& data, void (*stage_fn)(const Model&, Data&)) {
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
  w.rk_act0 = data.act;
  w.rk_act_dot[0] = data.act_dot;

  for (int i = 1; i < 4; ++i) {
    // the stage's velocity (one nonzero a_ij per row), integrated from the step's start
    w.rk_dq = kA[i - 1] * w.rk_qvel[i - 1];
    data.qpos = w.rk_qpos0;
    detail::integrate_positions(model, data.qpos.data(), w.rk_dq.data(), h);
    data.qvel = w.rk_qvel0 + (h * kA[i - 1]) * w.rk_qacc[i - 1];
    // the stage's activation, unclamped (MuJoCo clamps only in the final update)
    data.act = w.rk_act0 + (h * kA[i - 1]) * w.rk_act_dot[i - 1];
    data.time = t0 + kA[i - 1] * h;
    stage_fn(model, data);
    w.rk_qvel[i] = data.qvel;
    w.rk_qacc[i] = data.qacc;
    w.rk_act_dot[i] = data.act_dot;
  }

  w.rk_dq.setZero();
  w.rk_dv.setZero();
  w.rk_dact.setZero();
  for (int i = 0; i < 4; ++i) {
    w.rk_dq += kB[i] * w.rk_qvel[i];
    w.rk_dv += kB[i] * w.rk_qacc[i];
    w.rk_dact += kB[i] * w.rk_act_dot[i];
  }
  data.act = w.rk_act0;
  detail::advance_activations(model, data, w.rk_dact.data(), h);
  data.qvel = w.rk_qvel0 + h * w.rk_dv;
  data.qpos = w.rk_qpos0;
  detail::integrate_positions(model, data.qpos.data(), w.rk_dq.data(), h);
  data.time = t0 + h;
}

}  // namespace

namespace detail {

void advance_activations(const Model& model, Data& data, const double* act_dot, double h) {
  const int first_stateful = model.nu - model.na;
  for (int k = 0; k < model.na; ++k) {
    double& act = data.act[k];
    act += h * act_dot[k];
    const int a = first_stateful + k;
    if (!model.actuator_actlimited[a]) continue;
    const auto& range = model.actuator_actrange[a];
    if (act < range[0]) act = range[0];
    if (act > range[1]) act = range[1];
  }
}

void integrate_positions(const Model& model, double* qpos, const double* qvel, double h) {
  for (int j = 0; j < model.njnt; ++j) {
    double* q = qpos + model.jnt_qposadr[j];
    const double* v = qvel + model.jnt_dofadr[j];
    switch (model.jnt_kind[j]) {
      case JointKind::kFree:
        for (int k = 0; k < 3; ++k) q[k] += h * v[k];
        turn_quat(q + 3, v + 3, h);
        break;
      case JointKind::kBall: turn_quat(q, v, h); break;
      default: q[0] += h * v[0]; break;  // hinge and slide
    }
  }
}

}  // namespace detail

void integrate_pos(const Model& model, Eigen::Ref<Eigen::VectorXd> qpos,
                   const Eigen::Ref<const Eigen::VectorXd>& qvel, double h) {
  check_argument_size(qpos.size(), model.nq, "lever::integrate_pos", "qpos");
  check_argument_size(qvel.size(), model.nv, "lever::integrate_pos", "qvel");
  // a copy: a Ref may be strided, the joint loop reads contiguous coordinates
  Eigen::VectorXd q = qpos, v = qvel;
  detail::integrate_positions(model, q.data(), v.data(), h);
  qpos = q;
}

void differentiate_pos(const Model& model, Eigen::Ref<Eigen::VectorXd> qvel, double h,
                       const Eigen::Ref<const Eigen::VectorXd>& qpos1,
                       const Eigen::Ref<const Eigen::VectorXd>& qpos2) {
  check_argument_size(qvel.size(), model.nv, "lever::differentiate_pos", "qvel");
  check_argument_size(qpos1.size(), model.nq, "lever::differentiate_pos", "qpos1");
  check_argument_size(qpos2.size(), model.nq, "lever::differentiate_pos", "qpos2");
  // copies: a Ref may be strided, a quaternion is read as four contiguous numbers
  const Eigen::VectorXd from = qpos1, to = qpos2;
  for (int j = 0; j < model.njnt; ++j) {
    int q = model.jnt_qposadr[j], v = model.jnt_dofadr[j];
    switch (model.jnt_kind[j]) {
      case JointKind::kFree:
        for (int k = 0; k < 3; ++k) qvel[v + k] = (to[q + k] - from[q + k]) / h;
        q += 3;
        v += 3;
        [[fallthrough]];
      case JointKind::kBall:
        qvel.segment<3>(v) = detail::quat_difference(&to[q], &from[q], h);
        break;
      default: qvel[v] = (to[q] - from[q]) / h;  // hinge and slide
    }
  }
}

void detail::step(const Model& model, Data& data, void (*forward_fn)(const Model&, Data&),
                  void (*stage_fn)(const Model&, Data&)) {
  if (!check_and_reset(model, data, data.qpos, Warning::kBadQpos)) {
    check_and_reset(model, data, data.qvel, Warning::kBadQvel);
  }
  forward_fn(model, data);
  if (check_and_reset(model, data, data.qacc, Warning::kBadQacc)) forward_fn(model, data);
  if (model.opt.enabled(kEnableFwdinv)) compare_forward_inverse(model, data);

  switch (model.opt.integrator) {
    case Integrator::kEuler: euler(model, data); break;
    case Integrator::kRK4: rk4(model, data, stage_fn); break;
    case Integrator::kImplicit: detail::implicit_step(model, data); break;
    case Integrator::kImplicitFast: detail::implicit_fast_step(model, data); break;
  }
}

void step(const Model& model, Data& data) {
  check_entry(model, data, "lever::step");
  // the lean pipeline: a step reads no geom frames of a model where nothing collides
  // (detail::step_forward)
  detail::step(model, data, detail::step_forward, detail::step_forward_without_sensors);
}

void step_all(const Model& model, Data& data) {
  check_entry(model, data, "lever::step_all");
  detail::step(model, data, forward, detail::forward_without_sensors);
}

void step1(const Model& model, Data& data) {
  check_entry(model, data, "lever::step1");
  if (!check_and_reset(model, data, data.qpos, Warning::kBadQpos)) {
    check_and_reset(model, data, data.qvel, Warning::kBadQvel);
  }
  position_stage(model, data);
  velocity_stage(model, data);
  // MuJoCo's mj_step1 calls the energy functions whatever the flag, and they clear it when off
  if (!model.opt.enabled(kEnableEnergy)) data.energy = {0.0, 0.0};
}

void step2(const Model& model, Data& data) {
  check_entry(model, data, "lever::step2");
  acceleration_stage(model, data);
  if (check_and_reset(model, data, data.qacc, Warning::kBadQacc)) forward(model, data);
  if (model.opt.enabled(kEnableFwdinv)) detail::compare_forward_inverse(model, data);
  // as in MuJoCo 2.2.2, the split step integrates RK4 models with Euler: RK4 needs forward() at
  // states in the middle of the step, which the caller's control is not part of. The implicit
  // integrators stay implicit (they need only the start of the step), as in MuJoCo 3 for
  // implicitfast.
  if (model.opt.integrator == Integrator::kImplicit) {
    detail::implicit_step(model, data);
  } else if (model.opt.integrator == Integrator::kImplicitFast) {
    detail::implicit_fast_step(model, data);
  } else {
    euler(model, data);
  }
}

}  // namespace lever
