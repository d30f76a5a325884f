// Forward kinematics, the spatial quantities every algorithm shares, and point Jacobians.
//
// Poses compose from the root outwards, body by body, joint by joint, as MuJoCo's mj_kinematics:
// a body starts at its parent's frame moved by (body_pos, body_quat); a hinge then turns it about
// the joint's axis through the joint's anchor, a slide moves it along the axis. The recursion
// carries each frame as a rotation matrix and an origin (R, p), and does for each joint kind only
// the arithmetic it needs: a hinge about a coordinate axis of its frame (arm2's -y, every Panda
// joint's z) turns two columns of R. So for each constant frame (a body on its parent, its inertial
// frame, a geom, a site), as set_const classified it (lever/model.hpp FramePlacement): an offset
// that is zero or along one axis takes one column of R, a frame that is not turned or is turned by
// a quarter turn copies R's columns; only the others pay for the whole product. The orientations as
// quaternions (xquat) are composed beside it only when asked: kinematics() does, in MuJoCo's order,
// so that xquat has MuJoCo's sign.
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

#include <cmath>

namespace lever {

namespace {

/// R <- R Rot_k(angle) for a turn about coordinate axis k of R's frame, given (c, s) = (cos,
/// sin) of the angle: column k stays, the other two turn into each other.
template <int k>
inline void turn_columns(Mat3& R, double c, double s) {
  constexpr int i = (k + 1) % 3, j = (k + 2) % 3;
  for (int row = 0; row < 3; ++row) {
    const double ri = R(row, i), rj = R(row, j);
    R(row, i) = c * ri + s * rj;
    R(row, j) = c * rj - s * ri;
  }
}

/// out = A B for 3x3 rotations (out is neither A nor B), row by row: row r of out is
/// A(r, 0) B.row(0) + A(r, 1) B.row(1) + A(r, 2) B.row(2), the rows' first two entries as one
/// pair (B is row-major) and the third alone, each sum in the order of the scalar product. B is
/// read once, before out is written (to the compiler, a store into out could change B).
inline void multiply(const Mat3& A, const Mat3& B, Mat3& out) {
  const Eigen::RowVector2d b0 = B.row(0).head<2>(), b1 = B.row(1).head<2>(),
                           b2 = B.row(2).head<2>();
  const double b02 = B(0, 2), b12 = B(1, 2), b22 = B(2, 2);
  for (int r = 0; r < 3; ++r) {
    const double a0 = A(r, 0), a1 = A(r, 1), a2 = A(r, 2);
    out.row(r).head<2>() = a0 * b0 + a1 * b1 + a2 * b2;
    out(r, 2) = a0 * b02 + a1 * b12 + a2 * b22;
  }
}

/// origin = p + R v for a constant offset v placed as `f` says (lever/model.hpp FramePlacement):
/// p, p plus one column of R, or the whole product; the terms left out are products with zero.
/// Written entry by entry, so that no temporary is copied into `origin` (which may be p).
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

/// out = R B for a constant rotation B placed as `f` says: R, R's columns moved and signed (a
/// quarter turn), or the product. out is not R.
inline void turn_frame(const Mat3& R, const Mat3& B, const FramePlacement& f, Mat3& out) {
  switch (f.turn) {
    case FramePlacement::Turn::kNone: out = R; return;
    case FramePlacement::Turn::kQuarter:
      for (int c = 0; c < 3; ++c) {
        const int k = f.column[c];
        const double sign = f.sign[c];
        out(0, c) = sign * R(0, k);
        out(1, c) = sign * R(1, k);
        out(2, c) = sign * R(2, k);
      }
      return;
    case FramePlacement::Turn::kGeneral: break;
  }
  multiply(R, B, out);
}

/// A constant frame (offset v, rotation B, placed as `f` says) on the frame (p, R): its origin
/// and rotation.
inline void place_frame(const Eigen::Vector3d& p, const Mat3& R, const Eigen::Vector3d& v,
                        const Mat3& B, const FramePlacement& f, Eigen::Vector3d& origin,
                        Mat3& rotation) {
  offset_point(p, R, v, f, origin);
  turn_frame(R, B, f, rotation);
}

/// The rotation by angle (c, s) = (cos, sin) about a unit axis, as a matrix (Rodrigues).
Mat3 axis_rotation(const Eigen::Vector3d& a, double c, double s) {
  const double t = 1.0 - c;
  Mat3 out;
  out << c + t * a[0] * a[0], t * a[0] * a[1] - s * a[2], t * a[0] * a[2] + s * a[1],
      t * a[0] * a[1] + s * a[2], c + t * a[1] * a[1], t * a[1] * a[2] - s * a[0],
      t * a[0] * a[2] - s * a[1], t * a[1] * a[2] + s * a[0], c + t * a[2] * a[2];
  return out;
}

// The arrays the placement reads and writes, each vector's data pointer loaded once per call:
// read through the std::vectors, every store into one array would make the compiler load the
// next array's data pointer again (Eigen's packet stores may alias any object).
struct BodyArrays {
  BodyArrays(const Model& model, Data& data)
      : parentid(model.body_parentid.data()),
        jntnum(model.body_jntnum.data()),
        jntadr(model.body_jntadr.data()),
        body_pos(model.body_pos.data()),
        body_quat(model.body_quat.data()),
        body_mat(model.body_mat.data()),
        body_placement(model.body_placement.data()),
        body_ipos(model.body_ipos.data()),
        body_imat(model.body_imat.data()),
        body_iplacement(model.body_iplacement.data()),
        jnt_kind(model.jnt_kind.data()),
        jnt_offset(model.jnt_offset.data()),
        jnt_qposadr(model.jnt_qposadr.data()),
        jnt_pos(model.jnt_pos.data()),
        jnt_axis(model.jnt_axis.data()),
        qpos0(model.qpos0.data()),
        qpos(data.qpos.data()),
        xpos(data.xpos.data()),
        xmat(data.xmat.data()),
        xquat(data.xquat.data()),
        xipos(data.xipos.data()),
        ximat(data.ximat.data()),
        xanchor(data.xanchor.data()),
        xaxis(data.xaxis.data()) {}

