// The eight checks in order, and the findings: every claim that does not check out.
#include <lever/check.hpp>

#include <cmath>
#include <optional>

#include <lever/data.hpp>
#include <lever/mjcf.hpp>

#include "format.hpp"
#include "util.hpp"

namespace lever::check {

namespace {

constexpr double kKinematicsTolerance = 1e-9;  // m: beyond rounding error, something is wrong
constexpr double kGravityTolerance = 1e-9;     // N m per N m of the largest torque
// the grip's measured slip force against m g / (2 mu), relative. What it allows: the bisection's
// resolution (1 %), the slip the speed-up threshold cannot see (0.5 % of the weight), and the
// finger force changing while the slip is judged (a slipping box turns a little and wedges the
// fingers apart: over the hold, the force of gripper.xml's trials near the slip rises by 10 %,
// and its mean over the judged half lags the force at the slip by a few %; measured -2.2 %)
constexpr double kGripTolerance = 0.05;

void kinematics_findings(const Kinematics& k, std::vector<std::string>& findings) {
  for (const SiteKinematics& s : k.sites) {
    if (s.max_error_transforms > kKinematicsTolerance) {
      findings.push_back("site " + s.site + ": site_xpos differs from the chain of transforms by " +
                         fmt::sci(s.max_error_transforms) + " m");
    }
    if (s.planar && s.planar->max_error > kKinematicsTolerance) {
      findings.push_back("site " + s.site + ": site_xpos differs from the planar formula by " +
                         fmt::sci(s.planar->max_error) + " m");
    }
  }
}

void budget_findings(const TorqueBudget& b, std::vector<std::string>& findings) {
  double scale = 1.0;
  for (const JointBudget& j : b.joints) scale = std::max(scale, std::abs(j.worst_torque));
  if (b.formula_max_error > kGravityTolerance * scale) {
    findings.push_back("qfrc_bias at rest differs from the gravity formula dV/dq by " +
                       fmt::sci(b.formula_max_error) + " N m");
  }
  for (const JointBudget& j : b.joints) {
    if (!j.actuated() || !j.loaded || !(j.ratio < 1.0)) continue;
    const char* unit = fmt::torque_unit(j.hinge);
    findings.push_back("joint " + j.joint +
                       ": its motor cannot hold its own arm: the worst-case "
                       "gravity torque is " +
                       fmt::fixed(j.worst_torque, 3) + " " + unit +
                       " (at q = " + fmt::list(j.worst_pose, 4) + ") and the motor limit " +
                       fmt::general(j.limit) + " " + unit + " (ratio " + fmt::fixed(j.ratio, 2) +
                       ")");
  }
}

void inertia_findings(const Inertia& in, const Structure& s, std::vector<std::string>& findings) {
  for (const std::string& body : in.bodies_without_inertial) {
    findings.push_back("body " + body +
                       " has no <inertial>: its mass and inertia were inferred "
                       "from its geoms at their density");
  }
  for (const VisualMass& v : in.visual_mass) {
    findings.push_back("geom " + v.geom + " does not collide but adds " + fmt::fixed(v.mass, 3) +
                       " kg to body " + v.body + " (group " + std::to_string(v.group) +
                       " lies inside inertiagrouprange " + std::to_string(in.inertiagrouprange[0]) +
                       " " + std::to_string(in.inertiagrouprange[1]) + ")");
  }
  for (const BodyInfo& b : s.bodies) {
    const Eigen::Vector3d& I = b.principal;  // ascending
    if (b.mass > 0 && I[0] + I[1] < I[2] * (1.0 - 1e-12)) {
      findings.push_back("body " + b.name + ": principal moments " + fmt::list(I, 5) +
                         " violate the triangle inequality (no rigid body has them)");
    }
  }
}

void clamping_findings(const Clamping& c, std::vector<std::string>& findings) {
  for (const std::string& motor : c.unbounded) {
    findings.push_back("motor " + motor +
                       " has ctrllimited=\"false\": it accepts any command "
                       "(nothing bounds the request, so nothing reports when it is too large)");
  }
}

// the model's own step must be stable where it starts: an unstable step is a claim (the timestep,
// the integrator) that does not check out; Euler's instability is a lesson, not a finding
void stability_findings(const StepStability& st, std::vector<std::string>& findings) {
  for (const StabilityAt& s : st.states) {
    if (!s.stable_model) {
      findings.push_back("the " + st.integrator + " step at " + s.where +
                         " is unstable at timestep " + fmt::general(st.timestep) +
                         " s: spectral radius " + fmt::fixed(s.rho_model, 4));
    }
  }
}

// the engine's warnings are never silent: a run that raised one (a state reset after a blow-up)
// has not checked what it was meant to
void warning_findings(const Report& r, std::vector<std::string>& findings) {
  for (const StopRest& s : r.stops.stops) {
    if (s.warnings > 0) {
      findings.push_back("joint " + s.joint + ": the run resting on its " +
                         (s.upper ? "upper" : "lower") + " stop raised " +
                         std::to_string(s.warnings) +
                         " engine warnings (a state was reset): its result is not meaningful");
    }
  }
  if (r.clamping.warnings > 0) {
    findings.push_back("evaluating the motors' commands raised " +
                       std::to_string(r.clamping.warnings) + " engine warnings");
  }
}

// the hand calculations of section (9) against the simulations
void contact_findings(const Contacts& c, std::vector<std::string>& findings) {
  if (!c.skipped.empty()) return;
  for (const ContactPairInfo& p : c.pairs) {
    if (!p.agrees) {
      findings.push_back("contacts between " + p.geom1 + " and " + p.geom2 +
                         " got other parameters than their mix (condim, friction, solref, solimp, "
                         "margin - gap)");
    }
  }
  for (const std::string& s : c.strays) {
    findings.push_back("a contact between " + s + ", which the filters say cannot touch");
  }
  const RestingDepth& r = c.rest;
  if (r.skipped.empty() && !r.settled) {
    findings.push_back("body " + r.body + " did not come to rest on " + r.plane + " within " +
                       fmt::general(r.time_bound) + " s: its resting depth is not checked");
  } else if (r.skipped.empty() && !r.agrees()) {
    findings.push_back("body " + r.body + " rests " + fmt::sci(r.simulated) + " m deep in " +
                       r.plane + ", solref/solimp predict " + fmt::sci(r.predicted) + " m (bound " +
                       fmt::sci(r.bound) + " m)");
  }
  const Grip& g = c.grip;
  if (!g.skipped.empty()) return;
  for (const GripPad& p : g.pads) {
    if (p.agrees()) continue;
    findings.push_back("touch sensor " + p.sensor + " on finger " + p.finger + " reads " +
                       fmt::fixed(p.closed, 4) + " N closed and " + fmt::fixed(p.held, 4) +
                       " N held while its servo pushes " + fmt::fixed(p.servo_closed, 4) +
                       " and " + fmt::fixed(p.servo_held, 4) +
                       " N: its site does not cover the contacts, or the finger is not at rest");
  }
  if (!g.holds_by_hand()) {
    findings.push_back("the fingers (" + g.fingers[0] + ", " + g.fingers[1] + ") press body " +
                       g.body + " with at most " + fmt::fixed(g.servo_force, 3) +
                       " N; holding it needs m g / (2 mu) = " + fmt::fixed(g.needed, 3) +
                       " N (mu " + fmt::general(g.mu) + ")");
  }
  if (g.holds_by_hand() && !std::isfinite(g.hold_force)) {
    findings.push_back("body " + g.body + " slipped out of the full grip in the simulation (" +
                       fmt::fixed(g.slip_force, 4) + " N) although the hand calculation says " +
                       fmt::fixed(g.servo_force, 4) + " N holds it");
  }
  if (!g.holds_by_hand() && std::isfinite(g.hold_force)) {
    findings.push_back("body " + g.body + " held in the simulation with " +
                       fmt::fixed(g.hold_force, 4) + " N although the hand calculation needs " +
                       fmt::fixed(g.needed, 4) + " N");
  }
  // the box must hold above the hand calculation's force and slip below it, to the resolution
  // of the search and the creep's share of the drop (check.md)
  const double tolerance = kGripTolerance * g.needed;
  if (g.hold_force < g.needed - tolerance) {
    findings.push_back("body " + g.body + " held with a finger force of " +
                       fmt::fixed(g.hold_force, 4) +
                       " N, below m g / (2 mu) = " + fmt::fixed(g.needed, 4) + " N");
  }
  if (g.slip_force > g.needed + tolerance) {
    findings.push_back("body " + g.body + " slipped with a finger force of " +
                       fmt::fixed(g.slip_force, 4) +
                       " N, above m g / (2 mu) = " + fmt::fixed(g.needed, 4) + " N");
  }
}

}  // namespace

std::string Report::skipped(int section) const {
  if (floating_joints.empty()) return "";
  switch (section) {
    case 2:
    case 3:
    case 5:
    case 7:
    case 8:
      return "the model has ball or free joints (" + floating_joints +
             "): this section varies each joint as a hinge or slide over its range";
    default: return "";
  }
}

namespace {

// A user actuator's force is the callback's (MuJoCo's mjcb_act_gain, mjcb_act_bias,
// mjcb_act_dyn), which a model file does not carry: without it the engine would use MuJoCo's
// stand-ins (gain 1, bias 0, no activation change), and every section that reads the actuators
// (the torque budget from gainprm and biasprm, the servos' targets in the stop runs, the step's
// linearization) would report on a force the user never wrote. So the model is refused by name,
// callbacks installed or not: the sections read the force law from the parameters.
void refuse_user_actuators(const Model& model) {
  for (int a = 0; a < model.nu; ++a) {
    const char* user = actuator_user_attribute(model, a);
    if (user == nullptr) continue;
    const std::string name = actuator_label(model, a);
    throw ModelError("lever check: actuator " + name + " has " + user +
                         " \"user\": its force comes from a callback (MuJoCo's mjcb_act_*) "
                         "that lever check cannot know; its sections read each actuator's force "
                         "from gainprm, biasprm and dynprm. Check a copy of the model with a "
                         "built-in type in its place.",
                     "actuator", a);
  }
}

}  // namespace

Report run_check(const Inputs& inputs) {
  const Model& model = inputs.model;
  refuse_user_actuators(model);
  // the sections that vary each joint over its range, lift weights at the joints and linearize
  // the step in qpos are written for hinges and slides: a ball or free joint skips them
  std::string floating;
  for (int j = 0; j < model.njnt; ++j) {
    if (model.jnt_type[j] != JointType::kBall && model.jnt_type[j] != JointType::kFree) continue;
    floating += (floating.empty() ? "" : ", ") + joint_label(model, j);
  }
  if (!inputs.key.empty()) {  // an unknown keyframe is refused before any work, listing the keys
    Data data(model);
    reset_keyframe(model, data, inputs.key);
  }
  Report report;
  report.model = model.name;
  report.source = model.source;
  report.floating_joints = floating;
  const bool jointed = floating.empty();
  report.structure = check_structure(model);
  if (jointed) {
    report.kinematics = check_kinematics(model);
    report.budget = check_torque_budget(model);
  }
  report.inertia = check_inertia(inputs, report.budget);
  if (jointed) report.stops = check_soft_stops(model);
  report.clamping = check_clamping(model);
  if (jointed) {
    report.singular = check_singular_poses(model, inputs.key);
    report.stability = check_step_stability(model, inputs.key);
  }
  report.contacts = check_contacts(model);

  kinematics_findings(report.kinematics, report.findings);
  budget_findings(report.budget, report.findings);
  inertia_findings(report.inertia, report.structure, report.findings);
  clamping_findings(report.clamping, report.findings);
  stability_findings(report.stability, report.findings);
  warning_findings(report, report.findings);
  contact_findings(report.contacts, report.findings);
  // what the loader noticed (geom pairs that can collide and that lever cannot compute)
  for (const std::string& w : model.warnings) report.findings.push_back(w);
  return report;
}

Report check_model(const Model& model, const std::string& key) {
  std::optional<Model> inferred;
  std::string inferred_error =
      "the model was not loaded from a file, so it cannot be reloaded "
      "with inertias inferred from its geoms";
  if (!model.source.empty()) {
    try {
      inferred = mjcf::load_file(model.source, {.infer_inertia_from_geoms = true});
      inferred_error.clear();
    } catch (const Error& e) {
      inferred_error = e.what();
    }
  }
  return run_check({model, inferred ? &*inferred : nullptr, inferred_error, key});
}

Report check_file(const std::string& path, const std::string& key) {
  return check_model(mjcf::load_file(path), key);
}

}  // namespace lever::check
