// lever/model.hpp: the compiled model, constant while a simulation runs.
//
// Every array that has a MuJoCo 2.2.2 counterpart keeps mjModel's name, index order and meaning
// (`body_pos`, `jnt_range`, `dof_damping`, ...), so a student can read the two side by side.
// Quaternions are (w, x, y, z); 3-vectors and 3x3 matrices are expressed in the frame named in
// each field's comment. Index 0 of every body array is the world body.
//
// The model has three parts:
//   1. the parameters, filled by a compiler (mjcf_lite) or by hand;
//   2. the constants that `set_const()` derives from them at qpos0, as MuJoCo's mj_setConst does
//      (`dof_invweight0`, `dof_M0`, `body_invweight0`, `body_subtreemass`);
//   3. lever's own link tree (`link_*`, `body_link`, ...), which `set_const()` also derives, so the
//      algorithms can walk one degree of freedom per link, as in Featherstone's tables.
// After editing any parameter, call `lever::set_const(model)` before evaluating it again.
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

#include <lever/spatial.hpp>

namespace lever {

/// Joint types; the numeric values are MuJoCo's mjtJoint.
enum class JointType : int { kSlide = 2, kHinge = 3 };

/// Integrators; the numeric values are MuJoCo's mjtIntegrator (implicit is not supported).
enum class Integrator : int { kEuler = 0, kRK4 = 1 };

/// Geom types; the numeric values are MuJoCo's mjtGeom.
enum class GeomType : int { kSphere = 2, kCapsule = 3, kEllipsoid = 4, kCylinder = 5, kBox = 6 };

/// Simulation options (<option>).
struct Options {
  double timestep = 0.002;                          ///< s
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};         ///< m/s^2, world frame
  Integrator integrator = Integrator::kEuler;
};

/// Compiler settings that stay meaningful after compilation (read by `lever check`).
struct CompilerInfo {
  std::array<int, 2> inertiagrouprange{0, 5};  ///< geom groups that contribute mass
  bool inertia_from_geoms_allowed = true;      ///< inertiafromgeom was not "false"
};

struct Model {
  std::string name = "MuJoCo Model";  ///< <mujoco model="...">
  std::string source;                 ///< file the model came from ("" if built in memory)
  Options opt;
  CompilerInfo compiler;

  // ---- sizes -------------------------------------------------------------------------------
  int nq = 0;     ///< generalized coordinates (hinge and slide joints only: nq == nv)
  int nv = 0;     ///< degrees of freedom
  int nu = 0;     ///< actuators
  int nbody = 1;  ///< bodies, world included
  int njnt = 0;   ///< joints
  int ngeom = 0;  ///< geoms
  int nsite = 0;  ///< sites

  // ---- bodies (nbody) ------------------------------------------------------------------------
  std::vector<std::string> body_name{"world"};
  std::vector<int> body_parentid{0};     ///< parent body; the world is its own parent
  std::vector<int> body_rootid{0};       ///< the world child this body hangs from
  std::vector<int> body_jntnum{0};       ///< joints of this body
  std::vector<int> body_jntadr{-1};      ///< first joint, -1 if none
  std::vector<int> body_dofnum{0};       ///< dofs of this body
  std::vector<int> body_dofadr{-1};      ///< first dof, -1 if none
  std::vector<int> body_geomnum{0};      ///< geoms of this body
  std::vector<int> body_geomadr{-1};     ///< first geom, -1 if none
  std::vector<Eigen::Vector3d> body_pos{Eigen::Vector3d::Zero()};  ///< in parent frame
  std::vector<Eigen::Vector4d> body_quat{Eigen::Vector4d(1, 0, 0, 0)};  ///< relative to parent
  std::vector<Eigen::Vector3d> body_ipos{Eigen::Vector3d::Zero()};  ///< centre of mass, body frame
  std::vector<Eigen::Vector4d> body_iquat{Eigen::Vector4d(1, 0, 0, 0)};  ///< principal axes
  std::vector<double> body_mass{0.0};                                  ///< kg
  std::vector<Eigen::Vector3d> body_inertia{Eigen::Vector3d::Zero()};  ///< principal, kg m^2
  /// lever: true where the body's mass came from <inertial>, false where it was inferred
  /// from geoms (or the body has no mass at all)
  std::vector<bool> body_explicit_inertial{false};
  std::vector<int> body_line{0};  ///< lever: source line of the <body> element (0: unknown)

  // ---- joints (njnt) -------------------------------------------------------------------------
  std::vector<std::string> jnt_name;
  std::vector<JointType> jnt_type;
  std::vector<int> jnt_qposadr;
  std::vector<int> jnt_dofadr;
  std::vector<int> jnt_bodyid;
  std::vector<bool> jnt_limited;
  std::vector<std::array<double, 2>> jnt_solref;  ///< limit solref (timeconst, dampratio)
  std::vector<std::array<double, 5>> jnt_solimp;  ///< limit solimp (d0, dmax, width, mid, power)
  std::vector<Eigen::Vector3d> jnt_pos;   ///< anchor, in the body frame before this joint moves
  std::vector<Eigen::Vector3d> jnt_axis;  ///< unit axis, same frame
  std::vector<double> jnt_stiffness;      ///< N m/rad or N/m
  std::vector<std::array<double, 2>> jnt_range;  ///< rad or m
  std::vector<double> jnt_margin;
  Eigen::VectorXd qpos0;        ///< (nq) default pose: each joint's `ref`
  Eigen::VectorXd qpos_spring;  ///< (nq) spring reference: each joint's `springref`

