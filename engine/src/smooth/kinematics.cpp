// Forward kinematics, the spatial quantities every algorithm shares, and point Jacobians.
//
// Poses compose from the root outwards, body by body, joint by joint, as MuJoCo's mj_kinematics,
// and with its arithmetic, operation for operation, so that every pose is MuJoCo's to the last
// bit (two boxes face to face touch or not by that bit): a body's orientation is a quaternion,
// its parent's times body_quat (a mocap body's: mocap_quat), times each joint's turn (a
// hinge's axis-angle quaternion, a ball's qpos); its origin is its parent's plus the parent's
// rotation of body_pos, moved along a slide's world axis, and swung about a turning joint's
// anchor. The quaternion is then normalized (always scaled by 1 / |q|) and turned into the matrix
// xmat. A constant frame on a body (its inertial frame, a geom, a site) is placed the same way:
// origin p + R v, rotation the matrix of xquat * q. Only products with exact zeros and ones are
// left out (as set_const classified each frame, lever/model.hpp FramePlacement, and a hinge about
// a coordinate axis): leaving them out changes no bit. A body welded to the world (no joint on
// the way to it) has the same frames at every state: set_const places it once and each call copies
// its frames (Model::body_static).
//
// Then, as MuJoCo's mj_comPos, the quantities the dynamics needs, in absolute coordinates (world
// axes, origin at the subtree centre of mass of the body's world child, c):
//   cdof_i   = [a; a x (c - p)] for a hinge with world axis a through anchor p, [0; a] for a slide,
//              i.e. the joint's motion subspace S_i (Featherstone's s_i in absolute coordinates);
//   cinert_b = the body's spatial inertia about c.
#include <lever/kinematics.hpp>

#include <lever/error.hpp>

#include "basics/basics.hpp"
#include "model/model_room.hpp"
#include "smooth/smooth.hpp"

#include <algorithm>
#include <cmath>

