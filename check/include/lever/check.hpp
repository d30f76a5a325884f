// lever/check.hpp: lesson 5.1's six checks of a robot model and lesson 5.2's two more (eight), for
// any model of the subset. The
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
//   (6) clamping: commands beyond ctrlrange, and motors that cannot hold their own arm;
//   (7) singular poses: the site Jacobian's singular values over the joint ranges, at qpos0 and the
//       keyframes, and which joint axes align there;
//   (8) stability of the step: the spectral radius of the step's linearisation for the model's
//       integrator and for explicit Euler, the largest stable timestep, the armature Euler needs.
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
  std::string type = "hinge";                      ///< hinge, slide, ball or free
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
  /// A servo (force = gain ctrl + bias(length, velocity)): ctrl is a target position, and the
  /// joint torque it can give is gear x forcerange (motor_torque_range in util.hpp).
  bool servo = false;
  double kp = 0.0, kv = 0.0;  ///< a position servo's stiffness -biasprm[1] and damping -biasprm[2]
  std::array<double, 3> gainprm{0.0, 0.0, 0.0}, biasprm{0.0, 0.0, 0.0};  ///< first three
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
  // servos only (servo == false for motors): a position servo holds the worst pose off its target
  bool servo = false;           ///< driven by a servo: ctrl is a target, the limit its forcerange
  double stiffness = 0.0;       ///< sum of gear^2 kp of its servos, N m/rad
  double sag = 0.0;             ///< |worst_torque| / stiffness: the target-to-pose offset, rad
  double hold_target = 0.0;     ///< ctrl that holds the worst pose (one servo on the joint)
  bool target_outside = false;  ///< that ctrl lies outside the servo's ctrlrange
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
  /// the runs hold ctrl at 0, which is zero torque for a motor but a target for a servo: the
  /// joints whose position servos hold them at a target of 0 in every run, each with the target:
  /// "shoulder (0 rad)", "slider (0 m)"
  std::vector<std::string> servo_held_joints;
};

// ---- (6) clamping -------------------------------------------------------------------------------

struct Clamping {
  Eigen::VectorXd ctrl, actuator_force;
  int warnings = 0;  ///< engine warnings raised by forward() (there are none for clamping)
  std::vector<std::string> unbounded;  ///< motors with ctrllimited="false"
  bool newton_metres = false;  ///< every motor drives a hinge with gear 1: forces are in N m
  // servos (ctrl is a target): the command clamped to ctrlrange, the force that target asks for at
  // qpos0 and rest (gain target + bias) and what forcerange lets through (actuator_force)
  std::vector<uint8_t> servo;         ///< (nu) which actuators are servos
  Eigen::VectorXd target, raw_force;  ///< (nu) ctrl clamped to ctrlrange; gain target + bias
  Eigen::VectorXd qpos;               ///< the pose forward() ran at (qpos0)
  bool any_servo() const;
};

// ---- (7) singular poses
// --------------------------------------------------------------------------

/// Two joints whose world axes are parallel (and collinear: on one line) at a pose.
struct JointAlignment {
  std::string first, second;
  bool collinear = false;
  double angle = 0.0;     ///< between the axes (or the axis and its reverse), rad
  double distance = 0.0;  ///< between the axis lines, m (collinear when ~0)
};

/// The site Jacobian at one pose: its singular values in the rows the arm can move in.
struct JacobianAt {
  std::string where;  ///< "qpos0", "keyframe home", "worst 1", ...
  Eigen::VectorXd q;
  Eigen::VectorXd sigma;        ///< the task space's singular values, descending (rank of them)
  double manipulability = 0.0;  ///< their product: sqrt(det(J J^T)) when rows == rank
  double condition = kInf;      ///< sigma_max / sigma_min
  Eigen::VectorXd null_motion;  ///< unit joint velocity that moves the site least (nv)
  std::vector<JointAlignment> aligned;
};

