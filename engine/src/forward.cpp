// The forward pipeline and inverse dynamics, stage by stage as MuJoCo 2.2.2's mj_forward and
// mj_inverse: position (kinematics, contacts, M, constraint rows, transmission), velocity (passive,
// bias, reference accelerations), acceleration (motors, smooth dynamics, constraint solve).
#include <lever/collision.hpp>
#include <lever/constraint.hpp>
#include <lever/dynamics.hpp>
#include <lever/forward.hpp>
#include <lever/kinematics.hpp>

#include "internal.hpp"

namespace lever {

namespace {

// Record a warning if any element of x is bad (NaN or beyond 1e10); true if one was.
bool record_if_bad(Data& data, const Eigen::VectorXd& x, Warning kind) {
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (is_bad(x[i])) {
      record_warning(data, kind, static_cast<int>(i));
      return true;
    }
  }
  return false;
}

// The state forward() and inverse() read: warn about what cannot give finite results.
void check_inputs(Data& data) {
  record_if_bad(data, data.qpos, Warning::kBadQpos);
  record_if_bad(data, data.qvel, Warning::kBadQvel);
  record_if_bad(data, data.qfrc_applied, Warning::kBadQfrcApplied);
}

// The position stage after the kinematics: contacts, M and its factor, constraint rows,
// transmission.
void after_kinematics(const Model& model, Data& data) {
  if (model.contacts_possible) {
    collision(model, data);
  } else {
    data.ncon = 0;
  }
  crba(model, data);
  factor_mass(model, data);
  make_constraint(model, data);
  transmission(model, data);
}

// forward()'s stages, on the kinematics of the caller's choice (kinematics(), or the lean step's
// step_kinematics()), the entry check left to the caller.
void forward_stages(const Model& model, Data& data, void (*kinematics_stage)(const Model&, Data&)) {
  check_inputs(data);
  kinematics_stage(model, data);
  after_kinematics(model, data);
  velocity_stage(model, data);
  acceleration_stage(model, data);
  record_if_bad(data, data.qacc, Warning::kBadQacc);
}

}  // namespace

void position_stage(const Model& model, Data& data) {
  kinematics(model, data);
  after_kinematics(model, data);
}

void velocity_stage(const Model& model, Data& data) {
  passive(model, data);
  bias(model, data);
  reference_constraint(model, data);
}

void acceleration_stage(const Model& model, Data& data) {
  // the unconstrained acceleration, then the limit forces
  actuation(model, data);
  data.qfrc_smooth = data.qfrc_passive - data.qfrc_bias + data.qfrc_applied + data.qfrc_actuator;
  data.qacc_smooth = data.qfrc_smooth;
  solve_mass(model, data, data.qacc_smooth);
  solve_constraint(model, data);
}

void forward(const Model& model, Data& data) {
  check_entry(model, data, "lever::forward");
  forward_stages(model, data, kinematics);
}

namespace detail {

void step_forward(const Model& model, Data& data) { forward_stages(model, data, step_kinematics); }

}  // namespace detail

void inverse(const Model& model, Data& data) {
  check_entry(model, data, "lever::inverse");
  check_inputs(data);
  record_if_bad(data, data.qacc, Warning::kBadQacc);
  position_stage(model, data);
  velocity_stage(model, data);

  // the constraint forces implied by the given qacc: f = -D (J qacc - a_ref) where that pushes
  // into a stop or contact, an elliptic cone's by its zone
  constraint_forces_at(data, data.qacc);

  // M qacc + bias (armature included) is what every force together must supply
  rnea(model, data, data.qacc, data.qfrc_inverse);
  data.qfrc_inverse -= data.qfrc_passive + data.qfrc_constraint;
}

}  // namespace lever