namespace lever {

namespace {

/// origin = p + R v (MuJoCo's rotVecMat, then the sum) for a constant offset v placed as `f`
/// says: p, p plus one column of R, or the whole product; the terms left out are products with
/// zero, which change no bit of the sum. Written entry by entry, so that no temporary is copied
/// into `origin` (which may be p).
inline void offset_point(const Eigen::Vector3d& p, const Mat3& R, const Eigen::Vector3d& v,
                         const FramePlacement& f, Eigen::Vector3d& origin) {
  switch (f.offset) {
    case FramePlacement::Offset::kZero: origin = p; return;
    case FramePlacement::Offset::kAlongAxis: {
      const int k = f.axis;
      const double x = v[k];
      for (int r = 0; r < 3; ++r) origin[r] = p[r] + R(r, k) * x;
      return;
    }
    case FramePlacement::Offset::kGeneral: break;
  }
  for (int r = 0; r < 3; ++r) {
    origin[r] = p[r] + (R(r, 0) * v[0] + R(r, 1) * v[1] + R(r, 2) * v[2]);
  }
}

/// The rotation matrix of a unit quaternion written into R (MuJoCo's quat2Mat, term for term).
inline void quat_into_mat(const Quat& q, Mat3& R) {
  const double q00 = q[0] * q[0], q01 = q[0] * q[1], q02 = q[0] * q[2], q03 = q[0] * q[3];
  const double q11 = q[1] * q[1], q12 = q[1] * q[2], q13 = q[1] * q[3];
  const double q22 = q[2] * q[2], q23 = q[2] * q[3], q33 = q[3] * q[3];
  R(0, 0) = q00 + q11 - q22 - q33;
  R(1, 1) = q00 - q11 + q22 - q33;
  R(2, 2) = q00 - q11 - q22 + q33;
  R(0, 1) = 2 * (q12 - q03);
  R(0, 2) = 2 * (q13 + q02);
  R(1, 0) = 2 * (q12 + q03);
  R(1, 2) = 2 * (q23 - q01);
  R(2, 0) = 2 * (q13 - q02);
  R(2, 1) = 2 * (q23 + q01);
}

/// A constant frame (offset v, quaternion q, placed as `f` says) on the body frame (p, R, its
/// quaternion body_quat): its origin and rotation. A frame that is not turned takes R itself (the
/// product with the identity quaternion is exact); any other, the matrix of body_quat * q.
inline void place_frame(const Eigen::Vector3d& p, const Mat3& R, const Quat& body_quat,
                        const Eigen::Vector3d& v, const Quat& q, const FramePlacement& f,
                        Eigen::Vector3d& origin, Mat3& rotation) {
  offset_point(p, R, v, f, origin);
  if (f.turn == FramePlacement::Turn::kNone) {
    rotation = R;
  } else {
    quat_into_mat(quat_mul(body_quat, q), rotation);
  }
}

// What a pass over the bodies places besides each body's own frame (xpos, xquat, xmat): every
// caller asks for what it reads and nothing more.
struct Placed {
  bool joint_frames = false;      // each joint's anchor and axis (xanchor, xaxis)
  bool inertial_origin = false;   // the centre of mass (xipos)
  bool inertial_axes = false;     // the principal axes (ximat)
};
constexpr Placed kFramesAlone{};                    // body_poses(), place_site()
constexpr Placed kEveryFrame{true, true, true};      // poses(), kinematics()
constexpr Placed kForJacobian{true, true, false};   // jac_site_from_q(): cdof's and c's inputs

// The frame (pos, quat) moved by joint j of its body (not a free joint), in mj_kinematics's
// order: the joint's world axis and anchor from the frame so far, then a slide's shift or a
// turn's quaternion, and for a turn about an anchor off the origin, the origin swung back so that
// the anchor stays.
template <bool kJointFrames>
[[gnu::always_inline]] inline void move_joint(const Model& m, Data& d, int j, Eigen::Vector3d& pos,
                                              Quat& quat) {
  const JointKind kind = m.jnt_kind[j];
  const int qadr = m.jnt_qposadr[j];
  const double* q = d.qpos.data() + qadr;
  const Eigen::Vector3d& axis = m.jnt_axis[j];
  // the anchor; at a zero jnt_pos, pos itself (the rotated zero adds nothing)
  const bool offset = m.jnt_offset[j];
  Eigen::Vector3d anchor = pos;
  if (offset) anchor = detail::quat_rotate(quat, m.jnt_pos[j]) + pos;
  if constexpr (kJointFrames) d.xanchor[j] = anchor;
  switch (kind) {
    case JointKind::kSlide: {
      const Eigen::Vector3d world_axis = detail::quat_rotate(quat, axis);
      if constexpr (kJointFrames) d.xaxis[j] = world_axis;
      pos += world_axis * (q[0] - m.qpos0[qadr]);
      return;  // nothing turns
    }
    case JointKind::kBall:  // qpos is the turn itself, a unit quaternion
      if constexpr (kJointFrames) d.xaxis[j] = detail::quat_rotate(quat, axis);
      quat = quat_mul(quat, Quat(q[0], q[1], q[2], q[3]));
      break;
    default: {  // a hinge: the quaternion of its angle about its axis (none at angle 0)
      if constexpr (kJointFrames) d.xaxis[j] = detail::quat_rotate(quat, axis);
      const double angle = q[0] - m.qpos0[qadr];
      if (angle == 0.0) break;
      const double sh = std::sin(angle * 0.5), ch = std::cos(angle * 0.5);
      switch (kind) {
        // about a coordinate axis: the product's terms with the turn's zero components left out
        case JointKind::kHingeX: quat = quat_mul_axis(quat, 0, ch, axis[0] * sh); break;
        case JointKind::kHingeY: quat = quat_mul_axis(quat, 1, ch, axis[1] * sh); break;
        case JointKind::kHingeZ: quat = quat_mul_axis(quat, 2, ch, axis[2] * sh); break;
        default: quat = quat_mul(quat, Quat(ch, axis[0] * sh, axis[1] * sh, axis[2] * sh));
      }
    }
  }
  // the anchor stays where it is: the origin swings around it
  if (offset) {
    const Eigen::Vector3d arm = anchor - pos;
    const Eigen::Vector3d turned = detail::quat_rotate(quat, m.jnt_pos[j]);
    for (int r = 0; r < 3; ++r) pos[r] += arm[r] - turned[r];
  }
}

// Body b's frame (xpos, xquat, xmat) on its parent's, which is placed, with qpos's quaternions
// normalized; and what kPlace asks for besides: its joints' anchors and axes (xanchor, xaxis),
// its inertial frame's origin (xipos) and axes (ximat). Model's and Data's arrays are read where
// they are: a per-call copy of their data pointers cost some 50 instructions a call and saved
// none (the stores into Data reload them from the copy as they would from Data).
template <Placed kPlace>
[[gnu::always_inline]] inline void place_body(const Model& m, Data& d, int b) {
  constexpr bool kJointFrames = kPlace.joint_frames;
  const int first_joint = m.body_jntadr[b], last_joint = first_joint + m.body_jntnum[b];
  // composed in place in Data: nothing of the body's pose is held in registers across the calls
  // to sincos, which would save and restore it
  Eigen::Vector3d& pos = d.xpos[b];
  Mat3& R = d.xmat[b];
  Quat& quat = d.xquat[b];
  if (last_joint == first_joint + 1 && m.jnt_kind[first_joint] == JointKind::kFree) {
    // a free body's pose is its qpos (body_pos and body_quat only gave qpos0); its joint's
    // anchor is the body's origin and its axis z, by MuJoCo's convention
    const double* q = d.qpos.data() + m.jnt_qposadr[first_joint];
    pos = Eigen::Vector3d(q[0], q[1], q[2]);
    quat = Quat(q[3], q[4], q[5], q[6]);
    if constexpr (kJointFrames) {
      d.xanchor[first_joint] = pos;
      d.xaxis[first_joint] = Eigen::Vector3d::UnitZ();
    }
  } else {
    const int p = m.body_parentid[b];
    const int mocap = m.body_mocapid[b];
    if (mocap >= 0) {  // a mocap body: where the user put it (its parent is the world)
      const FramePlacement general;
      offset_point(d.xpos[p], d.xmat[p], d.mocap_pos[mocap], general, pos);
      quat = quat_mul(d.xquat[p], d.mocap_quat[mocap]);
    } else {
      const FramePlacement& placement = m.body_placement[b];
      offset_point(d.xpos[p], d.xmat[p], m.body_pos[b], placement, pos);
      if (placement.turn == FramePlacement::Turn::kNone) {
        quat = d.xquat[p];
      } else {
        quat = quat_mul(d.xquat[p], m.body_quat[b]);
      }
    }
    // no free joint here: validate() allows one only as its body's single joint
    for (int j = first_joint; j < last_joint; ++j) move_joint<kJointFrames>(m, d, j, pos, quat);
  }
  detail::normalize_quat(quat.data());
  quat_into_mat(quat, R);
  if constexpr (kPlace.inertial_origin && kPlace.inertial_axes) {
    place_frame(pos, R, quat, m.body_ipos[b], m.body_iquat[b], m.body_iplacement[b], d.xipos[b],
                d.ximat[b]);
  } else if constexpr (kPlace.inertial_origin) {
    offset_point(pos, R, m.body_ipos[b], m.body_iplacement[b], d.xipos[b]);
  }
}

// A body welded to the world (Model::body_static): the frames set_const placed once, which are
// what place_body() would compose (they depend on no coordinate), and the inertial frame where
// kPlace asks for it. It has no joint frames.
template <Placed kPlace>
[[gnu::always_inline]] inline void copy_static_body(const Model& m, Data& d, int b) {
  d.xpos[b] = m.body_static_xpos[b];
  d.xquat[b] = m.body_static_xquat[b];
  d.xmat[b] = m.body_static_xmat[b];
  if constexpr (kPlace.inertial_origin) d.xipos[b] = m.body_static_xipos[b];
  if constexpr (kPlace.inertial_axes) d.ximat[b] = m.body_static_ximat[b];
}

// Body b placed on its parent, which is placed: copied where set_const placed it (one of the
// bodies welded to the world from body 1 on, Model::body_static_leading).
template <Placed kPlace>
[[gnu::always_inline]] inline void place_or_copy_body(const Model& m, Data& d, int b) {
  if (b <= m.body_static_leading) {
    copy_static_body<kPlace>(m, d, b);
  } else {
    place_body<kPlace>(m, d, b);
  }
}

// Every body but the world, root to leaves: the leading ones welded to the world copied, the
// others placed. A model without such bodies keeps the loop from body 1: one from a number known
// only at run time cost arm2's body_poses() some twenty instructions a call (GCC kept its
// counters on the stack).
template <Placed kPlace>
[[gnu::always_inline]] inline void place_every_body(const Model& m, Data& d) {
  const int nbody = m.nbody, leading = m.body_static_leading;
  if (leading == 0) {
    for (int b = 1; b < nbody; ++b) place_body<kPlace>(m, d, b);
    return;
  }
  for (int b = 1; b <= leading; ++b) copy_static_body<kPlace>(m, d, b);
  for (int b = leading + 1; b < nbody; ++b) place_body<kPlace>(m, d, b);
}

// Constant frames on their bodies (geoms, sites): frame i of n at (pos[i], quat[i]), placed as
// placement[i] says, on body bodyid[i], into (xpos[i], xmat[i]).
void place_attached(int n, const int* bodyid, const Eigen::Vector3d* pos, const Quat* quat,
                    const FramePlacement* placement, const Data& d, Eigen::Vector3d* xpos,
                    Mat3* xmat) {
  for (int i = 0; i < n; ++i) {
    const int b = bodyid[i];
    place_frame(d.xpos[b], d.xmat[b], d.xquat[b], pos[i], quat[i], placement[i], xpos[i],
                xmat[i]);
  }
}

// The world's frame, which every other frame is placed on: set on every call, as MuJoCo's
// mj_kinematics does, so that a value a caller wrote into it cannot move the robot; its inertial
// frame where the pass places inertial frames.
template <Placed kPlace = kEveryFrame>
inline void place_world(Data& data) {
  data.xpos[0].setZero();
  data.xmat[0].setIdentity();
  if constexpr (kPlace.inertial_origin) data.xipos[0].setZero();
  if constexpr (kPlace.inertial_axes) data.ximat[0].setIdentity();
  data.xquat[0] = Quat(1.0, 0.0, 0.0, 0.0);
}

// The state's quaternions normalized in place, as mj_kinematics starts: the ball and free
// joints' in qpos, and the mocap bodies'.
inline void normalize_state_quats(const Model& model, Data& data) {
  // only ball and free joints have quaternions in qpos, and only they make nq exceed nv
  if (model.nq > model.nv) detail::normalize_joint_quats(model, data.qpos.data());
  for (int i = 0; i < model.nmocap; ++i) detail::normalize_quat(data.mocap_quat[i].data());
}

// Which frames attached to the bodies a pass places.
enum class Attached { kNone, kSites, kGeomsAndSites };

// Body frames (xpos, xquat, xmat), joint anchors and axes, inertial frames, and the attached
// frames asked for.
void place_bodies(const Model& model, Data& data, Attached attached) {
  normalize_state_quats(model, data);
  place_world(data);
  place_every_body<kEveryFrame>(model, data);
  if (attached == Attached::kNone) return;
  if (attached == Attached::kGeomsAndSites) {
    place_attached(model.ngeom, model.geom_bodyid.data(), model.geom_pos.data(),
                   model.geom_quat.data(), model.geom_placement.data(), data,
                   data.geom_xpos.data(), data.geom_xmat.data());
  }
  place_attached(model.nsite, model.site_bodyid.data(), model.site_pos.data(),
                 model.site_quat.data(), model.site_placement.data(), data,
                 data.site_xpos.data(), data.site_xmat.data());
}

// The three rotations of a ball (or of a free joint): about the body's own axes, the columns of
// its rotation (MuJoCo takes the body's final frame, so a ball is its body's last joint).
void rotation_subspace(const Mat3& body_rotation, const Eigen::Vector3d& to_origin, Motion* S) {
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d axis = body_rotation.col(k);
    S[k].head<3>() = axis;
    S[k].tail<3>() = cross(axis, to_origin);
  }
}

// A body's spatial inertia in world axes about a point c from its centre of mass (out): mass m,
// first moment m c, and the rotational inertia R diag(d) R^T about the centre of mass (principal
// axes R = ximat, principal moments d) moved to the point by the parallel-axis theorem, written
// into out's members: the symmetric product's six entries once each, no temporary. Each product
// and sum is MuJoCo's mju_inertCom's (entry (r, s) is row r of R against row s of R diag(d);
// the diagonal's shift is m (c_j^2 + c_k^2)): a thin rod's axial entry of M is what is left when
// terms 1e4 times larger cancel, and keeps MuJoCo's last bit only if these do.
inline void world_inertia(const Mat3& R, const Eigen::Vector3d& d, double m,
                          const Eigen::Vector3d& c, RigidInertia& out) {
  double Rd[3][3];  // column k of R scaled by the principal moment about it
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) Rd[r][k] = R(r, k) * d[k];
  }
  const auto entry = [&](int r, int s) {  // row r of R against row s of R diag(d)
    return R(r, 0) * Rd[s][0] + R(r, 1) * Rd[s][1] + R(r, 2) * Rd[s][2];
  };
  const Eigen::Vector3d mc = m * c;
  out.m = m;
  out.h = mc;
  Eigen::Matrix3d& I = out.I;
  I(0, 0) = entry(0, 0) + m * (c[1] * c[1] + c[2] * c[2]);
  I(1, 1) = entry(1, 1) + m * (c[0] * c[0] + c[2] * c[2]);
  I(2, 2) = entry(2, 2) + m * (c[0] * c[0] + c[1] * c[1]);
  I(0, 1) = I(1, 0) = entry(0, 1) - mc[0] * c[1];
  I(0, 2) = I(2, 0) = entry(0, 2) - mc[0] * c[2];
  I(1, 2) = I(2, 1) = entry(1, 2) - mc[1] * c[2];
}