struct SiteSingularity {
  std::string site;
  int rows = 6;  ///< 6: [jacp; jacr] (nv >= 6); 3: jacp (fewer joints than 6)
  int rank = 0;  ///< its rank at generic poses: the number of singular values that count
  std::vector<JacobianAt> states;  ///< qpos0 and each keyframe
  std::vector<JacobianAt> worst;   ///< the most singular poses found, least sigma_min first
};

struct SingularPoses {
  std::string search;  ///< how the worst poses were searched
  long evaluations = 0;
  double parallel_tolerance = 1e-3;  ///< rad, and m for collinear
  std::vector<SiteSingularity> sites;
};

// ---- (8) stability of the step
// -------------------------------------------------------------------

/// How a simulation from a state went: it settles (|qvel| dies out), keeps moving (a limit cycle:
/// an unstable step whose growth the forcerange clamp caps), or blows up (an engine warning, or
/// |qvel| past the bound).
struct StabilityRun {
  std::string integrator;
  std::string armature;  ///< "the model's", "x on every joint" or "per joint [..]"
  int steps = 0;
  double max_qvel = 0.0;
  double final_qvel = 0.0;  ///< max |qvel| over the last tenth of the run
  int saturated = 0;        ///< steps where some actuator force sat on its forcerange
  int blowup_step = -1;     ///< first step with an engine warning or |qvel| > bound (-1: none)
  int warnings = 0;
  bool settled = false;  ///< no blow-up and final_qvel <= the settle bound
  bool bounded() const { return blowup_step < 0; }
};

/// Where the step's stability changes along one parameter (a timestep, or an armature), as a
/// search found it: stability evaluated on a log-spaced grid from `from` to `to` (an armature
/// search tries 0 first), and each change between two neighbouring points bisected until its two
/// sides are within a relative `resolution`. Stability need not change only once: each change the
/// grid shows is listed. A change narrower than the grid's spacing can be missed.
struct StabilityScan {
  double from = 0.0, to = 0.0;
  int points = 0;  ///< grid points evaluated
  /// relative width a change is bisected to: fine enough that the value's printed digits do not
  /// depend on how the grid's points round
  double resolution = 1e-9;
  bool stable_first = false;  ///< stability at the first point (0 for an armature, else `from`)
  /// each change of stability, ascending, given by its stable side s: the step is stable at s
  /// and not at s (1 + resolution) (a timestep going unstable) or s / (1 + resolution) (an
  /// armature becoming stable)
  std::vector<double> changes;
  /// true when stability changes more than once (the reported value then rests on a choice:
  /// the largest timestep below which every one is stable, the smallest armature above which
  /// every one is)
  bool several() const { return changes.size() > 1; }
};

struct StabilityAt {
  std::string where;  ///< "keyframe home" or "qpos0"
  Eigen::VectorXd qpos, qvel, ctrl;
  double growth = 0.0;     ///< max Re(eig) of the continuous linearisation d[qvel; qacc]/dx, 1/s
  double rho_model = 0.0;  ///< spectral radius of the model's step (its integrator)
  double rho_euler = 0.0;  ///< of explicit Euler's step at the same timestep
  bool stable_model = false, stable_euler = false;
  /// the largest timestep below which every timestep scanned is stable (0: unstable already at
  /// the scan's smallest; kInf: stable up to the cap)
  double max_dt_model = 0.0, max_dt_euler = 0.0;
  StabilityScan dt_scan_model, dt_scan_euler;  ///< the searches behind them
  /// armatures for explicit Euler at the model's timestep, each the smallest above which every
  /// armature scanned is stable (0: stable with none; kInf: unstable up to the cap):
  double armature_all = 0.0;           ///< the same on every joint
  std::vector<double> armature_each;   ///< per joint, the others at ample x armature_all
  double armature_floor = kInf;        ///< the least floor t with max(each_i, t) stable together
  std::vector<double> armature_alone;  ///< per joint, the others as in the model
  StabilityScan armature_scan_all, armature_scan_floor;  ///< the searches behind them
  std::vector<StabilityScan> armature_scan_each, armature_scan_alone;
  double rho_euler_with = 0.0;  ///< Euler's radius, margin x armature_all on every joint
  double rho_euler_each = 0.0;  ///< Euler's radius, margin x armature_each per joint
  bool stable_euler_each = false;
  std::vector<StabilityRun> runs;  ///< model as is, Euler without and with armature
  /// rho against the timestep (log-spaced, h/10 to 10 h), for the chart
  std::vector<double> sweep_dt, sweep_rho_model, sweep_rho_euler;
};

