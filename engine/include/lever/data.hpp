// lever/data.hpp: the state of a simulation, its outputs and its workspace.
//
// Data is sized once from a Model and never reallocates: forward() and step() allocate nothing.
// Fields are grouped by the stage that writes them, as in MuJoCo's mjdata.h, and keep mjData's
// names and meanings. Everything in it is expressed in the world frame unless a comment says
// otherwise. One Model can serve many Data (one per thread).
//
// Every array lives in one block the Data allocates when it is made (as mj_makeData does): each
// array starts on a cache line and the Data is aligned to one, so two Data never share a line.
// The arrays are views into that block (lever/arena.hpp), with mjData's names and shapes:
// data.qpos reads and writes like an Eigen::VectorXd, data.xpos like a std::vector of
// Eigen::Vector3d, but none can change its size (assigning another size throws StateError) and none
// is copied alone: `auto x = data.qpos` does not compile; `Eigen::VectorXd x = data.qpos` copies
// the numbers, and copying a Data copies every array into a new block. A function that reads an
// array takes Eigen::Ref<const Eigen::VectorXd> (a const Eigen::VectorXd& would copy it).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <lever/arena.hpp>
#include <lever/model.hpp>
#include <lever/spatial.hpp>

namespace lever {

/// Kinds of warning, as MuJoCo's mjtWarning for the ones lever can raise ("bad" means NaN or
/// |x| > 1e10, MuJoCo's mju_isBad). step() resets the state on a bad qpos, qvel or qacc, as
/// mj_step does; forward() and inverse() evaluate what they are given and record the warning, so a
/// NaN in their outputs is never silent.
enum class Warning : int {
  kInertia = 0,     ///< a pivot of M's factorization was below 1e-15 (M near singular)
  kBadQpos,         ///< qpos was bad (step: the state was reset)
  kBadQvel,         ///< qvel was bad (step: the state was reset)
  kBadQacc,         ///< qacc was bad (step: the state was reset)
  kBadCtrl,         ///< ctrl was bad: every control was treated as zero for that evaluation
  kBadQfrcApplied,  ///< qfrc_applied was bad (lever's own; MuJoCo does not check it)
  /// collision(): two geoms of a pair of types lever has no function for (mesh, hfield, cylinder
  /// or ellipsoid against anything but a plane) came within their bounding spheres and were not
  /// collided (lever's own; lastinfo is the first geom of the pair)
  kContactUnsupported,
  /// step_derivatives(): the constraint rows' active set (the contacts, the rows that push) or a
  /// spatial tendon's wrapping at the step's end, or at an RK4 stage, is not the one at its
  /// start; A and B hold the start's
  /// (lever's own; lastinfo: the rows at the step's end)
  kActiveSetChanges,
  kCount
};

/// Human-readable name of a warning kind.
const char* warning_name(Warning w);

/// The record of one kind of warning (MuJoCo's mjWarningStat).
struct WarningStat {
  int number = 0;    ///< how many times it happened since the last reset
  int lastinfo = 0;  ///< the index (dof, actuator) involved the last time
};

/// One contact between two geoms (MuJoCo's mjContact): written by the collision functions (dist,
/// pos, frame) and the pipeline that mixes the two geoms' parameters (the rest).
struct Contact {
  double dist = 0;               ///< signed distance along the normal (< 0: penetration)
  Eigen::Vector3d pos{0, 0, 0};  ///< world frame, midway between the two surfaces
  /// rows: the normal (from geom1 into geom2), then two tangents (MuJoCo's mjContact.frame,
  /// which stores the same three axes as 9 numbers)
  Mat3 frame = Mat3::Zero();
  double includemargin = 0;  ///< margin - gap: rows only within this distance
  std::array<double, 5> friction{1, 1, 0.005, 0.0001, 0.0001};  ///< tangent1, 2, spin, roll1, 2
  std::array<double, 2> solref{0.02, 1};
  std::array<double, 5> solimp{0.9, 0.95, 0.001, 0.5, 2};
  int dim = 3;  ///< condim: 1, 3, 4 or 6
  int geom1 = -1, geom2 = -1;
  int exclude = 0;       ///< 1: beyond includemargin, no rows (MuJoCo's "in gap")
  int efc_address = -1;  ///< first row, -1 if none
  double mu = 0;         ///< friction of the regularized cone, friction[0] sqrt(R_1 / R_0)
};

/// What a constraint row is; the numeric values are MuJoCo's mjtConstraint (every kind: equality
/// constraints, dof and tendon friction loss, joint and tendon limits, contacts without a friction
/// cone, with a pyramidal or an elliptic one).
enum class ConstraintType : int {
  kEquality = 0,
  kFrictionDof = 1,
  kFrictionTendon = 2,
  kLimitJoint = 3,
  kLimitTendon = 4,
  kContactFrictionless = 5,
  kContactPyramidal = 6,
  kContactElliptic = 7
};

/// A constraint row's state after the solve (MuJoCo's mjtConstraintState): satisfied (no force),
/// active (MuJoCo's "quadratic": an equality row always, a friction-loss row while its force is
/// inside +-frictionloss, every row of an elliptic cone when its force is inside the cone), a
/// friction-loss row at its bound (linear cost: force +frictionloss, kLinearNeg, or
/// -frictionloss, kLinearPos), or, for every row of an elliptic cone, on the cone's surface (the
/// cone's middle zone).
enum class ConstraintState : int {
  kSatisfied = 0,
  kActive = 1,
  kLinearNeg = 2,
  kLinearPos = 3,
  kCone = 4
};

/// The sensor noise generator's starting state (Data::sensor_noise_state).
inline constexpr std::uint64_t kSensorNoiseSeed = 0x5eed5eed5eed5eedULL;

/// One body's part of the implicit step's d qfrc_bias / d qvel as MuJoCo 2.2.2's mjd_rne_vel
/// forms it (derivatives/bias_velocity_chain.cpp): a 6 x 6 matrix of the state, row-major, then
/// one column's derivatives of the body's velocity, acceleration and force.
struct BiasVelocityBody {
  std::array<double, 36> coupling;  ///< d (v x* (I v)) / d v at cvel
  Motion velocity;                  ///< d cvel / d qvel_c
  Motion acceleration;              ///< d cacc / d qvel_c (the velocity-product part)
  Force force;                      ///< d cfrc_body / d qvel_c, then summed over the subtree
  int branch;                       ///< 1: in the column's dof's subtree; 2: above it; 0: neither
};

/// Data's workspace (preallocated; contents are meaningless between calls but where it says).
struct DataWorkspace {
  /// (nbody) crba()'s composite inertias, kept until the next position stage: the implicit step
  /// and the derivatives read them after forward()
  ArenaArray<RigidInertia> crb;
  ArenaArray<double> subtree_mass;  ///< (nbody) kinematics(): each subtree's mass, summed as
                                    ///< MuJoCo's mj_comPos sums it
  ArenaArray<Motion> cacc;       ///< (nbody) body accelerations
  ArenaArray<Force> cfrc;        ///< (nbody) body forces
  ArenaArray<Motion> body_vel;   ///< (nbody) subtree_velocities(): each centre of mass's
                                 ///< velocity, world axes
  ArenaMatrix LD2;               ///< (nv x nv) factor of M + h diag(damping) (Euler)
  ArenaVector LD2DiagInv;        ///< (nv)
  ArenaVector vec1, vec2, vec3;  ///< (nv) scratch
  ArenaMatrix halfJ;             ///< (nv x nefc_max) L^-T J^T, with M = L^T D L
  ArenaMatrix halfJ_scaled;      ///< (nv x nefc_max) D^-1 L^-T J^T
  ArenaMatrix A;                 ///< (nefc_max x nefc_max) J M^-1 J^T + R
  ArenaMatrix L;                 ///< (nefc_max x nefc_max) A's active part, then its factor
  ArenaVector lcp_f, lcp_w;      ///< (nefc_max) row forces and complementary residuals
  ArenaVector lcp_rhs;           ///< (nefc_max) the active rows' right-hand side
  ArenaArray<int> lcp_active;    ///< (nefc_max) 1 for rows in the active set
  ArenaArray<int> lcp_index;     ///< (nefc_max) the active rows, in order
  // the Newton solver (constraint/newton.cpp) and the primal problem it shares (primal.cpp)
  ArenaMatrix newton_H;                  ///< (nv x nv) Hessian of the cost, then its factor
  ArenaVector newton_grad, newton_dir;   ///< (nv) gradient and Newton direction
  ArenaVector newton_Mdir, newton_Merr;  ///< (nv) M dir, M (qacc - qacc_smooth)
  ArenaVector newton_trial, newton_err;  ///< (nv) a trial acceleration, qacc - qacc_smooth
  ArenaVector newton_jar, newton_jv;     ///< (nefc_max) J qacc - aref, J dir
  ArenaVector newton_x, newton_grad_x;   ///< (nefc_max) rows' jar at a point, d cost / d jar
  // the CG solver (constraint/cg.cpp) shares the Newton solver's vectors (newton_grad: the
  // gradient, newton_dir: the search direction, newton_Mdir: M times it) and adds these
  ArenaVector cg_Mgrad;                   ///< (nv) M^-1 gradient
  ArenaVector cg_grad_old, cg_Mgrad_old;  ///< (nv) both at the previous iterate
  /// make_constraint(): whether the products with the rows are summed as MuJoCo sums them with
  /// its sparse Jacobian (sparse_jacobian) rather than its dense one
  bool sparse_row_sums = false;
  // a contact's rows in its own frame (make_constraint): contact i's frame rows
  // (normal, two tangents, then the spin and the two rolls; one row without friction) are rows
  // efc_address.. of contact_frame_J, over the span of dofs contact_span[2 i] (the first) ..,
  // contact_span[2 i + 1] of them, that holds the dofs of its two bodies' paths to the root
  // which are not on both (zero elsewhere in the span; outside it, not written). Every row of
  // the contact is a combination of them (a pyramid edge is n +- mu_k t_k), so the solvers
  // work on these few rows over this span.
  ArenaRowMatrix contact_frame_J;  ///< (nefc_max x nv)
  ArenaArray<int> contact_span;    ///< (2 nconmax)
  ArenaArray<int> dof_chain;       ///< (2 nv) scratch: two bodies' dofs to the root
  /// (12 x nv) an equality constraint's Jacobians: body 1's translational and rotational,
  /// then body 2's
  ArenaMatrix equality_jac;
  /// (12 x nv) a spatial tendon's segment: its first end's translational and rotational
  /// Jacobians, then its second end's
  ArenaMatrix tendon_jac;
  /// (12 x nv) a site or slider-crank transmission's Jacobians: the site's translational and
  /// rotational, then the reference (slider) site's
  ArenaMatrix transmission_jac;
  ArenaArray<double> contact_weight;  ///< (36 nconmax) a Hessian's part of each contact, W of
                                      ///< C^T W C in its frame (dim x dim, row-major)
  ArenaArray<double> frame_scratch;   ///< (6 nv) W C over a contact's dofs
  ArenaArray<int> hessian_envelope;   ///< (nv) solve_with_hessian: the factor's envelope,
                                      ///< one past each column's last nonzero
  ArenaVector rk_qpos0, rk_qvel0, rk_dq, rk_dv;  ///< RK4 stages (rk_qpos0 nq, the rest nv)
  ArenaVector rk_qvel[4], rk_qacc[4];
  ArenaVector rk_act0, rk_dact;  ///< (na) RK4: the step's start activation, its update
  ArenaVector rk_act_dot[4];     ///< (na) each stage's act_dot
  ArenaMatrix qDeriv;  ///< (nv x nv) implicit: d qfrc_smooth / d qvel
  ArenaMatrix qLU;     ///< (nv x nv) implicit: M - h qDeriv, then its factor (U + I) L
  /// (nbody) implicit: each body's part of d qfrc_bias / d qvel in MuJoCo's chain-rule form
  /// (derivatives/bias_velocity_chain.cpp), one dof's column at a time
  ArenaArray<BiasVelocityBody> bias_chain_body;
  /// (nv) implicit: d cdof_dot / d qvel of each dof, in that column
  ArenaArray<Motion> bias_chain_dof;
  // collision(): contacts are gathered here and copied to `contact` only when all
  // of them fit, so that a refusal leaves the last contacts in place
  ArenaArray<Contact> contact;       ///< (nconmax)
  ArenaArray<Contact> pair_contact;  ///< (kMaxPairContacts) one geom pair's contacts
  ArenaArray<double> body_aabb;      ///< (6 nbody) broad phase: bounds along the eigenframe's axes
  // place_site(): the bodies from a site's body up to (not including) the world
  ArenaArray<int> body_path;  ///< (nbody)
};

/// Data's members (Data below adds the block its arrays live in); fields are read as data.qpos.
struct DataFields {
  // ---- state (inputs) ------------------------------------------------------------------------
  double time = 0.0;         ///< s
  ArenaVector qpos;          ///< (nq) joint positions, rad or m
  ArenaVector qvel;          ///< (nv) joint velocities
  ArenaVector ctrl;          ///< (nu) motor commands, before clamping (never modified)
  ArenaVector act;           ///< (na) activations of the actuators with dynamics
  ArenaVector qfrc_applied;  ///< (nv) user-applied joint forces
  /// (nmocap) where the mocap bodies are, in the world frame: set from body_pos and body_quat by
  /// the constructor and reset(), from the keyframe by reset_keyframe(), then written by the user;
  /// kinematics() normalizes mocap_quat in place, as MuJoCo's mj_kinematics does
  ArenaArray<Eigen::Vector3d> mocap_pos;
  ArenaArray<Eigen::Vector4d> mocap_quat;

