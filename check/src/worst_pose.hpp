// The pose, within the joint ranges, where gravity loads each joint most: max |qfrc_bias_i| at
// rest over the box of joint ranges.
//
// Starts: the pose with every joint at 0, qpos0, every joint at each end of its range (the others
// at 0), and a coarse grid (nv <= 3) or random samples (nv > 3), a bounded number of evaluations
// in both cases. From the best starts of each joint, coordinate ascent maximizes |tau_i| one
// coordinate at a time, exactly: holding the others, a hinge angle enters the gravity torque as
// A cos q + B sin q + C (a slide coordinate linearly), so three evaluations give the curve and its
// extremes, and the best of those and the range ends is kept. Ties go to the simple poses (all
// zero, qpos0, range ends), and coordinates that do not matter are put back to 0 or qpos0.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include <lever/data.hpp>
#include <lever/model.hpp>

namespace lever::check {

/// qfrc_bias at rest at any pose, counting evaluations.
class GravityProbe {
 public:
  explicit GravityProbe(const Model& model);
  const ArenaVector& operator()(const Eigen::VectorXd& qpos);
  long evaluations() const { return evaluations_; }

 private:
  const Model& model_;
  Data data_;
  long evaluations_ = 0;
};

struct WorstPose {
  double torque = 0.0;  ///< signed qfrc_bias of the joint there
  Eigen::VectorXd qpos;
};

/// One worst pose per joint; `how` describes the search.
std::vector<WorstPose> worst_gravity_poses(const Model& model, GravityProbe& probe,
                                           std::string& how);

}  // namespace lever::check
