// The forward pipeline and inverse dynamics, stage by stage as MuJoCo 2.2.2's mj_forward and
// mj_inverse: position (kinematics, contacts, M, constraint rows, transmission), velocity (passive,
// bias, reference accelerations), acceleration (motors, smooth dynamics, constraint solve), each
// followed by its sensors (skipped inside an RK4 step, as MuJoCo skips them).
#include <lever/collision.hpp>
#include <lever/constraint.hpp>
#include <lever/dynamics.hpp>
#include <lever/forward.hpp>
#include <lever/kinematics.hpp>

#include "basics/basics.hpp"
#include "constraint/constraint_room.hpp"
#include "model/model_room.hpp"
#include "pipeline/pipeline.hpp"
#include "sensors/sensors.hpp"
#include "smooth/smooth.hpp"

namespace lever {

namespace {

// Record a warning if any element of x (one of Data's vectors, read in place) is bad (NaN or
// beyond 1e10).
template <class Vector>
void record_if_bad(Data& data, const Vector& x, Warning kind) {
  const int bad = first_bad(x.data(), static_cast<int>(x.size()));
  if (bad >= 0) record_warning(data, kind, bad);
}

// The state forward() and inverse() read: warn about what cannot give finite results.
void check_inputs(Data& data) {
  record_if_bad(data, data.qpos, Warning::kBadQpos);
  record_if_bad(data, data.qvel, Warning::kBadQvel);
  record_if_bad(data, data.qfrc_applied, Warning::kBadQfrcApplied);
}

// The position stage after the kinematics: contacts, M and its factor (unless `factor` is false:
// for a caller that solves nothing with it), constraint rows, transmission.
void after_kinematics(const Model& model, Data& data, bool factor = true) {
  // the flags read here too, so that one switched after set_const still holds (MuJoCo reads them
  // in mj_collision)
  if (model.contacts_possible && !model.opt.disabled(kDisableContact) &&
      !model.opt.disabled(kDisableConstraint)) {
    collision(model, data);
  } else {
    data.ncon = 0;
  }
  if (model.ntendon > 0) unchecked::tendon(model, data);
  unchecked::crba(model, data);
  if (factor) unchecked::factor_mass(model, data);
  unchecked::make_constraint(model, data);
  unchecked::transmission(model, data);
  // adhesion: after the contacts' rows
  if (model.has_body_transmission) unchecked::body_transmission(model, data);
}

// The velocity stage without its sensors.
void velocity_core(const Model& model, Data& data) {
  if (model.ntendon > 0) unchecked::tendon_velocity(model, data);
  unchecked::passive(model, data);
  unchecked::bias(model, data);
  unchecked::reference_constraint(model, data);
}

// The acceleration stage's smooth part: actuator forces, qfrc_smooth, and qacc_smooth
// (M^-1 qfrc_smooth) unless `acceleration` is false (then it holds qfrc_smooth).
void smooth_acceleration(const Model& model, Data& data, bool acceleration = true) {
  unchecked::actuation(model, data);
  double* const qfrc_smooth = data.qfrc_smooth.data();
  double* const qacc_smooth = data.qacc_smooth.data();
  const double* const passive = data.qfrc_passive.data();
  const double* const bias = data.qfrc_bias.data();
  const double* const applied = data.qfrc_applied.data();
  const double* const actuator = data.qfrc_actuator.data();
  for (int i = 0; i < model.nv; ++i) {
    qfrc_smooth[i] = passive[i] - bias[i] + applied[i] + actuator[i];
    qacc_smooth[i] = qfrc_smooth[i];
  }
  if (acceleration) unchecked::solve_mass(model, data, qacc_smooth);
}

// The acceleration stage without its sensors: the unconstrained acceleration, then the
// constraint forces.
void acceleration_core(const Model& model, Data& data) {
  smooth_acceleration(model, data);
  unchecked::solve_constraint(model, data);
}

// forward()'s stages, on the kinematics of the caller's choice (kinematics(), or the lean step's
// step_kinematics()), the entry check left to the caller; the sensors too unless `sensors` is
// false (MuJoCo's mj_forwardSkip with skipsensor, as its RK4 stages call it).
void forward_stages(const Model& model, Data& data, void (*kinematics_stage)(const Model&, Data&),
                    bool sensors) {
  // a model without sensors pays one test here, not three calls
  const bool with_sensors = sensors && model.nsensor > 0;
  check_inputs(data);
  const bool energy = model.opt.enabled(kEnableEnergy);
  kinematics_stage(model, data);
  after_kinematics(model, data);
  if (with_sensors) sensor_position(model, data);
  if (energy) unchecked::energy_position(model, data);
  velocity_core(model, data);
  if (with_sensors) sensor_velocity(model, data);
  if (energy) unchecked::energy_velocity(model, data);
  acceleration_core(model, data);
  if (with_sensors) sensor_acceleration(model, data);
  record_if_bad(data, data.qacc, Warning::kBadQacc);
}

// The lean step reads neither xquat nor the geom frames where nothing collides; sensors may
// (framequat, a geom's frame, the rangefinder), so a model with sensors takes the whole
// kinematics.
void (*step_kinematics_for(const Model& model))(const Model&, Data&) {
  return model.nsensor > 0 ? kinematics : detail::step_kinematics;
}

}  // namespace

void position_stage(const Model& model, Data& data) {
  kinematics(model, data);
  after_kinematics(model, data);
  sensor_position(model, data);
  if (model.opt.enabled(kEnableEnergy)) unchecked::energy_position(model, data);
}

void velocity_stage(const Model& model, Data& data) {
  velocity_core(model, data);
  sensor_velocity(model, data);
  if (model.opt.enabled(kEnableEnergy)) unchecked::energy_velocity(model, data);
}

void acceleration_stage(const Model& model, Data& data) {
  acceleration_core(model, data);
  sensor_acceleration(model, data);
}

void forward(const Model& model, Data& data) {
  check_entry(model, data, "lever::forward");
  forward_stages(model, data, kinematics, true);
}

namespace detail {

void step_forward(const Model& model, Data& data) {
  forward_stages(model, data, step_kinematics_for(model), true);
}

void forward_without_sensors(const Model& model, Data& data) {
  forward_stages(model, data, kinematics, false);
}

void step_forward_without_sensors(const Model& model, Data& data) {
  forward_stages(model, data, step_kinematics_for(model), false);
}

void forward_until_solve(const Model& model, Data& data) {
  detail::step_kinematics(model, data);
  after_kinematics(model, data, false);
  velocity_core(model, data);
  smooth_acceleration(model, data, false);
}

void forward_solve(const Model& model, Data& data) {
  unchecked::factor_mass(model, data);
  unchecked::solve_mass(model, data, data.qacc_smooth.data());
  unchecked::solve_constraint(model, data);
}

void compare_forward_inverse(const Model& model, Data& data) {
  data.solver_fwdinv = {0.0, 0.0};
  if (data.nefc == 0) return;
  // what forward() applied, and what it found, kept while inverse dynamics at its qacc reuses
  // the same arrays (MuJoCo's mj_compareFwdInv; it keeps the inverse's qfrc_inverse)
  ArenaVector& forward_constraint = data.work.vec1;
  ArenaVector& applied = data.work.vec2;
  ArenaVector& forward_efc_force = data.work.lcp_f;  // (nefc_max) the pivoting solver's
  forward_constraint = data.qfrc_constraint;
  forward_efc_force.head(data.nefc) = data.efc_force.head(data.nefc);
  applied = data.qfrc_applied + data.qfrc_actuator;

  constraint_forces_at(data, data.qacc);
  rnea(model, data, data.qacc, data.qfrc_inverse);
  data.qfrc_inverse -= data.qfrc_passive + data.qfrc_constraint;

  data.solver_fwdinv[0] = (forward_constraint - data.qfrc_constraint).norm();
  data.solver_fwdinv[1] = (applied - data.qfrc_inverse).norm();
  data.qfrc_constraint = forward_constraint;
  data.efc_force.head(data.nefc) = forward_efc_force.head(data.nefc);
}

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

  // M qacc + bias (armature included) is what every force together must supply; summed as
  // mj_inverse sums it, the armature's term, the passive and the constraint forces in turn
  unchecked::newton_euler(model, data, data.qacc.data(), data.qfrc_inverse.data());
  for (int i = 0; i < model.nv; ++i) {
    data.qfrc_inverse[i] += model.dof_armature[i] * data.qacc[i] - data.qfrc_passive[i] -
                            data.qfrc_constraint[i];
  }
  sensor_acceleration(model, data);
}

}  // namespace lever
