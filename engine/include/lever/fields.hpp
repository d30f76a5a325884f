// lever/fields.hpp: one table of the arrays in Model and Data (name, element type, shape, stage).
//
// As MuJoCo's mjxmacro.h does for mjModel and mjData, each array is listed once, here, and
// everything that has to walk over the arrays expands the table instead of keeping its own list:
// the Data constructor (sizes), the size checks of every public function, the command line's JSON
// and CSV dumps, the comparison with MuJoCo, and the Python and JavaScript bindings.
//
// Every listed array is contiguous and row-major: it is an (rows, cols) array of doubles, ints or
// bytes starting at one pointer. `rows` names a size of the model (nq, nv, nu, na, nbody, njnt, ngeom,
// nsite, npair, nexclude, neq, nmocap, ntendon, nwrap, nefc: the live constraint rows of a Data;
// `one` for a single row); `cols` is a number, or -1 for nv. The last column says whether MuJoCo 2.2.2's mjModel/mjData has an array of
// the same name, shape and meaning (`mujoco`) or not (`own`: lever's own, or laid out differently
// from MuJoCo's).
//
// Adding an array to Model or Data: declare the member, then add its row here. The static_asserts
// in fields.cpp check that its element type and layout match the row.
//
// The table sizes Model as it sizes Data: whoever builds a model (lever::mjcf's compiler, the
// harness's copy of a MuJoCo model, a model built by hand) sets the counts (nbody, njnt, nq, ...),
// calls size_model(), which lays every array out in the model's one block, and writes each element
// by index. Arrays of Model outside the table: the names (one string per object,
// LEVER_MODEL_NAMES below, outside the block because their entries are not numbers), and in the
// block the keyframes (key_time, nkey; key_qpos, key_qvel, key_ctrl, key_act, nkey x nq, nv, nu,
// na; key_mpos, key_mquat, nkey x 3 nmocap, 4 nmocap) and what set_const derives for the kernels
// (body_mat, jnt_kind, actuator_kind, ...), whose entries are not numbers; size_model sizes them all.
// `visual`, the file's asset lists, is counted by the file and never read by the engine.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <lever/data.hpp>
#include <lever/model.hpp>

// Widths counted by a size of the model rather than written as a number (the `cols` of the user
// data arrays): negative, so that FieldInfo::cols_size tells which size counts them.
namespace lever::counted_cols {
inline constexpr int nuser_body = -2, nuser_jnt = -3, nuser_geom = -4, nuser_site = -5,
                     nuser_actuator = -6, nuser_sensor = -7, nv = -8, nuser_tendon = -9;
}  // namespace lever::counted_cols