struct StepStability {
  double timestep = 0.0;
  std::string integrator;
  double fd_eps = 1e-6;          ///< central-difference step on [qpos; qvel]
  double slack = 1e-3;           ///< stable: rho <= max(1, exp(h growth)) (1 + slack)
  double dt_cap = 1.0;           ///< s: the timestep search stops here
  double dt_floor = 1e-3;        ///< the timestep search starts at this times the model's timestep
  double armature_start = 1e-6;  ///< kg m^2: the armature search's grid starts here (after 0)
  int points_per_decade = 10;    ///< grid density of the searches
  double armature_cap = 1e4;     ///< kg m^2: the armature search stops here
  double margin = 1.1;           ///< the simulation uses this times the smallest armature
  double qvel_bound = 1e3;       ///< a run blows up past this |qvel|
  double settle_qvel = 1e-3;     ///< a run settles when |qvel| stays below this over its last tenth
  double ample = 10.0;           ///< per joint: the other joints get this times armature_all
  std::vector<std::string> joints;
  std::vector<StabilityAt> states;
};

// ---- (9) contacts (lesson 5.3)
// -------------------------------------------------------------------

/// Two geoms that can touch: the filters passed (contype/conaffinity, not on one welded body, not
/// parent and child, no <exclude>) or named by a <pair>, with the parameters a contact between
/// them gets (mixed by priority, else max and solmix, as MuJoCo's driver; a <pair>'s own).
struct ContactPairInfo {
  std::string geom1, geom2;
  bool explicit_pair = false;  ///< from <contact><pair>
  int condim = 3;
  std::array<double, 3> friction{0, 0, 0};  ///< sliding, torsional, rolling
  std::array<double, 2> solref{0, 0};
  std::array<double, 5> solimp{0, 0, 0, 0, 0};
  double margin = 0.0, gap = 0.0;
  int seen = 0;        ///< contacts between them in the section's simulations
  bool agrees = true;  ///< each of those got these parameters
};

/// A free body resting on a plane: the depth the soft contact predicts against the simulation's.
/// At rest a = 0 and v = 0, so each row pushes f = D aref = K d(p) p / R with R = (1 - d)/d A:
/// n_contacts n_rows K d(p)^2 p / ((1 - d(p)) A) = m g_n, solved for the depth p by bisection.
struct RestingDepth {
  std::string skipped;  ///< why it was not computed ("": computed)
  std::string body, plane, start;
  double mass = 0.0, gravity = 0.0;  ///< kg; the component of gravity along the plane's normal
  int condim = 3, contacts = 0, rows = 0;  ///< contacts at rest; rows per contact
  bool elliptic = false;  ///< elliptic cones: one normal row per contact carries the weight
  double friction = 0.0, impratio = 1.0;
  std::array<double, 2> solref{0, 0};
  std::array<double, 5> solimp{0, 0, 0, 0, 0};
  double K = 0.0;          ///< 1 / (dmax^2 timeconst^2 dampratio^2), 1/s^2
  double invweight = 0.0;  ///< t: the two bodies' translational body_invweight0, 1/kg
  double A = 0.0;  ///< a row's approximate inverse inertia: t (normal row), or 2 mu^2 (1+mu^2)
                   ///< t/impratio (pyramid edge)
  double predicted = 0.0;      ///< m
  double impedance = 0.0;      ///< d(predicted)
  double simulated = 0.0;      ///< m: the contacts' mean depth at rest
  double spread = 0.0;         ///< m: deepest minus shallowest contact at rest
  double time = 0.0;           ///< s simulated
  double final_speed = 0.0;    ///< max |qvel| of the body at the end
  double settle_speed = 1e-9;  ///< m/s (rad/s): at rest below this
  double time_bound = 20.0;    ///< s of simulation at most
  bool settled = false;
  int unsupported = 0;  ///< warnings of geom pairs lever cannot collide coming near, in the run
  double bound = 0.0;   ///< |simulated - predicted| allowed, m (how it is reasoned: check.md)
  bool agrees() const { return settled && std::abs(simulated - predicted) <= bound; }
};