// The subtree centres of mass (subtree_com) of the bodies b >= top for which in(b) holds (every
// body: top 0; one tree: its root, and in(b) that b is in it): mass-weighted positions and masses,
// summed leaves to root, then each sum scaled by its mass's reciprocal, in MuJoCo's mj_comPos
// order: a body's own term is added after its children's (the sums start from zero), the
// children's in falling index order, and its sum is scaled once it has gone to the parent (its
// last bit is MuJoCo's only in that order). The top body's sum goes to no parent.
template <class In>
[[gnu::always_inline]] inline void subtree_centres(const Model& model, Data& data, int top, In in) {
  const int nbody = model.nbody;
  const int* const parentid = model.body_parentid.data();
  const double* const mass = model.body_mass.data();
  const Eigen::Vector3d* const xipos = data.xipos.data();
  Eigen::Vector3d* const subtree_com = data.subtree_com.data();
  double* const subtree_mass = data.work.subtree_mass.data();
  for (int b = top; b < nbody; ++b) {
    if (!in(b)) continue;
    subtree_com[b].setZero();
    subtree_mass[b] = 0.0;
  }
  for (int b = nbody - 1; b >= top; --b) {
    if (!in(b)) continue;
    subtree_com[b] += xipos[b] * mass[b];
    subtree_mass[b] += mass[b];
    if (b > top) {
      subtree_com[parentid[b]] += subtree_com[b];
      subtree_mass[parentid[b]] += subtree_mass[b];
    }
    if (subtree_mass[b] < detail::kMinVal) {
      subtree_com[b] = xipos[b];
    } else {
      subtree_com[b] *= 1.0 / subtree_mass[b];
    }
  }
}

