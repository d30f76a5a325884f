// Name lookups of the Model, and the names of its option flags.
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

}  // namespace lever