  // ---- position stage: kinematics() ------------------------------------------------------------
  ArenaArray<Eigen::Vector3d> xpos;       ///< (nbody) body frame origins
  ArenaArray<Eigen::Vector4d> xquat;      ///< (nbody) body orientations (w, x, y, z)
  ArenaArray<Mat3> xmat;                  ///< (nbody) body rotations (local -> world)
  ArenaArray<Eigen::Vector3d> xipos;      ///< (nbody) centres of mass
  ArenaArray<Mat3> ximat;                 ///< (nbody) principal axes of inertia
  ArenaArray<Eigen::Vector3d> site_xpos;  ///< (nsite)
  ArenaArray<Mat3> site_xmat;             ///< (nsite)
  ArenaArray<Eigen::Vector3d> xanchor;    ///< (njnt) joint anchors
  ArenaArray<Eigen::Vector3d> xaxis;      ///< (njnt) joint axes (unit)
  ArenaArray<Eigen::Vector3d> geom_xpos;  ///< (ngeom)
  ArenaArray<Mat3> geom_xmat;             ///< (ngeom)
  // Spatial quantities below are in absolute coordinates: world axes, origin at the centre of mass
  // of the subtree hanging from the body's world child (MuJoCo's "c-frame").
  ArenaArray<Eigen::Vector3d> subtree_com;  ///< (nbody) centre of mass of each body's subtree
  ArenaArray<Motion> cdof;                  ///< (nv) motion subspace of each dof
  ArenaArray<RigidInertia> cinert;          ///< (nbody) spatial inertia of each body

