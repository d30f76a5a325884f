// lever/model.hpp: the compiled model, constant while a simulation runs.
//
// Every array that has a MuJoCo 2.2.2 counterpart keeps mjModel's name, index order and meaning
// (`body_pos`, `jnt_range`, `dof_damping`, ...), so a student can read the two side by side.
// Quaternions are (w, x, y, z); 3-vectors and 3x3 matrices are expressed in the frame named in
// each field's comment. Index 0 of every body array is the world body.
//
// The model has two parts:
//   1. the parameters, filled by a compiler (mjcf_lite) or by hand;
//   2. what `set_const()` derives from them: the constants MuJoCo's mj_setConst freezes at qpos0
//      (`dof_invweight0`, `dof_M0`, `body_invweight0`, `body_subtreemass`), and a few constant
//      rotation matrices and flags that spare the algorithms repeated work.
// After editing any parameter, call `lever::set_const(model)` before evaluating it again. Every
// array lives in the model's one block (see Model below): its length follows from the counts, and
// changing a count means calling `lever::size_model(model)` (lever/fields.hpp) again.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <lever/arena.hpp>
#include <lever/spatial.hpp>

namespace lever {

/// Joint types; the numeric values are MuJoCo's mjtJoint.
enum class JointType : int { kFree = 0, kBall = 1, kSlide = 2, kHinge = 3 };

/// Coordinates (qpos entries) of a joint of this type: a free joint's position and quaternion, a
/// ball's quaternion, one number for a hinge or a slide.
constexpr int joint_nq(JointType type) {
  return type == JointType::kFree ? 7 : type == JointType::kBall ? 4 : 1;
}

/// Degrees of freedom (qvel entries) of a joint of this type: a quaternion's are three rates of
/// turn, about the body's own axes.
constexpr int joint_nv(JointType type) {
  return type == JointType::kFree ? 6 : type == JointType::kBall ? 3 : 1;
}

/// How a joint moves its body, as the kernels need to know it. set_const derives it from jnt_type
/// and jnt_axis so that a kernel dispatches once per joint and does only the arithmetic that
/// joint needs: a hinge about a coordinate axis of its body (arm2's -y, every Panda joint's z)
/// turns by a quaternion with two zero components, so half of its product is left out. Every
/// kernel reads a joint's coordinates at jnt_qposadr and its dofs at jnt_dofadr, so kinds whose
/// qpos is longer than their dofs (ball and free joints: a quaternion for three rotational dofs)
/// extend this list without changing the kernels' loops.
enum class JointKind : uint8_t {
  kHingeX,  ///< hinge about +-x of the body frame
  kHingeY,  ///< hinge about +-y
  kHingeZ,  ///< hinge about +-z
  kHinge,   ///< hinge about any other axis
  kSlide,   ///< slide along its axis
  kBall,    ///< ball: a unit quaternion (w, x, y, z), three rotational dofs about body axes
  kFree,    ///< free: position, then a quaternion; three translational dofs, then three rotational
};

/// How kinematics() places a constant frame (a body on its parent, a body's inertial frame, a
/// geom or a site on its body) at offset v and rotation B in its parent's frame (p, R): set_const
/// decides it once per frame, so that placing it does only the arithmetic it needs.
struct FramePlacement {
  /// The offset R v: nothing (v = 0), one column of R (v along one coordinate axis, `axis`; an
  /// arm's links mostly are), or the whole product.
  enum class Offset : uint8_t { kZero, kAlongAxis, kGeneral };
  /// The rotation R B: R itself (B = 1), R's columns moved and signed (B a quarter turn to within
  /// the rounding of its quaternion: column c of R B is sign[c] times column column[c] of R;
  /// MJCF's quat="1 1 0 0", a fromto along an axis), or the whole product. kinematics() takes
  /// only kNone's shortcut: it composes a quarter turn's quaternion as any other, so that the
  /// rounding of its 1/sqrt(2) lands in the last bit where MuJoCo's does.
  enum class Turn : uint8_t { kNone, kQuarter, kGeneral };
  Offset offset = Offset::kGeneral;
  uint8_t axis = 0;
  Turn turn = Turn::kGeneral;
  std::array<uint8_t, 3> column{0, 1, 2};
  std::array<double, 3> sign{1.0, 1.0, 1.0};
};

/// Integrators; the numeric values are MuJoCo's mjtIntegrator. kImplicit is MuJoCo 2.2.2's
/// `implicit`: implicit in every velocity-dependent force. kImplicitFast is MuJoCo 3's
/// `implicitfast` (mjINT_IMPLICITFAST; MuJoCo 2.2.2 has no such integrator): implicit in the
/// joint damping and the actuators' velocity terms only, not in the Coriolis and centrifugal forces.
enum class Integrator : int { kEuler = 0, kRK4 = 1, kImplicit = 2, kImplicitFast = 3 };

/// The integrator's name as MJCF writes it: "Euler", "RK4", "implicit" or "implicitfast".
constexpr const char* integrator_name(Integrator integrator) {
  switch (integrator) {
    case Integrator::kEuler: return "Euler";
    case Integrator::kRK4: return "RK4";
    case Integrator::kImplicit: return "implicit";
    case Integrator::kImplicitFast: return "implicitfast";
  }
  return "unknown";
}

/// Actuator gain, bias and activation-dynamics types; the numeric values are MuJoCo's mjtGain,
/// mjtBias and mjtDyn. An actuator with dynamics has an
/// activation act (data.act), which its force multiplies instead of ctrl: an integrator's rate is
/// ctrl, a filter's (ctrl - act) / dynprm[0], a muscle's MuJoCo's activation dynamics
/// (lever/dynamics.hpp muscle_activation_rate). A muscle's gain and bias are its force-length-
/// velocity and passive curves (muscle_gain, muscle_bias). The user types are the model's
/// callbacks' (Model::actuator_gain_callback, ..., MuJoCo's mjcb_act_gain, ...).
enum class GainType : int { kFixed = 0, kAffine = 1, kMuscle = 2, kUser = 3 };
enum class BiasType : int { kNone = 0, kAffine = 1, kMuscle = 2, kUser = 3 };
enum class DynType : int { kNone = 0, kIntegrator = 1, kFilter = 2, kMuscle = 3, kUser = 4 };

/// Number of activation-dynamics parameters per actuator (MuJoCo's mjNDYN).
inline constexpr int kDynParameters = 10;

/// Number of gain and bias parameters per actuator (MuJoCo's mjNGAIN, mjNBIAS).
inline constexpr int kGainParameters = 10;
inline constexpr int kBiasParameters = 10;

// ---- actuator kind ----------------------------------------------------------------
/// What an actuator's force law amounts to, decided once per actuator from its gain and bias
/// (set_const, actuator_kind_of), so that the checks, the lab, identification and the command
/// line ask one question instead of each testing the parameters its own way.
enum class ActuatorKind : uint8_t {
  kMotor,          ///< gain and bias independent of the joint's state: ctrl is a force
  kPositionServo,  ///< affine bias, biasprm[1] = -gainprm[0] != 0: kp (ctrl - length) + ...
  kVelocityServo,  ///< affine bias, biasprm[1] = 0, biasprm[2] = -gainprm[0] != 0: kv (ctrl - vel.)
  kGeneral,        ///< gain or bias depends on length or velocity, the bias not tied to the gain
};

/// The kind of an actuator with these types and parameters: a position or velocity servo when
/// its bias is tied to its gain as above, else kGeneral when gain or bias has a nonzero length or
/// velocity term, else kMotor.
ActuatorKind actuator_kind_of(GainType gaintype, const std::array<double, kGainParameters>& gainprm,
                              BiasType biastype,
                              const std::array<double, kBiasParameters>& biasprm);

/// Whether ctrl is a target rather than a force: every kind but a motor.
constexpr bool is_servo(ActuatorKind kind) { return kind != ActuatorKind::kMotor; }

// ---- sensors --------------------------------------------------------------------------------
/// Sensor types; the numeric values are MuJoCo 2.2.2's mjtSensor. lever evaluates every type
/// but user sensors (MuJoCo fills those from a callback), which the
/// compiler and validate() refuse by name.
enum class SensorType : int {
  kTouch = 0,
  kAccelerometer,
  kVelocimeter,
  kGyro,
  kForce,
  kTorque,
  kMagnetometer,
  kRangefinder,
  kJointPos,
  kJointVel,
  kTendonPos,
  kTendonVel,
  kActuatorPos,
  kActuatorVel,
  kActuatorFrc,
  kBallQuat,
  kBallAngVel,
  kJointLimitPos,
  kJointLimitVel,
  kJointLimitFrc,
  kTendonLimitPos,
  kTendonLimitVel,
  kTendonLimitFrc,
  kFramePos,
  kFrameQuat,
  kFrameXAxis,
  kFrameYAxis,
  kFrameZAxis,
  kFrameLinVel,
  kFrameAngVel,
  kFrameLinAcc,
  kFrameAngAcc,
  kSubtreeCom,
  kSubtreeLinVel,
  kSubtreeAngMom,
  kClock,
  kUser
};

/// The MJCF element of a sensor type ("touch", "framepos", ...).
const char* sensor_type_name(SensorType type);

/// What a sensor's numbers are (MuJoCo's mjtDataType): noise and cutoff treat them by it.
enum class SensorDataType : int { kReal = 0, kPositive, kAxis, kQuaternion };

/// The stage after which a sensor can be evaluated (MuJoCo's mjtStage).
enum class SensorStage : int { kNone = 0, kPosition, kVelocity, kAcceleration };

/// The kinds of object a sensor (or its reference frame) is attached to; the numeric values are
/// MuJoCo's mjtObj. kBody is a body's inertial frame (centre of mass, principal axes), kXBody its
/// own frame.
enum class ObjectType : int {
  kUnknown = 0,
  kBody = 1,
  kXBody = 2,
  kJoint = 3,
  kGeom = 5,
  kSite = 6,
  kCamera = 7,
  kTendon = 17,
  kActuator = 18
};

/// What a sensor of a type outputs and when, as MuJoCo 2.2.2's compiler sets it (a user
/// sensor's come from its element: dim 0 here).
struct SensorLayout {
  int dim;                 ///< numbers
  SensorDataType datatype;
  SensorStage stage;
  /// what it must be attached to: kSite, kJoint, kActuator, kBody (subtree sensors), kTendon;
  /// kXBody for a frame sensor (any of body, xbody, geom, site); kUnknown for the clock
  ObjectType object;
};
SensorLayout sensor_layout(SensorType type);

/// Whether lever knows sensors of this type (every type of MuJoCo 2.2.2's; user sensors are
/// evaluated by Model::sensor_callback, as MuJoCo's by mjcb_sensor).
bool sensor_type_supported(SensorType type);

/// Row-major matrix, for per-keyframe arrays (key_qpos is nkey x nq, as MuJoCo's).
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Geom types; the numeric values are MuJoCo's mjtGeom.
/// A mesh geom (kMesh): lever::mjcf reads its file only when it gives its body mass (then its
/// frame, size, mass and inertia are MuJoCo's, from the mesh); otherwise it is kept massless, with
/// its frame as written and size zero.
enum class GeomType : int {
  kPlane = 0,   ///< infinite in x and y of its frame (size: half-extents drawn, spacing)
  kHfield = 1,  ///< height field (never collides in lever: refused when it could)
  kSphere = 2,
  kCapsule = 3,
  kEllipsoid = 4,
  kCylinder = 5,
  kBox = 6,
  kMesh = 7
};

/// A neighbour in a mesh's hull graph with its point (Model::mesh_hull_neighbours): the hull
/// vertex's number, -1 at the end of a list, its vertex in the mesh's frame, and the length of
/// its own neighbour list (where the climb goes next, read with the point that sent it there).
struct HullNeighbour {
  double point[3];
  int vertex;
  int length;
};

/// Equality constraint types; the numeric values are MuJoCo's mjtEq (MuJoCo 2.2.2 refuses its
/// distance constraint). kTendon couples two tendons' lengths as kJoint couples two joints.
enum class EqualityType : int { kConnect = 0, kWeld = 1, kJoint = 2, kTendon = 3 };

/// What a tendon's path is made of (MuJoCo's mjtWrap). A fixed tendon's path is joints only (its
/// length a linear combination of their coordinates); a spatial tendon's runs through sites,
/// around spheres and cylinders, split by pulleys. lever computes both.
enum class WrapType : int { kNone = 0, kJoint = 1, kPulley = 2, kSite = 3, kSphere = 4, kCylinder = 5 };

/// How an actuator reaches the dofs (MuJoCo's mjtTrn): a joint (its gear in the joint's own frame,
/// or for ball and free joints in the parent's: kJointInParent), a slider-crank (a crank site
/// pulled by a rod of cranklength from a slider site moving along its z axis), a tendon, or a
/// site (a wrench at the site, in its frame; with a reference site, the length is the site's pose
/// in the reference's frame), or a body (MuJoCo's adhesion: no length; its moment is minus the
/// mean of the normal Jacobians of the contacts touching the body's geoms, so it is computed
/// after the contacts' rows, in the constraint room).
enum class TransmissionType : int {
  kJoint = 0,
  kJointInParent = 1,
  kSliderCrank = 2,
  kTendon = 3,
  kSite = 4,
  kBody = 5
};

/// Numbers per equality constraint in eq_data (MuJoCo's mjNEQDATA). What they mean by type:
///   connect: anchor in body 1's frame (0-2), the same point in body 2's frame at qpos0 (3-5);
///   weld:    anchor in body 2's frame (0-2), the relative pose of body 2 in body 1's frame:
///            position (3-5) and quaternion (6-9), torquescale (10);
///   joint:   polynomial coefficients (0-4): q1 - q1_0 = sum_k c_k (q2 - q2_0)^k.
/// The compiler's default leaves 1 at entries 1 and 10 of every type (as MuJoCo's).
inline constexpr int kEqualityData = 11;

/// Friction cones; the numeric values are MuJoCo's mjtCone.
enum class Cone : int { kPyramidal = 0, kElliptic = 1 };

/// Constraint solvers; the numeric values are MuJoCo's mjtSolver.
enum class Solver : int {
  kPGS = 0,     ///< MuJoCo's projected Gauss-Seidel on the dual, opt.iterations sweeps at most,
                ///< stopped by opt.tolerance (at tolerance 0 too)
  kCG = 1,      ///< MuJoCo's conjugate gradients, stopped by opt.tolerance and opt.iterations
  kNewton = 2,  ///< Newton's method: lever solves the problem exactly (tolerance not read)
};

/// MuJoCo's layouts of the constraint Jacobian (<option jacobian>); the numeric values are its
/// mjtJacobian. lever keeps its own layout whatever the option says, and sums each product with a
/// row in the order MuJoCo's layout sums it (sparse_jacobian), so that its last bits are MuJoCo's.
enum class JacobianLayout : int {
  kDense = 0,
  kSparse = 1,
  kAuto = 2,  ///< sparse from 60 dofs on (MuJoCo's mj_isSparse), else dense
};

/// The features <option><flag> switches off (MuJoCo's mjtDisableBit, the same bits): each set
/// bit of Options::disableflags removes what MuJoCo 2.2.2 removes.
enum DisableBit : int {
  kDisableConstraint = 1 << 0,    ///< the whole constraint stage: no rows, no contacts
  kDisableEquality = 1 << 1,      ///< equality constraint rows
  kDisableFrictionloss = 1 << 2,  ///< friction-loss rows (joints and tendons)
  kDisableLimit = 1 << 3,         ///< limit rows (joints and tendons)
  kDisableContact = 1 << 4,       ///< the collision stage and contact rows
  kDisablePassive = 1 << 5,       ///< springs, damping, the medium's forces
  kDisableGravity = 1 << 6,       ///< gravity (in qfrc_bias, cacc, the potential energy)
  kDisableClampctrl = 1 << 7,     ///< clamping ctrl to ctrlrange
  kDisableWarmstart = 1 << 8,     ///< PGS's warm start from qacc_warmstart (Newton and CG
                                  ///< start cold in lever: at tolerance 0 the answer is the same)
  kDisableFilterparent = 1 << 9,  ///< the broad phase's parent-child filter
  kDisableActuation = 1 << 10,    ///< actuator forces
  kDisableRefsafe = 1 << 11,      ///< solref[0] >= 2 timestep
  kDisableSensor = 1 << 12,       ///< the sensor stages (sensordata left as it was)
};
inline constexpr int kDisableBits = 13;  ///< MuJoCo's mjNDISABLE

/// The optional features <option><flag> switches on (MuJoCo's mjtEnableBit, the same bits).
enum EnableBit : int {
  kEnableOverride = 1 << 0,     ///< every contact takes opt.o_margin, o_solref, o_solimp
  kEnableEnergy = 1 << 1,       ///< forward() computes data.energy
  kEnableFwdinv = 1 << 2,       ///< step() compares forward and inverse dynamics (solver_fwdinv)
  kEnableSensornoise = 1 << 3,  ///< each sensor's noise is added
  kEnableMulticcd = 1 << 4,     ///< up to four more contacts per convex pair
};
inline constexpr int kEnableBits = 5;  ///< MuJoCo's mjNENABLE

/// The MJCF names of the flags, bit k of disableflags (enableflags) named by element k.
extern const char* const kDisableNames[kDisableBits];
extern const char* const kEnableNames[kEnableBits];

/// Simulation options (<option>).
struct Options {
  double timestep = 0.002;                   ///< s
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};  ///< m/s^2, world frame
  Integrator integrator = Integrator::kEuler;
  // contact: MuJoCo 2.2.2's <option> defaults
  Cone cone = Cone::kPyramidal;  ///< friction cone of contact rows
  double impratio = 1.0;         ///< frictional-to-normal impedance ratio (elliptic cones)
  Solver solver = Solver::kNewton;  ///< constraint solver (MuJoCo's default, Newton)
  int iterations = 100;   ///< most CG iterations or PGS sweeps (lever's Newton solve stops on
                          ///< convergence)
  double tolerance = 1e-8;  ///< CG's tolerance, on the cost's decrease and gradient, and PGS's,
                            ///< on a sweep's decrease (MuJoCo's)
  JacobianLayout jacobian = JacobianLayout::kAuto;  ///< MuJoCo's layout of the rows (its order
                                                    ///< of sums; see sparse_jacobian)
  // the general convex pairs' Minkowski portal refinement (MuJoCo 2.2.2's defaults)
  double mpr_tolerance = 1e-6;  ///< MPR's boundary tolerance
  int mpr_iterations = 50;      ///< most MPR iterations
  /// Earth's magnetic field, world frame (the magnetometer reads it in its site's frame)
  Eigen::Vector3d magnetic{0.0, -0.5, 0.0};
  // the medium the bodies move in: MuJoCo 2.2.2's passive fluid forces, each body replaced by the
  // box of its inertia (smooth/fluid.cpp); none while viscosity and density are both 0
  double viscosity = 0.0;                  ///< Pa s: Stokes drag on the box's mean-diameter sphere
  double density = 0.0;                    ///< kg/m^3: quadratic drag on the box's faces
  Eigen::Vector3d wind{0.0, 0.0, 0.0};     ///< m/s, world frame: the medium's own velocity
  // what every contact takes instead of its own with <flag override="enable"> (MuJoCo's defaults)
  double o_margin = 0.0;
  std::array<double, 2> o_solref{0.02, 1.0};
  std::array<double, 5> o_solimp{0.9, 0.95, 0.001, 0.5, 2.0};
  int disableflags = 0;  ///< DisableBit bits (<option><flag name="disable">)
  int enableflags = 0;   ///< EnableBit bits (<option><flag name="enable">)

