// ModelSpec -> lever::Model, as MuJoCo 2.2.2's compiler (mjCModel::Compile) does it for the
// subset: bodies numbered depth-first, frames and orientation forms, inertia from <inertial> or
// from geoms, bounds, joint limits in radians, dof tree, motors, checks; then set_const().
#pragma once

#include <lever/model.hpp>

#include "spec.hpp"

namespace lever::mjcf::detail {

/// Compile a parsed model; throws Problem for bad input. set_const() is not called here.
Model compile(const ModelSpec& spec);

}  // namespace lever::mjcf::detail