  // ---- position stage: collision()
  // ----------------------------------------------------
  int ncon = 0;                 ///< contacts found
  ArenaArray<Contact> contact;  ///< (nconmax) the first ncon are current

  // ---- position stage: crba(), factor_mass() --------------------------------------------------
  ArenaMatrix M;          ///< (nv x nv) joint-space inertia, full and symmetric, armature included
  ArenaMatrix qLD;        ///< (nv x nv) M = L^T D L: D on the diagonal, L^T above it (L(k, i) at
                          ///< (i, k); unit diagonal implied), the rest unused
  ArenaVector qLDiagInv;  ///< (nv) 1 / D

  // ---- position stage: tendons (tendon()) -----------------------------------------------------
  ArenaVector ten_length;  ///< (ntendon)
  ArenaRowMatrix ten_J;    ///< (ntendon x nv) d length / d qpos, dense (MuJoCo's dense ten_J)
  // a spatial tendon's path as it lies now (MuJoCo's): tendon t's points are wrap_xpos and
  // wrap_obj entries ten_wrapadr[t] .. + ten_wrapnum[t], counted in points (two per row, so that
  // a path whose every geom wraps still fits the nwrap rows); a fixed tendon has none
  ArenaArray<int> ten_wrapadr;  ///< (ntendon) its first point
  ArenaArray<int> ten_wrapnum;  ///< (ntendon) its points: the sites, each wrapping geom's
                                ///< two tangent points, a pulley's marker
  /// (nwrap x 2) each point's object: -1 a site, -2 a pulley's marker (at the origin), else the
  /// geom whose surface the point is on; entries past the live points keep old values
  ArenaArray<std::array<int, 2>> wrap_obj;
  /// (nwrap x 6) the points, world frame, two per row (x y z x y z)
  ArenaArray<std::array<double, 6>> wrap_xpos;