  // the model's
  const int *parentid, *jntnum, *jntadr;
  const Eigen::Vector3d* body_pos;
  const Quat* body_quat;
  const Mat3* body_mat;
  const FramePlacement* body_placement;
  const Eigen::Vector3d* body_ipos;
  const Mat3* body_imat;
  const FramePlacement* body_iplacement;
  const JointKind* jnt_kind;
  const uint8_t* jnt_offset;
  const int* jnt_qposadr;
  const Eigen::Vector3d *jnt_pos, *jnt_axis;
  const double* qpos0;
  // the state and what is placed
  const double* qpos;
  Eigen::Vector3d* xpos;
  Mat3* xmat;
  Quat* xquat;
  Eigen::Vector3d* xipos;
  Mat3* ximat;
  Eigen::Vector3d *xanchor, *xaxis;
};

// R and quat turned by hinge j about coordinate axis k of the body's frame (set_const's
// kHingeX, kHingeY, kHingeZ), given (ch, sh) = (cos, sin) of half its angle: R's column k, signed
// with the joint's axis, is the world axis.
template <int k, bool kOrientations, bool kJointFrames>
[[gnu::always_inline]] inline void turn_about_axis(const BodyArrays& a, int j, double ch, double sh,
                                                   Mat3& R, Quat& quat) {
  const double sign = a.jnt_axis[j][k];
  if constexpr (kJointFrames) a.xaxis[j] = sign * R.col(k);
  turn_columns<k>(R, ch * ch - sh * sh, sign * (2.0 * sh * ch));
  if constexpr (kOrientations) quat = quat_mul_axis(quat, k, ch, sign * sh);
}

// The frame (pos, R) and its quaternion moved by joint j of its body (not a free joint).
template <bool kOrientations, bool kJointFrames>
[[gnu::always_inline]] inline void move_joint(const BodyArrays& a, int j, Eigen::Vector3d& pos,
                                              Mat3& R, Quat& quat) {
  const JointKind kind = a.jnt_kind[j];
  const int qadr = a.jnt_qposadr[j];
  const double* q = a.qpos + qadr;
  const Eigen::Vector3d& axis = a.jnt_axis[j];
  // the joint's anchor and world axis, kept in Data only when asked for
  const bool offset = a.jnt_offset[j];
  const Eigen::Vector3d anchor = offset ? Eigen::Vector3d(pos + rotate(R, a.jnt_pos[j])) : pos;
  if constexpr (kJointFrames) a.xanchor[j] = anchor;
  switch (kind) {
    case JointKind::kSlide: {
      const Eigen::Vector3d world_axis = rotate(R, axis);
      if constexpr (kJointFrames) a.xaxis[j] = world_axis;
      pos += world_axis * (q[0] - a.qpos0[qadr]);
      return;  // nothing turns: the anchor need not be kept
    }
    case JointKind::kBall: {  // qpos is the turn itself, a unit quaternion
      const Quat turn(q[0], q[1], q[2], q[3]);
      if constexpr (kJointFrames) a.xaxis[j] = rotate(R, axis);
      const Mat3 before = R;
      multiply(before, quat_to_mat(turn), R);
      if constexpr (kOrientations) quat = quat_mul(quat, turn);
      break;
    }
    default: {  // a hinge: half angles for the quaternion, the whole angle for R
      const double half = 0.5 * (q[0] - a.qpos0[qadr]);
      const double sh = std::sin(half), ch = std::cos(half);
      switch (kind) {
        case JointKind::kHingeX:
          turn_about_axis<0, kOrientations, kJointFrames>(a, j, ch, sh, R, quat);
          break;
        case JointKind::kHingeY:
          turn_about_axis<1, kOrientations, kJointFrames>(a, j, ch, sh, R, quat);
          break;
        case JointKind::kHingeZ:
          turn_about_axis<2, kOrientations, kJointFrames>(a, j, ch, sh, R, quat);
          break;
        default: {
          const double c = ch * ch - sh * sh, s = 2.0 * sh * ch;
          if constexpr (kJointFrames) a.xaxis[j] = rotate(R, axis);
          const Mat3 before = R;
          multiply(before, axis_rotation(axis, c, s), R);
          if constexpr (kOrientations)
            quat = quat_mul(quat, Quat(ch, axis[0] * sh, axis[1] * sh, axis[2] * sh));
        }
      }
    }
  }
  // the anchor stays where it is: the frame's origin swings around it
  if (offset) pos = anchor - rotate(R, a.jnt_pos[j]);
}

// Body b's frame (xpos, xmat) on its parent's, which is placed, with qpos's quaternions
// normalized. With kOrientations, also its quaternion xquat, composed in MuJoCo's order; with
// kJointFrames, also its joints' anchors and axes (xanchor, xaxis) and its inertial frame (xipos,
// ximat). place_site() asks for the frame alone.
template <bool kOrientations, bool kJointFrames>
[[gnu::always_inline]] inline void place_body(const BodyArrays& a, int b) {
  const int p = a.parentid[b];
  const int first_joint = a.jntadr[b], last_joint = first_joint + a.jntnum[b];
  // composed in place in Data: nothing of the body's pose is held in registers across the calls
  // to sincos, which would save and restore it
  Eigen::Vector3d& pos = a.xpos[b];
  Mat3& R = a.xmat[b];
  Quat& quat = a.xquat[b];
  if (last_joint == first_joint + 1 && a.jnt_kind[first_joint] == JointKind::kFree) {
    // a free body's pose is its qpos (body_pos and body_quat only gave qpos0); its joint's
    // anchor is the body's origin and its axis z, by MuJoCo's convention
    const double* q = a.qpos + a.jnt_qposadr[first_joint];
    const Quat turn(q[3], q[4], q[5], q[6]);
    pos = Eigen::Vector3d(q[0], q[1], q[2]);
    R = quat_to_mat(turn);
    if constexpr (kOrientations) quat = quat_renormalized(turn);
    if constexpr (kJointFrames) {
      a.xanchor[first_joint] = pos;
      a.xaxis[first_joint] = Eigen::Vector3d::UnitZ();
    }
  } else {
    const FramePlacement& placement = a.body_placement[b];
    place_frame(a.xpos[p], a.xmat[p], a.body_pos[b], a.body_mat[b], placement, pos, R);
    if constexpr (kOrientations) {
      if (placement.turn != FramePlacement::Turn::kNone) {
        quat = quat_mul(a.xquat[p], a.body_quat[b]);
      } else {
        quat = a.xquat[p];
      }
    }
    // no free joint here: validate() allows one only as its body's single joint
    for (int j = first_joint; j < last_joint; ++j) {
      move_joint<kOrientations, kJointFrames>(a, j, pos, R, quat);
    }
    if constexpr (kOrientations) quat = quat_renormalized(quat);
  }
  if constexpr (kJointFrames) {
    place_frame(pos, R, a.body_ipos[b], a.body_imat[b], a.body_iplacement[b], a.xipos[b],
                a.ximat[b]);
  }
}

// Constant frames on their bodies (geoms, sites): frame i of n at (pos[i], mat[i]), placed as
// placement[i] says, on body bodyid[i], into (xpos[i], xmat[i]).
void place_attached(int n, const int* bodyid, const Eigen::Vector3d* pos, const Mat3* mat,
                    const FramePlacement* placement, const Eigen::Vector3d* body_xpos,
                    const Mat3* body_xmat, Eigen::Vector3d* xpos, Mat3* xmat) {
  for (int i = 0; i < n; ++i) {
    const int b = bodyid[i];
    place_frame(body_xpos[b], body_xmat[b], pos[i], mat[i], placement[i], xpos[i], xmat[i]);
  }
}

// The world's frame, which every other frame is placed on: set on every call, as MuJoCo's
// mj_kinematics does, so that a value a caller wrote into it cannot move the robot. Its
// quaternion only with the others (poses() and place_site() compose none).
inline void place_world(Data& data, bool orientation) {
  data.xpos[0].setZero();
  data.xmat[0].setIdentity();
  data.xipos[0].setZero();
  data.ximat[0].setIdentity();
  if (orientation) data.xquat[0] = Quat(1.0, 0.0, 0.0, 0.0);
}

// What place_bodies() writes besides the body frames, joint anchors and axes, inertial frames and
// site frames.
struct Placed {
  bool orientations;  // the bodies' quaternions (xquat), composed in MuJoCo's order
  bool geoms;         // geom_xpos, geom_xmat
};

// Body frames (xpos, xmat), joint anchors and axes, inertial frames, sites, and what `placed` asks
// for.
void place_bodies(const Model& model, Data& data, Placed placed) {
  // only ball and free joints have quaternions in qpos, and only they make nq exceed nv
  if (model.nq > model.nv) detail::normalize_joint_quats(model, data.qpos.data());
  place_world(data, placed.orientations);
  const BodyArrays arrays(model, data);
  const int nbody = model.nbody;
  if (placed.orientations) {
    for (int b = 1; b < nbody; ++b) place_body<true, true>(arrays, b);
  } else {
    for (int b = 1; b < nbody; ++b) place_body<false, true>(arrays, b);
  }
  if (placed.geoms) {
    place_attached(model.ngeom, model.geom_bodyid.data(), model.geom_pos.data(),
                   model.geom_mat.data(), model.geom_placement.data(), arrays.xpos, arrays.xmat,
                   data.geom_xpos.data(), data.geom_xmat.data());
  }
  place_attached(model.nsite, model.site_bodyid.data(), model.site_pos.data(),
                 model.site_mat.data(), model.site_placement.data(), arrays.xpos, arrays.xmat,
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
// axes R = ximat, principal moments d) moved to the point by the parallel-axis theorem
// (RigidInertia::from_com's arithmetic), written into out's members: the symmetric product's six
// entries once each, no temporary.
inline void world_inertia(const Mat3& R, const Eigen::Vector3d& d, double m,
                          const Eigen::Vector3d& c, RigidInertia& out) {
  double Rd[3][3];  // column k of R scaled by the principal moment about it
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) Rd[r][k] = R(r, k) * d[k];
  }
  const auto entry = [&](int r, int s) {  // row r of R diag(d) against row s of R
    return Rd[r][0] * R(s, 0) + Rd[r][1] * R(s, 1) + Rd[r][2] * R(s, 2);
  };
  const Eigen::Vector3d mc = m * c;
  out.m = m;
  out.h = mc;
  Eigen::Matrix3d& I = out.I;
  I(0, 0) = entry(0, 0) + (mc[1] * c[1] + mc[2] * c[2]);
  I(1, 1) = entry(1, 1) + (mc[0] * c[0] + mc[2] * c[2]);
  I(2, 2) = entry(2, 2) + (mc[0] * c[0] + mc[1] * c[1]);
  I(0, 1) = I(1, 0) = entry(0, 1) - mc[0] * c[1];
  I(0, 2) = I(2, 0) = entry(0, 2) - mc[0] * c[2];
  I(1, 2) = I(2, 1) = entry(1, 2) - mc[1] * c[2];
}

// Subtree centres of mass, body inertias and joint motion subspaces in absolute coordinates.
// Each array's data pointer is loaded once (see BodyArrays).
void com_quantities(const Model& model, Data& data) {
  const int nbody = model.nbody;
  const int* const parentid = model.body_parentid.data();
  const int* const rootid = model.body_rootid.data();
  const double* const mass = model.body_mass.data();
  const double* const subtreemass = model.body_subtreemass.data();
  const Eigen::Vector3d* const inertia = model.body_inertia.data();
  const Eigen::Vector3d* const xipos = data.xipos.data();
  const Mat3* const ximat = data.ximat.data();
  Eigen::Vector3d* const subtree_com = data.subtree_com.data();
  RigidInertia* const cinert = data.cinert.data();

  // mass-weighted positions, summed leaves to root
  for (int b = 0; b < nbody; ++b) subtree_com[b] = mass[b] * xipos[b];
  for (int b = nbody - 1; b > 0; --b) subtree_com[parentid[b]] += subtree_com[b];
  for (int b = 0; b < nbody; ++b) {
    const double m = subtreemass[b];
    subtree_com[b] = m < detail::kMinVal ? xipos[b] : Eigen::Vector3d(subtree_com[b] / m);
  }

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
  place_bodies(model, data, {.orientations = false, .geoms = true});
}

void kinematics(const Model& model, Data& data) {
  check_entry(model, data, "lever::kinematics");
  place_bodies(model, data, {.orientations = true, .geoms = true});
  com_quantities(model, data);
}

void place_site(const Model& model, Data& data, int site) {
  check_entry(model, data, "lever::place_site");
  if (site < 0 || site >= model.nsite) {
    throw StateError("lever::place_site: site " + std::to_string(site) + " is not in 0.." +
                     std::to_string(model.nsite - 1) + ".");
  }
  if (model.nq > model.nv) detail::normalize_joint_quats(model, data.qpos.data());
  // the path from the site's body to the world, then placed from the world outwards: each body
  // on its parent, as place_bodies() does, and no other body
  int* const path = data.work.body_path.data();
  int length = 0;
  for (int b = model.site_bodyid[site]; b > 0; b = model.body_parentid[b]) path[length++] = b;
  place_world(data, false);
  const BodyArrays arrays(model, data);
  while (length > 0) place_body<false, false>(arrays, path[--length]);
  place_attached(1, &model.site_bodyid[site], &model.site_pos[site], &model.site_mat[site],
                 &model.site_placement[site], arrays.xpos, arrays.xmat, &data.site_xpos[site],
                 &data.site_xmat[site]);
}

namespace detail {

void step_kinematics(const Model& model, Data& data) {
  // nothing in a step reads xquat but a weld's rows (equality constraints), nor the geom frames
  // unless collision runs; the site frames are what a caller reads after a step (an end
  // effector's position), and cost little
  place_bodies(model, data, {.orientations = model.neq > 0, .geoms = model.contacts_possible});
  com_quantities(model, data);
}

}  // namespace detail

namespace {

// The Jacobians of a point fixed to a body, once the arguments are known to fit.
void point_jacobians(const Model& model, const Data& data, int body, const Eigen::Vector3d& point,
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

}  // namespace

void jac_point(const Model& model, const Data& data, int body, const Eigen::Vector3d& point,
               Eigen::Ref<Eigen::MatrixXd> jacp, Eigen::Ref<Eigen::MatrixXd> jacr) {
  check_entry(model, data, "lever::jac_point");
  check_jacobians(model, jacp, jacr, "lever::jac_point");
  if (body < 0 || body >= model.nbody) {
    throw StateError("lever::jac_point: body " + std::to_string(body) + " is not in 0.." +
                     std::to_string(model.nbody - 1) + ".");
  }
  point_jacobians(model, data, body, point, jacp, jacr);
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
  point_jacobians(model, data, model.site_bodyid[site], data.site_xpos[site], jacp, jacr);
}

}  // namespace lever