  bool disabled(DisableBit bit) const { return (disableflags & bit) != 0; }
  bool enabled(EnableBit bit) const { return (enableflags & bit) != 0; }
};

/// Whether MuJoCo 2.2.2 holds this model's constraint Jacobian sparse (mj_isSparse): option
/// jacobian "sparse", or "auto" with 60 dofs or more. Its products with the rows then add each
/// row's stored entries one after another (mju_dotSparse, as Debian's libmujoco 2.2.2 is built,
/// without AVX) instead of in mju_dot's four running sums.
inline bool sparse_jacobian(const Options& opt, int nv) {
  return opt.jacobian == JacobianLayout::kSparse ||
         (opt.jacobian == JacobianLayout::kAuto && nv >= 60);
}

/// Whether the model's bodies feel MuJoCo 2.2.2's fluid forces (opt.viscosity or opt.density > 0).
inline bool has_fluid(const Options& opt) { return opt.viscosity > 0 || opt.density > 0; }

/// Compiler settings that stay meaningful after compilation (read by `lever check`).
struct CompilerInfo {
  std::array<int, 2> inertiagrouprange{0, 5};  ///< geom groups that contribute mass
  bool inertia_from_geoms_allowed = true;      ///< inertiafromgeom was not "false"
};

/// What a model file says that changes no dynamics (assets, lights, cameras, materials), kept so
/// that tools can show it. The engine never reads it.
struct VisualInfo {
  std::string meshdir, texturedir;                    ///< <compiler>, as written
  std::vector<std::string> mesh_name, mesh_file;      ///< <asset><mesh>; file "" if inline
  std::vector<std::string> material_name;             ///< <asset><material>
  std::vector<std::string> texture_name;              ///< <asset><texture>
  std::vector<std::string> light_name, camera_name;   ///< lights and cameras ("" if unnamed)
  std::vector<std::string> geom_mesh, geom_material;  ///< (ngeom) names, "" if none
};