// X(name, element type, rows, cols, origin)
#define LEVER_MODEL_FIELDS(X)                                \
  X(body_parentid, int, nbody, 1, mujoco)                    \
  X(body_rootid, int, nbody, 1, mujoco)                      \
  X(body_jntnum, int, nbody, 1, mujoco)                      \
  X(body_jntadr, int, nbody, 1, mujoco)                      \
  X(body_dofnum, int, nbody, 1, mujoco)                      \
  X(body_dofadr, int, nbody, 1, mujoco)                      \
  X(body_geomnum, int, nbody, 1, mujoco)                     \
  X(body_geomadr, int, nbody, 1, mujoco)                     \
  X(body_pos, double, nbody, 3, mujoco)                      \
  X(body_quat, double, nbody, 4, mujoco)                     \
  X(body_ipos, double, nbody, 3, mujoco)                     \
  X(body_iquat, double, nbody, 4, mujoco)                    \
  X(body_mass, double, nbody, 1, mujoco)                     \
  X(body_subtreemass, double, nbody, 1, mujoco)              \
  X(body_inertia, double, nbody, 3, mujoco)                  \
  X(body_invweight0, double, nbody, 2, mujoco)               \
  X(body_simple, uint8_t, nbody, 1, mujoco)                  \
  X(body_static, uint8_t, nbody, 1, own)                     \
  X(body_static_xpos, double, nbody, 3, own)                 \
  X(body_static_xquat, double, nbody, 4, own)                \
  X(body_static_xmat, double, nbody, 9, own)                 \
  X(body_static_xipos, double, nbody, 3, own)                \
  X(body_static_ximat, double, nbody, 9, own)                \
  X(body_explicit_inertial, uint8_t, nbody, 1, own)          \
  X(body_line, int, nbody, 1, own)                           \
  X(body_mocapid, int, nbody, 1, mujoco)                     \
  X(jnt_type, int, njnt, 1, mujoco)                          \
  X(jnt_qposadr, int, njnt, 1, mujoco)                       \
  X(jnt_dofadr, int, njnt, 1, mujoco)                        \
  X(jnt_bodyid, int, njnt, 1, mujoco)                        \
  X(jnt_limited, uint8_t, njnt, 1, mujoco)                   \
  X(jnt_solref, double, njnt, 2, mujoco)                     \
  X(jnt_solimp, double, njnt, 5, mujoco)                     \
  X(jnt_pos, double, njnt, 3, mujoco)                        \
  X(jnt_axis, double, njnt, 3, mujoco)                       \
  X(jnt_stiffness, double, njnt, 1, mujoco)                  \
  X(jnt_range, double, njnt, 2, mujoco)                      \
  X(jnt_margin, double, njnt, 1, mujoco)                     \
  X(qpos0, double, nq, 1, mujoco)                            \
  X(qpos_spring, double, nq, 1, mujoco)                      \
  X(dof_bodyid, int, nv, 1, mujoco)                          \
  X(dof_jntid, int, nv, 1, mujoco)                           \
  X(dof_parentid, int, nv, 1, mujoco)                        \
  X(dof_armature, double, nv, 1, mujoco)                     \
  X(dof_damping, double, nv, 1, mujoco)                      \
  X(dof_invweight0, double, nv, 1, mujoco)                   \
  X(dof_M0, double, nv, 1, mujoco)                           \
  X(dof_simplenum, int, nv, 1, mujoco)                       \
  X(dof_frictionloss, double, nv, 1, mujoco)                 \
  X(dof_solref, double, nv, 2, mujoco)                       \
  X(dof_solimp, double, nv, 5, mujoco)                       \
  X(geom_type, int, ngeom, 1, mujoco)                        \
  X(geom_contype, int, ngeom, 1, mujoco)                     \
  X(geom_conaffinity, int, ngeom, 1, mujoco)                 \
  X(geom_bodyid, int, ngeom, 1, mujoco)                      \
  X(geom_group, int, ngeom, 1, mujoco)                       \
  X(geom_size, double, ngeom, 3, mujoco)                     \
  X(geom_pos, double, ngeom, 3, mujoco)                      \
  X(geom_quat, double, ngeom, 4, mujoco)                     \
  X(geom_rgba, double, ngeom, 4, own) /* float in MuJoCo */  \
  X(geom_mass, double, ngeom, 1, own)                        \
  X(site_bodyid, int, nsite, 1, mujoco)                      \
  X(site_size, double, nsite, 3, mujoco)                     \
  X(site_pos, double, nsite, 3, mujoco)                      \
  X(site_quat, double, nsite, 4, mujoco)                     \
  X(site_type, int, nsite, 1, mujoco)                        \
  X(actuator_trntype, int, nu, 1, mujoco)                    \
  X(actuator_trnid, int, nu, 2, mujoco)                      \
  X(actuator_cranklength, double, nu, 1, mujoco)             \
  X(actuator_dyntype, int, nu, 1, mujoco)                    \
  X(actuator_dynprm, double, nu, 10, mujoco)                 \
  X(actuator_actlimited, uint8_t, nu, 1, mujoco)             \
  X(actuator_actrange, double, nu, 2, mujoco)                \
  X(actuator_lengthrange, double, nu, 2, mujoco)             \
  X(actuator_gaintype, int, nu, 1, mujoco)                   \
  X(actuator_biastype, int, nu, 1, mujoco)                   \
  X(actuator_gainprm, double, nu, 10, mujoco)                \
  X(actuator_biasprm, double, nu, 10, mujoco)                \
  X(actuator_ctrllimited, uint8_t, nu, 1, mujoco)            \
  X(actuator_forcelimited, uint8_t, nu, 1, mujoco)           \
  X(actuator_gear, double, nu, 6, mujoco)                    \
  X(actuator_ctrlrange, double, nu, 2, mujoco)               \
  X(actuator_forcerange, double, nu, 2, mujoco)              \
  X(actuator_length0, double, nu, 1, mujoco)                 \
  X(actuator_acc0, double, nu, 1, mujoco)                    \
  X(actuator_scalar_dof, int, nu, 1, own)                    \
  LEVER_MODEL_CONTACT_FIELDS(X)                              \
  LEVER_MODEL_SENSOR_FIELDS(X)                               \
  LEVER_MODEL_EQUALITY_FIELDS(X)                             \
  LEVER_MODEL_USER_FIELDS(X)                                 \
  LEVER_MODEL_TENDON_FIELDS(X)