  // ---- position stage: actuator transmission ---------------------------------------------------
  ArenaVector actuator_length;     ///< (nu) the transmission's length (lever/model.hpp TransmissionType)
  ArenaRowMatrix actuator_moment;  ///< (nu x nv) d actuator_length / d qpos (MuJoCo's, dense)

  // ---- position stage: constraint rows (make_constraint) -----------------------------------
  // MuJoCo's order: the active equality constraints' rows (3 a connect, 6 a weld, 1 a joint or
  // tendon coupling), one row per dof with friction loss, then per tendon with friction loss,
  // joint limits within `margin` of a stop, then tendon limits, then
  // each contact's rows (data.contact, those with exclude == 0): one for a frictionless contact,
  // two per friction direction for a pyramid, condim rows (normal first) for an elliptic cone.
  int nefc = 0;                         ///< rows
  int ne = 0;                           ///< of them, equality rows (the first ne)
  int nf = 0;                           ///< of them, friction-loss rows (the next nf)
  ArenaArray<ConstraintType> efc_type;  ///< (nefc)
  /// (nefc) equality constraint, dof (friction loss), joint (limit), tendon (its friction loss or
  /// limit) or contact index (contact)
  ArenaArray<int> efc_id;
  ArenaRowMatrix efc_J;  ///< (nefc x nv) constraint Jacobian, rows dense
  /// (nefc) the dof of a row whose efc_J is sign e_dof (a friction-loss or limit row), else -1
  ArenaArray<int> efc_dof;
  /// (nefc) +1 lower stop, -1 upper: a limit's efc_J = sign e_dof; +1 a friction-loss row
  ArenaArray<double> efc_sign;
  ArenaVector efc_frictionloss;  ///< (nefc) a friction-loss row's bound on |force|, else 0
  ArenaVector efc_pos;           ///< (nefc) signed distance to the stop (< 0 past it)
  ArenaVector efc_margin;        ///< (nefc)
  ArenaVector efc_diagApprox;    ///< (nefc) R * imp / (1 - imp), MuJoCo's final value
  ArenaVector efc_R;             ///< (nefc) regularizer
  ArenaVector efc_D;             ///< (nefc) 1 / R
  ArenaVector efc_imp;           ///< (nefc) impedance from solimp
  ArenaVector efc_K;             ///< (nefc) stiffness of the reference dynamics
  ArenaVector efc_B;             ///< (nefc) damping of the reference dynamics