struct Model;
struct Data;

/// What evaluates a model's user sensors (<sensor><user>), MuJoCo's mjcb_sensor: called after a
/// stage (kPosition, kVelocity, kAcceleration) in which the model has user sensors, to write their
/// numbers at sensor_adr in data.sensordata (noise and cutoff are applied after it). Without one,
/// their numbers stay as they are (zero in a new Data), as in MuJoCo.
using SensorCallback = std::function<void(const Model&, Data&, SensorStage)>;

/// What evaluates an actuator's user-defined part (gaintype, biastype or dyntype "user"), MuJoCo's
/// mjcb_act_gain, mjcb_act_bias and mjcb_act_dyn: the gain, the bias, or act_dot of actuator
/// `actuator`, from the model and the data as actuation() has them then (transmission, lengths and
/// velocities current; the forces of the actuators before it written; for act_dot, every force
/// and qfrc_actuator). Without one, MuJoCo's values: gain 1, bias 0, act_dot 0.
using ActuatorCallback = std::function<double(const Model&, const Data&, int actuator)>;

/// Model's members (Model below adds the block its arrays live in); fields are read as model.nq,
/// model.body_pos.
struct ModelFields {
  std::string name = "MuJoCo Model";  ///< <mujoco model="...">
  std::string source;                 ///< file the model came from ("" if built in memory)
  Options opt;
  CompilerInfo compiler;
  VisualInfo visual;
  /// What the compiler noticed that MuJoCo would simulate and lever does not (geom pairs that can
  /// collide and that lever has no contact function for), one sentence each; empty for a clean
  /// model.
  std::vector<std::string> warnings;

