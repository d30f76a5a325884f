// The Model's block (its arrays' layout, copies and moves), its name lookups, the names of its
// option flags, and what an actuator's transmission drives.
#include <lever/error.hpp>
#include <lever/fields.hpp>
#include <lever/model.hpp>

#include <cstring>
#include <new>
#include <utility>

#include "model/model_room.hpp"

namespace lever {

namespace detail {

// The arrays outside the field table, in the same block: the keyframes and what set_const
// derives for the kernels. An array added to Model that is not in the table gets its size here.
void lay_out_own_model_arrays(Model& m, ModelArrayPlacer& place) {
  const std::size_t nbody = m.nbody, ngeom = m.ngeom, nsite = m.nsite, njnt = m.njnt, nu = m.nu;
  place(m.key_time, static_cast<std::size_t>(m.nkey));
  place(m.key_qpos, m.nkey, m.nq);
  place(m.key_qvel, m.nkey, m.nv);
  place(m.key_ctrl, m.nkey, m.nu);
  place(m.key_act, m.nkey, m.na);
  place(m.key_mpos, m.nkey, 3 * m.nmocap);
  place(m.key_mquat, m.nkey, 4 * m.nmocap);
  place(m.body_mat, nbody);
  place(m.body_imat, nbody);
  place(m.geom_mat, ngeom);
  place(m.site_mat, nsite);
  place(m.body_placement, nbody);
  place(m.body_iplacement, nbody);
  place(m.geom_placement, ngeom);
  place(m.site_placement, nsite);
  place(m.jnt_kind, njnt);
  place(m.jnt_offset, njnt);
  place(m.actuator_kind, nu);
  place(m.body_weldid, nbody);
  place(m.body_collision, nbody);
  place(m.geom_aabb, ngeom);
  place(m.mesh_hull_neighbours, static_cast<std::size_t>(m.nmeshgraph));
}

void lay_out_model(Model& model, ModelArrayPlacer& place) {
  lay_out_model_table_arrays(model, place);
  lay_out_own_model_arrays(model, place);
}

}  // namespace detail

Model::Model() {
  size_model(*this);
  // the world body: its own parent and root, no joints, dofs or geoms, unturned frames
  body_mocapid[0] = -1;
  body_jntadr[0] = -1;
  body_dofadr[0] = -1;
  body_geomadr[0] = -1;
  body_quat[0] = Eigen::Vector4d(1, 0, 0, 0);
  body_iquat[0] = Eigen::Vector4d(1, 0, 0, 0);
}

Model::Model(const Model& other) : ModelFields(other), block_(other.block_.bytes()) {
  // the views copied above still point into other's block: point them into this one
  if (block_.bytes() > 0) std::memcpy(block_.data(), other.block_.data(), block_.bytes());
  detail::ModelArrayPlacer rebase(block_.data(), detail::ModelArrayPlacer::Mode::kRebase,
                                  other.block_.data());
  detail::lay_out_model(*this, rebase);
}

Model::Model(Model&& other) noexcept
    : ModelFields(std::move(other)), block_(std::move(other.block_)) {
  // the block did not move, so the views taken above are valid; other's no longer are
  detail::ModelArrayPlacer detach(nullptr, detail::ModelArrayPlacer::Mode::kDetach);
  detail::lay_out_model(other, detach);
  other.fit_tag = 0;
}

Model& Model::operator=(const Model& other) {
  if (&other != this) *this = Model(other);
  return *this;
}

Model& Model::operator=(Model&& other) noexcept {
  if (&other != this) {
    this->~Model();
    new (this) Model(std::move(other));
  }
  return *this;
}

const char* const kDisableNames[kDisableBits] = {
    "constraint", "equality", "frictionloss", "limit",    "contact",  "passive", "gravity",
    "clampctrl",  "warmstart", "filterparent", "actuation", "refsafe", "sensor"};
const char* const kEnableNames[kEnableBits] = {"override", "energy", "fwdinv", "sensornoise",
                                               "multiccd"};

namespace {
int find_name(const std::vector<std::string>& names, const std::string& n) {
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == n) return static_cast<int>(i);
  }
  return -1;
}
}  // namespace