  // ---- velocity stage ------------------------------------------------------------------------
  ArenaArray<Motion> cvel;        ///< (nbody) spatial velocity of each body
  ArenaArray<Motion> cdof_dot;    ///< (nv) time derivative of cdof
  ArenaVector actuator_velocity;  ///< (nu)
  ArenaVector ten_velocity;       ///< (ntendon) ten_J qvel
  ArenaVector qfrc_passive;       ///< (nv) joint springs and damping
  ArenaVector qfrc_bias;          ///< (nv) C(q, qvel) qvel + g(q): M qacc + qfrc_bias = tau
  ArenaVector efc_vel;            ///< (nefc) J qvel
  ArenaVector efc_aref;           ///< (nefc) reference acceleration

  // ---- acceleration stage --------------------------------------------------------------------
  ArenaVector actuator_force;             ///< (nu) after ctrl clamping, gain and force clamping
  ArenaVector act_dot;                    ///< (na) d act / dt
  ArenaVector qfrc_actuator;              ///< (nv)
  ArenaVector qfrc_smooth;                ///< (nv) passive - bias + applied + actuator
  ArenaVector qacc_smooth;                ///< (nv) M^-1 qfrc_smooth
  ArenaVector efc_b;                      ///< (nefc) J qacc_smooth - aref
  ArenaVector efc_force;                  ///< (nefc) constraint force of each row
  ArenaArray<ConstraintState> efc_state;  ///< (nefc)
  ArenaVector qfrc_constraint;            ///< (nv) J^T efc_force
  ArenaVector qacc;                       ///< (nv) joint accelerations
  /// (nv) the last constraint solve's qacc (qacc_smooth without rows), where the next PGS solve
  /// starts from (MuJoCo's qacc_warmstart); reset() zeroes it
  ArenaVector qacc_warmstart;
  /// the constraint solve's iterations: with opt.solver CG or PGS, MuJoCo's count (its
  /// solver_iter); with Newton, lever's Newton steps (0 for the exact one-sided solves), not
  /// MuJoCo's
  int solver_iter = 0;
  ArenaVector qfrc_inverse;               ///< (nv) inverse(): force that produces qacc

