// The eight checks in order, and the findings: every claim that does not check out.
#include <lever/check.hpp>

#include <cmath>
#include <optional>

#include <lever/data.hpp>
#include <lever/mjcf.hpp>

#include "format.hpp"

namespace lever::check {

namespace {

constexpr double kKinematicsTolerance = 1e-9;  // m: beyond rounding error, something is wrong
constexpr double kGravityTolerance = 1e-9;     // N m per N m of the largest torque

const char* torque_unit(bool hinge) { return hinge ? "N m" : "N"; }

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
    const char* unit = torque_unit(j.hinge);
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

}  // namespace

Report run_check(const Inputs& inputs) {
  const Model& model = inputs.model;
  if (model.nq != model.nv) {
    // the sections search joint ranges, lift weights against gravity at the joints and
    // linearize the step: all written for a robot fixed to the world
    std::string joints;
    for (int j = 0; j < model.njnt; ++j) {
      if (model.jnt_type[j] != JointType::kBall && model.jnt_type[j] != JointType::kFree) continue;
      joints += (joints.empty() ? "'" : ", '") + model.jnt_name[j] + "'";
    }
    throw ModelError(
        "lever check checks arms fixed to the world (hinge and slide joints); this "
        "model has ball or free joints (" +
        joints + "). lever forward, simulate and diff evaluate it.");
  }
  if (!inputs.key.empty()) {  // an unknown keyframe is refused before any work, listing the keys
    Data data(model);
    reset_keyframe(model, data, inputs.key);
  }
  Report report;
  report.model = model.name;
  report.source = model.source;
  report.structure = check_structure(model);
  report.kinematics = check_kinematics(model);
  report.budget = check_torque_budget(model);
  report.inertia = check_inertia(inputs, report.budget);
  report.stops = check_soft_stops(model);
  report.clamping = check_clamping(model);
  report.singular = check_singular_poses(model, inputs.key);
  report.stability = check_step_stability(model, inputs.key);

  kinematics_findings(report.kinematics, report.findings);
  budget_findings(report.budget, report.findings);
  inertia_findings(report.inertia, report.structure, report.findings);
  clamping_findings(report.clamping, report.findings);
  stability_findings(report.stability, report.findings);
  warning_findings(report, report.findings);
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
