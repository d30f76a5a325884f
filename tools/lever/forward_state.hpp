// The state options shared by `lever forward` and `lever simulate`: --key, --qpos, --qvel, --ctrl,
// and the units and labels both commands print. Header-only, so the command's build needs no
// change.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <lever/data.hpp>
#include <lever/lab/lab.hpp>
#include <lever/model.hpp>

#include "cli.hpp"

namespace lever::cli {

/// Set data's state from --key, then --qpos, --qvel and --ctrl (comma-separated lists of nq, nv
/// and nu numbers). --key NAME starts from the keyframe (time, qpos, qvel, ctrl as
/// mj_resetDataKeyframe sets them); an omitted list keeps what reset() or the keyframe gives.
/// Wrong counts, text that is not a number, non-finite numbers and an unknown keyframe (the error
/// lists the model's keyframes) throw UsageError (exit 2).
inline void set_state_from_args(const Args& args, const Model& model, Data& data) {
  reset(model, data);
  if (args.has("key")) {
    try {
      reset_keyframe(model, data, args.get("key"));
    } catch (const StateError& e) {
      throw UsageError{std::string("--key: ") + e.what()};
    }
  }
  data.qpos = args.get_vector("qpos", model.nq, data.qpos);
  data.qvel = args.get_vector("qvel", model.nv, data.qvel);
  data.ctrl = args.get_vector("ctrl", model.nu, data.ctrl);
}

/// A name to print: the object's name, or "#index" when it has none.
inline std::string label_of(const std::string& name, int index) {
  return name.empty() ? std::string("#").append(std::to_string(index)) : name;
}

/// What actuator a drives: its transmission's kind ("joint", "tendon", "site", "crank") and the
/// object's label, for the tables that list actuators.
struct TransmissionText {
  const char* kind;
  std::string object;
};

inline TransmissionText transmission_text(const Model& model, int a) {
  const int id = model.actuator_trnid[a][0];
  switch (model.actuator_trntype[a]) {
    case TransmissionType::kTendon: return {"tendon", label_of(model.tendon_name[id], id)};
    case TransmissionType::kSite: return {"site", label_of(model.site_name[id], id)};
    case TransmissionType::kSliderCrank: return {"crank", label_of(model.site_name[id], id)};
    default: return {"joint", label_of(model.jnt_name[id], id)};
  }
}

/// Units of a joint's position, velocity, acceleration and force.
struct JointUnits {
  const char *pos, *vel, *acc, *force;
};

inline JointUnits joint_units(const Model& model, int joint) {
  if (model.jnt_type[joint] == JointType::kHinge) return {"rad", "rad/s", "rad/s^2", "N m"};
  return {"m", "m/s", "m/s^2", "N"};
}

/// Units of actuator a's force: its joint's for a hinge or slide, N m for a ball's torque, N along
/// a tendon or slider-crank; a free joint's or a site's force is the scale of its gear's wrench.
inline const char* actuator_force_units(const Model& model, int a) {
  const int id = model.actuator_trnid[a][0];
  switch (model.actuator_trntype[a]) {
    case TransmissionType::kTendon:
    case TransmissionType::kSliderCrank: return "N";
    case TransmissionType::kSite: return "x gear";
    default: break;
  }
  if (model.jnt_type[id] == JointType::kBall) return "N m";
  if (model.jnt_type[id] == JointType::kFree) return "x gear";
  return joint_units(model, id).force;
}

/// What text output prints for a number that is not finite (JSON prints null): never "nan" or
/// "inf", so that a blow-up cannot pass for a value; the command says so on stderr.
inline constexpr const char* kNonFinite = "n/a";

/// One number with a printf format ("%.6g"), or kNonFinite.
inline std::string num(double x, const char* fmt = "%.6g") {
  if (!std::isfinite(x)) return kNonFinite;
  char buf[48];
  std::snprintf(buf, sizeof buf, fmt, x + 0.0);  // + 0.0: no "-0"
  return buf;
}

/// "(a, b, c)" with %.6g numbers, for readable tables.
inline std::string vec_text(const Eigen::Ref<const Eigen::VectorXd>& v, const char* fmt = "%.6g") {
  std::string s = "(";
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (i > 0) s += ", ";
    s += num(v[i], fmt);
  }
  return s + ")";
}

using lab::outputs_finite;
using lab::WarningLog;

/// One line on stderr per kind of warning in the log:
/// "lever forward: warning: qvel is NaN or larger than 1e10 ... (1 time, last at index 0)".
inline void print_warnings(const char* command, const WarningLog& log) {
  for (const std::string& line : log.lines()) {
    std::fprintf(stderr, "lever %s: warning: %s\n", command, line.c_str());
  }
}

/// The line a command prints on stderr when a number it printed was not finite.
inline void print_non_finite(const char* command) {
  std::fprintf(stderr,
               "lever %s: error: the results hold numbers that are not finite (printed as %s in "
               "text, null in JSON, empty in CSV)\n",
               command, kNonFinite);
}

}  // namespace lever::cli