  // ---- sensors: each stage's sensors after that stage (sensors room) -------------------------
  ArenaVector sensordata;  ///< (nsensordata) sensor i's numbers from sensor_adr[i]
  // Written only when an acceleration sensor needs them (MuJoCo's mj_rnePostConstraint), else
  // left as they were (zero in a new Data), as in MuJoCo:
  ArenaArray<Motion> cacc;     ///< (nbody) body accelerations, gravity's included as -g at the
                               ///< world
  ArenaArray<Force> cfrc_int;  ///< (nbody) force the parent exerts on the body's subtree
  ArenaArray<Force> cfrc_ext;  ///< (nbody) external forces on the body: contacts
  // Written only when a subtree velocity sensor needs them (MuJoCo's mj_subtreeVel):
  ArenaArray<Eigen::Vector3d> subtree_linvel;  ///< (nbody) velocity of the subtree's centre of mass
  ArenaArray<Eigen::Vector3d> subtree_angmom;  ///< (nbody) angular momentum about it
  /// The sensor noise's generator (splitmix64), set to kSensorNoiseSeed when the Data is made
  /// and by reset(): the same steps draw the same noise, run after run.
  std::uint64_t sensor_noise_state = 0;

  // ---- other ---------------------------------------------------------------------------------
  std::array<double, 2> energy{0.0, 0.0};  ///< compute_energy(): potential, kinetic (J)
  /// step() with <flag fwdinv="enable"> (MuJoCo's mj_compareFwdInv): the norms of the
  /// constraint force's and the applied force's differences between the forward solve and
  /// inverse dynamics at its qacc (0, 0 without constraint rows)
  std::array<double, 2> solver_fwdinv{0.0, 0.0};
  std::array<WarningStat, static_cast<int>(Warning::kCount)> warning{};

