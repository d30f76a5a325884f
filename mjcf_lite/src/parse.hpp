// From the validated element tree to a ModelSpec: sections in MuJoCo's order (compiler, option,
// default, worldbody, actuator, wherever they are written), classes applied, values typed.
#pragma once

#include "reader.hpp"
#include "spec.hpp"

namespace lever::mjcf::detail {

/// `ignore_inertials`: read the model as if it had no <inertial> elements.
ModelSpec parse_model(const Element& root, bool ignore_inertials);

}  // namespace lever::mjcf::detail