// Subtree centres of mass, body inertias and joint motion subspaces in absolute coordinates.
void com_quantities(const Model& model, Data& data) {
  const int nbody = model.nbody;
  const int* const rootid = model.body_rootid.data();
  const double* const mass = model.body_mass.data();
  const Eigen::Vector3d* const inertia = model.body_inertia.data();
  const Eigen::Vector3d* const xipos = data.xipos.data();
  const Mat3* const ximat = data.ximat.data();
  Eigen::Vector3d* const subtree_com = data.subtree_com.data();
  RigidInertia* const cinert = data.cinert.data();

  subtree_centres(model, data, 0, [](int) { return true; });

  // each body's inertia about its tree's centre of mass, world axes
  for (int b = 1; b < nbody; ++b) {
    const Eigen::Vector3d c = xipos[b] - subtree_com[rootid[b]];
    world_inertia(ximat[b], inertia[b], mass[b], c, cinert[b]);
  }

  // each dof's motion subspace: [a; a x (c - p)] for a rotation about world axis a through
  // anchor p, [0; a] for a translation along a
  const int* const dofadr = model.jnt_dofadr.data();
  const int* const jnt_bodyid = model.jnt_bodyid.data();
  const JointKind* const jnt_kind = model.jnt_kind.data();
  const Eigen::Vector3d* const xanchor = data.xanchor.data();
  const Eigen::Vector3d* const xaxis = data.xaxis.data();
  const Mat3* const xmat = data.xmat.data();
  Motion* const cdof = data.cdof.data();
  for (int j = 0; j < model.njnt; ++j) {
    Motion* const S = cdof + dofadr[j];
    const int b = jnt_bodyid[j];
    const Eigen::Vector3d to_origin = subtree_com[rootid[b]] - xanchor[j];
    switch (jnt_kind[j]) {
      case JointKind::kSlide:
        S[0].head<3>().setZero();
        S[0].tail<3>() = xaxis[j];
        break;
      case JointKind::kFree:
        // three translations along the world axes, then three rotations as a ball's
        for (int k = 0; k < 3; ++k) {
          S[k].head<3>().setZero();
          S[k].tail<3>() = Eigen::Vector3d::Unit(k);
        }
        rotation_subspace(xmat[b], to_origin, S + 3);
        break;
      case JointKind::kBall: rotation_subspace(xmat[b], to_origin, S); break;
      default: {  // a hinge
        const Eigen::Vector3d& axis = xaxis[j];
        S[0].head<3>() = axis;
        S[0].tail<3>() = cross(axis, to_origin);
      }
    }
  }
}

