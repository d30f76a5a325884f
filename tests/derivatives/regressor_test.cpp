// The inertial-parameter regressor: Y pi against rnea (two analytic results: the project's 1e-12),
// the conversions to and from MJCF's <inertial>, the base parameters, and identification of arm2
// with a heavier link 2 from its own simulated, noise-free data.
#include <catch2/catch.hpp>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>
#include <lever/regressor.hpp>

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <lever/harness/tolerance.hpp>
#include "../property/property_models.hpp"
#include "smooth_states.hpp"

namespace lever::test {

namespace {

// The joint forces that explain the simulated motion, Y pi = qfrc_actuator + qfrc_applied +
// qfrc_constraint - springs (forward's M qacc + bias = passive + actuator + applied + constraint).
Eigen::VectorXd explained_force(const Model& model, const Data& data) {
  Eigen::VectorXd f = data.qfrc_actuator + data.qfrc_applied + data.qfrc_constraint;
  for (int j = 0; j < model.njnt; ++j) {
    const int q = model.jnt_qposadr[j];
    f[model.jnt_dofadr[j]] -= model.jnt_stiffness[j] * (data.qpos[q] - model.qpos_spring[q]);
  }
  return f;
}

}  // namespace

TEST_CASE("regressor: Y pi equals rnea + damping qvel (gain columns left out)",
          "[derivatives][regressor]") {
  for (ModelCase& c : hinge_and_slide_models(every_model())) {
    INFO(c.name);
    const Model& model = c.model;
    const int inertial = 10 * (model.nbody - 1) + 2 * model.nv;
    Data data(model);
    const Eigen::VectorXd pi = model_parameters(model);
    Eigen::MatrixXd Y(model.nv, regressor_columns(model));
    Eigen::VectorXd tau(model.nv);
    std::mt19937_64 rng(c.seed);
    for (int k = 0; k < 100; ++k) {
      apply(random_state(model, rng), data);
      const Eigen::VectorXd qacc = random_qacc(model, rng);
      kinematics(model, data);
      regressor(model, data, qacc, Y);
      rnea(model, data, qacc, tau);
      for (int i = 0; i < model.nv; ++i) tau[i] += model.dof_damping[i] * data.qvel[i];
      const Eigen::VectorXd Ypi = Y.leftCols(inertial) * pi.head(inertial);  // gains left out
      CHECK((Ypi - tau).cwiseAbs().maxCoeff() <= allowed(largest(tau)));
    }
  }
}

TEST_CASE("regressor: with ctrl, the gain columns reproduce the actuators' torque",
          "[derivatives][regressor]") {
  // Y pi = rnea + damping qvel - (the fixed-gain actuators' gain-scaled torque). forward()'s
  // qfrc_actuator, less each fixed-gain actuator's gain-free force and each other actuator's
  // force, is that torque, on every dof where no actuator's force is clamped
  int compared = 0;
  for (ModelCase& c : hinge_and_slide_models(every_model())) {
    INFO(c.name);
    const Model& model = c.model;
    Data data(model);
    const Eigen::VectorXd pi = model_parameters(model);
    const std::vector<int> gains = gain_actuators(model);
    Eigen::MatrixXd Y(model.nv, regressor_columns(model));
    Eigen::VectorXd tau(model.nv);
    std::mt19937_64 rng(c.seed + 11);
    for (int k = 0; k < 100; ++k) {
      apply(random_state(model, rng), data);
      forward(model, data);
      const Eigen::VectorXd qacc = random_qacc(model, rng);
      regressor(model, data, qacc, Y);
      rnea(model, data, qacc, tau);
      Eigen::VectorXd expected = tau - data.qfrc_actuator;
      std::vector<char> clamped(static_cast<std::size_t>(model.nv), 0);
      for (int a = 0; a < model.nu; ++a) {
        const int j = model.actuator_trnid[a][0];
        const int q = model.jnt_qposadr[j], d = model.jnt_dofadr[j];
        const double gear = model.actuator_gear[a][0];
        const bool fixed = std::find(gains.begin(), gains.end(), a) != gains.end();
        expected[d] +=
            gear * (fixed ? actuator_gain_free_force(model, a, data.qpos[q], data.qvel[d])
                          : data.actuator_force[a]);
        const auto& f = model.actuator_forcerange[a];
        if (model.actuator_forcelimited[a] &&
            (data.actuator_force[a] <= f[0] || data.actuator_force[a] >= f[1])) {
          clamped[static_cast<std::size_t>(d)] = 1;
        }
      }
      for (int i = 0; i < model.nv; ++i) expected[i] += model.dof_damping[i] * data.qvel[i];
      const Eigen::VectorXd Ypi = Y * pi;
      const double scale = std::max(largest(tau), largest(data.qfrc_actuator));
      for (int i = 0; i < model.nv; ++i) {
        if (clamped[static_cast<std::size_t>(i)]) continue;
        ++compared;
        CHECK(std::abs(Ypi[i] - expected[i]) <= allowed(scale));
      }
    }
  }
  CHECK(compared > 1000);
}

TEST_CASE("regressor: gain columns, names and servos' tied bias", "[derivatives][regressor]") {
  const Model arm2 = mjcf::load_file(model_path("models/arm2.xml"));
  const std::vector<std::string> names = regressor_names(arm2);
  REQUIRE(regressor_columns(arm2) == 26);
  CHECK(names[24] == "shoulder.gain");
  CHECK(names[25] == "elbow.gain");
  CHECK(gain_tied_bias(arm2, 0) == 0);
  // the base parameters: both gains identifiable beside the 9 of the inertia, none without ctrl
  CHECK(base_parameters(arm2).rank == 11);
  const BaseParameters without = base_parameters_with_gains(arm2, {});
  CHECK(without.rank == 9);
  CHECK(std::count(without.unidentifiable.begin(), without.unidentifiable.end(), 25) == 1);
  // panda7's position servos: the gain kp carries biasprm[1] = -kp with it
  Model panda = mjcf::load_file(model_path("models/panda7.xml"));
  CHECK(gain_tied_bias(panda, 3) == 1);
  Eigen::VectorXd pi = model_parameters(panda);
  const int column = regressor_columns(panda) - panda.nu + 3;
  CHECK(pi[column] == panda.actuator_gainprm[3][0]);
  pi[column] = 1234.5;
  set_model_parameters(panda, pi);
  CHECK(panda.actuator_gainprm[3][0] == 1234.5);
  CHECK(panda.actuator_biasprm[3][1] == -1234.5);
  CHECK(panda.actuator_biasprm[3][2] != -1234.5);  // kv is not the gain's
}

TEST_CASE("regressor: every model's bodies to and from their parameters",
          "[derivatives][regressor]") {
  for (ModelCase& c : hinge_and_slide_models(every_model())) {
    INFO(c.name);
    const Model& model = c.model;
    for (int b = 1; b < model.nbody; ++b) {
      if (model.body_mass[b] == 0) continue;
      INFO("body " << b);
      const InertialParameters pi = body_parameters(model, b);
      const PrincipalInertia inertial = RigidInertia::from_parameters(pi).to_principal();
      CHECK(std::abs(inertial.mass - model.body_mass[b]) <= allowed(model.body_mass[b]));
      CHECK((inertial.pos - model.body_ipos[b]).cwiseAbs().maxCoeff() <=
            allowed(model.body_ipos[b].cwiseAbs().maxCoeff()));
      // the same inertia about the centre of mass (principal axes may come in another order)
      const auto central = [](const Eigen::Vector4d& q, const Eigen::Vector3d& d) {
        const Eigen::Matrix3d R = quat_to_mat(quat_normalized(q));
        return Eigen::Matrix3d(R * d.asDiagonal() * R.transpose());
      };
      const Eigen::Matrix3d expected = central(model.body_iquat[b], model.body_inertia[b]);
      CHECK((central(inertial.quat, inertial.diaginertia) - expected).cwiseAbs().maxCoeff() <=
            allowed(expected.cwiseAbs().maxCoeff()));
      CHECK((RigidInertia::from_principal(inertial).to_parameters() - pi).cwiseAbs().maxCoeff() <=
            allowed(pi.cwiseAbs().maxCoeff()));
    }
  }
}

TEST_CASE("regressor: a model is not given parameters that are no rigid body",
          "[derivatives][regressor]") {
  // one body's refusals: tests/unit/inertia_test.cpp; here the model is left as it was
  const PrincipalInertia rod{1.0, {0.25, 0, 0}, {1, 0, 0, 0}, {0.0001, 0.02, 0.02}};
  InertialParameters flat = RigidInertia::from_principal(rod).to_parameters();
  flat[4] += 1.0;  // Ixx far above Iyy + Izz
  Model model = mjcf::load_file(model_path("models/arm2.xml"));
  const Model before = model;
  Eigen::VectorXd all = model_parameters(model);
  all.segment<10>(10) = flat;  // link2
  CHECK_THROWS_WITH(set_model_parameters(model, all), Catch::Contains("link2"));
  CHECK(model.body_inertia[2] == before.body_inertia[2]);  // nothing half-written
}

TEST_CASE("regressor: the base parameters reproduce Y pi", "[derivatives][regressor]") {
  for (ModelCase& c : hinge_and_slide_models(every_model())) {
    INFO(c.name);
    const Model& model = c.model;
    const BaseParameters base = base_parameters(model);
    REQUIRE(base.rank > 0);
    REQUIRE(static_cast<int>(base.names.size()) == base.rank);
    const Eigen::VectorXd pi = model_parameters(model);
    const Eigen::VectorXd theta = base.K * pi;
    Data data(model);
    Eigen::MatrixXd Y(model.nv, regressor_columns(model));
    std::mt19937_64 rng(c.seed + 5);
    double worst = 0;
    for (int k = 0; k < 50; ++k) {
      apply(random_state(model, rng), data);
      const Eigen::VectorXd qacc = random_qacc(model, rng);
      kinematics(model, data);
      regressor(model, data, qacc, Y);
      const Eigen::VectorXd full = Y * pi;
      const Eigen::VectorXd reduced = base.base_regressor(Y) * theta;
      worst = std::max(worst, (full - reduced).cwiseAbs().maxCoeff() / allowed(largest(full)));
    }
    // K comes out of a QR factorization of random data; its rounding (1e-16 times the condition
    // of the base columns) still keeps the reproduction within the project's bound
    INFO("worst " << worst << " of the bound");
    CHECK(worst <= 1.0);
  }
}

TEST_CASE("regressor: arm2's base parameters have names that say what they combine",
          "[derivatives][regressor]") {
  const Model model = mjcf::load_file(model_path("models/arm2.xml"));
  const BaseParameters base = base_parameters(model);
  // two hinges about the same axis: link1's mass and link2's inertia about other axes do not
  // show; each dof has its armature and damping
  CHECK(base.rank < regressor_columns(model));
  bool armature = false, lumped = false;
  for (const std::string& name : base.names) {
    armature = armature || name.find("shoulder.armature") != std::string::npos;
    lumped = lumped || name.find(" + ") != std::string::npos;
  }
  CHECK(armature);
  CHECK(lumped);
  for (const int column : base.unidentifiable) CHECK(base.K.col(column).isZero(0));
}

TEST_CASE("regressor: arm2 with a heavier link 2 is identified from its own simulated data",
          "[derivatives][regressor][identify]") {
  const Model prior = mjcf::load_file(model_path("models/arm2.xml"));
  Model truth = prior;
  truth.body_mass[2] = 1.6;          // link 2 twice as heavy
  truth.body_ipos[2] << 0.25, 0, 0;  // its centre of mass further out
  truth.body_inertia[2] *= 2.0;
  set_const(truth);

  // noise-free data: the true model driven by random torques from random states
  Data data(truth);
  std::mt19937_64 rng(21);
  const int samples = 200;
  // the structure is the prior's; the motors' torque is data here, not a gain to estimate
  const BaseParameters base = base_parameters_with_gains(prior, {});
  Eigen::MatrixXd W(samples * prior.nv, base.rank);
  Eigen::VectorXd target(samples * prior.nv);
  Eigen::MatrixXd Y(prior.nv, regressor_columns(prior));
  Data prior_data(prior);
  for (int s = 0; s < samples; ++s) {
    apply(smooth_state(truth, rng, true), data);
    forward(truth, data);
    // the regressor needs only kinematics, which is the prior's too (same joints and bodies)
    prior_data.qpos = data.qpos;
    prior_data.qvel = data.qvel;
    kinematics(prior, prior_data);
    regressor(prior, prior_data, data.qacc, Y);
    W.middleRows(s * prior.nv, prior.nv) = base.base_regressor(Y);
    target.segment(s * prior.nv, prior.nv) = explained_force(truth, data);
  }
  const Eigen::VectorXd theta = W.colPivHouseholderQr().solve(target);
  const Eigen::VectorXd expected = base.K * model_parameters(truth);
  const Eigen::VectorXd before = base.K * model_parameters(prior);
  INFO("identified " << theta.transpose() << "\ntrue       " << expected.transpose());
  for (int k = 0; k < base.rank; ++k) {
    UNSCOPED_INFO(base.names[k] << ": prior " << before[k] << ", true " << expected[k]
                                << ", identified " << theta[k]);
  }
  // 1e-8: the identification target (a least-squares solve, not an evaluation)
  CHECK((theta - expected).cwiseAbs().maxCoeff() <= 1e-8 * std::max(1.0, largest(expected)));
  CHECK((before - expected).cwiseAbs().maxCoeff() > 0.1);  // there was something to find
}

}  // namespace lever::test