// user data: each kind's numbers (MJCF `user`), rows padded with zeros to nuser_<kind>
#define LEVER_MODEL_USER_FIELDS(X)                                              \
  X(body_user, double, nbody, counted_cols::nuser_body, mujoco)                 \
  X(jnt_user, double, njnt, counted_cols::nuser_jnt, mujoco)                    \
  X(geom_user, double, ngeom, counted_cols::nuser_geom, mujoco)                 \
  X(site_user, double, nsite, counted_cols::nuser_site, mujoco)                 \
  X(tendon_user, double, ntendon, counted_cols::nuser_tendon, mujoco)           \
  X(actuator_user, double, nu, counted_cols::nuser_actuator, mujoco)            \
  X(sensor_user, double, nsensor, counted_cols::nuser_sensor, mujoco)

// tendons and the objects of their paths
#define LEVER_MODEL_TENDON_FIELDS(X)                 \
  X(tendon_adr, int, ntendon, 1, mujoco)             \
  X(tendon_num, int, ntendon, 1, mujoco)             \
  X(tendon_limited, uint8_t, ntendon, 1, mujoco)     \
  X(tendon_width, double, ntendon, 1, mujoco)        \
  X(tendon_solref_lim, double, ntendon, 2, mujoco)   \
  X(tendon_solimp_lim, double, ntendon, 5, mujoco)   \
  X(tendon_solref_fri, double, ntendon, 2, mujoco)   \
  X(tendon_solimp_fri, double, ntendon, 5, mujoco)   \
  X(tendon_range, double, ntendon, 2, mujoco)        \
  X(tendon_margin, double, ntendon, 1, mujoco)       \
  X(tendon_stiffness, double, ntendon, 1, mujoco)    \
  X(tendon_damping, double, ntendon, 1, mujoco)      \
  X(tendon_frictionloss, double, ntendon, 1, mujoco) \
  X(tendon_lengthspring, double, ntendon, 1, mujoco) \
  X(tendon_length0, double, ntendon, 1, mujoco)      \
  X(tendon_invweight0, double, ntendon, 1, mujoco)   \
  X(wrap_type, int, nwrap, 1, mujoco)                \
  X(wrap_objid, int, nwrap, 1, mujoco)               \
  X(wrap_prm, double, nwrap, 1, mujoco)

// sensors: what each one measures, on which object, and where its numbers go
#define LEVER_MODEL_SENSOR_FIELDS(X)              \
  X(sensor_type, int, nsensor, 1, mujoco)         \
  X(sensor_datatype, int, nsensor, 1, mujoco)     \
  X(sensor_needstage, int, nsensor, 1, mujoco)    \
  X(sensor_objtype, int, nsensor, 1, mujoco)      \
  X(sensor_objid, int, nsensor, 1, mujoco)        \
  X(sensor_reftype, int, nsensor, 1, mujoco)      \
  X(sensor_refid, int, nsensor, 1, mujoco)        \
  X(sensor_dim, int, nsensor, 1, mujoco)          \
  X(sensor_adr, int, nsensor, 1, mujoco)          \
  X(sensor_cutoff, double, nsensor, 1, mujoco)    \
  X(sensor_noise, double, nsensor, 1, mujoco)

