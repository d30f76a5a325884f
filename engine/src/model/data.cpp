// Data: sized once from the Model, so that evaluating and stepping never allocate.
#include <lever/collision.hpp>
#include <lever/data.hpp>
#include <lever/error.hpp>

#include <algorithm>

#include "model/model_room.hpp"

namespace lever {

const char* warning_name(Warning w) {
  switch (w) {
    case Warning::kInertia: return "mass matrix is too close to singular";
    case Warning::kBadQpos: return "qpos is NaN or larger than 1e10 (step resets the state)";
    case Warning::kBadQvel: return "qvel is NaN or larger than 1e10 (step resets the state)";
    case Warning::kBadQacc: return "qacc is NaN or larger than 1e10 (step resets the state)";
    case Warning::kBadCtrl: return "ctrl is NaN or larger than 1e10: controls set to zero";
    case Warning::kBadQfrcApplied: return "qfrc_applied is NaN or larger than 1e10";
    case Warning::kContactUnsupported:
      return "geoms of a pair lever cannot collide (mesh, hfield, or cylinder or ellipsoid against "
             "a non-plane) came within their bounding spheres: no contact made";
    case Warning::kActiveSetChanges:
      return "the constraints' active set changes within the step: its derivatives hold the "
             "start's";
    case Warning::kCount: break;
  }
  return "unknown warning";
}

namespace {

// The mocap bodies where the model puts them (body_pos, body_quat), as mj_resetData does.
void place_mocap_at_bodies(const Model& model, Data& data) {
  for (int b = 0; b < model.nbody; ++b) {
    const int id = model.body_mocapid[b];
    if (id < 0) continue;
    data.mocap_pos[id] = model.body_pos[b];
    data.mocap_quat[id] = model.body_quat[b];
  }
}

}  // namespace

Data::Data(const Model& model)
    : nefc_max(constraint_rows_max(model)),
      nq(model.nq),
      nv(model.nv),
      nu(model.nu),
      nbody(model.nbody),
      njnt(model.njnt),
      ngeom(model.ngeom),
      nsite(model.nsite) {
  // every array of the field table, zero-filled at its size; then the values that are not zero
  detail::size_data_arrays(model, *this);
  model_tag = model.fit_tag;  // sized from this model: it fits
  qpos = model.qpos0;
  place_mocap_at_bodies(model, *this);
  for (auto& q : xquat) q = Eigen::Vector4d(1, 0, 0, 0);
  for (auto* list : {&xmat, &ximat, &geom_xmat, &site_xmat}) {
    for (Mat3& R : *list) R.setIdentity();
  }
  std::fill(efc_id.begin(), efc_id.end(), -1);
  std::fill(efc_dof.begin(), efc_dof.end(), -1);

  // what is not in the table: lever's spatial inertias, and the workspace
  cinert.assign(nbody, RigidInertia{});
  contact.assign(static_cast<size_t>(std::max(0, model.nconmax)), Contact{});
  work.contact.assign(contact.size(), Contact{});
  work.pair_contact.assign(kMaxPairContacts, Contact{});
  work.body_aabb.assign(6 * static_cast<size_t>(nbody), 0.0);
  work.body_path.assign(nbody, 0);
  qLD = Eigen::MatrixXd::Zero(nv, nv);
  work.crb.assign(nbody, RigidInertia{});
  work.subtree_mass.assign(nbody, 0.0);
  work.cacc.assign(nbody, Motion::Zero());
  work.cfrc.assign(nbody, Force::Zero());
  work.body_vel.assign(nbody, Motion::Zero());
  sensor_noise_state = kSensorNoiseSeed;
  work.LD2 = Eigen::MatrixXd::Zero(nv, nv);
  work.LD2DiagInv = Eigen::VectorXd::Zero(nv);
  work.vec1 = work.vec2 = work.vec3 = Eigen::VectorXd::Zero(nv);
  work.halfJ = work.halfJ_scaled = Eigen::MatrixXd::Zero(nv, nefc_max);
  work.A = Eigen::MatrixXd::Zero(nefc_max, nefc_max);
  work.L = Eigen::MatrixXd::Zero(nefc_max, nefc_max);
  work.lcp_f = work.lcp_w = work.lcp_rhs = Eigen::VectorXd::Zero(nefc_max);
  work.lcp_active.assign(nefc_max, 0);
  work.lcp_index.assign(nefc_max, 0);
  work.newton_H = Eigen::MatrixXd::Zero(nv, nv);
  for (Eigen::VectorXd* v : {&work.newton_grad, &work.newton_dir, &work.newton_Mdir,
                             &work.newton_Merr, &work.newton_trial, &work.newton_err}) {
    *v = Eigen::VectorXd::Zero(nv);
  }
  for (Eigen::VectorXd* v :
       {&work.newton_jar, &work.newton_jv, &work.newton_x, &work.newton_grad_x}) {
    *v = Eigen::VectorXd::Zero(nefc_max);
  }
  efc_J = RowMatrix::Zero(nefc_max, nv);
  work.contact_frame_J = RowMatrix::Zero(nefc_max, nv);
  work.contact_span.assign(2 * contact.size(), 0);
  work.dof_chain.assign(2 * static_cast<size_t>(nv), 0);
  work.equality_jac = Eigen::MatrixXd::Zero(12, nv);
  work.tendon_jac = Eigen::MatrixXd::Zero(12, nv);
  work.transmission_jac = Eigen::MatrixXd::Zero(12, nv);
  work.contact_weight.assign(36 * contact.size(), 0.0);
  work.frame_scratch.assign(6 * static_cast<size_t>(nv), 0.0);
  work.hessian_envelope.assign(nv, 0);
  work.rk_qpos0 = Eigen::VectorXd::Zero(nq);
  work.rk_dq = Eigen::VectorXd::Zero(nv);  // a velocity: nv, not nq
  work.rk_qvel0 = work.rk_dv = Eigen::VectorXd::Zero(nv);
  for (int i = 0; i < 4; ++i) {
    work.rk_qvel[i] = Eigen::VectorXd::Zero(nv);
    work.rk_qacc[i] = Eigen::VectorXd::Zero(nv);
    work.rk_act_dot[i] = Eigen::VectorXd::Zero(model.na);
  }
  work.rk_act0 = work.rk_dact = Eigen::VectorXd::Zero(model.na);
  work.qDeriv = Eigen::MatrixXd::Zero(nv, nv);
  work.qLU = Eigen::MatrixXd::Zero(nv, nv);
  work.subtree_coupling.assign(nbody, VelocityCoupling());
}

int warning_count(const Data& data) {
  int n = 0;
  for (const WarningStat& w : data.warning) n += w.number;
  return n;
}

std::string warning_text(const Data& data) {
  std::string text;
  for (int k = 0; k < static_cast<int>(Warning::kCount); ++k) {
    const WarningStat& w = data.warning[k];
    if (w.number == 0) continue;
    text += std::string(warning_name(static_cast<Warning>(k))) + " (" + std::to_string(w.number) +
            (w.number == 1 ? " time" : " times") + ", last at index " + std::to_string(w.lastinfo) +
            ")\n";
  }
  return text;
}

void reset(const Model& model, Data& data) {
  check_entry(model, data, "lever::reset");
  data.time = 0.0;
  data.qpos = model.qpos0;
  data.qvel.setZero();
  data.ctrl.setZero();
  data.act.setZero();
  data.act_dot.setZero();
  data.qfrc_applied.setZero();
  place_mocap_at_bodies(model, data);
  data.qacc.setZero();
  data.nefc = 0;
  data.ncon = 0;
  data.warning = {};
  data.sensordata.setZero();
  data.sensor_noise_state = kSensorNoiseSeed;  // the same noise again, as after making the Data
}

void reset_keyframe(const Model& model, Data& data, int key) {
  check_entry(model, data, "lever::reset_keyframe");
  if (key < 0 || key >= model.nkey) {
    throw StateError("lever::reset_keyframe: keyframe " + std::to_string(key) +
                     " does not exist (the model has " + std::to_string(model.nkey) +
                     " keyframes).");
  }
  reset(model, data);
  data.time = model.key_time[key];
  data.qpos = model.key_qpos.row(key).transpose();
  data.qvel = model.key_qvel.row(key).transpose();
  data.ctrl = model.key_ctrl.row(key).transpose();
  data.act = model.key_act.row(key).transpose();
  for (int i = 0; i < model.nmocap; ++i) {
    for (int k = 0; k < 3; ++k) data.mocap_pos[i][k] = model.key_mpos(key, 3 * i + k);
    for (int k = 0; k < 4; ++k) data.mocap_quat[i][k] = model.key_mquat(key, 4 * i + k);
  }
}

void reset_keyframe(const Model& model, Data& data, const std::string& key) {
  const int id = model.key(key);
  if (id < 0) {
    std::string names;
    for (const std::string& n : model.key_name) names += (names.empty() ? "'" : ", '") + n + "'";
    throw StateError(
        "lever::reset_keyframe: the model has no keyframe named '" + key + "' (" +
        (names.empty() ? std::string("it has no named keyframes") : "it has " + names) + ").");
  }
  reset_keyframe(model, data, id);
}

}  // namespace lever