  // ---- sizes -------------------------------------------------------------------------------
  int nq = 0;         ///< generalized coordinates (a ball has 4 and a free joint 7: nq >= nv)
  int nv = 0;         ///< degrees of freedom
  int nu = 0;         ///< actuators
  /// activations: one per actuator with dynamics (dyntype not none), which come after the
  /// stateless ones; actuator a's is act[a - (nu - na)]
  int na = 0;
  int nbody = 1;      ///< bodies, world included
  int njnt = 0;       ///< joints
  int ngeom = 0;      ///< geoms
  int nsite = 0;      ///< sites
  int nkey = 0;       ///< keyframes
  int npair = 0;      ///< explicit contact pairs (<contact><pair>)
  int nexclude = 0;   ///< excluded body pairs (<contact><exclude>)
  int nmesh = 0;      ///< meshes (<asset><mesh>), each as MuJoCo compiles it if lever read it
  int nmeshvert = 0;  ///< their vertices, all meshes
  int nmeshgraph = 0;  ///< their convex hulls' graphs, all meshes (ints)
  int nmeshface = 0;   ///< their triangles, all meshes
  int nsensor = 0;      ///< sensors
  int nsensordata = 0;  ///< numbers all sensors output together (the sum of sensor_dim)
  int neq = 0;        ///< equality constraints (<equality>)
  int ntendon = 0;    ///< tendons (<tendon>)
  int nwrap = 0;      ///< objects in all tendons' paths (a fixed tendon's joints)
  int nmocap = 0;     ///< mocap bodies: children of the world without joints, placed by Data's
                      ///< mocap_pos and mocap_quat (MJCF's <body mocap="true">)
  // user data: numbers per object that the engine never reads (MJCF's `user`), each kind's rows
  // padded with zeros to its width (<size nuser_*>, else the longest list of the kind)
  int nuser_body = 0, nuser_jnt = 0, nuser_geom = 0, nuser_site = 0, nuser_tendon = 0,
      nuser_actuator = 0, nuser_sensor = 0;
  int nconmax = 100;  ///< most contacts a Data holds (<size nconmax>; MuJoCo 2.2.2's default)
  int njmax = 500;    ///< most constraint rows a Data holds (<size njmax>)

  // ---- bodies (nbody) ------------------------------------------------------------------------
  std::vector<std::string> body_name{"world"};
  ArenaArray<int> body_parentid;  ///< parent body; the world is its own parent
  ArenaArray<int> body_rootid;    ///< the world child this body hangs from
  ArenaArray<int> body_mocapid;  ///< its row of mocap_pos/mocap_quat, or -1 (in body order)
  ArenaArray<int> body_jntnum;    ///< joints of this body
  ArenaArray<int> body_jntadr;   ///< first joint, -1 if none
  ArenaArray<int> body_dofnum;    ///< dofs of this body
  ArenaArray<int> body_dofadr;   ///< first dof, -1 if none
  ArenaArray<int> body_geomnum;   ///< geoms of this body
  ArenaArray<int> body_geomadr;  ///< first geom, -1 if none
  ArenaArray<Eigen::Vector3d> body_pos;       ///< in parent frame
  ArenaArray<Eigen::Vector4d> body_quat;  ///< relative to parent
  ArenaArray<Eigen::Vector3d> body_ipos;  ///< centre of mass, body frame
  ArenaArray<Eigen::Vector4d> body_iquat;  ///< principal axes
  ArenaArray<double> body_mass;                                    ///< kg
  ArenaArray<Eigen::Vector3d> body_inertia;    ///< principal, kg m^2
  /// lever: true where the body's mass came from <inertial>, false where it was inferred
  /// from geoms (or the body has no mass at all)
  ArenaArray<uint8_t> body_explicit_inertial;
  ArenaArray<int> body_line;  ///< lever: source line of the <body> element (0: unknown)