void check_jacobians(const Model& model, const Eigen::Ref<Eigen::MatrixXd>& jacp,
                     const Eigen::Ref<Eigen::MatrixXd>& jacr, const char* where) {
  for (const auto* J : {&jacp, &jacr}) {
    if (J->rows() != 3 || J->cols() != model.nv) {
      throw StateError(std::string(where) + ": a Jacobian must be 3 x " + std::to_string(model.nv) +
                       ", not " + std::to_string(J->rows()) + " x " + std::to_string(J->cols()) +
                       ".");
    }
  }
}

}  // namespace

void poses(const Model& model, Data& data) {
  check_entry(model, data, "lever::poses");
  place_bodies(model, data, Attached::kGeomsAndSites);
}

void kinematics(const Model& model, Data& data) {
  check_entry(model, data, "lever::kinematics");
  place_bodies(model, data, Attached::kGeomsAndSites);
  com_quantities(model, data);
}

void body_poses(const Model& model, Data& data) {
  check_entry(model, data, "lever::body_poses");
  normalize_state_quats(model, data);
  place_world<kFramesAlone>(data);
  place_every_body<kFramesAlone>(model, data);
}

void body_kinematics(const Model& model, Data& data) {
  check_entry(model, data, "lever::body_kinematics");
  place_bodies(model, data, Attached::kNone);
  com_quantities(model, data);
}

