// lever/diff/twin.hpp: one model file loaded into lever and into MuJoCo 2.2.2, side by side.
#pragma once

#include <mujoco/mujoco.h>

#include <lever/data.hpp>
#include <lever/model.hpp>
#include <string>
#include <vector>

#include <lever/harness/from_mujoco.hpp>
#include <lever/harness/random_state.hpp>

namespace lever::diff {

/// Where lever's Model comes from. MuJoCo always compiles the file itself.
enum class Path {
  kLoader,  ///< lever::mjcf::load_file: what users get (compiler and engine together)
  kEngine,  ///< from_mujoco: MuJoCo's compiled parameters (the engine alone)
};

/// "loader" or "engine".
const char* path_name(Path path);
/// One line saying what the path compares.
const char* path_description(Path path);

/// Write state s into MuJoCo's data, with the warm start cleared as after mj_resetData.
void set_mujoco_state(const mjModel* m, mjData* d, const test::State& s);

/// How far d->qacc is from the minimizer of the problem MuJoCo solves, by MuJoCo's own gradient:
/// |M^-1 (M (qacc - qacc_smooth) - J' efc_force(J qacc - aref))|, relative to max(1, |qacc|).
/// Zero at the minimizer but for rounding. Leaves d as it found it.
double mujoco_distance_to_minimizer(const mjModel* m, mjData* d);
/// MuJoCo's answer counts as stuck short of the minimizer when mujoco_distance_to_minimizer
/// exceeds this: a hundredth of the solver's bound (1e-10). At the minimizer rounding leaves
/// 1e-14 to 1e-12 (measured on legged_elliptic.xml, 40000 forwards).
inline constexpr double kStalled = 1e-12;

/// The inputs mj_forward writes back into: mj_kinematics normalizes the quaternions of qpos (ball
/// and free joints) and mocap_quat in place, and a unit quaternion normalized once more can move
/// in its last bit (normalizing twice can alternate between two roundings). Where the contacts are
/// discontinuous in the state, that bit decides MuJoCo's answer: at a random state of ANYmal B
/// with its legs deep in its body, one ulp of the base quaternion adds a seventh contact between
/// two boxes and moves qacc by 65. So a forward the harness repeats (a restart of MuJoCo's solver,
/// mj_step after a converged forward) starts from the inputs the first forward was given, as
/// lever's single forward and step do.
class ForwardInputs {
 public:
  /// Saves d's qpos and mocap_quat.
  ForwardInputs(const mjModel* m, const mjData* d);
  /// Writes them back into d.
  void restore(mjData* d) const;

 private:
  std::vector<double> qpos_, mocap_quat_;
};

/// mj_forward on (m, d), restarted from its own answer while that moves it, and from a cold start
/// where it is still short of the minimizer by its own gradient (Twin::mujoco_forward). Every
/// restart starts from the qpos and mocap_quat the first forward was given (ForwardInputs).
void mujoco_forward_converged(const mjModel* m, mjData* d, bool restart_solver);
/// After a forward on (m, d) from `given`: MuJoCo's solver restarted from its own answer while
/// that moves it, and from a cold start where it is still short of the minimizer by its own
/// gradient (the answer nearer to it kept), each restart a forward from `given`. The rest of
/// mujoco_forward_converged.
void converge_mujoco_solver(const mjModel* m, mjData* d, const ForwardInputs& given);
/// mj_step; with restart_solver, its forward warm-started from the converged answer, so that the
/// step starts from the minimizer rather than where MuJoCo's solver stopped, and from the state
/// d held before (ForwardInputs), as mj_step alone would start.
void mujoco_step_converged(const mjModel* m, mjData* d, bool restart_solver);

/// lever and MuJoCo on the same model file. MuJoCo's energy computation is switched on.
class Twin {
 public:
  /// Throws (lever::Error, std::runtime_error) if either side cannot load the file, or if the
  /// two compiled models differ in their sizes.
  Twin(const std::string& file, Path path);

  const std::string& file() const { return file_; }
  Path path() const { return path_; }

  /// Use this integrator on both sides.
  void set_integrator(Integrator integrator);
  /// Use this friction cone and impratio on both sides (a model's elliptic variant).
  void set_cone(Cone cone, double impratio);
  /// mj_forward, then, with restart_mujoco_solver, mj_forward again warm-started from MuJoCo's
  /// own answer while that moves it by more than rounding (at most 20 times). MuJoCo's Newton solver compares costs,
  /// and where the cost is large (1e5) it stops when a further decrease no longer shows in it,
  /// short of the minimizer with elliptic cones; a restart lets its line search start afresh.
  /// Where MuJoCo's own gradient (M^-1 times it) still puts the answer more than 1e-12 away, a
  /// cold start (from qacc_smooth) too, and the answer with the smaller gradient is kept.
  void mujoco_forward();
  /// On by default where MuJoCo's solver can stop short: a model with contacts and elliptic
  /// cones solved by Newton (or CG, which the twin runs as Newton; set_cone sets it again).
  /// The twin runs MuJoCo at tolerance 0 (and lever too) where the solver decides contacts,
  /// equality constraints or friction loss, and MuJoCo's CG as its Newton solver there: the
  /// minimizer does not depend on the method, and CG stalls short of it.
  bool restart_mujoco_solver = false;

  /// Write the same state into both; both warm starts are cleared, as after mj_resetData.
  void set_state(const test::State& s);
  /// Copy MuJoCo's current state (time, qpos, qvel, ctrl, act, qfrc_applied, qacc_warmstart) into
  /// lever.
  void follow_mujoco();
  /// Reset both to the start of a run: the start keyframe (the model's first unless
  /// start_from_key() chose another; lever's reset_keyframe against mj_resetDataKeyframe), else,
  /// for a model without keyframes, as mj_resetData does.
  void reset();
  /// Start runs from the keyframe called `key`. Throws StateError, listing the model's
  /// keyframes, if it has none of that name (and changes nothing).
  void start_from_key(const std::string& key);
  /// The name of the state reset() starts from: "keyframe 'NAME'" or "rest at qpos0".
  std::string start_name() const;

  lever::Model model;
  lever::Data data;
  test::MjModelPtr m;
  test::MjDataPtr d;

 private:
  Twin(const std::string& file, Path path, test::MjModelPtr mj);
  bool mujoco_solver_stops_short() const;
  std::string file_;
  Path path_;
  int start_key_ = -1;  // the keyframe reset() starts from; -1: rest at qpos0
};

}  // namespace lever::diff