  // ---- joints (njnt) -------------------------------------------------------------------------
  std::vector<std::string> jnt_name;
  ArenaArray<JointType> jnt_type;
  ArenaArray<int> jnt_qposadr;
  ArenaArray<int> jnt_dofadr;
  ArenaArray<int> jnt_bodyid;
  ArenaArray<uint8_t> jnt_limited;
  ArenaArray<std::array<double, 2>> jnt_solref;  ///< limit solref (timeconst, dampratio)
  ArenaArray<std::array<double, 5>> jnt_solimp;  ///< limit solimp (d0, dmax, width, mid, power)
  ArenaArray<Eigen::Vector3d> jnt_pos;   ///< anchor, in the body frame before this joint moves
  ArenaArray<Eigen::Vector3d> jnt_axis;  ///< unit axis, same frame
  ArenaArray<double> jnt_stiffness;      ///< N m/rad or N/m
  ArenaArray<std::array<double, 2>> jnt_range;  ///< rad or m
  ArenaArray<double> jnt_margin;
  ArenaVector qpos0;        ///< (nq) default pose: each joint's `ref`
  ArenaVector qpos_spring;  ///< (nq) spring reference: each joint's `springref`

  // ---- dofs (nv) -----------------------------------------------------------------------------
  ArenaArray<int> dof_bodyid;
  ArenaArray<int> dof_jntid;
  ArenaArray<int> dof_parentid;  ///< previous dof on the path to the world, -1 if none
  ArenaArray<double> dof_armature;
  ArenaArray<double> dof_damping;
  /// dry friction: a constraint row of force within +-frictionloss while the dof moves
  ArenaArray<double> dof_frictionloss;
  ArenaArray<std::array<double, 2>> dof_solref;  ///< friction loss solref (joint solreffriction)
  ArenaArray<std::array<double, 5>> dof_solimp;  ///< friction loss solimp (joint solimpfriction)
  ArenaArray<double> dof_invweight0;             ///< set_const: diag of M^-1 at qpos0
  ArenaArray<double> dof_M0;                     ///< set_const: diag of M at qpos0
  /// set_const: for a dof of a simple body (see body_simple), how many simple dofs run from it
  /// without a break, this one included (across consecutive simple bodies, as MuJoCo counts);
  /// 0 for a dof of another body (MuJoCo's dof_simplenum)
  ArenaArray<int> dof_simplenum;

  // ---- geoms (ngeom) -------------------------------------------------------------------------
  std::vector<std::string> geom_name;
  ArenaArray<GeomType> geom_type;
  ArenaArray<int> geom_bodyid;
  ArenaArray<int> geom_contype;
  ArenaArray<int> geom_conaffinity;
  ArenaArray<int> geom_group;
  ArenaArray<Eigen::Vector3d> geom_size;
  ArenaArray<Eigen::Vector3d> geom_pos;   ///< body frame
  ArenaArray<Eigen::Vector4d> geom_quat;  ///< relative to the body
  ArenaArray<Eigen::Vector4d> geom_rgba;
  /// lever: the geom's own mass (density x volume, or its `mass` attribute), whether or not
  /// it contributed to its body (see body_explicit_inertial and compiler.inertiagrouprange)
  ArenaArray<double> geom_mass;
  // contact parameters, as mjModel's
  ArenaArray<int> geom_condim;                    ///< 1, 3, 4 or 6
  ArenaArray<int> geom_priority;                  ///< the higher one's parameters win
  ArenaArray<double> geom_solmix;                 ///< weight when mixing solref/solimp
  ArenaArray<Eigen::Vector3d> geom_friction;      ///< sliding, torsional, rolling
  ArenaArray<std::array<double, 2>> geom_solref;  ///< contact solref
  ArenaArray<std::array<double, 5>> geom_solimp;  ///< contact solimp
  ArenaArray<double> geom_margin;                 ///< contact detection distance
  ArenaArray<double> geom_gap;                    ///< contacts within margin - gap make rows
  ArenaArray<double> geom_rbound;                 ///< bounding sphere radius (0: plane)
  ArenaArray<int> geom_dataid;  ///< a mesh geom's mesh, -1 for other geoms

  // ---- meshes (nmesh), as MuJoCo 2.2.2 compiles them for collision --------------------------
  ArenaArray<int> mesh_vertadr;   ///< first vertex in mesh_vert
  ArenaArray<int> mesh_vertnum;   ///< vertices; 0 for a mesh lever did not read (no geom needs it)
  ArenaArray<int> mesh_graphadr;  ///< first int of its hull graph in mesh_graph, -1 if none
  /// (nmeshvert) vertices in the geom's frame (the mesh's centre of mass and principal axes);
  /// floats in MuJoCo, held here as the doubles they convert to
  ArenaArray<Eigen::Vector3d> mesh_vert;
  /// (nmeshgraph) each mesh's convex hull (qhull's, as MuJoCo): numvert, numface, then per hull
  /// vertex the address of its neighbour list, its vertex in the mesh, then the neighbour lists
  /// (hull vertex numbers, each list ended by -1), then the hull's triangles (mesh vertices)
  ArenaArray<int> mesh_graph;
  ArenaArray<int> mesh_faceadr;  ///< first triangle in mesh_face
  ArenaArray<int> mesh_facenum;  ///< triangles; 0 for a mesh lever did not read
  /// (nmeshface) each triangle's three vertices, numbered within its mesh (what the rangefinder's
  /// ray meets, MuJoCo's mj_rayMesh)
  ArenaArray<std::array<int, 3>> mesh_face;

  // ---- explicit contact pairs (npair) and exclusions (nexclude) ------------------------------
  ArenaArray<int> pair_dim;
  ArenaArray<int> pair_geom1, pair_geom2;
  ArenaArray<int> pair_signature;  ///< ((body1 + 1) << 16) + body2 + 1, sorted (MuJoCo's)
  ArenaArray<std::array<double, 2>> pair_solref;
  ArenaArray<std::array<double, 5>> pair_solimp;
  ArenaArray<double> pair_margin, pair_gap;
  ArenaArray<std::array<double, 5>> pair_friction;
  ArenaArray<int> exclude_signature;  ///< ((body1 + 1) << 16) + body2 + 1, sorted (MuJoCo's)

