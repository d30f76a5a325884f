// The smooth pipeline: kinematics (kinematics.cpp), the recursions (recursion.hpp), CRBA and the
// LTDL factorization of M (crba.cpp), RNEA and the bias forces (rnea.cpp), the passive forces
// (passive.cpp), the tendons (tendon.cpp; a spatial tendon's wrapping, wrap.cpp), the actuators
// (actuation.cpp) and the energies (energy.cpp). Everything here
// depends on the state and the model alone, never on contacts or constraint rows.
#pragma once

#include <Eigen/Core>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever {

/// Factor M + h diag(dof_damping) into data.work.LD2 (the Euler step's implicit damping).
void factor_mass_damped(const Model& model, Data& data, double h);

/// x <- L^-T x, the first half of solve_mass (M = L^T D L): M^-1 = L^-1 D^-1 L^-T, so that
/// J M^-1 J^T = Y^T D^-1 Y with Y = L^-T J^T.
void solve_mass_half(const Model& model, const Data& data, Eigen::Ref<Eigen::VectorXd> x);

/// Factor M - h D, for a symmetric D non-zero only where M is, into data.work.LD2 as M is
/// factored (LTDL on the tree: MuJoCo 3's mj_factorI of implicitfast's matrix).
void factor_mass_minus(const Model& model, Data& data, const Eigen::Ref<const Eigen::MatrixXd>& D,
                       double h);

/// x = (M + h diag(dof_damping))^-1 x with factor_mass_damped()'s factor (or M - h D with
/// factor_mass_minus()'s).
void solve_mass_damped(const Model& model, const Data& data, Eigen::Ref<Eigen::VectorXd> x);

/// The steps of forward()'s stages: each the public function of the same name (lever/dynamics.hpp,
/// lever/constraint.hpp) without its entry check. forward(), step(), inverse(), step1() and step2()
/// check Model and Data once, at their door, and then run these.
namespace unchecked {
void crba(const Model& model, Data& data);
void factor_mass(const Model& model, Data& data);
void solve_mass(const Model& model, const Data& data, double* x);  // x: nv numbers
void bias(const Model& model, Data& data);
/// tau = ID(q, qd, qdd) without the armature's term (MuJoCo's mj_rne); qdd == nullptr means zero
/// acceleration. Also leaves the body velocities and the derivatives of the motion subspaces in
/// data (cvel, cdof_dot) (rnea.cpp).
void newton_euler(const Model& model, Data& data, const double* qdd, double* tau);
void passive(const Model& model, Data& data);
void transmission(const Model& model, Data& data);
void actuation(const Model& model, Data& data);
/// ten_length and ten_J (tendon.cpp)
void tendon(const Model& model, Data& data);
/// ten_velocity = ten_J qvel (tendon.cpp)
void tendon_velocity(const Model& model, Data& data);
/// data.energy[0]: the potential energy, after the position stage (MuJoCo's mj_energyPos): the
/// weights unless gravity is disabled, the springs unless passive forces are.
void energy_position(const Model& model, Data& data);
/// data.energy[1]: the kinetic energy qvel' M qvel / 2 (mj_energyVel).
void energy_velocity(const Model& model, Data& data);
}  // namespace unchecked

/// The tendons' spring-dampers, J^T f, added to qfrc_passive (tendon.cpp; passive() calls it).
void add_tendon_passive(const Model& model, Data& data);

/// A muscle's gain and bias differentiated (muscle.cpp's curves, in the actuator's length and
/// velocity): the step's derivatives read them (transition/). Where a curve has a kink the
/// branch muscle_gain takes is differentiated.
struct MusclePartials {
  double gain = 0;                            ///< muscle_gain
  double gain_per_length = 0;                 ///< d gain / d length
  double gain_per_velocity = 0;               ///< d gain / d velocity (muscle_gain_per_velocity)
  double gain_per_velocity_per_length = 0;    ///< d^2 gain / d velocity d length
  double gain_per_velocity_per_velocity = 0;  ///< d^2 gain / d velocity^2
  double bias_per_length = 0;                 ///< d muscle_bias / d length
};
MusclePartials muscle_partials(double length, double velocity,
                               const std::array<double, 2>& lengthrange, double acc0,
                               const double* gainprm, const double* biasprm);

