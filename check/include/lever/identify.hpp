// lever/identify.hpp: least-squares identification of a model's base inertial parameters (and
// armature and damping) from a measured or simulated trajectory, and a model written back.
//
// The equations are inverse dynamics through the regressor (lever/regressor.hpp):
//   Y_base(q, qvel, qacc) theta = qfrc_actuator + qfrc_applied + qfrc_constraint - springs
// one row per dof and sample, theta the base parameters of the prior model (their structure
// depends on the kinematics only, which the prior must get right). Springs are taken from the
// prior. `lever identify` is this file's command-line face.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include <lever/model.hpp>
#include <lever/regressor.hpp>

namespace lever::identify {

/// A trajectory, one column per sample.
struct Trajectory {
  Eigen::VectorXd time;              ///< (N) s
  Eigen::MatrixXd qpos, qvel, qacc;  ///< (nv x N)
  /// (nv x N) the joint force the motors, the user and the joint stops applied:
  /// qfrc_actuator + qfrc_applied + qfrc_constraint
  Eigen::MatrixXd force;
  std::string qacc_source;   ///< where qacc came from (its columns, or differences of qvel)
  std::string force_source;  ///< where the motor forces came from
};

/// Read a trajectory in `lever simulate --csv`'s columns: time, qpos[joint], qvel[joint], and
/// optionally qacc[joint] (else qacc is the forward difference of qvel to the next row, the last
/// row dropped: the acceleration a semi-implicit Euler step applied), the actuator force
/// actuator_force[motor] (else ctrl[motor], turned into a force as the prior's actuators do at the
/// row's qpos and qvel: ctrl clamped to ctrlrange, gain * ctrl + bias with an affine gain and bias
/// in length = gear qpos and velocity = gear qvel, then clamped to forcerange), and
/// qfrc_constraint[joint] (else zero). A joint or motor is
/// named as `lever simulate` names it (its name, or #index). Other columns are ignored. Throws
/// lever::Error naming the file, line and column for a missing column, a field that is not a finite
/// number, a row of the wrong length, or fewer rows than the identification needs.
Trajectory read_csv(const Model& prior, const std::string& path);

/// What identify() found.
struct Result {
  BaseParameters base;             ///< the prior's base parameters (names, K)
  Eigen::VectorXd prior;           ///< (rank) K pi of the prior model
  Eigen::VectorXd estimate;        ///< (rank) least-squares estimate
  Eigen::VectorXd standard_error;  ///< (rank) sqrt(diag(sigma^2 (W^T W)^-1))
  double residual_rms = 0.0;       ///< of the fit, in N m (N for slides)
  int samples = 0, equations = 0;  ///< N and N nv
  /// base parameters the data barely excites: in the direction of W's singular vectors whose
  /// singular value is below 1e-6 of the largest (W with columns scaled to unit norm); their
  /// estimates are not to be trusted
  std::vector<std::string> unexcited;
  /// the full parameter vector (regressor_columns) closest to the prior (each parameter scaled by
  /// its kind's size in the prior) whose base parameters are the estimate: what a model written
  /// from the result holds; unidentifiable combinations keep the prior's values
  Eigen::VectorXd parameters;
  /// empty when `parameters` is a physical model; else why not (which body fails, and how)
  std::string not_physical;
};

/// Least squares on the base regressor. Throws lever::Error when the trajectory does not fit the
/// prior (sizes) or has fewer equations than base parameters plus one.
Result identify(const Model& prior, const Trajectory& data);

/// The prior with the result's parameters (inertials, armature, damping), set_const applied.
/// Throws ModelError if they are not physical (result.not_physical says why beforehand).
Model identified_model(const Model& prior, const Result& result);

/// Write the MJCF file `prior_path` again with each body's <inertial> and each joint's armature
/// and damping replaced by the identified model's (bodies and joints in document order, as MuJoCo
/// numbers them). Everything else is kept as written; inertiafromgeom="true" becomes "auto".
/// Throws lever::Error if the file cannot be read or written or does not match the model.
void write_model(const std::string& prior_path, const Model& identified,
                 const std::string& out_path);

}  // namespace lever::identify
