// lever/regressor.hpp: the inertial-parameter regressor, tau = Y(q, qvel, qacc) pi, and the base
// (identifiable) parameters of a model.
//
// Inverse dynamics is linear in each body's ten inertial parameters when they are written in the
// body's own frame (Atkeson, An and Hollerbach 1986; Khalil and Dombre's "standard parameters"):
//   pi_b = [m, m cx, m cy, m cz, Ixx, Iyy, Izz, Ixy, Ixz, Iyz]
// with c the centre of mass in the body frame and I the rotational inertia about the body frame's
// origin, in body axes. The regressor adds, per dof, a column for armature (qacc_i) and one for
// viscous damping (qvel_i), so that
//   Y pi = rnea(q, qvel, qacc) + damping * qvel = qfrc_inverse + qfrc_spring + qfrc_constraint
// (rnea includes armature). lever's motors have a fixed gain of 1 (their gear is part of the
// transmission), so there is no actuator-gain column. docs/derivatives.md has the derivation.
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

/// Columns of the regressor: 10 per body (bodies 1..nbody-1, in order), then nv armature, then nv
/// damping columns.
int regressor_columns(const Model& model);

/// A name per column: "link1.m", "link1.mx", ..., "link1.Iyz", "shoulder.armature",
/// "shoulder.damping" (a body or joint without a name is called body<i> / dof<i>).
std::vector<std::string> regressor_names(const Model& model);

/// The model's own parameter vector pi (regressor_columns(model) values).
Eigen::VectorXd model_parameters(const Model& model);

/// Write a parameter vector back into a model (inertials, dof_armature, dof_damping) and call
/// set_const. Throws ModelError (naming the body) if a body's parameters are not physical.
void set_model_parameters(Model& model, const Eigen::Ref<const Eigen::VectorXd>& pi);

/// Y (nv x regressor_columns) at data.qpos, data.qvel and the given qacc: Y pi = rnea(qacc) +
/// dof_damping * qvel. @pre kinematics() at data.qpos. Allocates nothing.
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
/// (joints inside their ranges, qvel and qacc in [-2, 2] and [-10, 10]), factored by
/// column-pivoted QR: the pivoted columns of full rank are the base columns, every other column
/// is a combination of them, K = [I beta] in pivot order (columns whose |R_kk| is below 1e-9 of
/// the largest count as dependent).
BaseParameters base_parameters(const Model& model, int samples = 50, unsigned long long seed = 1);

}  // namespace lever
