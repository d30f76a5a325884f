// Forward kinematics and site Jacobians.
//
// Each link's pose relative to its parent link is its constant tree pose followed by its joint's
// motion (Featherstone's Xup = XJ Xtree); world poses compose these from the root outwards, as
// MuJoCo's mj_kinematics does. Bodies and sites then hang from their link by constant offsets.
// Orientations are carried as quaternions and normalized at every link, so that xquat matches
// MuJoCo's (same composition order, same sign) and xmat stays orthonormal.
#include <lever/kinematics.hpp>

#include <cmath>

namespace lever {

namespace {

// Pose of link i relative to its parent link at joint displacement theta = qpos - qpos0.
struct RelativePose {
  Quat quat;
  Eigen::Matrix3d R;
  Eigen::Vector3d pos;
};

RelativePose joint_pose(const Model& model, int i, double theta) {
  RelativePose rel;
  const Eigen::Vector3d& axis = model.link_axis[i];
  const Eigen::Matrix3d tree_R = model.link_Xtree[i].E.transpose();
  if (model.link_type[i] == JointType::kHinge) {
    // rotation about the axis through the link origin; the origin does not move
    const double s = std::sin(0.5 * theta), c = std::cos(0.5 * theta);
    rel.quat = quat_mul(model.link_tree_quat[i], Quat(c, axis.x() * s, axis.y() * s, axis.z() * s));
    rel.pos = model.link_tree_pos[i];
  } else {
    // translation along the axis, expressed in the parent link's frame
    rel.quat = model.link_tree_quat[i];
    rel.pos = model.link_tree_pos[i] + tree_R * (axis * theta);
  }
  rel.R = quat_to_mat(rel.quat);
  return rel;
}

}  // namespace

void kinematics(const Model& model, Data& data) {
  // links, root to leaves: Xup and world poses
  for (int i = 0; i < model.nv; ++i) {
    const int lambda = model.dof_parentid[i];
    const int qadr = model.jnt_qposadr[model.dof_jntid[i]];
    const RelativePose rel = joint_pose(model, i, data.qpos[qadr] - model.qpos0[qadr]);

    // ^i X_lambda: rotate parent coordinates into link i's, origin at rel.pos
    data.Xup[i].E = rel.R.transpose();
    data.Xup[i].r = rel.pos;

    if (lambda < 0) {
      data.link_xquat[i] = quat_normalized(rel.quat);
      data.link_xpos[i] = rel.pos;
    } else {
      data.link_xquat[i] = quat_normalized(quat_mul(data.link_xquat[lambda], rel.quat));
      data.link_xpos[i] = data.link_xpos[lambda] + data.link_xmat[lambda] * rel.pos;
    }
    data.link_xmat[i] = quat_to_mat(data.link_xquat[i]);
  }

  // bodies: a constant offset from their link (the world frame for bodies welded to it)
  for (int b = 1; b < model.nbody; ++b) {
    const int link = model.body_link[b];
    if (link < 0) {
      data.xquat[b] = quat_normalized(model.body_offset_quat[b]);
      data.xpos[b] = model.body_offset_pos[b];
    } else {
      data.xquat[b] = quat_normalized(quat_mul(data.link_xquat[link], model.body_offset_quat[b]));
      data.xpos[b] = data.link_xpos[link] + data.link_xmat[link] * model.body_offset_pos[b];
    }
    data.xmat[b] = quat_to_mat(data.xquat[b]);
    data.xipos[b] = data.xpos[b] + data.xmat[b] * model.body_ipos[b];
    data.ximat[b] = quat_to_mat(quat_mul(data.xquat[b], model.body_iquat[b]));
  }

  // sites
  for (int s = 0; s < model.nsite; ++s) {
    const int b = model.site_bodyid[s];
    data.site_xpos[s] = data.xpos[b] + data.xmat[b] * model.site_pos[s];
    data.site_xmat[s] = quat_to_mat(quat_mul(data.xquat[b], model.site_quat[s]));
  }
}

void jac_point(const Model& model, const Data& data, int body, const Eigen::Vector3d& point,
               Eigen::Ref<Eigen::MatrixXd> jacp, Eigen::Ref<Eigen::MatrixXd> jacr) {
  jacp.setZero();
  jacr.setZero();
  // every joint between the body and the world moves the point: walk the links to the root
  for (int i = model.body_link[body]; i >= 0; i = model.dof_parentid[i]) {
    const Eigen::Vector3d axis = data.link_xmat[i] * model.link_axis[i];
    if (model.link_type[i] == JointType::kHinge) {
      jacr.col(i) = axis;
      jacp.col(i) = axis.cross(point - data.link_xpos[i]);
    } else {
      jacp.col(i) = axis;
    }
  }
}

void jac_site(const Model& model, const Data& data, int site, Eigen::Ref<Eigen::MatrixXd> jacp,
              Eigen::Ref<Eigen::MatrixXd> jacr) {
  jac_point(model, data, model.site_bodyid[site], data.site_xpos[site], jacp, jacr);
}

}  // namespace lever
