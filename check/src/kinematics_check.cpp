// (2) Forward kinematics of every site at random poses within the joint ranges: the engine's
// site_xpos against a chain of transforms built from the model's numbers, and, where the site
// hangs from hinges with parallel axes (a planar arm), against the closed-form planar formula
//   p = p_1 + sum_k L_k [cos(phi_k + alpha_k) u + sin(phi_k + alpha_k) w] + h n,
//   alpha_k = sum_{m <= k} (q_m - qpos0_m) (signed by the axis' direction along n),
// with the link lengths L_k and directions phi_k measured from the model's own geometry at qpos0.
#include <cmath>
#include <random>

#include <lever/data.hpp>
#include <lever/kinematics.hpp>

#include <lever/check.hpp>
#include "reference.hpp"
#include "util.hpp"

namespace lever::check {

namespace {

constexpr int kPoses = 1000;
constexpr double kParallel = 1e-9;  // |a x n| below this: the axes are parallel

// An in-plane basis (u, w) for rotations about n, with w as close to "up" as the plane allows.
void plane_basis(const Model& model, const Eigen::Vector3d& n, Eigen::Vector3d& u,
                 Eigen::Vector3d& w) {
  const double g = model.opt.gravity.norm();
  const Eigen::Vector3d candidates[] = {
      g > 0 ? Eigen::Vector3d(-model.opt.gravity / g) : Eigen::Vector3d::UnitZ(),
      Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};
  for (const Eigen::Vector3d& up : candidates) {
    w = up - up.dot(n) * n;
    if (w.norm() > 1e-6) break;
  }
  w.normalize();
  u = w.cross(n);  // then n x u = w
}

// The planar chain the site hangs from, or nothing if its joints are not all parallel hinges.
std::optional<PlanarChain> planar_chain(const Model& model, int site) {
  const std::vector<int> path = joint_path(model, model.site_bodyid[site]);
  if (path.empty()) return std::nullopt;
  const ReferencePose pose = reference_pose(model, model.qpos0);
  PlanarChain chain;
  chain.normal = pose.jnt_axis[path[0]];
  for (const int j : path) {
    if (!is_hinge(model, j) || pose.jnt_axis[j].cross(chain.normal).norm() > kParallel) {
      return std::nullopt;
    }
    chain.joints.push_back(joint_label(model, j));
    chain.joint_ids.push_back(j);
    chain.signs.push_back(pose.jnt_axis[j].dot(chain.normal) > 0 ? 1.0 : -1.0);
  }
  plane_basis(model, chain.normal, chain.u, chain.w);
  chain.origin = pose.jnt_anchor[path[0]];
  for (size_t k = 0; k < path.size(); ++k) {
    const Eigen::Vector3d next =
        k + 1 < path.size() ? pose.jnt_anchor[path[k + 1]] : reference_site(model, pose, site);
    const Eigen::Vector3d r = next - pose.jnt_anchor[path[k]];
    chain.lengths.push_back(std::hypot(r.dot(chain.u), r.dot(chain.w)));
    chain.angles0.push_back(std::atan2(r.dot(chain.w), r.dot(chain.u)));
    chain.offset += r.dot(chain.normal);
  }
  return chain;
}

Eigen::Vector3d planar_formula(const Model& model, const PlanarChain& chain,
                               const Eigen::VectorXd& q) {
  double x = 0.0, z = 0.0, alpha = 0.0;
  for (size_t k = 0; k < chain.joint_ids.size(); ++k) {
    const int adr = model.jnt_qposadr[chain.joint_ids[k]];
    alpha += chain.signs[k] * (q[adr] - model.qpos0[adr]);
    x += chain.lengths[k] * std::cos(chain.angles0[k] + alpha);
    z += chain.lengths[k] * std::sin(chain.angles0[k] + alpha);
  }
  return chain.origin + x * chain.u + z * chain.w + chain.offset * chain.normal;
}

}  // namespace

Kinematics check_kinematics(const Model& model) {
  Kinematics result;
  result.poses = kPoses;
  Data data(model);
  for (int s = 0; s < model.nsite; ++s) {
    result.sites.push_back({site_label(model, s), 0.0, planar_chain(model, s)});
  }
  std::mt19937_64 rng(0);
  for (int i = 0; i < kPoses; ++i) {
    data.qpos = random_pose(model, rng);
    kinematics(model, data);
    const ReferencePose pose = reference_pose(model, data.qpos);
    for (int s = 0; s < model.nsite; ++s) {
      SiteKinematics& site = result.sites[s];
      const Eigen::Vector3d& xpos = data.site_xpos[s];
      site.max_error_transforms = std::max(
          site.max_error_transforms, (xpos - reference_site(model, pose, s)).cwiseAbs().maxCoeff());
      if (site.planar) {
        const Eigen::Vector3d formula = planar_formula(model, *site.planar, data.qpos);
        site.planar->max_error =
            std::max(site.planar->max_error, (xpos - formula).cwiseAbs().maxCoeff());
      }
    }
  }
  return result;
}

}  // namespace lever::check
