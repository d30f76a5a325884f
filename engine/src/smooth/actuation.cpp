// Actuators: transmission, clamping and the joint forces they produce (MuJoCo 2.2.2's
// mj_transmission and mj_fwdActuation for stateless actuators: motors, position and velocity
// servos, and <general> with fixed or affine gain and bias). Each transmission gives a length and
// a moment row, d length / d qpos (actuator_moment holds every row): a hinge or slide gear[0] qpos
// and gear[0] at its dof; a tendon gear[0] times the tendon's length and ten_J; a ball or free
// joint, a slider-crank and a site as their functions below say; a body's (adhesion's) moment
// needs the contacts' rows, so the constraint room fills it in after make_constraint (its row is
// zero here). actuator_velocity is moment qvel.
//
// Order, as MuJoCo: ctrl clamped to ctrlrange (on a copy; data.ctrl is never changed), force =
// gain * ctrl + bias, force clamped to forcerange, then the gear carries it to the joint. A
// position servo is gain kp and bias -kp length - kv velocity, so it pulls length to ctrl.
// Clamping is silent here; `lever check` reports it.
#include <lever/dynamics.hpp>

#include <algorithm>
#include <cmath>

#include "basics/basics.hpp"
#include "model/model_room.hpp"
#include "smooth/smooth.hpp"

