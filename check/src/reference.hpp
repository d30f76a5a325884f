// Independent reference calculations for `lever check`: forward kinematics as a chain of
// homogeneous transforms built directly from the model's numbers (body_pos, body_quat, jnt_pos,
// jnt_axis), and gravity torque as the derivative of potential energy. They share no code with
// the engine's link tree and recursive algorithms, so agreement to rounding error checks both.
#pragma once

#include <Eigen/Core>

#include <array>
#include <random>
#include <vector>

#include <lever/model.hpp>

namespace lever::check {

/// World poses of every body, and world anchor and axis of every joint, at one qpos.
struct ReferencePose {
  std::vector<Eigen::Matrix3d> body_R;      ///< (nbody) body frame -> world
  std::vector<Eigen::Vector3d> body_p;      ///< (nbody) body frame origin
  std::vector<Eigen::Vector3d> jnt_anchor;  ///< (njnt)
  std::vector<Eigen::Vector3d> jnt_axis;    ///< (njnt) unit
};

/// Compose the transforms from the world outwards: each body's pos/quat in its parent, then each
/// of its joints in order (a hinge turns the frame about its anchor by q - qpos0, a slide moves it
/// along its axis by q - qpos0), as MuJoCo's mj_kinematics defines them.
ReferencePose reference_pose(const Model& model, const Eigen::VectorXd& qpos);

/// A site's world position in that pose.
Eigen::Vector3d reference_site(const Model& model, const ReferencePose& pose, int site);

/// Gravity torque at rest: tau_g,j = -sum over bodies b that joint j moves of
/// m_b g . (a_j x (c_b - p_j)) for a hinge (axis a_j through p_j), -sum m_b g . a_j for a slide:
/// dV/dq, the torque the motors must supply to hold the pose (qfrc_bias's sign).
Eigen::VectorXd reference_gravity(const Model& model, const ReferencePose& pose);

/// The joints that move a body, root first.
std::vector<int> joint_path(const Model& model, int body);

/// Is body `b` the body `ancestor` or one of its descendants?
bool moves_with(const Model& model, int b, int ancestor);

/// The interval a joint is sampled and searched in: its range if limited, otherwise qpos0 +- pi
/// for a hinge and qpos0 +- kUnlimitedSlide for a slide.
constexpr double kUnlimitedSlide = 0.5;  // m
std::array<double, 2> joint_box(const Model& model, int joint);

/// A pose drawn uniformly from every joint's box.
Eigen::VectorXd random_pose(const Model& model, std::mt19937_64& rng);

/// The pose with every joint at 0, clamped into its box.
Eigen::VectorXd zero_pose(const Model& model);

}  // namespace lever::check