/// One trial of the grip: the fingers close on the box without gravity, then gravity acts.
struct GripTrial {
  double command = 0.0;       ///< the fingers' servo target (each finger's closing direction)
  double closed_force = 0.0;  ///< N: the fingers' servo force once closed (mean of the fingers)
  double force = 0.0;  ///< N: the same, averaged over the second half of the hold (the judged one)
  double drop = 0.0;   ///< m: how far the box fell while gravity acted
  double speedup = 0.0;  ///< m/s: its falling speed at the end minus at half the hold
  bool slipped = false;
};

/// A touch sensor on a finger (its site on a body that moves with the finger's joint) at the full
/// grip: the normal force it reads against what the finger's servo pushes. At rest the finger's
/// slide balances the servo against the box's push along it, so a pad that covers the contacts
/// reads the servo's force (cos of the normal's tilt from the slide, and the damping of a finger
/// still moving, are what separate them).
struct GripPad {
  std::string sensor, finger;  ///< the touch sensor, the finger servo
  double closed = 0.0;         ///< N: the sensor, closed without gravity
  double servo_closed = 0.0;   ///< N: |actuator_force| of the finger's servo then
  double held = 0.0;           ///< N: the sensor, mean over the second half of the hold
  double servo_held = 0.0;     ///< N: the servo, the same
  double tolerance = 0.01;     ///< relative: |sensor - servo| <= this x servo, closed and held
  bool agrees() const {
    return std::abs(closed - servo_closed) <= tolerance * servo_closed &&
           std::abs(held - servo_held) <= tolerance * servo_held;
  }
};

/// Two fingers pressing with force F hold a box of mass m when 2 mu F >= m g.
struct Grip {
  std::string skipped;  ///< why it was not computed ("": computed)
  std::string body;
  std::vector<std::string> fingers;  ///< the finger servos
  double mass = 0.0, gravity = 0.0, mu = 0.0;
  double needed = 0.0;        ///< N: m g / (2 mu)
  double servo_force = 0.0;   ///< N: the fingers' servo force at the command that closes most
  double servo_kp = 0.0;      ///< N/m (N m/rad): their stiffness
  double full_command = 0.0;  ///< that command (the end of ctrlrange towards the box)
  double touch = 0.0;         ///< the finger position holding the box at that command
  double close_time = 0.3, hold_time = 0.2;  ///< s: each trial's two phases
  double servo_force_closed = 0.0;           ///< N: measured at the full command once closed
  /// m/s: a box whose falling speed grows by more than this over the second half of the hold
  /// slips. A held box creeps (the soft friction rows are dampers: it sinks at a steady speed);
  /// a box the friction cannot hold accelerates at g (1 - F/F_needed): 0.005 m/s in 0.1 s is a
  /// shortfall of 0.5 % of the weight.
  double speedup_threshold = 0.005;
  double fall = 0.05;  ///< m: a drop beyond this is a slip too (the box left the fingers)
  double creep = 0.0;  ///< m: the drop at the full command
  std::vector<GripTrial> trials;  ///< in the order run: full, then lowered, then bisected
  double hold_force = kInf;       ///< N: the least force that held (kInf: none held)
  double slip_force = 0.0;        ///< N: the largest force that slipped (0: none slipped)
  double resolution = 0.01;       ///< the bisection stops at this relative width
  std::vector<GripPad> pads;      ///< the fingers' touch sensors, at the full grip
  bool holds_by_hand() const { return servo_force >= needed; }
};