/// d muscle_activation_rate / d ctrl and d act (the branch, activating or not, held).
void muscle_activation_rate_partials(double ctrl, double act, const double* dynprm,
                                     double& per_ctrl, double& per_act);

namespace detail {
/// out = M x (nv numbers each; data.M from crba()) summed as MuJoCo's mj_mulM walks its sparse M:
/// row i's diagonal product first, then its products with i's ancestors, nearest first; each
/// of those also added to the ancestor's row (crba.cpp). A simple dof's row is its diagonal.
void mass_times(const Model& model, const Data& data, const double* x, double* out);

// ---- a spatial tendon's wrapping (wrap.cpp): MuJoCo 2.2.2's mju_wrap

/// The path of a tendon from x0 to x1 around a sphere (or an infinite cylinder along its z axis)
/// of `radius` centred at `centre` with axes R: when the straight segment would pass through it,
/// the two tangent points (world frame) and the length of the path between them on the surface;
/// else -1 (the tendon runs straight). `side` (or nullptr): a side site's position, which picks
/// the side the path passes on, or, inside the geom, a path through it.
double wrap_around_geom(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1,
                        const Eigen::Vector3d& centre, const Mat3& R, double radius,
                        bool cylinder, const Eigen::Vector3d* side, Eigen::Vector3d& tangent0,
                        Eigen::Vector3d& tangent1);

/// The translational and rotational Jacobians (3 x nv each) of a point fixed to `body`, given in
/// world coordinates (MuJoCo's mj_jac), without the entry checks of jac_point (kinematics.cpp).
void point_jacobians(const Model& model, const Data& data, int body, const Eigen::Vector3d& point,
                     Eigen::Ref<Eigen::MatrixXd> jacp, Eigen::Ref<Eigen::MatrixXd> jacr);

// ---- the fluid forces (fluid.cpp): MuJoCo 2.2.2's inertia-box model, on when has_fluid(opt)

/// Every body's spatial velocity cvel from qvel (MuJoCo's mj_comVel without cdof_dot): the
/// passive stage needs it before bias() computes it again with the rest.
void body_velocities(const Model& model, Data& data);

/// qfrc_passive += each body's drag in the medium (viscosity, density, wind); writes cvel.
void add_fluid_forces(const Model& model, Data& data);

/// D += d (fluid forces) / d qvel as MuJoCo 2.2.2's implicit step takes it (mjd_inertiaBoxFluid),
/// at data.cvel (after forward()).
void add_fluid_velocity_terms(const Model& model, const Data& data,
                              Eigen::Ref<Eigen::MatrixXd> D);

// ---- the lean step pipeline: forward() without the outputs nothing in a step reads
// (xquat, and the geom frames when nothing can collide). After step() they are those of the last
// forward() or kinematics(); everything else is forward()'s to the bit
// (tests/property/lean_step.cpp).

/// kinematics() without xquat, and without the geom frames unless the collision stage runs
/// (kinematics.cpp).
void step_kinematics(const Model& model, Data& data);

/// Whether dof i starts a new motion segment of its body: its Sdot = v x S uses the body's
/// velocity before the segment. Each hinge or slide is its own segment; a ball's three rotations
/// share one, and so do a free joint's three translations and its three rotations (MuJoCo's
/// mj_comVel).
inline bool starts_segment(const Model& model, int i) {
  const int j = model.dof_jntid[i];
  const int offset = i - model.jnt_dofadr[j];
  return offset == 0 || (offset == 3 && model.jnt_kind[j] == JointKind::kFree);
}
}  // namespace detail

}  // namespace lever
