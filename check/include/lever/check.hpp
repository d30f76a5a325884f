// lever/check.hpp: lesson 5.1's six checks of a robot model, for any model of the subset. The
// library behind `lever check`, the Python package's `lever.check` and the browser build.
//
// A model is a list of claims (joints, masses, motor limits, sites); `run_check` tests each one
// against an independent calculation and collects what does not check out as findings:
//   (1) structure: what the compiled model contains;
//   (2) forward kinematics of every site against a chain of transforms built from the model's own
//       numbers, and against the closed-form planar formula where the site hangs from a planar
//       chain;
//   (3) the torque budget: worst-case gravity torque per joint, motor limit over it, payloads,
//       M(q) and the acceleration the spare torque gives;
//   (4) explicit inertias against those inferred from the geoms, and geoms that add mass unseen;
//   (5) soft joint stops: rest on each stop gravity can load, measure how far past it;
//   (6) clamping: commands beyond ctrlrange, and motors that cannot hold their own arm.
// Every number is computed by the engine (or by the independent formulas below); none is typed in.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <lever/model.hpp>

namespace lever::check {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- (1) structure -----------------------------------------------------------------------------

struct JointInfo {
  std::string name;
  bool hinge = true;
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();  ///< as in the model: the body frame
  std::array<double, 2> range{0.0, 0.0};
  bool limited = false;
  double damping = 0.0, armature = 0.0, stiffness = 0.0;
  double qpos0 = 0.0;
};

struct MotorInfo {
  std::string name, joint;
  double gear = 1.0;
  std::array<double, 2> ctrlrange{0.0, 0.0}, forcerange{0.0, 0.0};
  bool ctrllimited = false, forcelimited = false;
  std::array<double, 2> joint_torque{0.0, 0.0};  ///< gear x (ctrlrange and forcerange)
};

struct BodyInfo {
  std::string name;
  double mass = 0.0;
  Eigen::Vector3d principal = Eigen::Vector3d::Zero();  ///< principal moments, ascending
  bool explicit_inertial = false;                       ///< from <inertial>, not from geoms
};

struct Structure {
  std::vector<JointInfo> joints;
  std::vector<MotorInfo> motors;
  std::vector<std::string> sites, site_bodies;
  std::vector<BodyInfo> bodies;  ///< every body but the world
};

// ---- (2) forward kinematics ---------------------------------------------------------------------

/// A site that hangs from a chain of hinges with parallel axes: the closed-form planar formula.
struct PlanarChain {
  std::vector<std::string> joints;  ///< root to tip
  std::vector<int> joint_ids;       ///< the same, as joint indices
  std::vector<double> signs;        ///< +1 where a joint's axis is along normal, -1 against
  Eigen::Vector3d normal, u, w;     ///< rotation axis and the in-plane basis (w = normal x u)
  Eigen::Vector3d origin;           ///< first joint's anchor at qpos0, world frame
  std::vector<double> lengths;      ///< in-plane length of each link (last: to the site), m
  std::vector<double> angles0;      ///< its in-plane direction at qpos0, from u towards w, rad
  double offset = 0.0;              ///< constant component along the normal, m
  double max_error = 0.0;           ///< max |site_xpos - formula| over the poses, m
};

struct SiteKinematics {
  std::string site;
  double max_error_transforms = 0.0;  ///< max |site_xpos - chain of transforms|, m
  std::optional<PlanarChain> planar;
};

struct Kinematics {
  int poses = 0;
  std::vector<SiteKinematics> sites;
};

// ---- (3) torque budget --------------------------------------------------------------------------

struct JointBudget {
  std::string joint;
  bool hinge = true;
  double worst_torque = 0.0;   ///< qfrc_bias at rest at the worst pose (signed)
  Eigen::VectorXd worst_pose;  ///< qpos where |qfrc_bias| of this joint is largest
  bool loaded = true;          ///< false: gravity never loads this joint
  std::vector<std::string> motors;
  std::array<double, 2> torque_range{0.0, 0.0};  ///< joint torque the motors can produce
  double limit = 0.0;             ///< the bound on the side that holds the arm up (kInf: none)
  double ratio = kInf;            ///< limit / |worst_torque|
  double spare = 0.0;             ///< limit - |worst_torque|
  double acceleration = 0.0;      ///< spare / M_ii, signed, the other joints held rigid
  Eigen::VectorXd rigid_torques;  ///< M_ji acceleration + tau_g,j: holding joint j rigid (nv)
  bool actuated() const { return !motors.empty(); }
};

/// The largest point payload at a site that each motor can hold at its joint's worst pose.
struct SitePayload {
  std::string site;
  std::vector<double> per_joint;  ///< kg; kInf: the joint does not carry it; NaN: unactuated
  double min = kInf;
  int binding_joint = -1;
};

/// M(q) at a pose that is some joints' worst pose.
struct PoseInertia {
  Eigen::VectorXd q;
  Eigen::MatrixXd M;
  std::vector<int> joints;
};

struct TorqueBudget {
  int formula_poses = 0;
  double formula_max_error = 0.0;  ///< max |qfrc_bias - gravity formula| at rest, N m
  std::string search;              ///< how the worst poses were searched
  long evaluations = 0;            ///< qfrc_bias evaluations the search made
  double gravity = 0.0;            ///< |opt.gravity|
  std::vector<JointBudget> joints;
  std::vector<SitePayload> payload;
  std::vector<PoseInertia> poses;
};

// ---- (4) inertia --------------------------------------------------------------------------------

struct BodyInertia {
  std::string name;
  bool explicit_inertial = false;
  double mass = 0.0, inferred_mass = 0.0;
  Eigen::Vector3d principal = Eigen::Vector3d::Zero(), inferred_principal = Eigen::Vector3d::Zero();
};

struct JointTorqueInferred {
  std::string joint;
  double explicit_torque = 0.0, inferred_torque = 0.0;  ///< at the joint's worst pose
};

/// A geom that adds mass although it does not collide (visual only).
struct VisualMass {
  std::string geom, body;
  int group = 0;
  double mass = 0.0;
};

struct Inertia {
  bool inferred_available = false;
  std::string inferred_error;  ///< why the model could not be inferred from its geoms
  std::vector<BodyInertia> bodies;
  std::vector<JointTorqueInferred> torques;
  std::array<int, 2> inertiagrouprange{0, 5};
  std::vector<std::string> bodies_without_inertial;  ///< with mass, all of it from geoms
  std::vector<VisualMass> visual_mass;
  // the lesson's demonstration: 1 kg colliding box + 2 kg non-colliding geom in group 3
  double demo_default_mass = 0.0, demo_narrow_mass = 0.0;
  std::array<int, 2> demo_default_range{0, 5}, demo_narrow_range{0, 2};
};

// ---- (5) soft stops -----------------------------------------------------------------------------

struct StopRest {
  std::string joint;
  int joint_id = -1;
  bool hinge = true;
  bool upper = false;       ///< which stop
  double stop = 0.0;        ///< its position
  double margin = 0.0;      ///< the joint's limit margin: the row acts this far before it
  bool loadable = false;    ///< gravity pushes the joint into it at some pose tried
  bool from_qpos0 = false;  ///< started from qpos0 (the lesson's run)
  Eigen::VectorXd start;    ///< qpos the run started from
  double time = 0.0;        ///< simulated seconds in all
  double relax_time = 0.0;  ///< of which relaxing (quenched, undamped), to settle sooner
  bool settled = false;
  double max_qvel = 0.0;       ///< at the end
  bool rests_on_stop = false;  ///< a limit row of this joint holds it at the end
  double q = 0.0;              ///< final position of the joint
  double past = 0.0;           ///< how far past the stop (rad or m; > 0: past it)
  int rows = 0;                ///< limit rows at the end (data.nefc)
  double qfrc_constraint = 0.0, qfrc_bias = 0.0;  ///< of this joint, at the end
  double qfrc_passive = 0.0;                      ///< its spring (and damping), at the end
  Eigen::VectorXd final_qpos;
  int warnings = 0;  ///< engine warnings during the run
};

struct SoftStops {
  double settle_qvel = 1e-6;  ///< rad/s (or m/s)
  double settle_time = 1.0;   ///< s the velocities must stay below it
  double relax_qvel = 1e-3;   ///< rad/s (or m/s): relaxed enough to finish with a static solve
  double relax_bound = 30.0;  ///< s of relaxation, at most
  double time_bound = 120.0;  ///< s with the model's own damping, at most
  int runs = 0;               ///< simulations (stops that start from the same pose share one)
  std::vector<StopRest> stops;
};

// ---- (6) clamping -------------------------------------------------------------------------------

struct Clamping {
  Eigen::VectorXd ctrl, actuator_force;
  int warnings = 0;  ///< engine warnings raised by forward() (there are none for clamping)
  std::vector<std::string> unbounded;  ///< motors with ctrllimited="false"
  bool newton_metres = false;  ///< every motor drives a hinge with gear 1: forces are in N m
};

// ---- the report ---------------------------------------------------------------------------------

struct Report {
  std::string model, source;
  Structure structure;
  Kinematics kinematics;
  TorqueBudget budget;
  Inertia inertia;
  SoftStops stops;
  Clamping clamping;
  std::vector<std::string> findings;  ///< claims that do not check out
  int exit_status() const { return findings.empty() ? 0 : 1; }
};

/// The model as loaded, and the same file loaded again with every mass inferred from its geoms
/// (or why that failed).
struct Inputs {
  const Model& model;
  const Model* inferred = nullptr;
  std::string inferred_error;
};

/// Run the six checks.
Report run_check(const Inputs& inputs);

// the sections, each in its own file
Structure check_structure(const Model& model);
Kinematics check_kinematics(const Model& model);
TorqueBudget check_torque_budget(const Model& model);
Inertia check_inertia(const Inputs& inputs, const TorqueBudget& budget);
SoftStops check_soft_stops(const Model& model);
Clamping check_clamping(const Model& model);

/// Load a model file and run the six checks on it: the model as written, and the same file again
/// with every mass inferred from its geoms for section (4). Throws lever::Error (mjcf::ParseError)
/// when the file cannot be loaded as written.
Report check_file(const std::string& path);

/// Run the six checks on a model already loaded. Section (4) reloads `model.source` with inertias
/// inferred from the geoms when the model came from a file; a model built in memory gets the
/// reason in `inertia.inferred_error` instead.
Report check_model(const Model& model);

// ---- output (renderers: the report itself holds every number) ----------------------------------
std::string to_text(const Report& report);
void write_json(std::FILE* out, const Report& report);  ///< one JSON object, one line
std::string to_json(const Report& report);              ///< the same object, as text
std::string torque_budget_svg(const Report& report);

}  // namespace lever::check