// contact parameters: the geoms', the explicit <pair>s' and the <exclude>s'
#define LEVER_MODEL_CONTACT_FIELDS(X)        \
  X(geom_condim, int, ngeom, 1, mujoco)      \
  X(geom_priority, int, ngeom, 1, mujoco)    \
  X(geom_solmix, double, ngeom, 1, mujoco)   \
  X(geom_friction, double, ngeom, 3, mujoco) \
  X(geom_solref, double, ngeom, 2, mujoco)   \
  X(geom_solimp, double, ngeom, 5, mujoco)   \
  X(geom_margin, double, ngeom, 1, mujoco)   \
  X(geom_gap, double, ngeom, 1, mujoco)      \
  X(geom_rbound, double, ngeom, 1, mujoco)   \
  X(pair_dim, int, npair, 1, mujoco)         \
  X(pair_geom1, int, npair, 1, mujoco)       \
  X(pair_geom2, int, npair, 1, mujoco)       \
  X(pair_signature, int, npair, 1, mujoco)   \
  X(pair_solref, double, npair, 2, mujoco)   \
  X(pair_solimp, double, npair, 5, mujoco)   \
  X(pair_margin, double, npair, 1, mujoco)   \
  X(pair_gap, double, npair, 1, mujoco)      \
  X(pair_friction, double, npair, 5, mujoco) \
  X(exclude_signature, int, nexclude, 1, mujoco)  \
  LEVER_MODEL_MESH_FIELDS(X)

// meshes as MuJoCo compiles them for collision: the geoms' meshes, their vertices and hulls
#define LEVER_MODEL_MESH_FIELDS(X)                             \
  X(geom_dataid, int, ngeom, 1, mujoco)                        \
  X(mesh_vertadr, int, nmesh, 1, mujoco)                       \
  X(mesh_vertnum, int, nmesh, 1, mujoco)                       \
  X(mesh_graphadr, int, nmesh, 1, mujoco)                      \
  X(mesh_vert, double, nmeshvert, 3, own) /* float in MuJoCo */ \
  X(mesh_graph, int, nmeshgraph, 1, mujoco)                    \
  X(mesh_faceadr, int, nmesh, 1, mujoco)                       \
  X(mesh_facenum, int, nmesh, 1, mujoco)                       \
  X(mesh_face, int, nmeshface, 3, mujoco)

// equality constraints
#define LEVER_MODEL_EQUALITY_FIELDS(X)  \
  X(eq_type, int, neq, 1, mujoco)       \
  X(eq_obj1id, int, neq, 1, mujoco)     \
  X(eq_obj2id, int, neq, 1, mujoco)     \
  X(eq_active, uint8_t, neq, 1, mujoco) \
  X(eq_solref, double, neq, 2, mujoco)  \
  X(eq_solimp, double, neq, 5, mujoco)  \
  X(eq_data, double, neq, 11, mujoco)

// The names of Model's objects, one string each ("" if unnamed), outside the table above because
// their entries are not numbers. X(name, count): `count` is the Model member that counts them.
#define LEVER_MODEL_NAMES(X) \
  X(body_name, nbody)        \
  X(jnt_name, njnt)          \
  X(geom_name, ngeom)        \
  X(site_name, nsite)        \
  X(actuator_name, nu)       \
  X(sensor_name, nsensor)    \
  X(eq_name, neq)            \
  X(tendon_name, ntendon)    \
  X(key_name, nkey)

// The Model arrays set_const computes from the others (MuJoCo's mj_setConst's constants, and
// lever's actuator_scalar_dof and the frames of the bodies welded to the world). size_model()
// sizes them with the rest and set_const fills them; every other Model array is a parameter, filled by whoever builds the model (lever::mjcf's
// compiler, or by hand), and checked by validate() (lever/model_check.hpp).
#define LEVER_MODEL_CONSTANTS(X) \
  X(body_subtreemass) X(body_invweight0) X(body_simple) X(dof_invweight0) X(dof_M0) X(dof_simplenum) \
  X(body_static) X(body_static_xpos) X(body_static_xquat) X(body_static_xmat) X(body_static_xipos) \
  X(body_static_ximat) \
  X(tendon_length0) X(tendon_invweight0) X(actuator_length0) X(actuator_acc0) X(actuator_scalar_dof)