int Model::body(const std::string& n) const { return find_name(body_name, n); }
int Model::joint(const std::string& n) const { return find_name(jnt_name, n); }
int Model::site(const std::string& n) const { return find_name(site_name, n); }
int Model::actuator(const std::string& n) const { return find_name(actuator_name, n); }
int Model::key(const std::string& n) const { return find_name(key_name, n); }
int Model::geom(const std::string& n) const { return find_name(geom_name, n); }
int Model::sensor(const std::string& n) const { return find_name(sensor_name, n); }
int Model::equality(const std::string& n) const { return find_name(eq_name, n); }
int Model::tendon(const std::string& n) const { return find_name(tendon_name, n); }

int actuator_scalar_dof(const Model& model, int a) {
  const TransmissionType trn = model.actuator_trntype[a];
  if (trn != TransmissionType::kJoint && trn != TransmissionType::kJointInParent) return -1;
  const int j = model.actuator_trnid[a][0];
  const JointType type = model.jnt_type[j];
  if (type != JointType::kHinge && type != JointType::kSlide) return -1;
  return model.jnt_dofadr[j];
}

std::string actuator_label(const Model& model, int a) {
  return model.actuator_name[a].empty() ? std::to_string(a) : "'" + model.actuator_name[a] + "'";
}

const char* actuator_user_attribute(const Model& model, int a) {
  return model.actuator_gaintype[a] == GainType::kUser   ? "gaintype"
         : model.actuator_biastype[a] == BiasType::kUser ? "biastype"
         : model.actuator_dyntype[a] == DynType::kUser   ? "dyntype"
                                                         : nullptr;
}

void require_simple_actuators(const Model& model, const std::string& feature,
                              bool tendons_and_sites) {
  for (int a = 0; a < model.nu; ++a) {
    if (const char* user = actuator_user_attribute(model, a)) {
      const std::string name = actuator_label(model, a);
      throw ModelError(feature + ": actuator " + name + " has " + user +
                           " \"user\": its force is a callback's, which " + feature +
                           " cannot read as parameters; " + feature +
                           " handles stateless actuators with fixed or affine gain and bias only.",
                       "actuator", a);
    }
    const bool stateful = model.actuator_dyntype[a] != DynType::kNone;
    const bool muscle = model.actuator_gaintype[a] == GainType::kMuscle ||
                        model.actuator_biastype[a] == BiasType::kMuscle;
    if (stateful || muscle) {
      const std::string name = actuator_label(model, a);
      throw ModelError(feature + ": actuator " + name + " is " +
                           (muscle ? "a muscle" : "an actuator with activation dynamics") + "; " +
                           feature + " handles stateless actuators with fixed or affine gain "
                           "and bias only, not yet that one.",
                       "actuator", a);
    }
    if (actuator_scalar_dof(model, a) >= 0) continue;
    if (tendons_and_sites && model.actuator_trntype[a] == TransmissionType::kTendon) continue;
    const bool site = model.actuator_trntype[a] == TransmissionType::kSite;
    if (tendons_and_sites && site && model.actuator_trnid[a][1] < 0) continue;
    const char* what = site && model.actuator_trnid[a][1] >= 0 ? "a site with a reference site"
                                                                : "a site";
    switch (model.actuator_trntype[a]) {
      case TransmissionType::kJoint:
      case TransmissionType::kJointInParent: what = "a ball or free joint"; break;
      case TransmissionType::kSliderCrank: what = "a slider-crank"; break;
      case TransmissionType::kTendon: what = "a tendon"; break;
      case TransmissionType::kBody: what = "a body through its contacts (adhesion)"; break;
      default: break;
    }
    const std::string name = actuator_label(model, a);
    throw ModelError(feature + ": actuator " + name + " drives " + what + "; " + feature +
                         " handles actuators on hinge and slide joints only, not yet that "
                         "transmission.",
                     "actuator", a);
  }
}

}  // namespace lever
