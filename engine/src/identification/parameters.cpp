// A model's parameter vector (see lever/parameters.hpp): its layout and names, reading and writing
// it, and the gain split of the actuators' force.
#include <lever/error.hpp>
#include <lever/parameters.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "identification/identification.hpp"

namespace lever {

namespace {

using detail::kPerBody;
const char* const kParameterNames[kPerBody] = {"m",   "mx",  "my",  "mz",  "Ixx",
                                               "Iyy", "Izz", "Ixy", "Ixz", "Iyz"};

std::string body_label(const Model& model, int b) {
  return model.body_name[b].empty() ? std::string("body").append(std::to_string(b))
                                    : model.body_name[b];
}

std::string dof_label(const Model& model, int i) {
  const std::string& joint = model.jnt_name[model.dof_jntid[i]];
  return joint.empty() ? std::string("dof").append(std::to_string(i)) : joint;
}

std::string actuator_parameter_name(const Model& model, int a) {
  return model.actuator_name[a].empty() ? std::string("actuator").append(std::to_string(a))
                                        : model.actuator_name[a];
}

int inertial_columns(const Model& model) { return kPerBody * (model.nbody - 1); }

}  // namespace

bool has_gain_column(const Model& model, int actuator) {
  return model.actuator_gaintype[actuator] == GainType::kFixed;
}

std::vector<int> gain_actuators(const Model& model) {
  std::vector<int> out;
  for (int a = 0; a < model.nu; ++a) {
    if (has_gain_column(model, a)) out.push_back(a);
  }
  return out;
}

int gain_tied_bias(const Model& model, int a) {
  switch (model.actuator_kind[a]) {
    case ActuatorKind::kPositionServo: return 1;  // kp (ctrl - length)
    case ActuatorKind::kVelocityServo: return 2;  // kv (ctrl - velocity)
    default: return 0;
  }
}

double actuator_gain_basis(const Model& model, int a, double ctrl, double qpos, double qvel) {
  if (model.actuator_ctrllimited[a]) {
    const auto& range = model.actuator_ctrlrange[a];
    ctrl = std::min(std::max(ctrl, range[0]), range[1]);
  }
  const double gear = model.actuator_gear[a][0];
  switch (gain_tied_bias(model, a)) {
    case 1: return ctrl - gear * qpos;
    case 2: return ctrl - gear * qvel;
    default: return ctrl;
  }
}

double actuator_gain_free_force(const Model& model, int a, double qpos, double qvel) {
  if (model.actuator_biastype[a] != BiasType::kAffine) return 0.0;
  const double gear = model.actuator_gear[a][0];
  const double length = gear * qpos, velocity = gear * qvel;
  const auto& b = model.actuator_biasprm[a];
  const int tied = gain_tied_bias(model, a);
  return b[0] + (tied == 1 ? 0.0 : b[1] * length) + (tied == 2 ? 0.0 : b[2] * velocity);
}

InertialParameters body_parameters(const Model& model, int body) {
  const PrincipalInertia inertial{model.body_mass[body], model.body_ipos[body],
                                  model.body_iquat[body], model.body_inertia[body]};
  return RigidInertia::from_principal(inertial).to_parameters();
}

void set_body_parameters(Model& model, int body, const InertialParameters& pi) {
  PrincipalInertia inertial;
  try {
    inertial = RigidInertia::from_parameters(pi).to_principal();
  } catch (const ModelError& e) {
    throw ModelError("body '" + body_label(model, body) + "': " + e.what(), "body", body);
  }
  model.body_mass[body] = inertial.mass;
  model.body_ipos[body] = inertial.pos;
  model.body_iquat[body] = inertial.quat;
  model.body_inertia[body] = inertial.diaginertia;
}

int regressor_columns(const Model& model) {
  int gains = 0;  // counted, not listed: regressor() calls this and allocates nothing
  for (int a = 0; a < model.nu; ++a) gains += has_gain_column(model, a) ? 1 : 0;
  return inertial_columns(model) + 2 * model.nv + gains;
}

std::vector<std::string> regressor_names(const Model& model) {
  std::vector<std::string> names;
  names.reserve(static_cast<std::size_t>(regressor_columns(model)));
  for (int b = 1; b < model.nbody; ++b) {
    for (const char* p : kParameterNames) names.push_back(body_label(model, b) + "." + p);
  }
  for (int i = 0; i < model.nv; ++i) names.push_back(dof_label(model, i) + ".armature");
  for (int i = 0; i < model.nv; ++i) names.push_back(dof_label(model, i) + ".damping");
  for (const int a : gain_actuators(model)) {
    names.push_back(actuator_parameter_name(model, a) + ".gain");
  }
  return names;
}

Eigen::VectorXd model_parameters(const Model& model) {
  Eigen::VectorXd pi(regressor_columns(model));
  for (int b = 1; b < model.nbody; ++b) {
    pi.segment<kPerBody>(kPerBody * (b - 1)) = body_parameters(model, b);
  }
  const int tail = kPerBody * (model.nbody - 1);
  for (int i = 0; i < model.nv; ++i) {
    pi[tail + i] = model.dof_armature[i];
    pi[tail + model.nv + i] = model.dof_damping[i];
  }
  int column = tail + 2 * model.nv;
  for (const int a : gain_actuators(model)) pi[column++] = model.actuator_gainprm[a][0];
  return pi;
}

void set_model_parameters(Model& model, const Eigen::Ref<const Eigen::VectorXd>& pi) {
  if (pi.size() != regressor_columns(model)) {
    throw StateError("set_model_parameters: " + std::to_string(pi.size()) +
                     " parameters, the model has " + std::to_string(regressor_columns(model)) +
                     ".");
  }
  Model edited = model;  // nothing half-written if a body is not physical
  for (int b = 1; b < edited.nbody; ++b) {
    const InertialParameters pb = pi.segment<kPerBody>(kPerBody * (b - 1));
    // a body without mass stays without mass (a frame, or a body whose mass is below others)
    if (pb.isZero(0) && edited.body_mass[b] == 0) continue;
    set_body_parameters(edited, b, pb);
  }
  const int tail = kPerBody * (edited.nbody - 1);
  for (int i = 0; i < edited.nv; ++i) {
    edited.dof_armature[i] = pi[tail + i];
    edited.dof_damping[i] = pi[tail + edited.nv + i];
  }
  int column = tail + 2 * edited.nv;
  for (const int a : gain_actuators(model)) {
    const double gain = pi[column++];
    if (!std::isfinite(gain)) {
      throw ModelError("actuator '" + actuator_parameter_name(model, a) + "': gain " +
                       std::to_string(gain) + " is not finite.");
    }
    // a servo's tied bias entry follows its gain (read from the model before the edit)
    const int tied = gain_tied_bias(model, a);
    edited.actuator_gainprm[a][0] = gain;
    if (tied > 0) edited.actuator_biasprm[a][static_cast<std::size_t>(tied)] = -gain;
  }
  set_const(edited);
  model = std::move(edited);
}

}  // namespace lever
