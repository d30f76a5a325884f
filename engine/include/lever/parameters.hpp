// lever/parameters.hpp: a model's parameter vector pi, the one the regressor multiplies
// (lever/regressor.hpp): its layout and names, reading it from a model and writing it back, and
// the split of a fixed-gain actuator's force into the part its gain scales and the rest.
//
// pi holds, in order: ten inertial parameters per body (bodies 1..nbody-1, each in its own frame;
// RigidInertia::to_parameters, lever/spatial.hpp), nv armatures, nv dampings, and the gain
// gainprm[0] of each actuator in gain_actuators(model).
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include <lever/model.hpp>
#include <lever/spatial.hpp>

namespace lever {

/// The parameters of body b in a model.
InertialParameters body_parameters(const Model& model, int body);

/// Write pi into body b of a model (body_mass, body_ipos, body_iquat, body_inertia); call
/// set_const(model) afterwards. Throws ModelError naming the body unless pi is a rigid body's
/// (RigidInertia::to_principal).
void set_body_parameters(Model& model, int body, const InertialParameters& pi);

/// Whether an actuator has a gain column: its gain is fixed (GainType::kFixed).
bool has_gain_column(const Model& model, int actuator);

/// The actuators that have a gain column, in order: those whose gain is fixed
/// (GainType::kFixed: force = gainprm[0] ctrl + bias, linear in gainprm[0]). An affine gain is
/// not given one (its slopes in length and velocity would have to scale with it).
std::vector<int> gain_actuators(const Model& model);

/// Which bias entry a servo's gain carries along: 1 for a position servo (biastype affine,
/// biasprm[1] == -gainprm[0] != 0: force = kp (ctrl - length) + ...), else 2 for a velocity servo
/// (biasprm[1] == 0, biasprm[2] == -gainprm[0] != 0), else 0 (a motor, or a general actuator
/// whose bias does not follow its gain). A tied entry is identified and written with the gain.
int gain_tied_bias(const Model& model, int actuator);

/// The force of a fixed-gain actuator per unit gain at a joint position and velocity: ctrl
/// (clamped to ctrlrange) minus the tied length (gear q) or velocity (gear qvel). Its force before
/// the forcerange clamp is gainprm[0] * basis + actuator_gain_free_force.
double actuator_gain_basis(const Model& model, int actuator, double ctrl, double qpos, double qvel);

/// The part of a fixed-gain actuator's force (before the forcerange clamp) that does not scale
/// with the gain: its bias without the tied entry.
double actuator_gain_free_force(const Model& model, int actuator, double qpos, double qvel);

/// Columns of the regressor: 10 per body (bodies 1..nbody-1, in order), then nv armature, then nv
/// damping columns, then one per gain_actuators(model).
int regressor_columns(const Model& model);

/// A name per column: "link1.m", "link1.mx", ..., "link1.Iyz", "shoulder.armature",
/// "shoulder.damping", "shoulder.gain" (a body, joint or actuator without a name is called
/// body<i> / dof<i> / actuator<i>; a gain column is named after its actuator).
std::vector<std::string> regressor_names(const Model& model);

/// The model's own parameter vector pi (regressor_columns(model) values; gains are gainprm[0]).
Eigen::VectorXd model_parameters(const Model& model);

/// Write a parameter vector back into a model (inertials, dof_armature, dof_damping, each gain
/// actuator's gainprm[0] and its tied bias entry as -gain) and call set_const. Throws ModelError
/// (naming the body) if a body's parameters are not physical, or if a gain is not finite.
void set_model_parameters(Model& model, const Eigen::Ref<const Eigen::VectorXd>& pi);

}  // namespace lever
