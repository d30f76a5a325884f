// Data: sized once from the Model, so that evaluating and stepping never allocate.
#include <lever/collision.hpp>
#include <lever/data.hpp>
#include <lever/error.hpp>

#include <algorithm>
#include <cstring>
#include <new>

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
      return "the constraints' active set (contacts, pushing rows) or a spatial tendon's wrapping "
             "changes within the step: its derivatives hold the start's";
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

namespace {

// The arrays outside the field table, in the same block: lever's own kinds (spatial inertias,
// contacts), the constraint Jacobian, the factor of M, and the workspace. An array added to Data
// that is not in the table gets its size here, in one line.
void lay_out_own_arrays(Data& d, detail::ArrayPlacer& place) {
  const std::size_t nq = d.nq, nv = d.nv, na = d.na, nbody = d.nbody, nefc = d.nefc_max,
                    ncon = d.nconmax;
  place(d.cinert, nbody);
  place(d.contact, ncon);
  place(d.qLD, nv, nv);
  place(d.efc_J, nefc, nv);
  DataWorkspace& w = d.work;
  place(w.crb, nbody);
  place(w.subtree_mass, nbody);
  place(w.cacc, nbody);
  place(w.cfrc, nbody);
  place(w.body_vel, nbody);
  place(w.LD2, nv, nv);
  place(w.LD2DiagInv, nv);
  for (ArenaVector* v : {&w.vec1, &w.vec2, &w.vec3}) place(*v, nv);
  place(w.halfJ, nv, nefc);
  place(w.halfJ_scaled, nv, nefc);
  place(w.A, nefc, nefc);
  place(w.L, nefc, nefc);
  for (ArenaVector* v : {&w.lcp_f, &w.lcp_w, &w.lcp_rhs}) place(*v, nefc);
  place(w.lcp_active, nefc);
  place(w.lcp_index, nefc);
  place(w.newton_H, nv, nv);
  for (ArenaVector* v : {&w.newton_grad, &w.newton_dir, &w.newton_Mdir, &w.newton_Merr,
                         &w.newton_trial, &w.newton_err, &w.cg_Mgrad, &w.cg_grad_old,
                         &w.cg_Mgrad_old}) {
    place(*v, nv);
  }
  for (ArenaVector* v : {&w.newton_jar, &w.newton_jv, &w.newton_x, &w.newton_grad_x}) {
    place(*v, nefc);
  }
  place(w.contact_frame_J, nefc, nv);
  place(w.contact_span, 2 * ncon);
  place(w.dof_chain, 2 * nv);
  place(w.equality_jac, 12, nv);
  place(w.tendon_jac, 12, nv);
  place(w.transmission_jac, 12, nv);
  place(w.contact_weight, 36 * ncon);
  place(w.frame_scratch, 6 * nv);
  place(w.hessian_envelope, nv);
  place(w.rk_qpos0, nq);
  for (ArenaVector* v : {&w.rk_qvel0, &w.rk_dq, &w.rk_dv}) place(*v, nv);  // rk_dq: a velocity
  for (int i = 0; i < 4; ++i) {
    place(w.rk_qvel[i], nv);
    place(w.rk_qacc[i], nv);
    place(w.rk_act_dot[i], na);
  }
  place(w.rk_act0, na);
  place(w.rk_dact, na);
  place(w.qDeriv, nv, nv);
  place(w.qLU, nv, nv);
  place(w.bias_chain_body, nbody);
  place(w.bias_chain_dof, nv);
  place(w.contact, ncon);
  place(w.pair_contact, kMaxPairContacts);
  place(w.body_aabb, 6 * nbody);
  place(w.body_path, nbody);
}

void lay_out(Data& data, detail::ArrayPlacer::Mode mode, unsigned char* block) {
  detail::ArrayPlacer place(block, mode);
  detail::lay_out_table_arrays(data, place);
  lay_out_own_arrays(data, place);
}

std::size_t block_bytes(Data& data) {
  detail::ArrayPlacer measure(nullptr, detail::ArrayPlacer::Mode::kMeasure);
  detail::lay_out_table_arrays(data, measure);
  lay_out_own_arrays(data, measure);
  return measure.bytes();
}

}  // namespace

namespace detail {
void throw_arena_shape(long rows, long cols, long other_rows, long other_cols) {
  throw StateError("lever: a Data array of " + std::to_string(rows) + " x " + std::to_string(cols) +
                   " numbers was assigned " + std::to_string(other_rows) + " x " +
                   std::to_string(other_cols) +
                   ": a Data's arrays keep the sizes the model gave them (assign element by "
                   "element or with an array of that size).");
}
}  // namespace detail

Data::Data(const Model& model) {
  nefc_max = constraint_rows_max(model);
  nq = model.nq;
  nv = model.nv;
  nu = model.nu;
  nbody = model.nbody;
  njnt = model.njnt;
  ngeom = model.ngeom;
  nsite = model.nsite;
  nmocap = model.nmocap;
  nsensordata = model.nsensordata;
  ntendon = model.ntendon;
  nwrap = model.nwrap;
  na = model.na;
  nconmax = std::max(0, model.nconmax);
  // one block for every array, zeroed; then the values that are not zero
  block_ = ArenaBlock(block_bytes(*this));
  if (block_.bytes() > 0) std::memset(block_.data(), 0, block_.bytes());
  lay_out(*this, detail::ArrayPlacer::Mode::kConstruct, block_.data());
  model_tag = model.fit_tag;  // sized from this model: it fits
  qpos = model.qpos0;
  place_mocap_at_bodies(model, *this);
  for (auto& q : xquat) q = Eigen::Vector4d(1, 0, 0, 0);
  for (auto* list : {&xmat, &ximat, &geom_xmat, &site_xmat}) {
    for (Mat3& R : *list) R.setIdentity();
  }
  std::fill(efc_id.begin(), efc_id.end(), -1);
  std::fill(efc_dof.begin(), efc_dof.end(), -1);
  sensor_noise_state = kSensorNoiseSeed;
}

Data::Data(const Data& other) : DataFields(other), block_(other.block_.bytes()) {
  // the views copied above still point into other's block: point them into this one
  if (block_.bytes() > 0) std::memcpy(block_.data(), other.block_.data(), block_.bytes());
  lay_out(*this, detail::ArrayPlacer::Mode::kRebase, block_.data());
}

Data::Data(Data&& other) noexcept : DataFields(other), block_(std::move(other.block_)) {
  // the block did not move, so the views copied above are valid; other's no longer are, and a
  // call with it must walk the field table (and refuse it) instead of trusting its tag
  lay_out(other, detail::ArrayPlacer::Mode::kDetach, nullptr);
  other.model_tag = 0;
}

Data& Data::operator=(const Data& other) {
  if (&other != this) *this = Data(other);
  return *this;
}

Data& Data::operator=(Data&& other) noexcept {
  if (&other != this) {
    this->~Data();
    new (this) Data(std::move(other));
  }
  return *this;
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
  data.qacc_warmstart.setZero();
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
