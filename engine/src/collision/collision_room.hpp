// The collision room: the stage MuJoCo 2.2.2's mj_collision runs (driver.cpp: broad phase, pair
// filters, parameter mixing), the narrow phase's closed-form pairs (primitive.cpp, box.cpp,
// narrow_phase.hpp) and the body constants set_const computes for the broad phase.
#pragma once

#include <lever/model.hpp>

namespace lever::detail {

/// The collision stage's body constants, Model::body_weldid and body_collision
/// (driver.cpp; set_const computes them once, the broad phase reads them every call).
void build_collision_constants(Model& model);

}  // namespace lever::detail
