// lever/from_mujoco.hpp: a lever::Model copied field by field from MuJoCo's compiled mjModel.
//
// It lets the engine be compared with MuJoCo on exactly MuJoCo's compiled parameters, separately
// from mjcf_lite's compiler (which has its own tests against MuJoCo's).
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <string>

#include <lever/model.hpp>

namespace lever::test {

/// mjModel with its deleter.
using MjModelPtr = std::unique_ptr<mjModel, void (*)(mjModel*)>;
using MjDataPtr = std::unique_ptr<mjData, void (*)(mjData*)>;

/// Load a model file with MuJoCo; throws std::runtime_error with MuJoCo's message.
MjModelPtr mujoco_load(const std::string& path);

/// Load MJCF text with MuJoCo (through its virtual file system).
MjModelPtr mujoco_load_string(const std::string& xml);

MjDataPtr mujoco_data(const mjModel* m);

/// The lever model with MuJoCo's compiled parameters; set_const() already applied.
Model from_mujoco(const mjModel* m);

}  // namespace lever::test
