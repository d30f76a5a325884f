// (1) What the compiled model contains: joints, motors, sites, bodies.
#include <lever/check.hpp>
#include "util.hpp"

namespace lever::check {

namespace {

JointInfo joint_info(const Model& model, int j) {
  JointInfo info;
  info.name = joint_label(model, j);
  info.hinge = model.jnt_type[j] == JointType::kHinge;
  const JointType type = model.jnt_type[j];
  info.type = type == JointType::kHinge   ? "hinge"
              : type == JointType::kSlide ? "slide"
              : type == JointType::kBall  ? "ball"
                                          : "free";
  info.axis = model.jnt_axis[j];
  info.range = model.jnt_range[j];
  info.limited = model.jnt_limited[j];
  const int dof = model.jnt_dofadr[j];
  info.damping = model.dof_damping[dof];
  info.armature = model.dof_armature[dof];
  info.stiffness = model.jnt_stiffness[j];
  info.qpos0 = model.qpos0[model.jnt_qposadr[j]];
  return info;
}

MotorInfo motor_info(const Model& model, int a) {
  MotorInfo info;
  info.name = motor_label(model, a);
  const int id = model.actuator_trnid[a][0];
  switch (model.actuator_trntype[a]) {
    case TransmissionType::kTendon: info.joint = label(model.tendon_name[id], "tendon", id); break;
    case TransmissionType::kSite: info.joint = label(model.site_name[id], "site", id); break;
    case TransmissionType::kSliderCrank:
      info.joint = label(model.site_name[id], "crank site", id);
      break;
    default: info.joint = joint_label(model, id);
  }
  info.gear = model.actuator_gear[a][0];
  info.ctrlrange = model.actuator_ctrlrange[a];
  info.forcerange = model.actuator_forcerange[a];
  info.ctrllimited = model.actuator_ctrllimited[a];
  info.forcelimited = model.actuator_forcelimited[a];
  info.joint_torque = motor_torque_range(model, a);
  info.servo = is_servo(model.actuator_kind[a]);
  for (int k = 0; k < 3; ++k) {
    info.gainprm[k] = model.actuator_gainprm[a][k];
    info.biasprm[k] =
        model.actuator_biastype[a] == BiasType::kAffine ? model.actuator_biasprm[a][k] : 0.0;
  }
  if (info.servo) {
    info.kp = -info.biasprm[1];
    info.kv = -info.biasprm[2];
  }
  return info;
}

}  // namespace

Structure check_structure(const Model& model) {
  Structure s;
  for (int j = 0; j < model.njnt; ++j) s.joints.push_back(joint_info(model, j));
  for (int a = 0; a < model.nu; ++a) s.motors.push_back(motor_info(model, a));
  for (int i = 0; i < model.nsite; ++i) {
    s.sites.push_back(site_label(model, i));
    s.site_bodies.push_back(body_label(model, model.site_bodyid[i]));
  }
  for (int b = 1; b < model.nbody; ++b) {
    s.bodies.push_back({body_label(model, b), model.body_mass[b],
                        sorted_moments(model.body_inertia[b]),
                        model.body_explicit_inertial[b] != 0});
  }
  return s;
}

}  // namespace lever::check