  DataWorkspace work;  ///< preallocated scratch (above)

  /// the equality rows, a friction-loss row per dof, two limit rows per limited joint, and njmax
  /// more if the model can make contacts
  int nefc_max = 0;
  /// The fit_tag of the model this Data was last checked against (lever/fields.hpp check_fit):
  /// a call with that model compares tags instead of walking the field table (no array can change
  /// its size: assigning one of another size throws). 0: not checked yet, or moved from.
  std::uint64_t model_tag = 0;
  /// sizes of the model this Data was built for (checked on use: lever/fields.hpp check_fit)
  int nq = 0, nv = 0, nu = 0, nbody = 0, njnt = 0, ngeom = 0, nsite = 0;
  /// the other sizes the block was laid out with
  int nmocap = 0, nsensordata = 0, nconmax = 0, ntendon = 0, nwrap = 0, na = 0;
};

/// Data's arrays live in one block (lever/arena.hpp), allocated when the Data is made and sized by
/// the model alone, as MuJoCo's mj_makeData does: every array starts on a cache line, and the Data
/// itself is aligned to one, so that two Data (one per thread) never share a cache line. Copying a
/// Data copies the block; moving it keeps every view valid.
///
/// Adding an array: declare it in DataFields as a view (ArenaVector, ArenaMatrix, ArenaRowMatrix or
/// ArenaArray<T>, T a number, an enum, a fixed-size Eigen type or a struct of those), then give it
/// its size in one line: a row of LEVER_DATA_FIELDS (lever/fields.hpp) for an array readers see
/// (bindings, JSON, the comparison with MuJoCo), or a line of lay_out_own_arrays
/// (engine/src/model/data.cpp) for the workspace and what the table does not list. A new array is
/// zero (an ArenaArray of a struct: its default value) until the Data constructor says otherwise.
struct alignas(kCacheLine) Data : DataFields {
  explicit Data(const Model& model);
  Data(const Data& other);             ///< a copy of every array, in a new block
  Data(Data&& other) noexcept;         ///< takes the block: the views stay valid
  Data& operator=(const Data& other);  ///< the arrays' numbers and sizes become other's
  Data& operator=(Data&& other) noexcept;
  ~Data() = default;

  /// The block every array is a view into (bytes(): what the arrays take in memory).
  const ArenaBlock& block() const { return block_; }

 private:
  ArenaBlock block_;
};

/// Reset the state as MuJoCo's mj_resetData: qpos = qpos0; qvel, ctrl, qfrc_applied, qacc,
/// qacc_warmstart, time and warnings zero.
void reset(const Model& model, Data& data);

/// Reset to keyframe `key` as MuJoCo's mj_resetDataKeyframe: reset(), then time, qpos, qvel and
/// ctrl from the keyframe. Throws StateError naming the range if `key` is not in [0, nkey).
void reset_keyframe(const Model& model, Data& data, int key);

/// The same by the keyframe's name; throws StateError listing the model's keyframes if none has it.
void reset_keyframe(const Model& model, Data& data, const std::string& key);

/// Total number of warnings recorded since the last reset (0: nothing went wrong).
int warning_count(const Data& data);

/// One line per kind of warning recorded, e.g. "qvel is NaN or larger than 1e10: state reset
/// (2 times, last at index 1)"; empty when there is none.
std::string warning_text(const Data& data);

}  // namespace lever
