// The model's lifecycle, on the engine's top floor: validate() (model_check.cpp) and set_const()
// (set_const.cpp), which computes the constants once from every room below and evaluates the model
// at qpos0.
#pragma once

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever::detail {

/// The model evaluated once at qpos0, at rest and without control, into data (model_check.cpp):
/// throws ModelError naming the object whose numbers overflow (set_const's last step, once the
/// constants are computed).
void check_at_qpos0(const Model& model, Data& data);

}  // namespace lever::detail
