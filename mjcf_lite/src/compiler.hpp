// ModelSpec -> lever::Model, as MuJoCo 2.2.2's compiler (mjCModel::Compile) does it for the
// subset: bodies numbered depth-first, frames and orientation forms, inertia from <inertial> or
// from geoms, bounds, joint limits in radians, dof tree, motors, checks; then set_const().
#pragma once

#include <lever/model.hpp>
#include <vector>

#include "spec.hpp"

namespace lever::mjcf::detail {

/// Where each compiled object was written, by its id in the Model: lets a ModelError from
/// set_const() be reported at the element it came from.
struct Locations {
  std::vector<Place> body, joint, site, actuator;
};

/// Compile a parsed model; throws Problem for bad input. set_const() is not called here.
/// `where`, if given, receives each object's element.
Model compile(const ModelSpec& spec, Locations* where = nullptr);

}  // namespace lever::mjcf::detail
