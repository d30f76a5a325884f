// lever/regressor.hpp: the inertial-parameter regressor, tau = Y(q, qvel, qacc) pi, and the base
// (identifiable) parameters of a model.
//
// Inverse dynamics is linear in each body's ten inertial parameters when they are written in the
// body's own frame (Atkeson, An and Hollerbach 1986; Khalil and Dombre's "standard parameters"):
//   pi_b = [m, m cx, m cy, m cz, Ixx, Iyy, Izz, Ixy, Ixz, Iyz]
// with c the centre of mass in the body frame and I the rotational inertia about the body frame's
// origin, in body axes. The regressor adds, per dof, a column for armature (qacc_i) and one for
// viscous damping (qvel_i), and per actuator with a fixed gain a column for that gain
// (gainprm[0]), so that
//   Y pi = rnea(q, qvel, qacc) + damping * qvel - sum_a gear_a gainprm_a[0] basis_a
// (rnea includes armature; basis_a is the force per unit gain, see actuator_gain_basis). The gain
// columns carry a minus sign: the motors' gain-scaled torque moves to the parameter side, and
// what is left on the other side is known in absolute terms (an actuator force's gain-free part,
// the springs, the stops). Without the gain columns, Y pi = rnea + damping * qvel.
// docs/derivatives.md has the derivation.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

/// One body's ten inertial parameters, [m, m c (3), I about the origin (xx, yy, zz, xy, xz, yz)],
/// in the body frame.
using InertialParameters = Eigen::Matrix<double, 10, 1>;

/// What MJCF's <inertial> says: mass, centre of mass (pos), principal axes (quat, w x y z) and the
/// principal moments (diaginertia), all in the body frame (Model's body_mass, body_ipos,
/// body_iquat, body_inertia).
struct MjcfInertial {
  double mass = 0.0;
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();
  Eigen::Vector4d quat{1, 0, 0, 0};
  Eigen::Vector3d diaginertia = Eigen::Vector3d::Zero();
};

/// pi of an <inertial>: the parallel-axis theorem moves the inertia to the body origin.
InertialParameters to_parameters(const MjcfInertial& inertial);

/// The <inertial> of pi: centre of mass h / m, inertia about it, its principal axes and moments
/// (moments in increasing order, quat a proper rotation). Throws ModelError if pi is not
/// physically consistent: m > 0, principal moments > 0, each at most the sum of the other two.
MjcfInertial to_inertial(const InertialParameters& pi);

/// The parameters of body b in a model.
InertialParameters body_parameters(const Model& model, int body);

/// Write pi into body b of a model (body_mass, body_ipos, body_iquat, body_inertia); call
/// set_const(model) afterwards. Throws as to_inertial.
void set_body_parameters(Model& model, int body, const InertialParameters& pi);

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

/// Y (nv x regressor_columns) at data.qpos, data.qvel, data.ctrl and the given qacc:
/// Y pi = rnea(qacc) + dof_damping * qvel - sum_a gear_a gainprm_a[0] actuator_gain_basis_a
/// (the gain column of actuator a is -gear_a * basis_a in its joint's row). The forcerange clamp
/// is not modelled: where it binds the actuator's force is not linear in its gain, and a caller
/// drops that row (lever::identify does). @pre kinematics() at data.qpos. Allocates nothing.
void regressor(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& qacc,
               Eigen::Ref<Eigen::MatrixXd> Y);

/// The base parameters: the combinations of pi that inverse dynamics can distinguish.
struct BaseParameters {
  int rank = 0;                     ///< how many (the rank of the stacked regressor)
  std::vector<int> base;            ///< (rank) the column each base parameter is named after
  std::vector<int> unidentifiable;  ///< columns that appear in no base parameter (all-zero)
  Eigen::MatrixXd K;                ///< (rank x columns): base parameters = K pi
  std::vector<std::string> names;   ///< (rank) "link2.mx + 0.5 link2.m", ...
  /// The base regressor: Y_base = Y K^+ restricted to the base columns, i.e. Y.col(base[k]) for
  /// each k, since Y pi = Y_base (K pi) for every pi.
  Eigen::MatrixXd base_regressor(const Eigen::Ref<const Eigen::MatrixXd>& Y) const;
};

/// The base parameters of a model, from its regressor stacked over `samples` random states
/// (joints inside their ranges, qvel and qacc in [-2, 2] and [-10, 10], the ctrl of every gain
/// actuator uniform over its ctrlrange, or [-1, 1]), factored by column-pivoted QR: the pivoted
/// columns of full rank are the base columns, every other column is a combination of them,
/// K = [I beta] in pivot order (columns whose |R_kk| is below 1e-9 of the largest count as
/// dependent). Every gain column takes part.
BaseParameters base_parameters(const Model& model, int samples = 50, unsigned long long seed = 1);

/// The same with only the gain columns of `gains` (actuator ids, each in gain_actuators) taking
/// part: the other gain columns are zeroed in the stack, so they land in `unidentifiable` (their
/// gains are known, not estimated; their torque belongs on the known side). Throws StateError for
/// an actuator without a gain column.
BaseParameters base_parameters_with_gains(const Model& model, const std::vector<int>& gains,
                                          int samples = 50, unsigned long long seed = 1);

}  // namespace lever