  // ---- dofs (nv) -----------------------------------------------------------------------------
  std::vector<int> dof_bodyid;
  std::vector<int> dof_jntid;
  std::vector<int> dof_parentid;  ///< previous dof on the path to the world, -1 if none
  std::vector<double> dof_armature;
  std::vector<double> dof_damping;
  std::vector<double> dof_invweight0;  ///< set_const: diag of M^-1 at qpos0
  std::vector<double> dof_M0;          ///< set_const: diag of M at qpos0

  // ---- geoms (ngeom) -------------------------------------------------------------------------
  std::vector<std::string> geom_name;
  std::vector<GeomType> geom_type;
  std::vector<int> geom_bodyid;
  std::vector<int> geom_contype;
  std::vector<int> geom_conaffinity;
  std::vector<int> geom_group;
  std::vector<Eigen::Vector3d> geom_size;
  std::vector<Eigen::Vector3d> geom_pos;   ///< body frame
  std::vector<Eigen::Vector4d> geom_quat;  ///< relative to the body
  std::vector<Eigen::Vector4d> geom_rgba;
  /// lever: the geom's own mass (density x volume, or its `mass` attribute), whether or not
  /// it contributed to its body (see body_explicit_inertial and compiler.inertiagrouprange)
  std::vector<double> geom_mass;

  // ---- sites (nsite) -------------------------------------------------------------------------
  std::vector<std::string> site_name;
  std::vector<int> site_bodyid;
  std::vector<Eigen::Vector3d> site_pos;   ///< body frame
  std::vector<Eigen::Vector4d> site_quat;  ///< relative to the body
  std::vector<Eigen::Vector3d> site_size;

  // ---- actuators (nu): motors with a joint transmission ----------------------------------------
  std::vector<std::string> actuator_name;
  std::vector<int> actuator_trnid;  ///< joint id
  std::vector<std::array<double, 6>> actuator_gear;
  std::vector<bool> actuator_ctrllimited;
  std::vector<bool> actuator_forcelimited;
  std::vector<std::array<double, 2>> actuator_ctrlrange;
  std::vector<std::array<double, 2>> actuator_forcerange;

  // ---- set_const: MuJoCo's compile-time constants ---------------------------------------------
  std::vector<double> body_subtreemass;               ///< kg, this body and all below it
  std::vector<std::array<double, 2>> body_invweight0; ///< (translational, rotational) at qpos0

  // ---- set_const: lever's link tree, one link per dof (Featherstone's numbering) -------------
  // Link i moves with dof i; its parent link is dof_parentid[i] (-1: the world), always < i.
  // Link i's frame has the orientation of its body after the body's joints up to and including
  // joint i, and its origin on joint i's anchor, so that the joint turns or slides about the
  // frame's own origin (Featherstone's jcalc).
  std::vector<Eigen::Vector3d> link_tree_pos;   ///< link i's origin in its parent link's frame
                                                ///< at q = qpos0 (welded bodies between included)
  std::vector<Eigen::Vector4d> link_tree_quat;  ///< link i's orientation in its parent's at qpos0
  std::vector<Transform> link_Xtree;            ///< the same as a Plücker transform ^i X_lambda(i)
  std::vector<JointType> link_type;             ///< joint type of link i
  std::vector<Eigen::Vector3d> link_axis;       ///< unit joint axis, link frame
  std::vector<Motion> link_S;                   ///< motion subspace [axis; 0] or [0; axis]
  std::vector<RigidInertia> link_inertia;       ///< bodies rigidly attached to link i, link frame
  std::vector<int> body_link;  ///< the link whose frame carries body b (-1: the world frame)
  std::vector<Eigen::Vector3d> body_offset_pos;   ///< body b's origin in its link's frame
  std::vector<Eigen::Vector4d> body_offset_quat;  ///< body b's orientation in its link's frame

  // ---- names ---------------------------------------------------------------------------------
  /// Index of the named object, or -1. Linear search: meant for set-up code, not inner loops.
  int body(const std::string& n) const;
  int joint(const std::string& n) const;
  int site(const std::string& n) const;
  int actuator(const std::string& n) const;
  int geom(const std::string& n) const;
};

/// Derive the constants MuJoCo's mj_setConst computes (dof_invweight0, dof_M0, body_invweight0,
/// body_subtreemass) and lever's link tree from the model's parameters. Call it after building a
/// model by hand, and after editing any parameter (a mass, an inertia, armature, qpos0, ...).
/// Throws ModelError if the parameters are inconsistent (sizes, parent order, non-physical mass).
void set_const(Model& model);

}  // namespace lever
