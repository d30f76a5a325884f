// Forward kinematics, the spatial quantities every algorithm shares, and point Jacobians.
//
// Poses compose from the root outwards, body by body, joint by joint, as MuJoCo's mj_kinematics:
// a body starts at its parent's frame moved by (body_pos, body_quat); a hinge then turns it about
// the joint's axis through the joint's anchor, a slide moves it along the axis. Orientations are
// quaternions (normalized once per body, so xquat has MuJoCo's sign and xmat stays orthonormal).
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

// Body poses, joint anchors and axes; then inertial frames and sites.
void poses(const Model& model, Data& data) {
  detail::normalize_joint_quats(model, data.qpos.data());
  Eigen::Matrix3d turned;  // the body's rotation, when a joint needs it as a matrix
  for (int b = 1; b < model.nbody; ++b) {
    const int p = model.body_parentid[b];
    const Mat3& parent = data.xmat[p];
    Eigen::Vector3d pos;
    Quat quat;
    if (model.body_jntnum[b] == 1 && model.jnt_kind[model.body_jntadr[b]] == JointKind::kFree) {
      // a free body's pose is its qpos (body_pos and body_quat only gave qpos0); its joint's
      // anchor is the body's origin and its axis z, by MuJoCo's convention
      const int j = model.body_jntadr[b];
      const double* q = &data.qpos[model.jnt_qposadr[j]];
      pos = Eigen::Vector3d(q[0], q[1], q[2]);
      quat = Quat(q[3], q[4], q[5], q[6]);
      data.xanchor[j] = pos;
      data.xaxis[j] = Eigen::Vector3d::UnitZ();
    } else {
      pos = data.xpos[p] + rotate(parent, model.body_pos[b]);
      quat = model.body_rotated[b] ? quat_mul(data.xquat[p], model.body_quat[b]) : data.xquat[p];
    }

    for (int k = 0; k < model.body_jntnum[b]; ++k) {
      const int j = model.body_jntadr[b] + k;
      const JointKind kind = model.jnt_kind[j];
      if (kind == JointKind::kFree) break;  // placed above
      const int qadr = model.jnt_qposadr[j];
      const Eigen::Vector3d& axis = model.jnt_axis[j];
      if (k == 0) {
        // the body's first joint: its axis and anchor are constant in the parent's frame
        data.xaxis[j] = rotate(parent, model.jnt_axis_in_parent[j]);
        data.xanchor[j] = model.jnt_offset[j]
                              ? Eigen::Vector3d(pos + rotate(parent, model.jnt_pos_in_parent[j]))
                              : pos;
      } else {
        turned = quat_to_mat(quat);  // the body turned by its earlier joints
        data.xaxis[j] = rotate(turned, axis);
        data.xanchor[j] =
            model.jnt_offset[j] ? Eigen::Vector3d(pos + rotate(turned, model.jnt_pos[j])) : pos;
      }
      if (kind == JointKind::kSlide) {
        pos += data.xaxis[j] * (data.qpos[qadr] - model.qpos0[qadr]);
        continue;
      }
      if (kind == JointKind::kBall) {  // qpos is the turn itself, a unit quaternion
        const double* q = &data.qpos[qadr];
        quat = quat_mul(quat, Quat(q[0], q[1], q[2], q[3]));
      } else {
        const double theta = data.qpos[qadr] - model.qpos0[qadr];
        const double s = std::sin(0.5 * theta), c = std::cos(0.5 * theta);
        if (kind == JointKind::kHinge) {
          quat = quat_mul(quat, Quat(c, axis[0] * s, axis[1] * s, axis[2] * s));
        } else {  // about a coordinate axis: two of the turn's components are zero
          const int about = static_cast<int>(kind) - static_cast<int>(JointKind::kHingeX);
          quat = quat_mul_axis(quat, about, c, axis[about] * s);
        }
      }
      // the anchor stays where it is: the frame's origin swings around it
      if (model.jnt_offset[j]) {
        turned = quat_to_mat(quat);
        pos = data.xanchor[j] - rotate(turned, model.jnt_pos[j]);
      }
    }

    data.xquat[b] = quat_renormalized(quat);
    data.xmat[b] = quat_to_mat(data.xquat[b]);
    data.xpos[b] = pos;
    data.xipos[b] = pos + rotate(data.xmat[b], model.body_ipos[b]);
    if (model.body_irotated[b]) {
      data.ximat[b].noalias() = data.xmat[b] * model.body_imat[b];
    } else {
      data.ximat[b] = data.xmat[b];
    }
    data.subtree_com[b] = model.body_mass[b] * data.xipos[b];  // summed up in com_quantities()
  }

  for (int g = 0; g < model.ngeom; ++g) {
    const int b = model.geom_bodyid[g];
    data.geom_xpos[g] = data.xpos[b] + rotate(data.xmat[b], model.geom_pos[g]);
    if (model.geom_rotated[g]) {
      data.geom_xmat[g].noalias() = data.xmat[b] * model.geom_mat[g];
    } else {
      data.geom_xmat[g] = data.xmat[b];
    }
  }

  for (int s = 0; s < model.nsite; ++s) {
    const int b = model.site_bodyid[s];
    data.site_xpos[s] = data.xpos[b] + rotate(data.xmat[b], model.site_pos[s]);
    if (model.site_rotated[s]) {
      data.site_xmat[s].noalias() = data.xmat[b] * model.site_mat[s];
    } else {
      data.site_xmat[s] = data.xmat[b];
    }
  }
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

// Subtree centres of mass, body inertias and joint motion subspaces in absolute coordinates.
void com_quantities(const Model& model, Data& data) {
  // mass-weighted positions (poses() left each body's own), summed leaves to root
  data.subtree_com[0] = model.body_mass[0] * data.xipos[0];
  for (int b = model.nbody - 1; b > 0; --b) {
    data.subtree_com[model.body_parentid[b]] += data.subtree_com[b];
  }
  for (int b = 0; b < model.nbody; ++b) {
    const double m = model.body_subtreemass[b];
    data.subtree_com[b] = m < 1e-15 ? data.xipos[b] : Eigen::Vector3d(data.subtree_com[b] / m);
  }

  // each body's inertia about its tree's centre of mass, world axes: I_world = R diag(I) R^T
  for (int b = 1; b < model.nbody; ++b) {
    const Mat3& R = data.ximat[b];
    const Eigen::Vector3d& d = model.body_inertia[b];
    // column k of R scaled by the principal moment about it
    const Eigen::Matrix3d RD = R * d.asDiagonal();
    Eigen::Matrix3d Iw;
    Iw(0, 0) = RD(0, 0) * R(0, 0) + RD(0, 1) * R(0, 1) + RD(0, 2) * R(0, 2);
    Iw(1, 1) = RD(1, 0) * R(1, 0) + RD(1, 1) * R(1, 1) + RD(1, 2) * R(1, 2);
    Iw(2, 2) = RD(2, 0) * R(2, 0) + RD(2, 1) * R(2, 1) + RD(2, 2) * R(2, 2);
    Iw(0, 1) = Iw(1, 0) = RD(0, 0) * R(1, 0) + RD(0, 1) * R(1, 1) + RD(0, 2) * R(1, 2);
    Iw(0, 2) = Iw(2, 0) = RD(0, 0) * R(2, 0) + RD(0, 1) * R(2, 1) + RD(0, 2) * R(2, 2);
    Iw(1, 2) = Iw(2, 1) = RD(1, 0) * R(2, 0) + RD(1, 1) * R(2, 1) + RD(1, 2) * R(2, 2);
    const Eigen::Vector3d c = data.xipos[b] - data.subtree_com[model.body_rootid[b]];
    data.cinert[b] = RigidInertia::from_com(model.body_mass[b], c, Iw);
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

void kinematics(const Model& model, Data& data) {
  check_entry(model, data, "lever::kinematics");
  poses(model, data);
  com_quantities(model, data);
}

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
