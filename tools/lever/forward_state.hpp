// The state options shared by `lever forward` and `lever simulate`: --qpos, --qvel, --ctrl, and
// the units and labels both commands print. Header-only, so the command's build needs no change.
#pragma once

#include <Eigen/Core>

#include <cstdio>
#include <string>
#include <vector>

#include <lever/data.hpp>
#include <lever/model.hpp>

#include "cli.hpp"

namespace lever::cli {

/// Set data's state from --qpos, --qvel and --ctrl (comma-separated lists of nq, nv and nu
/// numbers). An omitted list keeps what reset() gives: qpos0 and zeros. Wrong counts, text that is
/// not a number, and non-finite numbers throw UsageError (exit 2).
inline void set_state_from_args(const Args& args, const Model& model, Data& data) {
  reset(model, data);
  data.qpos = args.get_vector("qpos", model.nq, model.qpos0);
  data.qvel = args.get_vector("qvel", model.nv, Eigen::VectorXd::Zero(model.nv));
  data.ctrl = args.get_vector("ctrl", model.nu, Eigen::VectorXd::Zero(model.nu));
}

/// A name to print: the object's name, or "#index" when it has none.
inline std::string label_of(const std::string& name, int index) {
  return name.empty() ? std::string("#").append(std::to_string(index)) : name;
}

/// Units of a joint's position, velocity, acceleration and force.
struct JointUnits {
  const char *pos, *vel, *acc, *force;
};

inline JointUnits joint_units(const Model& model, int joint) {
  if (model.jnt_type[joint] == JointType::kHinge) return {"rad", "rad/s", "rad/s^2", "N m"};
  return {"m", "m/s", "m/s^2", "N"};
}

/// "(a, b, c)" with %.6g numbers, for readable tables.
inline std::string vec_text(const Eigen::Ref<const Eigen::VectorXd>& v, const char* fmt = "%.6g") {
  std::string s = "(";
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    char buf[48];
    std::snprintf(buf, sizeof buf, fmt, v[i] + 0.0);  // + 0.0: no "-0"
    if (i > 0) s += ", ";
    s += buf;
  }
  return s + ")";
}

}  // namespace lever::cli
