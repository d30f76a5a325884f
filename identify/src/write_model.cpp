// The prior's MJCF written again with the identified parameters (see lever/identify.hpp): the
// writing is mjcf_lite's, which finds each body's, joint's and actuator's element where the
// loader recorded it (lever/mjcf/write.hpp).
#include <lever/identify.hpp>
#include <lever/mjcf/write.hpp>

namespace lever::identify {

void write_model(const std::string& prior_path, const Model& identified,
                 const std::string& out_path) {
  mjcf::write_file(prior_path, identified, out_path);
}

}  // namespace lever::identify