  // ---- equality constraints (neq) ---------------------------------------------------------------
  std::vector<std::string> eq_name;
  ArenaArray<EqualityType> eq_type;
  ArenaArray<int> eq_obj1id;  ///< body (connect, weld) or joint (joint)
  ArenaArray<int> eq_obj2id;  ///< the second body (0: the world) or joint (-1: none)
  ArenaArray<uint8_t> eq_active;
  ArenaArray<std::array<double, 2>> eq_solref;
  ArenaArray<std::array<double, 5>> eq_solimp;
  /// see kEqualityData; set_const completes a connect's anchor in body 2 and a weld's relative
  /// pose left zero (its quaternion all zero) from the bodies' poses at qpos0, as mj_setConst
  ArenaArray<std::array<double, kEqualityData>> eq_data;

  // ---- tendons (ntendon) and their paths (nwrap), as mjModel's -------------------------------
  // A fixed tendon's length is sum_k coef_k qpos(joint_k) over its path's joints (wrap_objid,
  // wrap_prm = coef), its Jacobian those coefficients at the joints' dofs. A spatial tendon's path
  // (its first object not a joint) runs through sites, wrapping around a sphere or cylinder geom
  // between two of them (wrap_prm: its side site, or -1), and splits at pulleys (wrap_objid -1,
  // wrap_prm the divisor of the branches after it); its length is the path's, its Jacobian the
  // path's segments' (smooth/tendon.cpp). Its force: a spring -stiffness (length - lengthspring)
  // - damping velocity along it; a limit row when it leaves range (limited), a friction-loss row
  // while it moves (frictionloss > 0).
  std::vector<std::string> tendon_name;
  ArenaArray<int> tendon_adr;  ///< first object of its path in wrap_*
  ArenaArray<int> tendon_num;  ///< objects in its path
  ArenaArray<uint8_t> tendon_limited;
  ArenaArray<double> tendon_width;  ///< drawn width (spatial tendons; no effect on dynamics)
  ArenaArray<std::array<double, 2>> tendon_solref_lim;  ///< limit solref
  ArenaArray<std::array<double, 5>> tendon_solimp_lim;  ///< limit solimp
  ArenaArray<std::array<double, 2>> tendon_solref_fri;  ///< friction loss solref
  ArenaArray<std::array<double, 5>> tendon_solimp_fri;  ///< friction loss solimp
  ArenaArray<std::array<double, 2>> tendon_range;       ///< length limits
  ArenaArray<double> tendon_margin;                     ///< limit rows within this of a stop
  ArenaArray<double> tendon_stiffness;
  ArenaArray<double> tendon_damping;
  ArenaArray<double> tendon_frictionloss;
  /// the spring's rest length; set_const replaces a negative one by the length at qpos_spring
  ArenaArray<double> tendon_lengthspring;
  ArenaArray<double> tendon_length0;     ///< set_const: length at qpos0
  ArenaArray<double> tendon_invweight0;  ///< set_const: J M^-1 J^T at qpos0
  ArenaArray<WrapType> wrap_type;        ///< (nwrap)
  ArenaArray<int> wrap_objid;            ///< (nwrap) the joint (site, geom) of the object
  ArenaArray<double> wrap_prm;           ///< (nwrap) a joint's coefficient, a geom's side site
                                          ///< (-1: none), a pulley's divisor

  // ---- sites (nsite) -------------------------------------------------------------------------
  std::vector<std::string> site_name;
  ArenaArray<int> site_bodyid;
  ArenaArray<Eigen::Vector3d> site_pos;   ///< body frame
  ArenaArray<Eigen::Vector4d> site_quat;  ///< relative to the body
  ArenaArray<Eigen::Vector3d> site_size;
  /// its shape: sphere, capsule, ellipsoid, cylinder or box (a touch sensor's zone)
  ArenaArray<GeomType> site_type;

  // ---- actuators (nu): stateless actuators on a joint or a tendon ------------------------------
  // force = gain * ctrl + bias, with gain = gainprm[0] (+ gainprm[1] length + gainprm[2] velocity
  // if affine) and bias = biasprm[0] + biasprm[1] length + biasprm[2] velocity (if affine): a
  // motor is gain 1 and no bias; a position servo gain kp and bias (0, -kp, -kv).
  std::vector<std::string> actuator_name;
  ArenaArray<TransmissionType> actuator_trntype;
  /// what it drives: [0] the joint, tendon or site (a slider-crank's crank site); [1] a
  /// slider-crank's slider site, a site transmission's reference site, else -1
  ArenaArray<std::array<int, 2>> actuator_trnid;
  ArenaArray<double> actuator_cranklength;  ///< a slider-crank's rod length (else 0)
  ArenaArray<DynType> actuator_dyntype;
  ArenaArray<std::array<double, kDynParameters>> actuator_dynprm;  ///< filter: tau; muscle:
                                                                    ///< tau_act, tau_deact
  ArenaArray<uint8_t> actuator_actlimited;  ///< its activation clamped to actrange after a step
  ArenaArray<std::array<double, 2>> actuator_actrange;
  /// the range of its length (a muscle's is mapped onto its operating range): as written, or
  /// computed by the compiler (set_length_ranges)
  ArenaArray<std::array<double, 2>> actuator_lengthrange;
  ArenaArray<GainType> actuator_gaintype;
  ArenaArray<BiasType> actuator_biastype;
  ArenaArray<std::array<double, kGainParameters>> actuator_gainprm;
  ArenaArray<std::array<double, kBiasParameters>> actuator_biasprm;
  ArenaArray<std::array<double, 6>> actuator_gear;
  ArenaArray<uint8_t> actuator_ctrllimited;
  ArenaArray<uint8_t> actuator_forcelimited;
  ArenaArray<std::array<double, 2>> actuator_ctrlrange;
  ArenaArray<std::array<double, 2>> actuator_forcerange;
  ArenaArray<double> actuator_length0;  ///< set_const: its length at qpos0
  /// set_const: |M^-1 moment| at qpos0, the acceleration a unit force gives (a muscle's force
  /// scale when its force is negative)
  ArenaArray<double> actuator_acc0;

