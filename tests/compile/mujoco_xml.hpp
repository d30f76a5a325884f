// MuJoCo's side of the compile tests: load MJCF text with mj_loadXML and compare its compiled
// mjModel with a lever::Model field by field.
#pragma once

#include <mujoco/mujoco.h>

#include <lever/harness/models.hpp>  // read_text
#include <lever/model.hpp>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace lever::test {

using MjModelHandle = std::unique_ptr<mjModel, void (*)(mjModel*)>;

/// MuJoCo's compiled model of MJCF text, or null with MuJoCo's message in `error`. Unless the text
/// says otherwise, autolimits is set to true first, since that is lever's (and MuJoCo 3's) default.
/// `files` (name -> bytes) are put beside it in MuJoCo's virtual file system, for mesh assets.
MjModelHandle mujoco_compile(const std::string& xml, std::string* error,
                             const std::map<std::string, std::string>& files = {});

/// The text without any <inertial .../> element (to compare inertia inferred from geoms).
std::string without_inertials(const std::string& xml);

/// Every difference between lever's compiled model and MuJoCo's beyond the agreement bound
/// |a - b| <= 1e-12 max(1, |b|) (quaternions up to sign), each as "field[index]: lever .. vs
/// mujoco ..", for lever's model `o` and MuJoCo's `m`. Covers the parameters (set_const's outputs
/// are compared separately).
std::vector<std::string> compare_parameters(const Model& o, const mjModel& m);

/// The same for what set_const derives: dof_invweight0, dof_M0, body_subtreemass,
/// body_invweight0.
std::vector<std::string> compare_constants(const Model& o, const mjModel& m);

/// compare_parameters and compare_constants together.
std::vector<std::string> compare_models(const Model& o, const mjModel& m);

/// Both compile `xml` (lever under the file name `name`); every difference of parameters and
/// constants, empty when they agree. MuJoCo refusing the text is a difference too (its message).
std::vector<std::string> compile_differences(const std::string& name, const std::string& xml);

/// lever's refusal of MJCF text (the ParseError's message), or "" if lever loads it.
std::string load_refusal(const std::string& xml);

}  // namespace lever::test
