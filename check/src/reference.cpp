#include "reference.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include <lever/spatial.hpp>

namespace lever::check {

ReferencePose reference_pose(const Model& model, const Eigen::VectorXd& qpos) {
  ReferencePose pose;
  pose.body_R.assign(model.nbody, Eigen::Matrix3d::Identity());
  pose.body_p.assign(model.nbody, Eigen::Vector3d::Zero());
  pose.jnt_anchor.assign(model.njnt, Eigen::Vector3d::Zero());
  pose.jnt_axis.assign(model.njnt, Eigen::Vector3d::Zero());
  for (int b = 1; b < model.nbody; ++b) {
    const int parent = model.body_parentid[b];
    Eigen::Matrix3d R = pose.body_R[parent] * quat_to_mat(quat_normalized(model.body_quat[b]));
    Eigen::Vector3d p = pose.body_p[parent] + pose.body_R[parent] * model.body_pos[b];
    for (int j = model.body_jntadr[b]; j >= 0 && j < model.body_jntadr[b] + model.body_jntnum[b];
         ++j) {
      const Eigen::Vector3d anchor = p + R * model.jnt_pos[j];
      const Eigen::Vector3d axis = (R * model.jnt_axis[j]).normalized();
      const int adr = model.jnt_qposadr[j];
      const double delta = qpos[adr] - model.qpos0[adr];
      if (model.jnt_type[j] == JointType::kHinge) {
        const Eigen::Matrix3d turn = Eigen::AngleAxisd(delta, axis).toRotationMatrix();
        R = turn * R;
        p = anchor + turn * (p - anchor);
      } else {
        p += axis * delta;
      }
      pose.jnt_anchor[j] = anchor;
      pose.jnt_axis[j] = axis;
    }
    pose.body_R[b] = R;
    pose.body_p[b] = p;
  }
  return pose;
}

Eigen::Vector3d reference_site(const Model& model, const ReferencePose& pose, int site) {
  const int b = model.site_bodyid[site];
  return pose.body_p[b] + pose.body_R[b] * model.site_pos[site];
}

bool moves_with(const Model& model, int b, int ancestor) {
  for (; b > 0; b = model.body_parentid[b]) {
    if (b == ancestor) return true;
  }
  return ancestor == 0;
}

Eigen::VectorXd reference_gravity(const Model& model, const ReferencePose& pose) {
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(model.nv);
  const Eigen::Vector3d& g = model.opt.gravity;
  for (int j = 0; j < model.njnt; ++j) {
    const Eigen::Vector3d& a = pose.jnt_axis[j];
    double t = 0.0;
    for (int b = 1; b < model.nbody; ++b) {
      if (model.body_mass[b] == 0.0 || !moves_with(model, b, model.jnt_bodyid[j])) continue;
      const Eigen::Vector3d com = pose.body_p[b] + pose.body_R[b] * model.body_ipos[b];
      const Eigen::Vector3d moved = model.jnt_type[j] == JointType::kHinge
                                        ? Eigen::Vector3d(a.cross(com - pose.jnt_anchor[j]))
                                        : a;
      t -= model.body_mass[b] * g.dot(moved);
    }
    tau[model.jnt_dofadr[j]] = t;
  }
  return tau;
}

std::vector<int> joint_path(const Model& model, int body) {
  std::vector<int> joints;
  for (int b = body; b > 0; b = model.body_parentid[b]) {
    for (int k = model.body_jntnum[b] - 1; k >= 0; --k) joints.push_back(model.body_jntadr[b] + k);
  }
  std::reverse(joints.begin(), joints.end());
  return joints;
}

std::array<double, 2> joint_box(const Model& model, int joint) {
  if (model.jnt_limited[joint]) return model.jnt_range[joint];
  const double q0 = model.qpos0[model.jnt_qposadr[joint]];
  const double reach =
      model.jnt_type[joint] == JointType::kHinge ? std::numbers::pi : kUnlimitedSlide;
  return {q0 - reach, q0 + reach};
}

Eigen::VectorXd random_pose(const Model& model, std::mt19937_64& rng) {
  Eigen::VectorXd q = model.qpos0;
  for (int j = 0; j < model.njnt; ++j) {
    const auto box = joint_box(model, j);
    q[model.jnt_qposadr[j]] = std::uniform_real_distribution<double>(box[0], box[1])(rng);
  }
  return q;
}

Eigen::VectorXd zero_pose(const Model& model) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.nq);
  for (int j = 0; j < model.njnt; ++j) {
    const auto box = joint_box(model, j);
    q[model.jnt_qposadr[j]] = std::clamp(0.0, box[0], box[1]);
  }
  return q;
}

}  // namespace lever::check
