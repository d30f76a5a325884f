// set_length_ranges(): the actuators' length ranges as MuJoCo 2.2.2's compiler finds them
// (mjCModel::LengthRange over mj_setLengthRange, engine_setconst.c), which a muscle needs to
// normalize its length.
//
// Which actuators: by the options' mode (none, muscles, muscles and user actuators, all), those
// without a range already. A user actuator is one with a user gain or bias (a callback); a user
// activation alone does not make one, as in MuJoCo. The simulation runs without actuation, so no
// callback is called (useexisting: lower < upper as written). With uselimit, a joint's or
// tendon's range is taken when it is limited. Otherwise the range is found by simulation: from
// qpos0 at rest, the actuator is pulled to each side in turn by an applied force
// qfrc_applied = +-accel moment / |M^-1 moment| (at most maxforce in norm), which gives its
// length an acceleration of about accel, while the velocity decays with timeconst, for inttotal
// seconds; the lengths reached over the last inteval seconds give the side's end (the least on
// the shortening side, the greatest on the lengthening side), and they must have settled to
// within tolrange of the range.
//
// The simulation runs on a copy of the model with MuJoCo's compiler flags: no contacts, no
// gravity, no passive forces, no friction loss and no actuation, at the options' timestep; the
// step is split as mj_step1 / mj_step2 so the applied force is computed at the step's pose.
// MuJoCo's flags are held here by the parameters they switch off (zero gravity, stiffness,
// frictionloss, fluid, actuator gains). Its Euler step still treats dof damping implicitly with
// passive forces off (it tests dof_damping, not the flag), so for Euler the damping stays and the
// passive force is cleared between the two halves; the implicit step's derivative leaves passive
// damping out with the flag, so there the damping is zeroed.
//
// MuJoCo 2.2.2 reads the actuator's joint or tendon for uselimit as actuator_trnid[a] of its
// flat (nu x 2) array, which is actuator a's own id only for a = 0 (a slip fixed in 2.3.0);
// lever reads actuator_trnid[a][0].
#include <lever/dynamics.hpp>
#include <lever/error.hpp>
#include <lever/fields.hpp>
#include <lever/forward.hpp>
#include <lever/model.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "basics/basics.hpp"
#include "lifecycle/lifecycle.hpp"

