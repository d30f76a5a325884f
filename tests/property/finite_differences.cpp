// Derivatives against central finite differences: the site Jacobians against the motion of
// site_xpos and site_xmat, and the gravity (and spring) torque against the potential energy.
//
// Step and bound: a central difference with step h errs by h^2/6 |f'''| (truncation) plus about
// eps |f| / h (rounding). With h = 1e-5 and |f|, |f'''| of order 1 (metres, radians, joules of
// these arms) that is ~2e-11 + ~1e-11. The bound, 1e-8 of the scale, sits well above both and
// far below any wrong term (a wrong axis, sign or lever arm changes a column by O(1)).
#include <Eigen/Geometry>

#include "property_models.hpp"

namespace lever::test {

namespace {

constexpr double kStep = 1e-5;
constexpr double kBound = 1e-8;
constexpr int kStates = kStatesPerModel / 4;  // 2 nv evaluations per state and quantity

// Kinematics and potential energy at qpos moved by delta along dof i: a hinge's or a slide's
// coordinate changes by delta, a ball's quaternion turns by delta about the body axis i stands
// for (integrate_pos, so a column is compared in the tangent space the Jacobian lives in).
void evaluate_moved(const Model& model, Data& data, const Eigen::VectorXd& qpos, int i,
                    double delta) {
  data.qpos = qpos;
  Eigen::VectorXd along = Eigen::VectorXd::Zero(model.nv);
  along[i] = delta;
  integrate_pos(model, data.qpos, along, 1.0);
  forward(model, data);
  compute_energy(model, data);
}

// The rotation taking R_minus to R_plus, as a rotation vector (world frame).
Eigen::Vector3d rotation_vector(const Eigen::Matrix3d& R_plus, const Eigen::Matrix3d& R_minus) {
  const Eigen::AngleAxisd aa(Eigen::Matrix3d(R_plus * R_minus.transpose()));
  return aa.angle() * aa.axis();
}

}  // namespace

TEST_CASE("property: site Jacobians equal central differences of site_xpos and site_xmat",
          "[property][jacobian]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    const Model& model = c.model;
    Data data(model), moved(model);
    std::mt19937_64 rng(c.seed);
    Eigen::MatrixXd jacp(3, model.nv), jacr(3, model.nv);
    for (int k = 0; k < states_for(c, kStates); ++k) {
      apply(random_state(model, rng), data);
      kinematics(model, data);
      for (int s = 0; s < model.nsite; ++s) {
        jac_site(model, data, s, jacp, jacr);
        for (int i = 0; i < model.nv; ++i) {
          evaluate_moved(model, moved, data.qpos, i, kStep);
          const Eigen::Vector3d p_plus = moved.site_xpos[s];
          const Eigen::Matrix3d R_plus = moved.site_xmat[s];
          evaluate_moved(model, moved, data.qpos, i, -kStep);
          const Eigen::Vector3d dp = (p_plus - moved.site_xpos[s]) / (2 * kStep);
          const Eigen::Vector3d dr = rotation_vector(R_plus, moved.site_xmat[s]) / (2 * kStep);
          INFO(c.name << ", seed " << c.seed << ", state " << k << ", site '" << model.site_name[s]
                      << "', dof " << i << "\n jacp " << jacp.col(i).transpose() << "\n   fd "
                      << dp.transpose() << "\n jacr " << jacr.col(i).transpose() << "\n   fd "
                      << dr.transpose());
          const double scale = std::max(1.0, data.site_xpos[s].norm());
          CHECK((jacp.col(i) - dp).cwiseAbs().maxCoeff() <= kBound * scale);
          CHECK((jacr.col(i) - dr).cwiseAbs().maxCoeff() <= kBound);
        }
      }
    }
  }
}

TEST_CASE("property: gravity and spring torques equal the gradient of the potential energy",
          "[property][gravity]") {
  for (const ModelCase& c : every_model_and_random_trees()) {
    const Model& model = c.model;
    Data data(model), moved(model);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < kStates; ++k) {
      State s = random_state(model, rng);
      s.qvel.setZero();  // at rest qfrc_bias is the gravity torque alone
      apply(s, data);
      forward(model, data);
      compute_energy(model, data);
      // dV/dq = g(q) + K (q - q_spring) = qfrc_bias - qfrc_passive at rest
      const Eigen::VectorXd torque = data.qfrc_bias - data.qfrc_passive;
      for (int i = 0; i < model.nv; ++i) {
        evaluate_moved(model, moved, s.qpos, i, kStep);
        const double v_plus = moved.energy[0];
        evaluate_moved(model, moved, s.qpos, i, -kStep);
        const double gradient = (v_plus - moved.energy[0]) / (2 * kStep);
        INFO(c.name << ", seed " << c.seed << ", state " << k << ", dof " << i << ": torque "
                    << torque[i] << " vs dV/dq " << gradient);
        const double scale = std::max({1.0, std::abs(data.energy[0]), std::abs(torque[i])});
        CHECK(std::abs(torque[i] - gradient) <= kBound * scale);
      }
    }
  }
}

}  // namespace lever::test