// X(name, element type, rows, cols, stage, origin); stage is the part of forward() that writes it,
// or `inverse` (written by inverse() only) or `energy` (by compute_energy(), and by forward() with
// <flag energy="enable">) or `step` (by step() with <flag fwdinv="enable">)
#define LEVER_DATA_FIELDS(X)                                   \
  X(qpos, double, nq, 1, state, mujoco)                        \
  X(qvel, double, nv, 1, state, mujoco)                        \
  X(ctrl, double, nu, 1, state, mujoco)                        \
  X(act, double, na, 1, state, mujoco)                         \
  X(qfrc_applied, double, nv, 1, state, mujoco)                \
  X(mocap_pos, double, nmocap, 3, state, mujoco)               \
  X(mocap_quat, double, nmocap, 4, state, mujoco)              \
  X(qacc, double, nv, 1, acceleration, mujoco)                 \
  X(qacc_warmstart, double, nv, 1, acceleration, mujoco)       \
  X(xpos, double, nbody, 3, position, mujoco)                  \
  X(xquat, double, nbody, 4, position, mujoco)                 \
  X(xmat, double, nbody, 9, position, mujoco)                  \
  X(xipos, double, nbody, 3, position, mujoco)                 \
  X(ximat, double, nbody, 9, position, mujoco)                 \
  X(xanchor, double, njnt, 3, position, mujoco)                \
  X(xaxis, double, njnt, 3, position, mujoco)                  \
  X(geom_xpos, double, ngeom, 3, position, mujoco)             \
  X(geom_xmat, double, ngeom, 9, position, mujoco)             \
  X(site_xpos, double, nsite, 3, position, mujoco)             \
  X(site_xmat, double, nsite, 9, position, mujoco)             \
  X(subtree_com, double, nbody, 3, position, mujoco)           \
  X(cdof, double, nv, 6, position, mujoco)                     \
  X(M, double, nv, -1, position, own) /* MuJoCo: qM, sparse */ \
  X(qLDiagInv, double, nv, 1, position, mujoco)                \
  X(ten_length, double, ntendon, 1, position, mujoco)          \
  X(ten_J, double, ntendon, counted_cols::nv, position, mujoco)              \
  X(ten_wrapadr, int, ntendon, 1, position, mujoco)            \
  X(ten_wrapnum, int, ntendon, 1, position, mujoco)            \
  X(wrap_obj, int, nwrap, 2, position, mujoco)                 \
  X(wrap_xpos, double, nwrap, 6, position, mujoco)             \
  X(actuator_length, double, nu, 1, position, mujoco)          \
  X(actuator_moment, double, nu, counted_cols::nv, position, mujoco)         \
  X(efc_type, int, nefc, 1, position, mujoco)                  \
  X(efc_id, int, nefc, 1, position, mujoco)                    \
  X(efc_pos, double, nefc, 1, position, mujoco)                \
  X(efc_margin, double, nefc, 1, position, mujoco)             \
  X(efc_diagApprox, double, nefc, 1, position, mujoco)         \
  X(efc_R, double, nefc, 1, position, mujoco)                  \
  X(efc_D, double, nefc, 1, position, mujoco)                  \
  X(efc_frictionloss, double, nefc, 1, position, mujoco)       \
  X(efc_sign, double, nefc, 1, position, own)                  \
  X(efc_dof, int, nefc, 1, position, own)                      \
  X(efc_imp, double, nefc, 1, position, own)                   \
  X(efc_K, double, nefc, 1, position, own)                     \
  X(efc_B, double, nefc, 1, position, own)                     \
  X(cvel, double, nbody, 6, velocity, mujoco)                  \
  X(cdof_dot, double, nv, 6, velocity, mujoco)                 \
  X(actuator_velocity, double, nu, 1, velocity, mujoco)        \
  X(ten_velocity, double, ntendon, 1, velocity, mujoco)        \
  X(qfrc_passive, double, nv, 1, velocity, mujoco)             \
  X(qfrc_bias, double, nv, 1, velocity, mujoco)                \
  X(efc_vel, double, nefc, 1, velocity, mujoco)                \
  X(efc_aref, double, nefc, 1, velocity, mujoco)               \
  X(actuator_force, double, nu, 1, acceleration, mujoco)       \
  X(act_dot, double, na, 1, acceleration, mujoco)              \
  X(qfrc_actuator, double, nv, 1, acceleration, mujoco)        \
  X(qfrc_smooth, double, nv, 1, acceleration, mujoco)          \
  X(qacc_smooth, double, nv, 1, acceleration, mujoco)          \
  X(efc_b, double, nefc, 1, acceleration, mujoco)              \
  X(efc_force, double, nefc, 1, acceleration, mujoco)          \
  X(efc_state, int, nefc, 1, acceleration, mujoco)             \
  X(qfrc_constraint, double, nv, 1, acceleration, mujoco)      \
  X(qfrc_inverse, double, nv, 1, inverse, mujoco)              \
  X(sensordata, double, nsensordata, 1, acceleration, mujoco) \
  X(cacc, double, nbody, 6, acceleration, mujoco)             \
  X(cfrc_int, double, nbody, 6, acceleration, mujoco)         \
  X(cfrc_ext, double, nbody, 6, acceleration, mujoco)         \
  X(subtree_linvel, double, nbody, 3, velocity, mujoco)       \
  X(subtree_angmom, double, nbody, 3, velocity, mujoco)       \
  X(energy, double, one, 2, energy, mujoco)                    \
  X(solver_fwdinv, double, one, 2, step, mujoco)