void place_site(const Model& model, Data& data, int site) {
  check_entry(model, data, "lever::place_site");
  if (site < 0 || site >= model.nsite) {
    throw StateError("lever::place_site: site " + std::to_string(site) + " is not in 0.." +
                     std::to_string(model.nsite - 1) + ".");
  }
  normalize_state_quats(model, data);
  // the path from the site's body to the world, then placed from the world outwards: each body
  // on its parent, as place_bodies() does, and no other body
  int* const path = data.work.body_path.data();
  int length = 0;
  for (int b = model.site_bodyid[site]; b > 0; b = model.body_parentid[b]) path[length++] = b;
  place_world<kFramesAlone>(data);
  while (length > 0) place_or_copy_body<kFramesAlone>(model, data, path[--length]);
  place_attached(1, &model.site_bodyid[site], &model.site_pos[site], &model.site_quat[site],
                 &model.site_placement[site], data, &data.site_xpos[site],
                 &data.site_xmat[site]);
}

namespace detail {

void step_kinematics(const Model& model, Data& data) {
  // nothing in a step reads the geom frames unless collision runs or a tendon wraps around a
  // geom; the site frames are what a caller reads after a step (an end effector's position), and
  // cost little
  place_bodies(model, data,
               model.contacts_possible || model.tendons_wrap_geoms ? Attached::kGeomsAndSites
                                                                   : Attached::kSites);
  com_quantities(model, data);
}

}  // namespace detail