namespace lever {

namespace {

using detail::kMinVal;

bool is_muscle(const Model& model, int a) {
  return model.actuator_gaintype[a] == GainType::kMuscle ||
         model.actuator_biastype[a] == BiasType::kMuscle;
}

bool is_user(const Model& model, int a) {
  return model.actuator_gaintype[a] == GainType::kUser ||
         model.actuator_biastype[a] == BiasType::kUser;
}

// whether the options ask for actuator a's range at all
bool wanted(const Model& model, int a, const LengthRangeOptions& options) {
  switch (options.mode) {
    case LengthRangeMode::kNone: return false;
    case LengthRangeMode::kMuscle: return is_muscle(model, a);
    case LengthRangeMode::kMuscleUser: return is_muscle(model, a) || is_user(model, a);
    case LengthRangeMode::kAll: return true;
  }
  return false;
}

bool has_range(const Model& model, int a) {
  return model.actuator_lengthrange[a][0] < model.actuator_lengthrange[a][1];
}

// The copy the simulation runs on: the compiler's disable flags held by their parameters.
Model simulation_model(const Model& model, const LengthRangeOptions& options) {
  Model sim = model;
  sim.opt.disableflags |= kDisableContact;
  sim.opt.gravity.setZero();
  sim.opt.viscosity = sim.opt.density = 0;
  if (options.timestep > 0) sim.opt.timestep = options.timestep;
  const bool implicit = sim.opt.integrator == Integrator::kImplicit ||
                        sim.opt.integrator == Integrator::kImplicitFast;
  std::fill(sim.jnt_stiffness.begin(), sim.jnt_stiffness.end(), 0.0);
  if (implicit) std::fill(sim.dof_damping.begin(), sim.dof_damping.end(), 0.0);
  std::fill(sim.dof_frictionloss.begin(), sim.dof_frictionloss.end(), 0.0);
  std::fill(sim.tendon_stiffness.begin(), sim.tendon_stiffness.end(), 0.0);
  std::fill(sim.tendon_damping.begin(), sim.tendon_damping.end(), 0.0);
  std::fill(sim.tendon_frictionloss.begin(), sim.tendon_frictionloss.end(), 0.0);
  for (int a = 0; a < sim.nu; ++a) {  // no actuation: every force zero, no activation
    sim.actuator_dyntype[a] = DynType::kNone;
    sim.actuator_gaintype[a] = GainType::kFixed;
    sim.actuator_biastype[a] = BiasType::kNone;
    sim.actuator_gainprm[a].fill(0.0);
    sim.actuator_biasprm[a].fill(0.0);
    sim.actuator_forcelimited[a] = 0;
    sim.actuator_actlimited[a] = 0;
  }
  sim.na = 0;
  size_model(sim);
  set_const(sim);
  return sim;
}

// One step of the simulation (MuJoCo's evalAct): the velocity decays, then the step is taken
// with the force that pulls actuator a to `side` (0: shorter, 1: longer); its length after.
double pulled_step(const Model& sim, Data& data, int a, int side, const LengthRangeOptions& options,
                   Eigen::VectorXd& x) {
  const double decay = std::exp(-sim.opt.timestep / std::max(0.01, options.timeconst));
  data.qvel *= decay;
  step1(sim, data);
  const bool implicit = sim.opt.integrator == Integrator::kImplicit ||
                        sim.opt.integrator == Integrator::kImplicitFast;
  if (!implicit) data.qfrc_passive.setZero();  // passive forces off (see the file's comment)
  x = data.actuator_moment.row(a).transpose();
  solve_mass(sim, data, x);
  double norm = x.norm();
  const double scale = (2 * side - 1) * options.accel / std::max(kMinVal, norm);
  data.qfrc_applied = data.actuator_moment.row(a).transpose() * scale;
  norm = data.qfrc_applied.norm();
  if (options.maxforce > 0 && norm > options.maxforce) {
    data.qfrc_applied *= options.maxforce / std::max(kMinVal, norm);
  }
  step2(sim, data);
  return data.actuator_length[a];
}

std::string show(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

[[noreturn]] void refuse(const Model& model, int a, const std::string& why) {
  const std::string name = actuator_label(model, a);
  throw ModelError("actuator " + name + ": " + why, "actuator", a);
}

// Actuator a's range by simulation, into model.actuator_lengthrange[a].
void simulate_length_range(Model& model, const Model& sim, Data& data, int a,
                           const LengthRangeOptions& options) {
  double lmin[2] = {0, 0}, lmax[2] = {0, 0};
  Eigen::VectorXd x(sim.nv);
  for (int side = 0; side < 2; ++side) {
    reset(sim, data);
    bool updated = false;
    while (data.time < options.inttotal) {
      const double length = pulled_step(sim, data, a, side, options, x);
      if (data.time == 0) {
        refuse(model, a, "the length-range simulation is unstable (the state was reset)");
      }
      if (data.time > options.inttotal - options.inteval) {
        if (length < lmin[side] || !updated) lmin[side] = length;
        if (length > lmax[side] || !updated) lmax[side] = length;
        updated = true;
      }
    }
    model.actuator_lengthrange[a][side] = side == 0 ? lmin[side] : lmax[side];
  }
  const auto& range = model.actuator_lengthrange[a];
  const double width = range[1] - range[0];
  if (width <= 0) {
    refuse(model, a, "the length-range simulation found an empty range (" + show(range[0]) + ", " +
                         show(range[1]) + ")");
  }
  for (int side = 0; side < 2; ++side) {
    if (lmax[side] - lmin[side] > options.tolrange * width) {
      refuse(model, a,
             std::string("the length-range simulation did not settle on the ") +
                 (side == 0 ? "short" : "long") + " side: its length moved over (" +
                 show(lmin[side]) + ", " + show(lmax[side]) + ") in the last inteval, the range is (" +
                 show(range[0]) + ", " + show(range[1]) + "); give the actuator a lengthrange, or "
                 "its joint or tendon a range with <lengthrange uselimit=\"true\">");
    }
  }
}

}  // namespace

void set_length_ranges(Model& model, const LengthRangeOptions& options) {
  std::vector<int> simulated;
  for (int a = 0; a < model.nu; ++a) {
    if (!wanted(model, a, options)) continue;
    if (options.useexisting && has_range(model, a)) continue;
    const int id = model.actuator_trnid[a][0];
    if (options.uselimit) {
      const TransmissionType trn = model.actuator_trntype[a];
      if ((trn == TransmissionType::kJoint || trn == TransmissionType::kJointInParent) &&
          model.jnt_limited[id]) {
        model.actuator_lengthrange[a] = model.jnt_range[id];
        continue;
      }
      if (trn == TransmissionType::kTendon && model.tendon_limited[id]) {
        model.actuator_lengthrange[a] = model.tendon_range[id];
        continue;
      }
    }
    simulated.push_back(a);
  }
  if (simulated.empty()) return;
  const Model sim = simulation_model(model, options);
  Data data(sim);
  for (const int a : simulated) simulate_length_range(model, sim, data, a, options);
}

}  // namespace lever
