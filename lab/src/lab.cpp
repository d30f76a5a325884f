#include <lever/lab/lab.hpp>

#include <cmath>
#include <numbers>

#include <utility>

#include <lever/dynamics.hpp>
#include <lever/error.hpp>
#include <lever/forward.hpp>

namespace lever::lab {

void validate(const Model& model, const Controller& controller) {
  if (controller.torque.size() != model.nu) {
    throw StateError("lab controller: torque has " + std::to_string(controller.torque.size()) +
                     " values but the model has " + std::to_string(model.nu) + " motors.");
  }
  if (!controller.torque.allFinite()) {
    throw StateError("lab controller: torque holds a value that is not finite.");
  }
  if (!(controller.excite >= 0.0 && controller.excite <= 1.0)) {
    throw StateError("lab controller: excite must be a fraction of the joint ranges in [0, 1].");
  }
  if (!controller.gravity_compensation && controller.excite == 0.0) return;
  for (int a = 0; a < model.nu; ++a) {
    const std::string name =
        model.actuator_name[a].empty() ? "#" + std::to_string(a) : model.actuator_name[a];
    if (model.actuator_gear[a][0] == 0) {
      throw StateError("lab controller: actuator " + name +
                       " has gear 0: gravity compensation or excitation cannot be expressed as "
                       "its ctrl.");
    }
    if (model.actuator_gaintype[a] != GainType::kFixed || model.actuator_gainprm[a][0] == 0) {
      throw StateError("lab controller: actuator " + name +
                       " has no fixed, nonzero gain: a torque added to the command cannot be "
                       "expressed as its ctrl.");
    }
  }
}

namespace {

// ctrl that adds `torque` to the joint of a fixed-gain actuator (motor or servo): the force is
// gain ctrl + bias, so whatever the bias, one more torque / (gear gain) of ctrl adds exactly torque
double ctrl_for_torque(const Model& model, int a, double torque) {
  return torque / (model.actuator_gear[a][0] * model.actuator_gainprm[a][0]);
}

// The excitation's reference for actuator a: a sum of sines inside its joint's range, and its rate.
std::pair<double, double> reference(const Model& model, double fraction, int a, const Data& data) {
  const int j = model.actuator_trnid[a][0];  // a hinge or slide (apply() checked)
  const int q = model.jnt_qposadr[j];
  const double mid =
      model.jnt_limited[j] ? 0.5 * (model.jnt_range[j][0] + model.jnt_range[j][1]) : model.qpos0[q];
  const double half =
      model.jnt_limited[j] ? 0.5 * (model.jnt_range[j][1] - model.jnt_range[j][0]) : 1.0;
  double ref = mid, ref_vel = 0.0;
  for (const double hz : {0.3, 0.71, 1.3}) {
    const double w = 2 * std::numbers::pi * (hz + 0.1 * a);
    ref += fraction * half / 3 * std::sin(w * data.time + a);
    ref_vel += fraction * half / 3 * w * std::cos(w * data.time + a);
  }
  return {ref, ref_vel};
}

// The excitation's command for actuator a: a servo is given the reference as its target (its
// own gains track it); a motor, the torque of a PD law tuned to dof_M0 (4 Hz, damping ratio 0.7)
double excitation(const Model& model, double fraction, int a, const Data& data) {
  const auto [ref, ref_vel] = reference(model, fraction, a, data);
  if (is_servo(model.actuator_kind[a])) return ref / model.actuator_gear[a][0];
  const int j = model.actuator_trnid[a][0];
  const int q = model.jnt_qposadr[j], dof = model.jnt_dofadr[j];
  const double wn = 2 * std::numbers::pi * 4.0;  // 4 Hz: faster than the reference's sines
  const double kp = wn * wn * model.dof_M0[dof], kd = 2 * 0.7 * wn * model.dof_M0[dof];
  return ctrl_for_torque(model, a, kp * (ref - data.qpos[q]) + kd * (ref_vel - data.qvel[dof]));
}

}  // namespace

void apply(const Model& model, const Controller& controller, Data& data) {
  for (int a = 0; a < model.nu; ++a) {
    data.ctrl[a] = controller.torque[a];
    // the compensation and the excitation are a hinge's or slide's: any other actuator (a tendon,
    // a site, a ball joint) gets its torque only
    const int dof = actuator_scalar_dof(model, a);
    if (dof < 0) continue;
    if (controller.gravity_compensation) {
      data.ctrl[a] += ctrl_for_torque(model, a, data.qfrc_bias[dof]);
    }
    if (controller.excite > 0) data.ctrl[a] += excitation(model, controller.excite, a, data);
  }
}

void WarningLog::collect(Data& data) {
  for (size_t k = 0; k < total_.size(); ++k) {
    if (data.warning[k].number == 0) continue;
    total_[k].number += data.warning[k].number;
    total_[k].lastinfo = data.warning[k].lastinfo;
    data.warning[k] = {};
  }
}

int WarningLog::count() const {
  int n = 0;
  for (const WarningStat& w : total_) n += w.number;
  return n;
}

std::vector<std::string> WarningLog::lines() const {
  std::vector<std::string> out;
  for (size_t k = 0; k < total_.size(); ++k) {
    const WarningStat& w = total_[k];
    if (w.number == 0) continue;
    out.push_back(std::string(warning_name(static_cast<Warning>(k))) + " (" +
                  std::to_string(w.number) + (w.number == 1 ? " time" : " times") +
                  ", last at index " + std::to_string(w.lastinfo) + ")");
  }
  return out;
}

bool outputs_finite(const Data& d) {
  const auto all = [](const auto& list) {
    for (const auto& x : list) {
      if (!x.allFinite()) return false;
    }
    return true;
  };
  return d.qpos.allFinite() && d.qvel.allFinite() && d.ctrl.allFinite() && all(d.xpos) &&
         all(d.xquat) && all(d.xmat) && all(d.xipos) && all(d.site_xpos) && all(d.site_xmat) &&
         d.M.allFinite() && d.qfrc_bias.allFinite() && d.qfrc_passive.allFinite() &&
         d.actuator_force.allFinite() && d.qfrc_actuator.allFinite() && d.qacc_smooth.allFinite() &&
         d.qacc.allFinite() && d.qfrc_constraint.allFinite() &&
         d.efc_pos.head(d.nefc).allFinite() && d.efc_force.head(d.nefc).allFinite() &&
         d.efc_aref.head(d.nefc).allFinite() && d.efc_R.head(d.nefc).allFinite() &&
         d.efc_D.head(d.nefc).allFinite() && std::isfinite(d.energy[0]) &&
         std::isfinite(d.energy[1]);
}

RunLog run(const Model& model, Data& data, const Controller& controller, long steps,
           const RowCallback& on_row) {
  validate(model, controller);
  if (steps < 0) throw StateError("lab run: the number of steps must not be negative.");
  RunLog log;
  log.clamped.assign(static_cast<size_t>(model.nu), 0);
  for (long k = 0;; ++k) {
    if (controller.gravity_compensation) forward(model, data);  // the current state's qfrc_bias
    apply(model, controller, data);
    forward(model, data);  // the row: everything at this state under this ctrl
    // a bad command is zeroed, not clamped: the warning says so, the clamping count does not
    const bool bad_ctrl = data.warning[static_cast<int>(Warning::kBadCtrl)].number > 0;
    log.warnings.collect(data);
    if (!outputs_finite(data)) ++log.non_finite_rows;
    if (on_row) on_row(k, data);
    if (k == steps) break;
    for (int a = 0; a < model.nu && !bad_ctrl; ++a) {
      if (actuator_clamped(model, data, a)) ++log.clamped[static_cast<size_t>(a)];
    }
    step(model, data);  // recomputes the same forward(), then integrates (or resets a bad state)
    log.warnings.collect(data);
  }
  return log;
}

}  // namespace lever::lab
