// lever/regressor.hpp: the inertial-parameter regressor, tau = Y(q, qvel, qacc) pi
// (engine/src/identification/regressor.cpp), and the base (identifiable) parameters of a model, the regressor's
// column space (engine/src/identification/base_parameters.cpp). pi, its layout and names, and reading and writing
// it in a model: lever/parameters.hpp; one body's conversions: RigidInertia (lever/spatial.hpp).
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
#include <lever/parameters.hpp>

namespace lever {

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