namespace lever {

/// The element type of an array.
enum class Scalar : int { kDouble, kInt, kByte };

/// The sizes an array's rows can be counted in.
enum class Size : int {
  kOne,
  kNq,
  kNv,
  kNu,
  kNbody,
  kNjnt,
  kNgeom,
  kNsite,
  kNefc,
  // contact
  kNpair,     ///< explicit contact pairs (<contact><pair>)
  kNexclude,  ///< excluded body pairs (<contact><exclude>)
  // meshes
  kNmesh,      ///< meshes
  kNmeshvert,  ///< mesh vertices, all meshes
  kNmeshgraph,  ///< ints of the meshes' hull graphs
  kNmeshface,   ///< the meshes' triangles
  // sensors
  kNsensor,     ///< sensors
  kNsensordata,  ///< the sensors' numbers together (data.sensordata)
  // equality constraints
  kNeq,       ///< equality constraints (<equality>)
  kNmocap,    ///< mocap bodies (<body mocap="true">)
  // user data widths (columns only)
  kNuserBody,
  kNuserJnt,
  kNuserGeom,
  kNuserSite,
  kNuserTendon,
  kNuserActuator,
  kNuserSensor,
  // tendons
  kNtendon,  ///< tendons (<tendon>)
  kNwrap,    ///< objects in the tendons' paths
  kNa        ///< activations (actuators with dynamics)
};

/// The part of forward() that writes a Data array (kState: an input; kInverse: inverse() only;
/// kEnergy: compute_energy(), or forward() with opt.enabled(kEnableEnergy); kStep: step() with
/// opt.enabled(kEnableFwdinv)).
enum class Stage : int { kState, kPosition, kVelocity, kAcceleration, kInverse, kEnergy, kStep };

/// One row of the table.
struct FieldInfo {
  const char* name;
  Scalar scalar;
  Size rows;
  int cols;        ///< < 0: as many as cols_size counts (M nv x nv; ten_J ntendon x nv; body_user
                   ///< nbody x nuser_body)
  Stage stage;     ///< Data arrays only
  bool in_mujoco;  ///< MuJoCo 2.2.2 has an array of this name, shape and meaning
  Size cols_size = Size::kOne;  ///< what counts the columns when cols < 0
};

/// An array of a Model or Data, located: `rows x cols` elements from `data`, row-major.
struct FieldView {
  const FieldInfo* info = nullptr;
  void* data = nullptr;
  int rows = 0, cols = 0;