// The Jacobians of a point fixed to a body, once the arguments are known to fit.
void detail::point_jacobians(const Model& model, const Data& data, int body, const Eigen::Vector3d& point,
                     Eigen::Ref<Eigen::MatrixXd> jacp, Eigen::Ref<Eigen::MatrixXd> jacr) {
  // write through column pointers: Eigen's dynamic-size assignment on a Ref costs more than the
  // arithmetic here
  double* const p = jacp.data();
  double* const r = jacr.data();
  const Eigen::Index p_stride = jacp.outerStride(), r_stride = jacr.outerStride();
  for (int i = 0; i < model.nv; ++i) {
    for (int row = 0; row < 3; ++row) p[i * p_stride + row] = r[i * r_stride + row] = 0.0;
  }
  const Eigen::Vector3d offset = point - data.subtree_com[model.body_rootid[body]];
  // the dofs between the body and the world: start at the nearest body that has any
  int b = body;
  while (b > 0 && model.body_dofnum[b] == 0) b = model.body_parentid[b];
  if (b == 0) return;
  for (int i = model.body_dofadr[b] + model.body_dofnum[b] - 1; i >= 0; i = model.dof_parentid[i]) {
    const Motion& S = data.cdof[i];
    const Eigen::Vector3d v =
        S.tail<3>() + cross(S.head<3>(), offset);  // point velocity per unit rate
    for (int row = 0; row < 3; ++row) {
      r[i * r_stride + row] = S[row];
      p[i * p_stride + row] = v[row];
    }
  }
}


void jac_point(const Model& model, const Data& data, int body, const Eigen::Vector3d& point,
               Eigen::Ref<Eigen::MatrixXd> jacp, Eigen::Ref<Eigen::MatrixXd> jacr) {
  check_entry(model, data, "lever::jac_point");
  check_jacobians(model, jacp, jacr, "lever::jac_point");
  if (body < 0 || body >= model.nbody) {
    throw StateError("lever::jac_point: body " + std::to_string(body) + " is not in 0.." +
                     std::to_string(model.nbody - 1) + ".");
  }
  detail::point_jacobians(model, data, body, point, jacp, jacr);
}

void jac_site(const Model& model, const Data& data, int site, Eigen::Ref<Eigen::MatrixXd> jacp,
              Eigen::Ref<Eigen::MatrixXd> jacr) {
  // checked here, before data.site_xpos is read, and named as the caller knows it
  check_entry(model, data, "lever::jac_site");
  check_jacobians(model, jacp, jacr, "lever::jac_site");
  if (site < 0 || site >= model.nsite) {
    throw StateError("lever::jac_site: site " + std::to_string(site) + " is not in 0.." +
                     std::to_string(model.nsite - 1) + ".");
  }
  detail::point_jacobians(model, data, model.site_bodyid[site], data.site_xpos[site], jacp, jacr);
}