struct Contacts {
  std::string skipped;  ///< why the section does not apply ("": it does)
  std::vector<ContactPairInfo> pairs;
  RestingDepth rest;
  Grip grip;
  std::vector<std::string> strays;  ///< "geom a and geom b": contacts of pairs not listed
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
  SingularPoses singular;
  StepStability stability;
  Contacts contacts;
  /// the model's ball and free joints ("": none): sections (2), (3), (5), (7) and (8) vary each
  /// joint as a hinge or slide over its range and are skipped for such a model (skipped())
  std::string floating_joints;
  /// why section `n` was not run ("": it was)
  std::string skipped(int section) const;
  std::vector<std::string> findings;  ///< claims that do not check out
  int exit_status() const { return findings.empty() ? 0 : 1; }
};

/// The model as loaded, and the same file loaded again with every mass inferred from its geoms
/// (or why that failed).
struct Inputs {
  const Model& model;
  const Model* inferred = nullptr;
  std::string inferred_error;
  std::string key;  ///< sections (7) and (8) at this keyframe only ("": qpos0 and every keyframe)
};

/// Run the checks (lesson 5.1's six, lesson 5.2's two, lesson 5.3's contacts).
Report run_check(const Inputs& inputs);

// the sections, each in its own file
Structure check_structure(const Model& model);
Kinematics check_kinematics(const Model& model);
TorqueBudget check_torque_budget(const Model& model);
Inertia check_inertia(const Inputs& inputs, const TorqueBudget& budget);
SoftStops check_soft_stops(const Model& model);
Clamping check_clamping(const Model& model);
/// `key`: only that keyframe (besides qpos0 in (7)); "": every keyframe. An unknown key throws
/// StateError listing the model's keyframes.
SingularPoses check_singular_poses(const Model& model, const std::string& key = "");
StepStability check_step_stability(const Model& model, const std::string& key = "");
/// (9): the pairs that can touch, a free body resting on a plane, the grip of two finger servos.
Contacts check_contacts(const Model& model);

/// The step's linearisation d[qpos'; qvel']/d[qpos; qvel] by central differences of lever::step
/// at (qpos, qvel, ctrl), and its spectral radius (the tools section (8) is built from).
Eigen::MatrixXd step_linearisation(const Model& model, const Eigen::VectorXd& qpos,
                                   const Eigen::VectorXd& qvel, const Eigen::VectorXd& ctrl,
                                   double eps = 1e-6);
double spectral_radius(const Eigen::MatrixXd& A);

/// Load a model file and run the eight checks on it: the model as written, and the same file again
/// with every mass inferred from its geoms for section (4). Throws lever::Error (mjcf::ParseError)
/// when the file cannot be loaded as written.
Report check_file(const std::string& path, const std::string& key = "");

/// Run the eight checks on a model already loaded. Section (4) reloads `model.source` with inertias
/// inferred from the geoms when the model came from a file; a model built in memory gets the
/// reason in `inertia.inferred_error` instead.
Report check_model(const Model& model, const std::string& key = "");

// ---- output (renderers: the report itself holds every number) ----------------------------------
std::string to_text(const Report& report);
void write_json(std::FILE* out, const Report& report);  ///< one JSON object, one line
std::string to_json(const Report& report);              ///< the same object, as text
std::string torque_budget_svg(const Report& report);
std::string singular_poses_svg(const Report& report);  ///< sigma_min at each state and worst pose
std::string step_stability_svg(const Report& report);  ///< spectral radii, Euler and the model's
std::string grip_svg(const Report& report);  ///< each grip trial's force and the box's drop

}  // namespace lever::check