  const double* doubles() const { return static_cast<const double*>(data); }
  double* doubles() { return static_cast<double*>(data); }
  long size() const { return static_cast<long>(rows) * cols; }
};

// ---- one contact's fields --------------------------------------------------------------------
// X(name, element type, count, origin): the members of lever::Contact, in MuJoCo's mjContact order
// (MuJoCo's H, the contact's cone Hessian, lever keeps in its solver's workspace instead). The JSON
// writer, the comparison with MuJoCo and the Python and JavaScript bindings expand this list; a
// member added to Contact is added here, and fields.cpp checks each row's type and count.
#define LEVER_CONTACT_FIELDS(X)    \
  X(dist, double, 1, mujoco)          \
  X(pos, double, 3, mujoco)           \
  X(frame, double, 9, mujoco)         \
  X(includemargin, double, 1, mujoco) \
  X(friction, double, 5, mujoco)      \
  X(solref, double, 2, mujoco)        \
  X(solimp, double, 5, mujoco)        \
  X(mu, double, 1, mujoco)            \
  X(dim, int, 1, mujoco)              \
  X(geom1, int, 1, mujoco)            \
  X(geom2, int, 1, mujoco)            \
  X(exclude, int, 1, mujoco)          \
  X(efc_address, int, 1, mujoco)

/// A member of lever::Contact: its name, element type (kDouble or kInt), how many numbers it holds
/// (frame: 9, row-major, the normal first) and where it lies, in bytes from a Contact's start.
struct ContactField {
  const char* name;
  Scalar scalar;
  int count;
  std::ptrdiff_t offset;

  const void* in(const Contact& c) const { return reinterpret_cast<const char*>(&c) + offset; }
  void* in(Contact& c) const { return reinterpret_cast<char*>(&c) + offset; }
};

/// LEVER_CONTACT_FIELDS, located in a Contact.
const std::vector<ContactField>& contact_field_table();

const std::vector<FieldInfo>& model_field_table();
const std::vector<FieldInfo>& data_field_table();

/// How many rows `size` counts in this model (kNefc: the most constraint rows it can have).
int size_of(const Model& model, Size size);

/// The most constraint rows a Data of this model holds: every equality constraint's rows, one
/// friction-loss row per dof with dof_frictionloss > 0, two limit rows per limited joint (as
/// jnt_limited is when the Data is made), and njmax contact rows when the model can make
/// contacts (Model::contacts_possible).
int constraint_rows_max(const Model& model);
/// The same for a Data (kNefc: its live rows, data.nefc).
int size_of(const Model& model, const Data& data, Size size);
const char* size_name(Size size);
const char* stage_name(Stage stage);
const char* scalar_name(Scalar scalar);

/// Every array of the model (data), located. Views of a const object must not be written.
std::vector<FieldView> model_fields(Model& model);
std::vector<FieldView> model_fields(const Model& model);
std::vector<FieldView> data_fields(const Model& model, Data& data);
std::vector<FieldView> data_fields(const Model& model, const Data& data);

/// One array by name; throws StateError naming it when there is no such array.
FieldView model_field(const Model& model, std::string_view name);
FieldView data_field(const Model& model, const Data& data, std::string_view name);

/// Whether set_const computes this Model array (LEVER_MODEL_CONSTANTS).
bool computed_by_set_const(std::string_view model_field);

/// Whether every array of the model has the size its counts give it (size_model gives it that
/// size, so a difference means a count changed since); throws ModelError naming the first array
/// that does not.
void check_model_sizes(const Model& model);

// ---- sizing a Model -----------------------------------------------------------------
/// Lays the model's arrays out in one new block, each the length its counts give it (nbody, njnt,
/// nq, nv, ngeom, nsite, nu, npair, nexclude, nmesh, nmeshvert, nmeshgraph, nmeshface, nkey, ...):
/// each array of the field table rows x cols numbers, the constants set_const computes included;
/// the keyframes and set_const's own arrays too, and the names (see the top of this file). The
/// numbers an array already holds within its new length are kept, and every new entry is zero (an
/// empty name; body_mocapid -1), so a builder sets the counts, calls this, and writes each element
/// by index, the world body's row included. Every view of the model's arrays taken before (a
/// pointer, an Eigen::Map) is invalid after it. Throws ModelError, changing nothing, when a count
/// is negative or nbody is 0 (the world is body 0). The model then needs set_const() again (its
/// fit_tag is cleared: no Data is taken to fit it until then).
void size_model(Model& model);

/// Throws StateError unless `data` was built for a model of this model's sizes and none of its
/// arrays was resized since (for example by assigning a vector of another length to data.qpos).
/// `where` names the function that checks, for the message. Allocates nothing when they fit.
void check_fit(const Model& model, const Data& data, const char* where);

}  // namespace lever