namespace {

// The motion subspace of dof i (a cdof column) as com_quantities() computes it, from the joint
// frames and the tree's centre of mass c, and the velocity per unit rate of the point at `offset`
// from c: jac_site_from_q()'s column i, each number as point_jacobians() finds it from cdof.
inline void dof_column(const Model& model, const Data& data, int i, const Eigen::Vector3d& c,
                       const Eigen::Vector3d& offset, double* p, double* r) {
  const int j = model.dof_jntid[i];
  const int k = i - model.jnt_dofadr[j];  // which of the joint's dofs
  Motion S;
  switch (model.jnt_kind[j]) {
    case JointKind::kSlide:
      S.head<3>().setZero();
      S.tail<3>() = data.xaxis[j];
      break;
    case JointKind::kFree:
      if (k < 3) {  // a translation along a world axis
        S.head<3>().setZero();
        S.tail<3>() = Eigen::Vector3d::Unit(k);
        break;
      }
      [[fallthrough]];
    case JointKind::kBall: {  // a rotation about one of the body's axes (rotation_subspace's)
      const Eigen::Vector3d axis = data.xmat[model.jnt_bodyid[j]].col(k % 3);
      S.head<3>() = axis;
      S.tail<3>() = cross(axis, c - data.xanchor[j]);
      break;
    }
    default: {  // a hinge
      const Eigen::Vector3d& axis = data.xaxis[j];
      S.head<3>() = axis;
      S.tail<3>() = cross(axis, c - data.xanchor[j]);
    }
  }
  const Eigen::Vector3d v = S.tail<3>() + cross(S.head<3>(), offset);
  for (int row = 0; row < 3; ++row) {
    r[row] = S[row];
    p[row] = v[row];
  }
}

}  // namespace

void jac_site_from_q(const Model& model, Data& data, int site, Eigen::Ref<Eigen::MatrixXd> jacp,
                     Eigen::Ref<Eigen::MatrixXd> jacr) {
  check_entry(model, data, "lever::jac_site_from_q");
  check_jacobians(model, jacp, jacr, "lever::jac_site_from_q");
  if (site < 0 || site >= model.nsite) {
    throw StateError("lever::jac_site_from_q: site " + std::to_string(site) + " is not in 0.." +
                     std::to_string(model.nsite - 1) + ".");
  }
  normalize_state_quats(model, data);
  place_world<kForJacobian>(data);
  const int body = model.site_bodyid[site];
  const int root = model.body_rootid[body];
  // the bodies of the site's tree, whose centre of mass c is where cdof's moments are taken
  // (the Jacobian is c's to the last bit only if c is): each body's frame, its joints' frames and
  // its centre of mass, no inertial axes, no other tree
  const int* const rootid = model.body_rootid.data();
  const auto in_tree = [rootid, root](int b) { return rootid[b] == root; };
  if (root > 0) {
    // the leading bodies welded to the world copied (a tree's root may be one), the others
    // placed; a model without them keeps its loop from the root (see place_every_body)
    const int leading = model.body_static_leading;
    if (leading == 0) {
      for (int b = root; b < model.nbody; ++b) {
        if (in_tree(b)) place_body<kForJacobian>(model, data, b);
      }
    } else {
      for (int b = root; b <= leading; ++b) {
        if (in_tree(b)) copy_static_body<kForJacobian>(model, data, b);
      }
      for (int b = std::max(root, leading + 1); b < model.nbody; ++b) {
        if (in_tree(b)) place_body<kForJacobian>(model, data, b);
      }
    }
    subtree_centres(model, data, root, in_tree);
  }
  place_attached(1, &model.site_bodyid[site], &model.site_pos[site], &model.site_quat[site],
                 &model.site_placement[site], data, &data.site_xpos[site],
                 &data.site_xmat[site]);

  // the columns from the last dof down: an ancestor of the site's body gets its column, every
  // other dof zeros (for a chain, none)
  int b = body;
  while (b > 0 && model.body_dofnum[b] == 0) b = model.body_parentid[b];
  int next = b > 0 ? model.body_dofadr[b] + model.body_dofnum[b] - 1 : -1;
  const Eigen::Vector3d c = data.subtree_com[root];
  const Eigen::Vector3d offset = data.site_xpos[site] - c;
  double* const p = jacp.data();
  double* const r = jacr.data();
  const Eigen::Index p_stride = jacp.outerStride(), r_stride = jacr.outerStride();
  for (int i = model.nv - 1; i >= 0; --i) {
    if (i == next) {
      dof_column(model, data, i, c, offset, p + i * p_stride, r + i * r_stride);
      next = model.dof_parentid[i];
    } else {
      for (int row = 0; row < 3; ++row) p[i * p_stride + row] = r[i * r_stride + row] = 0.0;
    }
  }
}

}  // namespace lever
