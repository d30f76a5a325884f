// lever/identify.hpp: least-squares identification of a model's base inertial parameters (and
// armature and damping) from a measured or simulated trajectory, and a model written back.
//
// The equations are inverse dynamics through the regressor (lever/regressor.hpp):
//   Y_base(q, qvel, qacc) theta = qfrc_actuator + qfrc_applied + qfrc_constraint - springs
// one row per dof and sample, theta the base parameters of the prior model (their structure
// depends on the kinematics only, which the prior must get right). Springs are taken from the
// prior. With Options::gains the chosen actuators' gains are estimated too: their gain-scaled
// torque moves to the left (the regressor's gain columns) and only their force's gain-free part
// stays on the right; rows where such an actuator's force may be clamped are dropped.
// `lever identify` is this file's command-line face.
#pragma once

#include <Eigen/Core>

#include <string>
#include <utility>
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
  Eigen::MatrixXd actuator_force;  ///< (nu x N) each actuator's force in `force` (before gear)
  Eigen::MatrixXd ctrl;  ///< (nu x N) the ctrl columns as written (unclamped); 0 x N without them
  bool qacc_differenced = false;  ///< qacc from differences of qvel (errors correlated in time)
  std::string qacc_source;        ///< where qacc came from (its columns, or differences of qvel)
  std::string force_source;       ///< where the motor forces came from
};

/// Read a trajectory in `lever simulate --csv`'s columns: time, qpos[joint], qvel[joint], and
/// optionally qacc[joint] (else qacc is the forward difference of qvel to the next row, the last
/// row dropped: the acceleration a semi-implicit Euler step applied), the actuator force
/// actuator_force[motor] (else ctrl[motor], turned into a force as the prior's actuators do at the
/// row's qpos and qvel: ctrl clamped to ctrlrange, gain * ctrl + bias with an affine gain and bias
/// in length = gear qpos and velocity = gear qvel, then clamped to forcerange), and
/// qfrc_constraint[joint] (else zero). A joint or motor is
/// named as `lever simulate` names it (its name, or #index). The ctrl columns are kept when all are
/// present (identifying gains needs them). Other columns are ignored. Throws
/// lever::Error naming the file, line and column for a missing column, a field that is not a finite
/// number, a row of the wrong length, or fewer rows than the identification needs.
Trajectory read_csv(const Model& prior, const std::string& path);

/// What to identify besides the inertial parameters, armature and damping.
struct Options {
  /// actuators (ids, each in gain_actuators(prior)) whose gain gainprm[0] is estimated from the
  /// trajectory's ctrl (a servo's tied bias entry with it); the others' forces are known
  std::vector<int> gains;
  /// bodies (ids) whose mass is known (kg); each one's centre of mass and inertia per unit mass
  /// are the prior's (a part that was weighed and whose shape is known). Its ten parameters move
  /// to the known side, which pins the scale that estimated gains and the inertia share.
  std::vector<std::pair<int, double>> known_masses;
};

/// What identify() found.
struct Result {
  BaseParameters base;     ///< the prior's base parameters (names, K)
  std::vector<int> gains;  ///< the actuators whose gains were estimated
  /// equations (sample, dof) left out because an estimated-gain actuator's force there is within
  /// 1% of its forcerange's width of an edge or beyond: the force is not linear in the gain where
  /// it clamps. Judged first for every gain within a factor of two of the prior's, then at each
  /// fit's estimate until the set settles.
  int dropped = 0;
  Eigen::VectorXd prior;     ///< (rank) K pi of the prior model
  Eigen::VectorXd estimate;  ///< (rank) least-squares estimate
  /// (rank) the estimate's standard errors: the square roots of the diagonal of the
  /// cluster-robust covariance (W^T W)^-1 (sum_c W_c^T r_c r_c^T W_c) (W^T W)^-1 c/(c-1) m/(m-p),
  /// clusters c of consecutive samples (a sample's dofs share their errors through M; differenced
  /// qacc's errors are correlated between neighbouring samples)
  Eigen::VectorXd standard_error;
  Eigen::VectorXd ols_standard_error;  ///< (rank) sqrt(diag(sigma^2 (W^T W)^-1)), for comparison
  double residual_rms = 0.0;           ///< of the fit, in N m (N for slides)
  int samples = 0, equations = 0;      ///< N and the equations used (N nv less the dropped)
  /// base parameters the data barely excites: in the direction of W's singular vectors whose
  /// singular value is below 1e-6 of the largest (W with columns scaled to unit norm); their
  /// estimates are not to be trusted
  std::vector<std::string> unexcited;
  /// The full parameter vector (regressor_columns) a model written from the result holds: every
  /// body's pseudo-inertia positive definite; its base parameters the estimate when a physical
  /// model has them (else the nearest ones a physical model has, in the data's own metric); and
  /// among those the one closest to the prior (Lee and Park's geodesic distance between each
  /// body's pseudo-inertias, plus ((p - p0) / scale)^2 for armature, damping and gains). Massless
  /// bodies stay massless; a known body keeps its known parameters.
  Eigen::VectorXd parameters;
  /// (rank) K parameters: the base parameters of the written model
  Eigen::VectorXd physical_estimate;
  /// true when the least-squares estimate itself is a physical model's (physical_estimate equals
  /// it to 1e-10 of the fit's scale); false when the constraint moved the fit
  bool estimate_physical = true;
  /// the residual's rms with physical_estimate instead of the estimate (>= residual_rms)
  double physical_residual_rms = 0.0;
  /// (nbody) each body's geodesic distance from the prior's pseudo-inertia (0 for the world, a
  /// massless or a known body)
  std::vector<double> distance_to_prior;
  /// empty when `parameters` is a physical model; else why not (e.g. a negative damping)
  std::string not_physical;
};

/// Least squares on the base regressor. Throws lever::Error when the trajectory does not fit the
/// prior (sizes), has fewer equations than base parameters plus one, lacks the ctrl that
/// estimating a gain needs, or when gains are estimated and nothing in the data is known in
/// absolute terms (all remaining forces zero: then the gains and the inertia scale together and
/// no data can separate them; keep one actuator's gain known).
Result identify(const Model& prior, const Trajectory& data, const Options& options = {});

/// The actuator named `name` (its name, or #index as `lever simulate` writes it) among those with
/// a gain column, or every one of them for "all". Throws lever::Error for a name that is not an
/// actuator or whose gain is not fixed.
std::vector<int> gain_actuators_named(const Model& prior, const std::string& names);

/// Parse `BODY=KG` (a body's name, or #index) into Options::known_masses' entry. Throws
/// lever::Error for an unknown body, a mass that is not a positive number, or a body without mass
/// in the prior (whose shape is then unknown).
std::pair<int, double> known_mass_named(const Model& prior, const std::string& text);

/// The prior with the result's parameters (inertials, armature, damping, gains), set_const applied.
/// Throws ModelError if they are not physical (result.not_physical says why beforehand).
Model identified_model(const Model& prior, const Result& result);

/// Write the MJCF file `prior_path` again with the identified model's inertials, armature,
/// damping and actuator gains where they differ from the file's, everything else as written
/// (lever::mjcf::write_file, lever/mjcf/write.hpp, says how each is written).
/// Throws lever::Error (or mjcf::ParseError) if the file cannot be read or written, does not
/// match the model, or cannot say it; out_path is then left as it was.
void write_model(const std::string& prior_path, const Model& identified,
                 const std::string& out_path);

}  // namespace lever::identify