namespace lever {

namespace {
double clamp(double x, const std::array<double, 2>& range) {
  if (x < range[0]) return range[0];
  if (x > range[1]) return range[1];
  return x;  // NaN passes through, as mju_clip
}
}  // namespace

namespace {

// ---- transmissions: each writes its actuator's length and its moment row (zeroed before) ----

// A joint: a hinge or slide carries gear[0] along its dof; a ball the rotation vector of its
// quaternion against gear[0..2], a free joint gear[0..2] on its translation and gear[3..5] on its
// rotation, with no length. In the parent's frame (kJointInParent) the rotational gear is turned
// back by the joint's quaternion, since a ball's and a free joint's rotational dofs are in the
// body's own frame.
void joint_transmission(const Model& model, const Data& data, int a, double* moment,
                        double& length) {
  const auto& gear = model.actuator_gear[a];
  const int j = model.actuator_trnid[a][0];
  const double* const q = data.qpos.data() + model.jnt_qposadr[j];
  double* const row = moment + model.jnt_dofadr[j];
  const JointType type = model.jnt_type[j];
  if (type == JointType::kHinge || type == JointType::kSlide) {
    length = q[0] * gear[0];
    row[0] = gear[0];
    return;
  }
  const bool in_parent = model.actuator_trntype[a] == TransmissionType::kJointInParent;
  const double* const quat = type == JointType::kBall ? q : q + 3;
  const double* const rotational_gear = type == JointType::kBall ? gear.data() : gear.data() + 3;
  Eigen::Vector3d axis_gear(rotational_gear[0], rotational_gear[1], rotational_gear[2]);
  if (in_parent) axis_gear = detail::quat_rotate(Quat(quat[0], -quat[1], -quat[2], -quat[3]), axis_gear);
  if (type == JointType::kBall) {
    const double identity[4] = {1, 0, 0, 0};
    length = detail::quat_difference(quat, identity).dot(axis_gear);
    for (int k = 0; k < 3; ++k) row[k] = axis_gear[k];
    return;
  }
  length = 0;  // a free joint has no meaningful length
  for (int k = 0; k < 3; ++k) {
    row[k] = gear[k];
    row[3 + k] = axis_gear[k];
  }
}

// A slider-crank: the crank site c hangs from a rod of length r whose other end slides along the
// slider site s's z axis a. With v = c - s, the slider's travel is a.v - sqrt((a.v)^2 + r^2 - v.v)
// (where the root is not real, a.v alone). Its moment is the chain rule through the Jacobians of
// v and of the axis a (which turns with the slider's body).
void slider_crank_transmission(const Model& model, Data& data, int a, double* moment,
                               double& length) {
  const int crank = model.actuator_trnid[a][0], slider = model.actuator_trnid[a][1];
  const double rod = model.actuator_cranklength[a];
  const Eigen::Vector3d axis = data.site_xmat[slider].col(2);
  const Eigen::Vector3d v = data.site_xpos[crank] - data.site_xpos[slider];
  const double av = v.dot(axis);
  const double det = av * av + rod * rod - v.dot(v);
  Eigen::Vector3d dl_dv, dl_da;
  if (det <= 0) {
    length = av;
    dl_da = v;
    dl_dv = axis;
  } else {
    const double root = std::sqrt(det);
    length = av - root;
    dl_dv = axis * (1 - av / root) + v * (1 / root);
    dl_da = v * (1 - av / root);
  }
  ArenaMatrix& jac = data.work.transmission_jac;
  auto crank_p = jac.middleRows(0, 3), crank_r = jac.middleRows(3, 3);
  auto slider_p = jac.middleRows(6, 3), slider_r = jac.middleRows(9, 3);
  detail::point_jacobians(model, data, model.site_bodyid[slider], data.site_xpos[slider], slider_p,
                          slider_r);
  detail::point_jacobians(model, data, model.site_bodyid[crank], data.site_xpos[crank], crank_p,
                          crank_r);
  const double g = model.actuator_gear[a][0];
  for (int i = 0; i < model.nv; ++i) {
    // the axis's rate is (the slider body's angular velocity) x axis
    const Eigen::Vector3d w = slider_r.col(i);
    const Eigen::Vector3d axis_rate(w[1] * axis[2] - w[2] * axis[1], w[2] * axis[0] - w[0] * axis[2],
                                    w[0] * axis[1] - w[1] * axis[0]);
    const Eigen::Vector3d v_rate = crank_p.col(i) - slider_p.col(i);
    double m = 0;
    for (int k = 0; k < 3; ++k) m += dl_da[k] * axis_rate[k] + dl_dv[k] * v_rate[k];
    moment[i] = m * g;
  }
  length *= g;
}

// A site: the gear is a wrench (force gear[0..2], torque gear[3..5]) in the site's frame, its
// moment the site's Jacobians projected on it; it has no length. With a reference site the gear
// is in the reference's frame, the Jacobians are relative to the reference's, and the length is
// the site's position (against gear[0..2]) and orientation (the rotation vector from the
// reference's, against gear[3..5]) in the reference's frame.
void site_transmission(const Model& model, Data& data, int a, double* moment, double& length) {
  const auto& gear = model.actuator_gear[a];
  const int site = model.actuator_trnid[a][0], ref = model.actuator_trnid[a][1];
  const int nv = model.nv;
  ArenaMatrix& jac = data.work.transmission_jac;
  auto site_p = jac.middleRows(0, 3), site_r = jac.middleRows(3, 3);
  auto ref_p = jac.middleRows(6, 3), ref_r = jac.middleRows(9, 3);
  detail::point_jacobians(model, data, model.site_bodyid[site], data.site_xpos[site], site_p, site_r);
  const Eigen::Vector3d force(gear[0], gear[1], gear[2]), torque(gear[3], gear[4], gear[5]);
  length = 0;
  if (ref < 0) {
    const Mat3& R = data.site_xmat[site];
    const Eigen::Vector3d f = R * force, t = R * torque;
    for (int i = 0; i < nv; ++i) moment[i] = site_p.col(i).dot(f) + site_r.col(i).dot(t);
    return;
  }
  const Mat3& R = data.site_xmat[ref];
  detail::point_jacobians(model, data, model.site_bodyid[ref], data.site_xpos[ref], ref_p, ref_r);
  if (force[0] != 0 || force[1] != 0 || force[2] != 0) {
    const Eigen::Vector3d offset = R.transpose() * (data.site_xpos[site] - data.site_xpos[ref]);
    length += offset.dot(force);
    const Eigen::Vector3d f = R * force;
    for (int i = 0; i < nv; ++i) moment[i] = (site_p.col(i) - ref_p.col(i)).dot(f);
  }
  if (torque[0] != 0 || torque[1] != 0 || torque[2] != 0) {
    // the two orientations from their bodies' (MuJoCo composes site_quat * xquat, in that order)
    const Quat q = quat_mul(model.site_quat[site], data.xquat[model.site_bodyid[site]]);
    const Quat q_ref = quat_mul(model.site_quat[ref], data.xquat[model.site_bodyid[ref]]);
    length += detail::quat_difference(q.data(), q_ref.data()).dot(torque);
    const Eigen::Vector3d t = R * torque;
    for (int i = 0; i < nv; ++i) moment[i] += (site_r.col(i) - ref_r.col(i)).dot(t);
  }
}

}  // namespace

void unchecked::transmission(const Model& model, Data& data) {
  const int nv = model.nv;
  for (int a = 0; a < model.nu; ++a) {
    double* const moment = data.actuator_moment.data() + static_cast<std::ptrdiff_t>(a) * nv;
    for (int i = 0; i < nv; ++i) moment[i] = 0.0;
    double& length = data.actuator_length[a];
    const int dof = model.actuator_scalar_dof[a];
    if (dof >= 0) {  // a hinge or slide: the common case, its velocity without the row
      const double g = model.actuator_gear[a][0];
      moment[dof] = g;
      length = data.qpos[model.jnt_qposadr[model.actuator_trnid[a][0]]] * g;
      data.actuator_velocity[a] = g * data.qvel[dof];
      continue;
    }
    switch (model.actuator_trntype[a]) {
      case TransmissionType::kJoint:
      case TransmissionType::kJointInParent:
        joint_transmission(model, data, a, moment, length);
        break;
      case TransmissionType::kSliderCrank:
        slider_crank_transmission(model, data, a, moment, length);
        break;
      case TransmissionType::kTendon: {
        const int t = model.actuator_trnid[a][0];
        const double g = model.actuator_gear[a][0];
        const double* const J = data.ten_J.data() + static_cast<std::ptrdiff_t>(t) * nv;
        length = data.ten_length[t] * g;
        for (int i = 0; i < nv; ++i) moment[i] = J[i] * g;
        break;
      }
      case TransmissionType::kSite:
        site_transmission(model, data, a, moment, length);
        break;
      case TransmissionType::kBody:
        // no length; the moment, from the contacts, is the constraint room's
        // (body_transmission.cpp), after make_constraint
        length = 0;
        break;
    }
    // MuJoCo's mj_fwdVelocity: moment qvel, a dense row in 2.2.2 whatever the layout (mju_dot)
    data.actuator_velocity[a] = dot_as_mujoco(moment, data.qvel.data(), 0, nv, nv);
  }
}

void transmission(const Model& model, Data& data) {
  check_entry(model, data, "lever::transmission");
  unchecked::transmission(model, data);
}

namespace {

// d act / dt of stateful actuator a at its clamped control and activation (MuJoCo's act_dot)
double activation_rate(const Model& model, int a, double ctrl, double act) {
  const auto& prm = model.actuator_dynprm[a];
  switch (model.actuator_dyntype[a]) {
    case DynType::kIntegrator: return ctrl;
    case DynType::kFilter: return (ctrl - act) / std::max(detail::kMinVal, prm[0]);
    case DynType::kMuscle: return muscle_activation_rate(ctrl, act, prm.data());
    case DynType::kNone: break;
    case DynType::kUser: break;  // the model's callback, after the forces (actuation below)
  }
  return 0.0;
}

}  // namespace

double actuator_gain(const Model& model, int a, double length, double velocity) {
  const auto& g = model.actuator_gainprm[a];
  switch (model.actuator_gaintype[a]) {
    case GainType::kAffine: return g[0] + g[1] * length + g[2] * velocity;
    case GainType::kMuscle:
      return muscle_gain(length, velocity, model.actuator_lengthrange[a], model.actuator_acc0[a],
                         g.data());
    case GainType::kFixed: break;
    case GainType::kUser: return 1.0;  // MuJoCo's without a callback (actuation calls it)
  }
  return g[0];
}

double actuator_bias(const Model& model, int a, double length, double velocity) {
  const auto& b = model.actuator_biasprm[a];
  switch (model.actuator_biastype[a]) {
    case BiasType::kAffine: return b[0] + b[1] * length + b[2] * velocity;
    case BiasType::kMuscle:
      return muscle_bias(length, model.actuator_lengthrange[a], model.actuator_acc0[a], b.data());
    case BiasType::kNone: break;
    case BiasType::kUser: break;  // MuJoCo's without a callback (actuation calls it)
  }
  return 0.0;
}

void unchecked::actuation(const Model& model, Data& data) {
  double* const qfrc = data.qfrc_actuator.data();
  for (int i = 0; i < model.nv; ++i) qfrc[i] = 0.0;
  if (model.nu == 0) return;
  double* const force = data.actuator_force.data();
  if (model.opt.disabled(kDisableActuation)) {
    for (int a = 0; a < model.nu; ++a) force[a] = 0.0;
    return;
  }

  // the clamped controls; one bad control zeroes them all (MuJoCo's mjWARN_BADCTRL)
  const double* const ctrl = data.ctrl.data();
  const bool clamp_ctrl = !model.opt.disabled(kDisableClampctrl);
  for (int a = 0; a < model.nu; ++a) {
    force[a] = clamp_ctrl && model.actuator_ctrllimited[a]
                   ? clamp(ctrl[a], model.actuator_ctrlrange[a])
                   : ctrl[a];
  }
  const int bad = first_bad(force, model.nu);
  if (bad >= 0) {
    record_warning(data, Warning::kBadCtrl, bad);
    for (int a = 0; a < model.nu; ++a) force[a] = 0.0;
  }

  const double* const length = data.actuator_length.data();
  const double* const velocity = data.actuator_velocity.data();
  const auto* const gear = model.actuator_gear.data();
  const int nv = model.nv;
  const int first_stateful = model.nu - model.na;  // actuator a's activation: act[a - this]
  for (int a = 0; a < model.nu; ++a) {
    // a stateful actuator's force follows its activation, a stateless one's the clamped ctrl
    const double input = a < first_stateful ? force[a] : data.act[a - first_stateful];
    if (a >= first_stateful) {  // from the clamped control, before force[a] is overwritten
      data.act_dot[a - first_stateful] = activation_rate(model, a, force[a], data.act[a - first_stateful]);
    }
    // a user gain or bias from the model's callback, as MuJoCo's mjcb_act_gain and mjcb_act_bias
    const double gain =
        model.actuator_gaintype[a] == GainType::kUser && model.actuator_gain_callback
            ? model.actuator_gain_callback(model, data, a)
            : actuator_gain(model, a, length[a], velocity[a]);
    double f = input * gain;
    f += model.actuator_biastype[a] == BiasType::kUser && model.actuator_bias_callback
             ? model.actuator_bias_callback(model, data, a)
             : actuator_bias(model, a, length[a], velocity[a]);
    if (model.actuator_forcelimited[a]) f = clamp(f, model.actuator_forcerange[a]);
    force[a] = f;
    const int dof = model.actuator_scalar_dof[a];
    if (dof >= 0) {
      qfrc[dof] += gear[a][0] * f;
      continue;
    }
    const double* const moment = data.actuator_moment.data() + static_cast<std::ptrdiff_t>(a) * nv;
    for (int j = 0; j < nv; ++j) qfrc[j] += moment[j] * f;  // moment^T f
  }
  // user activation dynamics, by the model's callback once every force is known (MuJoCo's
  // mjcb_act_dyn, called after qfrc_actuator); 0 without one
  for (int a = first_stateful; a < model.nu; ++a) {
    if (model.actuator_dyntype[a] != DynType::kUser) continue;
    data.act_dot[a - first_stateful] =
        model.actuator_dyn_callback ? model.actuator_dyn_callback(model, data, a) : 0.0;
  }
}

void actuation(const Model& model, Data& data) {
  check_entry(model, data, "lever::actuation");
  unchecked::actuation(model, data);
}

bool actuator_clamped(const Model& model, const Data& data, int a) {
  const double ctrl = data.ctrl[a];
  const auto& c = model.actuator_ctrlrange[a];
  if (model.actuator_ctrllimited[a] && (ctrl < c[0] || ctrl > c[1])) return true;
  const auto& f = model.actuator_forcerange[a];
  const double force = data.actuator_force[a];
  return model.actuator_forcelimited[a] && (force == f[0] || force == f[1]);
}

}  // namespace lever
