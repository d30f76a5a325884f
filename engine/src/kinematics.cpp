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

#include "internal.hpp"

#include <cmath>

namespace lever {

namespace {

/// R <- R Rot_k(angle) for a turn about coordinate axis k of R's frame, given (c, s) = (cos,
/// sin) of the angle: column k stays, the other two turn into each other.
void turn_columns(Mat3& R, int k, double c, double s) {
  static constexpr int kNext[3] = {1, 2, 0};
  const int i = kNext[k], j = kNext[i];
  for (int row = 0; row < 3; ++row) {
    const double ri = R(row, i), rj = R(row, j);
    R(row, i) = c * ri + s * rj;
    R(row, j) = c * rj - s * ri;
  }
}

/// out = A B for 3x3 rotations (out is neither A nor B), row by row: row r of out is
/// A(r, 0) B.row(0) + A(r, 1) B.row(1) + A(r, 2) B.row(2), the rows' first two entries as one
/// pair (B is row-major) and the third alone, each sum in the order of the scalar product.
inline void multiply(const Mat3& A, const Mat3& B, Mat3& out) {
  for (int r = 0; r < 3; ++r) {
    const double a0 = A(r, 0), a1 = A(r, 1), a2 = A(r, 2);
    out.row(r).head<2>() =
        a0 * B.row(0).head<2>() + a1 * B.row(1).head<2>() + a2 * B.row(2).head<2>();
    out(r, 2) = a0 * B(0, 2) + a1 * B(1, 2) + a2 * B(2, 2);
  }
}

/// p + R v for a constant offset v placed as `f` says (lever/model.hpp FramePlacement): p, p plus
/// one column of R, or the whole product. The terms left out are products with zero.
inline Eigen::Vector3d offset_point(const Eigen::Vector3d& p, const Mat3& R,
                                    const Eigen::Vector3d& v, const FramePlacement& f) {
  switch (f.offset) {
    case FramePlacement::Offset::kZero: return p;
    case FramePlacement::Offset::kAlongAxis: {
      const int k = f.axis;
      const double x = v[k];
      return Eigen::Vector3d(p[0] + R(0, k) * x, p[1] + R(1, k) * x, p[2] + R(2, k) * x);
    }
    case FramePlacement::Offset::kGeneral: break;
  }
  return p + rotate(R, v);
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
  origin = offset_point(p, R, v, f);
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

// Body b's frame (xpos, xmat) on its parent's, which is placed, with qpos's quaternions
// normalized. With kOrientations, also its quaternion xquat, composed in MuJoCo's order; with
// kJointFrames, also its joints' anchors and axes (xanchor, xaxis) and its inertial frame (xipos,
// ximat). place_site() asks for the frame alone.
template <bool kOrientations, bool kJointFrames>
[[gnu::always_inline]] inline void place_body(const Model& model, Data& data, int b) {
  const int p = model.body_parentid[b];
  Mat3& R = data.xmat[b];
  Eigen::Vector3d pos;
  Quat quat;
  if (model.body_jntnum[b] == 1 && model.jnt_kind[model.body_jntadr[b]] == JointKind::kFree) {
    // a free body's pose is its qpos (body_pos and body_quat only gave qpos0); its joint's
    // anchor is the body's origin and its axis z, by MuJoCo's convention
    const int j = model.body_jntadr[b];
    const double* q = &data.qpos[model.jnt_qposadr[j]];
    pos = Eigen::Vector3d(q[0], q[1], q[2]);
    quat = Quat(q[3], q[4], q[5], q[6]);
    R = quat_to_mat(quat);
    if constexpr (kJointFrames) {
      data.xanchor[j] = pos;
      data.xaxis[j] = Eigen::Vector3d::UnitZ();
    }
  } else {
    const FramePlacement& placement = model.body_placement[b];
    place_frame(data.xpos[p], data.xmat[p], model.body_pos[b], model.body_mat[b], placement, pos,
                R);
    if constexpr (kOrientations) {
      const bool turned = placement.turn != FramePlacement::Turn::kNone;
      quat = turned ? quat_mul(data.xquat[p], model.body_quat[b]) : data.xquat[p];
    }
  }

  for (int k = 0; k < model.body_jntnum[b]; ++k) {
    const int j = model.body_jntadr[b] + k;
    const JointKind kind = model.jnt_kind[j];
    if (kind == JointKind::kFree) break;  // placed above
    const int qadr = model.jnt_qposadr[j];
    const Eigen::Vector3d& axis = model.jnt_axis[j];
    // the joint's anchor and world axis, kept in Data only when asked for
    const Eigen::Vector3d anchor =
        model.jnt_offset[j] ? Eigen::Vector3d(pos + rotate(R, model.jnt_pos[j])) : pos;
    if constexpr (kJointFrames) data.xanchor[j] = anchor;
    Eigen::Vector3d world_axis;
    switch (kind) {
      case JointKind::kSlide:
        world_axis = rotate(R, axis);
        if constexpr (kJointFrames) data.xaxis[j] = world_axis;
        pos += world_axis * (data.qpos[qadr] - model.qpos0[qadr]);
        continue;               // nothing turns: the anchor need not be kept
      case JointKind::kBall: {  // qpos is the turn itself, a unit quaternion
        const Quat turn(data.qpos[qadr], data.qpos[qadr + 1], data.qpos[qadr + 2],
                        data.qpos[qadr + 3]);
        if constexpr (kJointFrames) data.xaxis[j] = rotate(R, axis);
        const Mat3 before = R;
        multiply(before, quat_to_mat(turn), R);
        if constexpr (kOrientations) quat = quat_mul(quat, turn);
        break;
      }
      default: {  // a hinge: half angles for the quaternion, the whole angle for R
        const double half = 0.5 * (data.qpos[qadr] - model.qpos0[qadr]);
        const double sh = std::sin(half), ch = std::cos(half);
        const double c = ch * ch - sh * sh, s = 2.0 * sh * ch;
        if (kind == JointKind::kHinge) {
          if constexpr (kJointFrames) data.xaxis[j] = rotate(R, axis);
          const Mat3 before = R;
          multiply(before, axis_rotation(axis, c, s), R);
          if constexpr (kOrientations)
            quat = quat_mul(quat, Quat(ch, axis[0] * sh, axis[1] * sh, axis[2] * sh));
        } else {  // about coordinate axis k of the frame, signed: R's column k is the axis
          const int about = static_cast<int>(kind) - static_cast<int>(JointKind::kHingeX);
          const double sign = axis[about];
          if constexpr (kJointFrames) data.xaxis[j] = sign * R.col(about);
          turn_columns(R, about, c, sign * s);
          if constexpr (kOrientations) quat = quat_mul_axis(quat, about, ch, sign * sh);
        }
      }
    }
    // the anchor stays where it is: the frame's origin swings around it
    if (model.jnt_offset[j]) pos = anchor - rotate(R, model.jnt_pos[j]);
  }

  if constexpr (kOrientations) data.xquat[b] = quat_renormalized(quat);
  data.xpos[b] = pos;
  if constexpr (kJointFrames) {
    place_frame(pos, R, model.body_ipos[b], model.body_imat[b], model.body_iplacement[b],
                data.xipos[b], data.ximat[b]);
  }
}

inline void place_site_frame(const Model& model, Data& data, int s) {
  const int b = model.site_bodyid[s];
  place_frame(data.xpos[b], data.xmat[b], model.site_pos[s], model.site_mat[s],
              model.site_placement[s], data.site_xpos[s], data.site_xmat[s]);
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
  if (placed.orientations) {
    for (int b = 1; b < model.nbody; ++b) place_body<true, true>(model, data, b);
  } else {
    for (int b = 1; b < model.nbody; ++b) place_body<false, true>(model, data, b);
  }

  for (int g = 0; g < (placed.geoms ? model.ngeom : 0); ++g) {
    const int b = model.geom_bodyid[g];
    place_frame(data.xpos[b], data.xmat[b], model.geom_pos[g], model.geom_mat[g],
                model.geom_placement[g], data.geom_xpos[g], data.geom_xmat[g]);
  }

  for (int s = 0; s < model.nsite; ++s) place_site_frame(model, data, s);
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
void com_quantities(const Model& model, Data& data) {
  // mass-weighted positions, summed leaves to root
  for (int b = 0; b < model.nbody; ++b) data.subtree_com[b] = model.body_mass[b] * data.xipos[b];
  for (int b = model.nbody - 1; b > 0; --b) {
    data.subtree_com[model.body_parentid[b]] += data.subtree_com[b];
  }
  for (int b = 0; b < model.nbody; ++b) {
    const double m = model.body_subtreemass[b];
    data.subtree_com[b] = m < 1e-15 ? data.xipos[b] : Eigen::Vector3d(data.subtree_com[b] / m);
  }

  // each body's inertia about its tree's centre of mass, world axes
  for (int b = 1; b < model.nbody; ++b) {
    const Eigen::Vector3d c = data.xipos[b] - data.subtree_com[model.body_rootid[b]];
    world_inertia(data.ximat[b], model.body_inertia[b], model.body_mass[b], c, data.cinert[b]);
  }

  // each dof's motion subspace: [a; a x (c - p)] for a rotation about world axis a through
  // anchor p, [0; a] for a translation along a
  for (int j = 0; j < model.njnt; ++j) {
    const int i = model.jnt_dofadr[j];
    const int b = model.jnt_bodyid[j];
    const Eigen::Vector3d to_origin = data.subtree_com[model.body_rootid[b]] - data.xanchor[j];
    switch (model.jnt_kind[j]) {
      case JointKind::kSlide:
        data.cdof[i].head<3>().setZero();
        data.cdof[i].tail<3>() = data.xaxis[j];
        break;
      case JointKind::kFree:
        // three translations along the world axes, then three rotations as a ball's
        for (int k = 0; k < 3; ++k) {
          data.cdof[i + k].head<3>().setZero();
          data.cdof[i + k].tail<3>() = Eigen::Vector3d::Unit(k);
        }
        rotation_subspace(data.xmat[b], to_origin, &data.cdof[i + 3]);
        break;
      case JointKind::kBall: rotation_subspace(data.xmat[b], to_origin, &data.cdof[i]); break;
      default: {  // a hinge
        const Eigen::Vector3d& axis = data.xaxis[j];
        data.cdof[i].head<3>() = axis;
        data.cdof[i].tail<3>() = cross(axis, to_origin);
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
  while (length > 0) place_body<false, false>(model, data, path[--length]);
  place_site_frame(model, data, site);
}

namespace detail {

void step_kinematics(const Model& model, Data& data) {
  // nothing in a step reads xquat, nor the geom frames unless collision runs; the site frames
  // are what a caller reads after a step (an end effector's position), and cost little
  place_bodies(model, data, {.orientations = false, .geoms = model.contacts_possible});
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