  // ---- sensors (nsensor): what each measures and where its numbers go in data.sensordata ----------
  std::vector<std::string> sensor_name;
  ArenaArray<SensorType> sensor_type;
  ArenaArray<SensorDataType> sensor_datatype;
  ArenaArray<SensorStage> sensor_needstage;  ///< the stage that evaluates it
  ArenaArray<ObjectType> sensor_objtype;     ///< what it is attached to (kUnknown: clock)
  ArenaArray<int> sensor_objid;              ///< that object's id (-1: clock)
  ArenaArray<ObjectType> sensor_reftype;     ///< a frame sensor's reference frame (kUnknown:
                                              ///< the world)
  ArenaArray<int> sensor_refid;              ///< its id (-1: the world)
  ArenaArray<int> sensor_dim;                ///< numbers it outputs
  ArenaArray<int> sensor_adr;                ///< its first number in data.sensordata
  ArenaArray<double> sensor_cutoff;  ///< > 0: each number clipped to +-cutoff (positive
                                      ///< sensors: to cutoff)
  /// evaluates the user sensors (set by the user; not part of a saved or pickled model)
  SensorCallback sensor_callback;
  /// evaluate the actuators' user gain, bias and activation dynamics (set by the user; not part
  /// of a saved or pickled model; a copy of the model shares them)
  ActuatorCallback actuator_gain_callback, actuator_bias_callback, actuator_dyn_callback;
  ArenaArray<double> sensor_noise;   ///< standard deviation of the noise added when
                                      ///< opt.enabled(kEnableSensornoise)

  // ---- user data: (nbody x nuser_body), (njnt x nuser_jnt), ... MuJoCo's *_user arrays -------
  ArenaRowMatrix body_user, jnt_user, geom_user, site_user, tendon_user, actuator_user,
      sensor_user;

  // ---- keyframes (nkey): named states to start from (<keyframe><key>) --------------------------
  std::vector<std::string> key_name;
  ArenaArray<double> key_time;
  ArenaRowMatrix key_qpos;  ///< (nkey x nq)
  ArenaRowMatrix key_qvel;  ///< (nkey x nv)
  ArenaRowMatrix key_ctrl;  ///< (nkey x nu)
  ArenaRowMatrix key_act;   ///< (nkey x na)
  ArenaRowMatrix key_mpos;   ///< (nkey x 3 nmocap) the mocap bodies' positions (default: body_pos)
  ArenaRowMatrix key_mquat;  ///< (nkey x 4 nmocap) their orientations, unit (default: body_quat)

  // ---- set_const: MuJoCo's compile-time constants ---------------------------------------------
  ArenaArray<double> body_subtreemass;                ///< kg, this body and all below it
  ArenaArray<std::array<double, 2>> body_invweight0;  ///< (translational, rotational) at qpos0
  /// 1 for a body whose block of M is diagonal and the same at every state, so that crba()
  /// copies it from dof_M0 and the LTDL steps skip its dofs (MuJoCo's body_simple, by its
  /// compiler's rule): its inertial frame is its own frame, it hangs from the world or from a
  /// body welded to the world, it has no child body, and its joints sit at its origin, a hinge's
  /// or slide's axis along one coordinate axis, with no joint after the first one that turns.
  ArenaArray<uint8_t> body_simple;
  bool has_simple_dofs = false;  ///< set_const: some dof_simplenum is not 0
  /// 1 for a body welded to the world: it has no joint, it is no mocap body, and its parent is
  /// the world or a body welded to it (a robot's base, a table). Its frames depend on no
  /// coordinate, so set_const places them once, as kinematics() would (body_static_xpos, ...,
  /// bit for bit), and kinematics() copies them rather than composing them again (see
  /// body_static_leading); 0 elsewhere (and zero frames).
  ArenaArray<uint8_t> body_static;
  ArenaArray<Eigen::Vector3d> body_static_xpos;   ///< such a body's xpos
  ArenaArray<Eigen::Vector4d> body_static_xquat;  ///< its xquat
  ArenaArray<Mat3> body_static_xmat;              ///< its xmat
  ArenaArray<Eigen::Vector3d> body_static_xipos;  ///< its xipos
  ArenaArray<Mat3> body_static_ximat;             ///< its ximat
  /// set_const: how many bodies from body 1 on, one after another, are welded to the world (a
  /// robot's base, the first body of its file): kinematics() copies their frames, with no
  /// question per body. A body welded to the world after a moving one is placed as any other
  /// (the same numbers). 0 while set_const itself places the bodies.
  int body_static_leading = 0;

  // ---- set_const: constant rotations, so kinematics() does not rebuild them every call ------
  ArenaArray<Mat3> body_mat;   ///< rotation of body_quat
  ArenaArray<Mat3> body_imat;  ///< rotation of body_iquat
  ArenaArray<Mat3> geom_mat;   ///< rotation of geom_quat
  ArenaArray<Mat3> site_mat;   ///< rotation of site_quat
  /// How each constant frame is placed (see FramePlacement): a body on its parent (body_pos,
  /// body_quat), its inertial frame (body_ipos, body_iquat), a geom, a site.
  ArenaArray<FramePlacement> body_placement, body_iplacement, geom_placement, site_placement;
  ArenaArray<JointKind> jnt_kind;  ///< what the kernels dispatch on (see JointKind)
  ArenaArray<uint8_t> jnt_offset;  ///< jnt_pos is not zero (the anchor is off the origin)

  // ---- set_const: each actuator's kind -------------------------------------------
  ArenaArray<ActuatorKind> actuator_kind;  ///< (nu) from its gain and bias (see ActuatorKind)
  /// (nu) the dof an actuator drives alone with moment gear[0] (a hinge or slide joint
  /// transmission), else -1: actuator_scalar_dof(model, a), which actuation() reads here
  ArenaArray<int> actuator_scalar_dof;

  // ---- set_const: the collision stage's body constants ---------------------------
  ArenaArray<int> body_weldid;  ///< (nbody) the body it is welded to: itself if it has joints,
                                 ///< else its parent's (MuJoCo's body_weldid)
  /// (nbody) what a body takes part in, in the broad phase (kBodyCollides | kBodyPairsWithAll)
  ArenaArray<uint8_t> body_collision;
  static constexpr uint8_t kBodyCollides = 1;      ///< a geom with contype or conaffinity
  static constexpr uint8_t kBodyPairsWithAll = 2;  ///< the world with geoms, or a static body
                                                   ///< holding a plane: paired with every body
  /// (ngeom) each geom's box in its own frame, centre then half sizes (MuJoCo 3's geom_aabb):
  /// the mesh's vertices' bounds, the primitives' from their sizes, zero for a plane. The
  /// collision stage tests two geoms' boxes before it runs MPR on them.
  ArenaArray<std::array<double, 6>> geom_aabb;
  /// (nmeshgraph) the hull graphs' neighbour lists with their points: at each neighbour's place
  /// in mesh_graph (and each list's end, vertex -1), that hull vertex, its point from mesh_vert
  /// and its list's length, so that the support function's climb reads a neighbour in one step; at
  /// the place of hull vertex h's list address (graph + 2 + h), vertex is the length of h's list
  /// (so that the climb counts its way through it); the graphs' other places unused
  ArenaArray<HullNeighbour> mesh_hull_neighbours;

