// Name lookups of the Model, the names of its option flags, and what an actuator's transmission
// drives.
#include <lever/error.hpp>
#include <lever/model.hpp>

namespace lever {

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

void require_simple_actuators(const Model& model, const std::string& feature,
                              bool tendons_and_sites) {
  for (int a = 0; a < model.nu; ++a) {
    const bool stateful = model.actuator_dyntype[a] != DynType::kNone;
    const bool muscle = model.actuator_gaintype[a] == GainType::kMuscle ||
                        model.actuator_biastype[a] == BiasType::kMuscle;
    if (stateful || muscle) {
      const std::string name =
          model.actuator_name[a].empty() ? std::to_string(a) : "'" + model.actuator_name[a] + "'";
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
    const std::string name =
        model.actuator_name[a].empty() ? std::to_string(a) : "'" + model.actuator_name[a] + "'";
    throw ModelError(feature + ": actuator " + name + " drives " + what + "; " + feature +
                         " handles actuators on hinge and slide joints only, not yet that "
                         "transmission.",
                     "actuator", a);
  }
}

}  // namespace lever
