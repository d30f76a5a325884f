// (3) The torque budget: for each joint, the worst-case gravity torque over the joint ranges and
// the pose where it occurs; the motor limit over it; the largest point payload each motor can
// hold at each site there,
//   m_p = (limit_i - |tau_g,i|) / (g |g_hat . J_i|)    (J_i: column i of the site's Jacobian);
// M(q) at that pose; and the acceleration the spare torque gives with the other joints held
// rigid, qacc_i = (limit_i - |tau_g,i|) / M_ii, with the torque holding joint j rigid needs,
// M_ji qacc_i + tau_g,j. The check of the gravity torque itself comes first: qfrc_bias at rest
// against dV/dq (reference_gravity) at random poses.
#include <cmath>
#include <random>

#include <lever/data.hpp>
#include <lever/dynamics.hpp>
#include <lever/kinematics.hpp>

#include <lever/check.hpp>
#include "reference.hpp"
#include "util.hpp"
#include "worst_pose.hpp"

namespace lever::check {

namespace {

constexpr int kFormulaPoses = 1000;

double formula_error(const Model& model, GravityProbe& probe) {
  std::mt19937_64 rng(1);
  double worst = 0.0;
  for (int i = 0; i < kFormulaPoses; ++i) {
    const Eigen::VectorXd q = random_pose(model, rng);
    const Eigen::VectorXd formula = reference_gravity(model, reference_pose(model, q));
    if (model.nv > 0) worst = std::max(worst, (probe(q) - formula).cwiseAbs().maxCoeff());
  }
  return worst;
}

void motors_of_joint(const Model& model, int j, JointBudget& budget) {
  budget.torque_range = {0.0, 0.0};
  int servos = 0, last = -1;
  for (int a = 0; a < model.nu; ++a) {
    if (actuator_scalar_dof(model, a) < 0 || model.actuator_trnid[a][0] != j) {
      continue;  // a tendon's, a site's, a slider-crank's force reaches the joints through its
                 // moment, which changes with the pose
    }
    const auto range = motor_torque_range(model, a);
    budget.motors.push_back(motor_label(model, a));
    budget.torque_range[0] += range[0];
    budget.torque_range[1] += range[1];
    if (is_servo(model.actuator_kind[a])) {
      const double gear = model.actuator_gear[a][0];
      if (model.actuator_biastype[a] == BiasType::kAffine)
        budget.stiffness -= gear * gear * model.actuator_biasprm[a][1];
      ++servos;
      last = a;
    }
  }
  budget.servo = servos > 0;
  if (!budget.servo) return;
  // holding at rest: qfrc_actuator = gear force = qfrc_bias, so the servo sits |tau| / kp off its
  // target; with one servo, the target that holds the pose: gear (g0 ctrl + b0 + b1 gear q) = tau
  budget.sag = budget.stiffness > 0 ? std::abs(budget.worst_torque) / budget.stiffness : kInf;
  if (servos == 1 && model.actuator_gainprm[last][0] != 0 && model.actuator_gear[last][0] != 0) {
    const double gear = model.actuator_gear[last][0];
    const auto& b = model.actuator_biasprm[last];
    const double q = budget.worst_pose[model.jnt_qposadr[j]];
    budget.hold_target =
        (budget.worst_torque / gear - b[0] - b[1] * gear * q) / model.actuator_gainprm[last][0];
    const auto& r = model.actuator_ctrlrange[last];
    budget.target_outside = model.actuator_ctrllimited[last] &&
                            (budget.hold_target < r[0] || budget.hold_target > r[1]);
  }
}

// Limit, ratio, spare torque, acceleration and rigid-holding torques at the worst pose.
void size_motor(const Eigen::MatrixXd& M, const Eigen::VectorXd& tau_g, int dof,
                JointBudget& budget) {
  if (!budget.actuated()) {  // nothing to size: every figure is undefined
    const double none = std::nan("");
    budget.limit = budget.ratio = budget.spare = budget.acceleration = none;
    budget.rigid_torques = Eigen::VectorXd::Constant(M.rows(), none);
    return;
  }
  const double need = std::abs(budget.worst_torque);
  const double direction = budget.worst_torque < 0 ? -1.0 : 1.0;
  budget.limit = direction > 0 ? budget.torque_range[1] : -budget.torque_range[0];
  budget.ratio = budget.loaded ? budget.limit / need : kInf;
  budget.spare = budget.limit - need;
  budget.acceleration = direction * budget.spare / M(dof, dof);
  budget.rigid_torques = M.col(dof) * budget.acceleration + tau_g;
}

// Payloads at every site, each joint at its own worst pose (kinematics done there).
void add_payloads(const Model& model, const Data& data, int j, TorqueBudget& result) {
  const JointBudget& budget = result.joints[j];
  const int dof = model.jnt_dofadr[j];
  const Eigen::Vector3d down = result.gravity > 0
                                   ? Eigen::Vector3d(model.opt.gravity / result.gravity)
                                   : Eigen::Vector3d::Zero();
  Eigen::MatrixXd jacp(3, model.nv), jacr(3, model.nv);
  for (int s = 0; s < model.nsite; ++s) {
    jac_site(model, data, s, jacp, jacr);
    const double per_kg = result.gravity * std::abs(down.dot(jacp.col(dof)));
    double kg = kInf;
    if (!budget.actuated()) {
      kg = std::nan("");
    } else if (per_kg > 1e-12) {
      kg = std::max(0.0, budget.spare) / per_kg;
    }
    result.payload[s].per_joint[j] = kg;
  }
}

void add_pose_inertia(const Eigen::VectorXd& q, const Eigen::MatrixXd& M, int j,
                      TorqueBudget& result) {
  for (PoseInertia& p : result.poses) {
    if (p.q == q) {
      p.joints.push_back(j);
      return;
    }
  }
  result.poses.push_back({q, M, {j}});
}

}  // namespace

TorqueBudget check_torque_budget(const Model& model) {
  TorqueBudget result;
  GravityProbe probe(model);
  result.formula_poses = kFormulaPoses;
  result.formula_max_error = formula_error(model, probe);
  result.gravity = model.opt.gravity.norm();
  const long before = probe.evaluations();
  const std::vector<WorstPose> worst = worst_gravity_poses(model, probe, result.search);
  result.evaluations = probe.evaluations() - before;

  for (int s = 0; s < model.nsite; ++s) {
    result.payload.push_back(
        {site_label(model, s), std::vector<double>(model.njnt, kInf), kInf, -1});
  }
  Data data(model);
  for (int j = 0; j < model.njnt; ++j) {
    JointBudget budget;
    budget.joint = joint_label(model, j);
    budget.hinge = is_hinge(model, j);
    budget.worst_torque = worst[j].torque;
    budget.worst_pose = worst[j].qpos;
    budget.loaded = std::abs(worst[j].torque) > kUnloaded;
    motors_of_joint(model, j, budget);

    data.qpos = worst[j].qpos;
    data.qvel.setZero();
    kinematics(model, data);
    crba(model, data);
    bias(model, data);
    size_motor(data.M, data.qfrc_bias, model.jnt_dofadr[j], budget);
    result.joints.push_back(budget);
    add_payloads(model, data, j, result);
    add_pose_inertia(worst[j].qpos, data.M, j, result);
  }
  for (SitePayload& p : result.payload) {
    for (int j = 0; j < model.njnt; ++j) {
      if (p.per_joint[j] < p.min) {  // false for NaN (unactuated)
        p.min = p.per_joint[j];
        p.binding_joint = j;
      }
    }
  }
  return result;
}

}  // namespace lever::check