  /// set_const: whether collision() can find contacts: the model has contact parameters (the
  /// geom_* contact arrays; a model built by hand without them has no contacts) and a <pair>, or
  /// two geoms on different bodies whose contype and conaffinity match. forward() runs the
  /// collision stage, and Data makes room for njmax contact rows, only then.
  bool contacts_possible = false;
  /// set_const: a spatial tendon wraps around a geom, so that the tendon stage reads the geoms'
  /// frames even where nothing collides (the lean step places them then too).
  bool tendons_wrap_geoms = false;
  /// set_const: an actuator has a body transmission (TransmissionType::kBody, <adhesion>), whose
  /// moment forward() computes from the contacts after the constraint rows; without one that
  /// pass is skipped.
  bool has_body_transmission = false;
  /// set_const: a dof or a tendon has friction loss (dof_frictionloss or tendon_frictionloss > 0),
  /// so that make_constraint looks for friction-loss rows (Data is sized for them then too).
  bool has_friction_loss = false;

  /// set_const: a number no other set_const call has given (0: never set). A Data checked
  /// against this model remembers it, so later calls need not check the whole field table again.
  std::uint64_t fit_tag = 0;

};

/// A compiled model. Its arrays live in one block (lever/arena.hpp), as MuJoCo's mjModel's do: each
/// starts on a cache line, and their lengths follow from the counts (nbody, njnt, nq, ...) alone.
/// The arrays are views with mjModel's names: model.body_mass reads and writes like a
/// std::vector<double>, model.qpos0 like an Eigen::VectorXd, but none changes its size on its own
/// (assigning another size throws StateError). A builder sets the counts, calls
/// lever::size_model(model) (lever/fields.hpp), which lays the block out anew (keeping what the
/// arrays held within their new lengths), and writes each element by index. Copying a Model copies
/// the block; moving it keeps every view where it was. The names, the options and the callbacks are
/// ordinary members.
///
/// Adding an array: declare it in ModelFields as a view, then give it its size in one line: a row
/// of LEVER_MODEL_FIELDS (lever/fields.hpp), or a line of lay_out_own_model_arrays
/// (engine/src/model/model.cpp) for what the table does not list.
struct Model : ModelFields {
  Model();                               ///< the world body alone
  Model(const Model& other);             ///< a copy of every array, in a new block
  Model(Model&& other) noexcept;         ///< takes the block: the views stay valid
  Model& operator=(const Model& other);  ///< the counts and arrays become other's
  Model& operator=(Model&& other) noexcept;
  ~Model() = default;

  /// The block every array is a view into (bytes(): what the arrays take in memory).
  const ArenaBlock& block() const { return block_; }

  // ---- names ---------------------------------------------------------------------------------
  /// Index of the named object, or -1. Linear search: meant for set-up code, not inner loops.
  int body(const std::string& n) const;
  int joint(const std::string& n) const;
  int site(const std::string& n) const;
  int actuator(const std::string& n) const;
  int geom(const std::string& n) const;
  int key(const std::string& n) const;
  int sensor(const std::string& n) const;
  int equality(const std::string& n) const;
  int tendon(const std::string& n) const;

 private:
  friend void size_model(Model& model);
  ArenaBlock block_;
};

/// The dof actuator `a` drives alone, with moment gear[0]: that of a hinge or slide joint
/// transmission (kJoint or kJointInParent, the same on those joints); -1 for every other
/// transmission (ball and free joints, tendons, slider-cranks, sites), whose moment is a row of
/// data.actuator_moment that depends on the state.
int actuator_scalar_dof(const Model& model, int a);

/// Actuator a as a message names it: 'its name' in quotes, or its index when it has none.
std::string actuator_label(const Model& model, int a);

/// The attribute that makes actuator a's force a user's callback (MuJoCo's mjcb_act_gain,
/// mjcb_act_bias, mjcb_act_dyn): "gaintype", "biastype" or "dyntype" (the first of them whose
/// type is user), or nullptr when its force is lever's own.
const char* actuator_user_attribute(const Model& model, int a);

/// Throws ModelError, naming `feature` and the first actuator that is not one, unless every
/// actuator is stateless (dyntype none), has a fixed or affine gain and bias (no muscle, no user
/// callback) and
/// drives a hinge or slide joint alone (actuator_scalar_dof >= 0), or, where
/// `tendons_and_sites`, a tendon (whose moment is gear ten_J) or a site without a reference site
/// (whose moment turns with the site): for the features (identification, the step's
/// derivatives, ...) written for actuators whose force is affine in ctrl and, but for those two,
/// whose moment is constant in the dofs it drives.
void require_simple_actuators(const Model& model, const std::string& feature,
                              bool tendons_and_sites = false);

/// The actuators whose length range the compiler computes (MJCF <compiler><lengthrange mode>,
/// MuJoCo's mjtLRMode): none, muscles, muscles and user-defined actuators (lever has none of
/// those: the same as muscles), all.
enum class LengthRangeMode : int { kNone = 0, kMuscle = 1, kMuscleUser = 2, kAll = 3 };

/// How the compiler computes actuator length ranges (MJCF <compiler><lengthrange>, MuJoCo's
/// mjLROpt, with its defaults).
struct LengthRangeOptions {
  LengthRangeMode mode = LengthRangeMode::kMuscle;
  bool useexisting = true;  ///< keep a range already given (lower < upper)
  bool uselimit = false;    ///< take a limited joint's or tendon's range
  double accel = 20;        ///< the length's target acceleration in the simulation
  double maxforce = 0;      ///< the most applied force (norm), 0: no bound
  double timeconst = 1;     ///< s: the velocity's decay time constant
  double timestep = 0.01;   ///< s: the simulation's timestep (0: the model's)
  double inttotal = 10;     ///< s: simulated time per side
  double inteval = 2;       ///< s: the final interval whose lengths give the range's end
  double tolrange = 0.05;   ///< the most the lengths may spread over inteval, relative to the range
};

/// Set actuator_lengthrange where the options ask for it, as MuJoCo 2.2.2's compiler does
/// (mj_setLengthRange): from the joint's or tendon's range (uselimit), or by simulating the model
/// from qpos0 with the actuator pulled each way (lifecycle/length_range.cpp says how). Call it
/// after set_const(). Throws ModelError naming the actuator when the simulation does not settle.
void set_length_ranges(Model& model, const LengthRangeOptions& options = {});

/// Derive the constants MuJoCo's mj_setConst computes (dof_invweight0, dof_M0, body_invweight0,
/// body_subtreemass) and lever's link tree from the model's parameters. Call it after building a
/// model by hand, and after editing any parameter (a mass, an inertia, armature, qpos0, ...).
/// Throws ModelError if the parameters are inconsistent (sizes, parent order, non-physical mass).
void set_const(Model& model);

}  // namespace lever
