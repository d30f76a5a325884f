// Lesson 5.1's hand formulas for the two-link arm, against lever on arm2.xml.
//
// The formulas' constants (link length L1, L2, masses m1, m2, centre-of-mass distances c1, c2,
// inertias I1, I2, gravity g, shoulder height) are read from the compiled model, so these tests
// check the *engine* against the closed forms. One test case instead checks the *file* against
// the numbers the lesson states, and says so.
//
// Bounds: the closed forms and the engine's recursive algorithms evaluate the same expressions in
// different orders, so they differ by rounding only: a few eps times the terms' magnitudes
// (the lesson measured 4.4e-16 m and 2.7e-15 N m). The bound 1e-13 (in m, N m, kg m^2) sits two
// orders above that and many orders below any wrong term.
#include <catch2/catch.hpp>
#include <cmath>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <random>

#include <lever/harness/random_state.hpp>
#include <lever/harness/models.hpp>
#include "two_link.hpp"

namespace lever::test {

namespace {

constexpr double kBound = 1e-13;
constexpr int kPoses = 1000;

Model arm2() { return mjcf::load_file(model_path("models/arm2.xml")); }

// A pose drawn uniformly within both joints' ranges, at rest.
void random_pose(const Model& model, Data& data, std::mt19937_64& rng) {
  for (int j = 0; j < 2; ++j) {
    const auto& range = model.jnt_range[j];
    data.qpos[j] = std::uniform_real_distribution<double>(range[0], range[1])(rng);
  }
  data.qvel.setZero();
}

}  // namespace

TEST_CASE("analytic: arm2's tip, gravity torque and M agree with the closed forms",
          "[analytic][arm2]") {
  const Model model = arm2();
  const TwoLink p = two_link(model);
  const int ee = model.site("ee");
  Data data(model);
  std::mt19937_64 rng(seed_for("arm2.xml"));
  for (int k = 0; k < kPoses; ++k) {
    random_pose(model, data, rng);
    forward(model, data);
    const double q1 = data.qpos[0], q2 = data.qpos[1];
    INFO("seed " << seed_for("arm2.xml") << ", pose " << k << ": q = (" << q1 << ", " << q2 << ")");

    const Eigen::Vector3d formula_tip = tip(p, q1, q2);
    INFO("site_xpos " << data.site_xpos[ee].transpose() << " vs formula "
                      << formula_tip.transpose());
    CHECK((data.site_xpos[ee] - formula_tip).cwiseAbs().maxCoeff() <= kBound);

    // at rest, qfrc_bias is the gravity torque (M qacc + qfrc_bias = tau)
    const Eigen::Vector2d tau_g = gravity_torque(p, q1, q2);
    INFO("qfrc_bias " << data.qfrc_bias.transpose() << " vs formula " << tau_g.transpose());
    CHECK((data.qfrc_bias - tau_g).cwiseAbs().maxCoeff() <= kBound);

    const Eigen::Matrix2d M = mass_matrix(p, q2);
    INFO("M\n" << data.M << "\nvs formula\n" << M);
    CHECK((data.M - M).cwiseAbs().maxCoeff() <= kBound);
  }
}

TEST_CASE("analytic: the lesson's motor sizing, computed by the engine", "[analytic][arm2]") {
  const Model model = arm2();
  const TwoLink p = two_link(model);
  const Eigen::Vector2d limit(model.actuator_ctrlrange[0][1], model.actuator_ctrlrange[1][1]);
  Data data(model);
  reset(model, data);  // qpos0: the arm horizontal, the largest gravity torque at both joints
  forward(model, data);
  const Eigen::Vector2d tau_g = data.qfrc_bias;

  SECTION("the spare shoulder torque accelerates the arm at (limit - tau_g1) / M11, elbow rigid") {
    // inverse dynamics at that acceleration: the shoulder needs exactly its limit, the elbow
    // M21 qdd1 + tau_g2 to stay rigid
    const double qdd1 = (limit[0] - tau_g[0]) / data.M(0, 0);
    Eigen::VectorXd tau(2);
    rnea(model, data, Eigen::Vector2d(qdd1, 0.0), tau);
    INFO("rnea " << tau.transpose() << ", shoulder limit " << limit[0]);
    CHECK(std::abs(tau[0] - limit[0]) <= kBound);
    CHECK(std::abs(tau[1] - (data.M(1, 0) * qdd1 + tau_g[1])) <= kBound);
  }

  SECTION(
      "a point payload at the tip of the lesson's size loads the shoulder exactly to its limit") {
    // m_p = (limit_1 - tau_g1) / (g (L1 + L2)); add it to link2 at the tip and recompile
    const double payload = (limit[0] - tau_g[0]) / (p.g * (p.L1 + p.L2));
    Model loaded = model;
    const int link2 = loaded.body("link2");
    const double m = p.m2 + payload;
    const double com = (p.m2 * p.c2 + payload * p.L2) / m;
    loaded.body_mass[link2] = m;
    loaded.body_ipos[link2].x() = com;
    // the point mass has no inertia of its own: parallel-axis terms about the new centre
    const double shift = p.m2 * (p.c2 - com) * (p.c2 - com) + payload * (p.L2 - com) * (p.L2 - com);
    loaded.body_inertia[link2].y() += shift;
    loaded.body_inertia[link2].z() += shift;
    set_const(loaded);
    Data loaded_data(loaded);
    reset(loaded, loaded_data);
    forward(loaded, loaded_data);
    INFO("payload " << payload << " kg: shoulder gravity torque " << loaded_data.qfrc_bias[0]);
    CHECK(std::abs(loaded_data.qfrc_bias[0] - limit[0]) <= kBound);
    // the elbow's own payload is larger: the shoulder is the binding joint
    const double elbow_payload = (limit[1] - tau_g[1]) / (p.g * p.L2);
    CHECK(elbow_payload > payload);
  }
}

// This test checks the FILE against the lesson's stated numbers (so they are typed here): the
// geometry, masses and motors of lesson 5.1, and the results it prints from them.
TEST_CASE("analytic: arm2.xml makes the lesson's claims", "[analytic][arm2][lesson]") {
  const Model model = arm2();
  const TwoLink p = two_link(model);
  CHECK(p.L1 == 0.5);
  CHECK(p.L2 == 0.4);
  CHECK(p.m1 == 1.0);
  CHECK(p.m2 == 0.8);
  CHECK(p.c1 == 0.25);
  CHECK(p.c2 == 0.2);
  CHECK(p.g == 9.81);
  // thin rods, m L^2 / 12, as the file's 15-digit decimals
  CHECK(std::abs(p.I1 / (p.m1 * p.L1 * p.L1 / 12) - 1) <= 1e-14);
  CHECK(std::abs(p.I2 / (p.m2 * p.L2 * p.L2 / 12) - 1) <= 1e-14);
  CHECK(model.jnt_range[0][0] == -1.2);
  CHECK(model.actuator_ctrlrange[0][1] == 25.0);
  CHECK(model.actuator_ctrlrange[1][1] == 15.0);

  // what the lesson prints, to its printed digits
  Data data(model);
  reset(model, data);
  forward(model, data);
  const Eigen::Vector2d tau_g = data.qfrc_bias;
  const auto digits = [](double x, int n) { return std::round(x * std::pow(10.0, n)); };
  CHECK(digits(tau_g[0], 3) == 7946);  // N m
  CHECK(digits(tau_g[1], 3) == 1570);
  CHECK(digits(25.0 / tau_g[0], 2) == 315);  // motor limit / gravity torque
  CHECK(digits(15.0 / tau_g[1], 2) == 956);
  CHECK(digits((25.0 - tau_g[0]) / (p.g * (p.L1 + p.L2)), 2) == 193);  // payload, kg
  CHECK(digits((15.0 - tau_g[1]) / (p.g * p.L2), 2) == 342);
  CHECK(digits(data.M(0, 0), 3) == 486);  // M11, kg m^2
  const double qdd1 = (25.0 - tau_g[0]) / data.M(0, 0);
  CHECK(digits(qdd1, 1) == 351);                            // rad/s^2
  CHECK(digits(data.M(1, 0) * qdd1 + tau_g[1], 2) == 587);  // N m at the elbow
}

}  // namespace lever::test
