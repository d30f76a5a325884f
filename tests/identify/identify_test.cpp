// lever::identify: arm2 with a heavier link 2, driven along a PD-tracked sum of sines inside its
// joint ranges, written as `lever simulate --csv` writes a trajectory, identified back from the
// prior arm2: the base parameters to 1e-8, and a written model whose inverse dynamics is the true
// model's on held-out states.
#include <catch2/catch.hpp>

#include <lever/identify.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <utility>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include <lever/harness/tolerance.hpp>

namespace lever::test {

namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("lever_identify_" + name)).string();
}

// arm2 with link 2 twice as heavy, its centre of mass further out and its inertia doubled
Model heavy_arm2() {
  Model truth = mjcf::load_file(model_path("models/arm2.xml"));
  truth.body_mass[2] = 1.6;
  truth.body_ipos[2] << 0.25, 0, 0;
  truth.body_inertia[2] *= 2.0;
  set_const(truth);
  return truth;
}

// A PD-tracked sum of sines inside the joint ranges, in `lever simulate --csv`'s columns: a motor
// gets the PD law's torque, a servo (affine bias) the reference itself as its target.
// Returns how many (row, actuator) pairs had the force on a forcerange edge.
int simulate_csv(const Model& model, double seconds, const std::string& path, bool with_qacc,
                 bool with_force = true, double swing = 0.4) {
  std::ofstream out(path);
  out << "time";
  for (const char* what : {"qpos", "qvel", "qacc"}) {
    if (!with_qacc && std::string(what) == "qacc") continue;
    for (int j = 0; j < model.njnt; ++j) out << "," << what << "[" << model.jnt_name[j] << "]";
  }
  for (int a = 0; a < model.nu; ++a) out << ",ctrl[" << model.actuator_name[a] << "]";
  if (with_force) {
    for (int a = 0; a < model.nu; ++a) out << ",actuator_force[" << model.actuator_name[a] << "]";
  }
  for (int j = 0; j < model.njnt; ++j) out << ",qfrc_constraint[" << model.jnt_name[j] << "]";
  out << "\n";
  out.precision(17);
  Data data(model);
  const auto steps = static_cast<long>(seconds / model.opt.timestep);
  int clamped = 0;
  for (long k = 0; k <= steps; ++k) {
    for (int a = 0; a < model.nu; ++a) {
      const int j = model.actuator_trnid[a][0];
      const double lo = model.jnt_range[j][0], hi = model.jnt_range[j][1];
      const double mid = 0.5 * (lo + hi), half = swing * (hi - lo);
      double ref = mid, ref_vel = 0;
      for (const double f : {0.3, 0.71, 1.3}) {  // Hz, three sines of a third of the swing each
        const double w = 2 * std::numbers::pi * (f + 0.1 * a);
        ref += half / 3 * std::sin(w * data.time + a);
        ref_vel += half / 3 * w * std::cos(w * data.time + a);
      }
      const int q = model.jnt_qposadr[j], d = model.jnt_dofadr[j];
      data.ctrl[a] = model.actuator_biastype[a] == BiasType::kAffine
                         ? ref
                         : 60 * (ref - data.qpos[q]) + 8 * (ref_vel - data.qvel[d]);
    }
    forward(model, data);
    out << data.time;
    for (int j = 0; j < model.njnt; ++j) out << "," << data.qpos[model.jnt_qposadr[j]];
    for (int j = 0; j < model.njnt; ++j) out << "," << data.qvel[model.jnt_dofadr[j]];
    if (with_qacc) {
      for (int j = 0; j < model.njnt; ++j) out << "," << data.qacc[model.jnt_dofadr[j]];
    }
    for (int a = 0; a < model.nu; ++a) out << "," << data.ctrl[a];
    if (with_force) {
      for (int a = 0; a < model.nu; ++a) out << "," << data.actuator_force[a];
    }
    for (int j = 0; j < model.njnt; ++j) out << "," << data.qfrc_constraint[model.jnt_dofadr[j]];
    out << "\n";
    for (int a = 0; a < model.nu; ++a) {
      const auto& f = model.actuator_forcerange[a];
      if (model.actuator_forcelimited[a] &&
          (data.actuator_force[a] == f[0] || data.actuator_force[a] == f[1])) {
        ++clamped;
      }
    }
    step(model, data);
  }
  return clamped;
}

}  // namespace

TEST_CASE("identify: arm2 with a heavier link 2, from its simulated trajectory", "[identify]") {
  const Model prior = mjcf::load_file(model_path("models/arm2.xml"));
  const Model truth = heavy_arm2();
  const std::string csv = temp_path("heavy.csv");
  simulate_csv(truth, 6.0, csv, true);

  const identify::Trajectory data = identify::read_csv(prior, csv);
  const identify::Result r = identify::identify(prior, data);
  const Eigen::VectorXd expected = r.base.K * model_parameters(truth);
  INFO("estimate " << r.estimate.transpose() << "\ntrue     " << expected.transpose());
  CHECK((r.estimate - expected).cwiseAbs().maxCoeff() <=
        1e-8 * std::max(1.0, expected.cwiseAbs().maxCoeff()));
  CHECK((r.prior - expected).cwiseAbs().maxCoeff() > 0.1);  // there was something to find
  // noise-free data from lever's own model: the fit's residual is rounding, far below 1e-10 N m
  CHECK(r.residual_rms < 1e-10);
  CHECK(r.unexcited.empty());
  INFO(r.not_physical);
  REQUIRE(r.not_physical.empty());

  // the written model loads and its inverse dynamics is the truth's on held-out states
  const std::string written = temp_path("identified.xml");
  identify::write_model(model_path("models/arm2.xml"), identify::identified_model(prior, r),
                        written);
  const Model identified = mjcf::load_file(written);
  Data a(truth), b(identified);
  std::mt19937_64 rng(99);
  for (int k = 0; k < 50; ++k) {
    const State s = random_state(truth, rng);
    apply(s, a);
    apply(s, b);
    a.qacc = b.qacc = random_qacc(truth, rng);
    inverse(truth, a);
    inverse(identified, b);
    const double scale = a.qfrc_inverse.cwiseAbs().maxCoeff();
    CHECK((a.qfrc_inverse - b.qfrc_inverse).cwiseAbs().maxCoeff() <= 1e-8 * std::max(1.0, scale));
  }
  std::filesystem::remove(csv);
  std::filesystem::remove(written);
}

TEST_CASE("identify: qacc differenced from qvel when the file has none", "[identify]") {
  // The forward difference of qvel is the acceleration the Euler step applied,
  // (M + h B)^-1 (forces), not forward()'s: M qacc_e + bias = forces - h B qacc_e. The extra
  // h B qacc_e reads as armature h b = 4e-5 kg m^2 (h = 2 ms, b = 0.02 N m s): the armature
  // estimates carry that, everything else is exact to rounding.
  const Model prior = mjcf::load_file(model_path("models/arm2.xml"));
  const Model truth = heavy_arm2();
  const std::string csv = temp_path("noqacc.csv");
  simulate_csv(truth, 6.0, csv, false);
  const identify::Trajectory data = identify::read_csv(prior, csv);
  CHECK(data.qacc_source.find("forward differences") != std::string::npos);
  const identify::Result r = identify::identify(prior, data);
  const Eigen::VectorXd expected = r.base.K * model_parameters(truth);
  const double h_b = truth.opt.timestep * 0.02;
  for (int k = 0; k < r.base.rank; ++k) {
    INFO(r.base.names[k] << ": " << r.estimate[k] << " vs " << expected[k]);
    const bool armature = r.base.names[k].find("armature") != std::string::npos;
    const double shift = armature ? h_b : 0.0;
    CHECK(std::abs(r.estimate[k] - expected[k] - shift) <= 1e-8);
  }
  std::filesystem::remove(csv);
}

TEST_CASE("identify: ctrl columns go through the prior's servos (gain, bias, both clamps)",
          "[identify]") {
  // panda7's position servos: force = kp ctrl - kp q - kv qd, clamped to +-87 / +-12 N m (the
  // reference swings far enough that the clamp binds part of the time). Without actuator_force
  // columns read_csv must rebuild gear * force from ctrl at each row's qpos and qvel: the same
  // joint forces as the file that has them (a motor's gain 1 would be off by kp and the bias).
  const Model panda = mjcf::load_file(model_path("models/panda7.xml"));
  const std::string with = temp_path("panda_force.csv"), without = temp_path("panda_ctrl.csv");
  const int clamped = simulate_csv(panda, 2.0, with, true, true);
  simulate_csv(panda, 2.0, without, true, false);
  const identify::Trajectory from_force = identify::read_csv(panda, with);
  const identify::Trajectory from_ctrl = identify::read_csv(panda, without);
  // both sides of the force clamp are visited, each at least a tenth of the time
  const auto pairs = static_cast<int>(from_ctrl.time.size()) * panda.nu;
  CHECK(clamped > pairs / 10);
  CHECK(clamped < pairs * 9 / 10);
  CHECK(from_ctrl.force_source.find("bias") != std::string::npos);
  REQUIRE(from_ctrl.force.cols() == from_force.force.cols());
  for (Eigen::Index k = 0; k < from_ctrl.force.cols(); ++k) {
    const double scale = from_force.force.col(k).cwiseAbs().maxCoeff();
    INFO("row " << k);
    CHECK((from_ctrl.force.col(k) - from_force.force.col(k)).cwiseAbs().maxCoeff() <=
          allowed(scale));
  }
  // and the identification from ctrl fits the prior itself to rounding
  const identify::Result r = identify::identify(panda, from_ctrl);
  CHECK(r.residual_rms < 1e-9);
  std::filesystem::remove(with);
  std::filesystem::remove(without);
}

TEST_CASE("identify: a motor's unknown gain, from ctrl", "[identify]") {
  // arm2 with the heavier link 2 and an elbow motor 1.3 times as strong as the prior says (a
  // wrong torque constant). The shoulder's gain stays known: it fixes the scale that the elbow's
  // gain and the inertia would otherwise share (gravity does not: its torque scales with mass).
  const Model prior = mjcf::load_file(model_path("models/arm2.xml"));
  Model truth = heavy_arm2();
  truth.actuator_gainprm[1][0] = 1.3;
  set_const(truth);
  const std::string csv = temp_path("gain.csv");
  simulate_csv(truth, 6.0, csv, true, false);  // ctrl only: the force is what is unknown
  const identify::Trajectory data = identify::read_csv(prior, csv);
  identify::Options options;
  options.gains = identify::gain_actuators_named(prior, "elbow");
  const identify::Result r = identify::identify(prior, data, options);
  const Eigen::VectorXd expected = r.base.K * model_parameters(truth);
  INFO("estimate " << r.estimate.transpose() << "\ntrue     " << expected.transpose());
  // 1e-8: the target for noise-free data (the least squares' conditioning, not a term)
  CHECK((r.estimate - expected).cwiseAbs().maxCoeff() <=
        1e-8 * std::max(1.0, expected.cwiseAbs().maxCoeff()));
  const int gain = regressor_columns(prior) - 1;  // elbow.gain
  CHECK(std::abs(r.parameters[gain] - 1.3) <= 1e-8);
  CHECK(r.residual_rms < 1e-10);
  CHECK(r.dropped == 0);  // no forcerange
  REQUIRE(r.not_physical.empty());
  // the written model has the gain: the motor became a <general gainprm="1.3">
  const std::string written = temp_path("gain.xml");
  identify::write_model(model_path("models/arm2.xml"), identify::identified_model(prior, r),
                        written);
  const Model identified = mjcf::load_file(written);
  CHECK(std::abs(identified.actuator_gainprm[1][0] - 1.3) <= 1e-8);
  CHECK(identified.actuator_gainprm[0][0] == 1.0);
  CHECK(identified.actuator_biastype[1] == BiasType::kNone);
  CHECK(identified.actuator_ctrlrange[1] == prior.actuator_ctrlrange[1]);
  // without a known gain nothing fixes the scale: a clear error, not a zero model
  options.gains = identify::gain_actuators_named(prior, "all");
  CHECK_THROWS_WITH(identify::identify(prior, data, options), Catch::Contains("scale together"));
  CHECK_THROWS_WITH(identify::gain_actuators_named(prior, "wrist"),
                    Catch::Contains("no actuator 'wrist'"));
  std::filesystem::remove(csv);
  std::filesystem::remove(written);
}

TEST_CASE("identify: a known mass pins the scale, and every gain is estimated", "[identify]") {
  // arm2 with both motors' torque constants wrong (1.3 and 0.8 where the prior says 1), link 2
  // twice as heavy (weighed: 1.6 kg; its shape, hence its centre of mass and inertia per kg, as
  // the prior's) and link 1 different in mass and centre of mass. From ctrl alone, with every
  // gain estimated, nothing in the data is absolute (a robot twice as heavy with motors twice as
  // strong moves the same); link 2's known mass makes its own base parameters known and so fixes
  // the scale: both gains and every base parameter are recovered.
  const Model prior = mjcf::load_file(model_path("models/arm2.xml"));
  Model truth = prior;
  truth.body_mass[2] = 1.6;
  truth.body_inertia[2] *= 2.0;
  truth.body_mass[1] = 1.3;
  truth.body_ipos[1] << 0.27, 0, 0.01;
  truth.actuator_gainprm[0][0] = 1.3;
  truth.actuator_gainprm[1][0] = 0.8;
  set_const(truth);
  const std::string csv = temp_path("known_mass.csv");
  simulate_csv(truth, 6.0, csv, true, false);  // ctrl only
  const identify::Trajectory data = identify::read_csv(prior, csv);
  identify::Options options;
  options.gains = identify::gain_actuators_named(prior, "all");
  CHECK_THROWS_WITH(identify::identify(prior, data, options), Catch::Contains("scale together"));
  options.known_masses.push_back(identify::known_mass_named(prior, "link2=1.6"));
  const identify::Result r = identify::identify(prior, data, options);
  const Eigen::VectorXd expected = r.base.K * model_parameters(truth);
  INFO("estimate " << r.estimate.transpose() << "\ntrue     " << expected.transpose());
  // the noise-free target
  CHECK((r.estimate - expected).cwiseAbs().maxCoeff() <=
        1e-8 * std::max(1.0, expected.cwiseAbs().maxCoeff()));
  const int first_gain = regressor_columns(prior) - 2;
  CHECK(std::abs(r.parameters[first_gain] - 1.3) <= 1e-8);
  CHECK(std::abs(r.parameters[first_gain + 1] - 0.8) <= 1e-8);
  CHECK(r.parameters[10] == Approx(1.6).epsilon(1e-15));  // link2.m as known
  CHECK(r.residual_rms < 1e-10);
  CHECK(r.estimate_physical);
  REQUIRE(r.not_physical.empty());
  const Model identified = identify::identified_model(prior, r);
  CHECK(identified.body_mass[2] == Approx(1.6).epsilon(1e-12));
  // bad known masses are refused by name
  CHECK_THROWS_WITH(identify::known_mass_named(prior, "link3=1"),
                    Catch::Contains("no body 'link3'"));
  CHECK_THROWS_WITH(identify::known_mass_named(prior, "link2=-1"),
                    Catch::Contains("not a mass > 0"));
  CHECK_THROWS_WITH(identify::known_mass_named(prior, "link2"), Catch::Contains("BODY=KG"));
  std::filesystem::remove(csv);
}

TEST_CASE("identify: a position servo's kp, rows where its force clamps dropped", "[identify]") {
  // panda7's servos (forcerange 87 / 12 N m, clamping part of the time): joint 4's kp is 20%
  // above the prior's in the truth. Its gain carries biasprm[1] = -kp; the rows where its force
  // is at the clamp are dropped (judged at the estimated kp), the rest recover kp.
  const Model prior = mjcf::load_file(model_path("models/panda7.xml"));
  Model truth = prior;
  const int servo = 3;
  const double kp = 1.2 * prior.actuator_gainprm[servo][0];
  truth.actuator_gainprm[servo][0] = kp;
  truth.actuator_biasprm[servo][1] = -kp;
  set_const(truth);
  const std::string csv = temp_path("servo.csv");
  simulate_csv(truth, 2.0, csv, true, false);
  const identify::Trajectory data = identify::read_csv(prior, csv);
  identify::Options options;
  options.gains = {servo};
  const identify::Result r = identify::identify(prior, data, options);
  const int gain = regressor_columns(prior) - prior.nu + servo;
  INFO("kp " << r.parameters[gain] << " vs " << kp << ", dropped " << r.dropped);
  CHECK(std::abs(r.parameters[gain] - kp) <= 1e-8 * kp);  // the noise-free target
  CHECK(r.dropped > 0);
  CHECK(r.residual_rms < 1e-9);
  const Model identified = identify::identified_model(prior, r);
  CHECK(identified.actuator_biasprm[servo][1] == -r.parameters[gain]);
  std::filesystem::remove(csv);
}

TEST_CASE("identify: write_model writes new gains as each actuator element says them",
          "[identify]") {
  // servo_affine.xml: a <general> position servo, a <motor>, a <position>, a <velocity>, and two
  // affine gains (no gain column). Every fixed gain scaled by 1.5 and written: the file read back
  // has the gains, each servo's tied bias at -gain, the untouched actuators as they were.
  const std::string path = model_path("tests/derivatives/servo_affine.xml");
  const Model prior = mjcf::load_file(path);
  const std::vector<int> gains = gain_actuators(prior);
  REQUIRE(gains.size() == 4);  // elbow, shoulder_motor, elbow_p, slide
  Eigen::VectorXd pi = model_parameters(prior);
  const int first = regressor_columns(prior) - static_cast<int>(gains.size());
  for (int g = 0; g < static_cast<int>(gains.size()); ++g) pi[first + g] *= 1.5;
  Model edited = prior;
  set_model_parameters(edited, pi);
  const std::string written = temp_path("servo_affine.xml");
  identify::write_model(path, edited, written);
  const Model back = mjcf::load_file(written);
  for (int a = 0; a < prior.nu; ++a) {
    INFO(prior.actuator_name[a]);
    CHECK(back.actuator_gaintype[a] == prior.actuator_gaintype[a]);
    CHECK(back.actuator_biastype[a] == prior.actuator_biastype[a]);
    for (int i = 0; i < 3; ++i) {
      CHECK(back.actuator_gainprm[a][i] == edited.actuator_gainprm[a][i]);
      CHECK(back.actuator_biasprm[a][i] == edited.actuator_biasprm[a][i]);
    }
    CHECK(back.actuator_gear[a] == prior.actuator_gear[a]);
    CHECK(back.actuator_ctrlrange[a] == prior.actuator_ctrlrange[a]);
    CHECK(back.actuator_forcerange[a] == prior.actuator_forcerange[a]);
    const bool fixed = std::find(gains.begin(), gains.end(), a) != gains.end();
    CHECK((back.actuator_gainprm[a][0] != prior.actuator_gainprm[a][0]) == fixed);
    const int tied = gain_tied_bias(prior, a);
    if (tied > 0) CHECK(back.actuator_biasprm[a][tied] == -back.actuator_gainprm[a][0]);
  }
  std::filesystem::remove(written);
}

TEST_CASE("identify: noisy data, estimates within their standard errors", "[identify]") {
  // arm2 with the heavier link 2; Gaussian noise of known sigma, each seed a new draw. Every
  // estimate must be within 4 standard errors of the truth, and over 20 seeds (180 estimates)
  // about 68% within one: a fraction far below (standard errors too small, e.g. not scaled by
  // the residual) or far above (too large, e.g. blind to correlated errors) fails.
  const Model prior = mjcf::load_file(model_path("models/arm2.xml"));
  const Model truth = heavy_arm2();
  // noise(trajectory, rng) adds the noise; shift: what the clean data's estimate differs by
  const auto run = [&](bool with_qacc, const auto& noise, const std::string& label) {
    const std::string csv = temp_path("noisy.csv");
    simulate_csv(truth, 6.0, csv, with_qacc);
    const identify::Trajectory clean = identify::read_csv(prior, csv);
    std::filesystem::remove(csv);
    const double h_b = with_qacc ? 0.0 : truth.opt.timestep * 0.02;  // see the test above
    int within1 = 0, within1_ols = 0, total = 0;
    for (int seed = 1; seed <= 20; ++seed) {
      identify::Trajectory noisy = clean;
      std::mt19937_64 rng(static_cast<unsigned long long>(seed));
      noise(noisy, rng);
      const identify::Result r = identify::identify(prior, noisy);
      const Eigen::VectorXd expected = r.base.K * model_parameters(truth);
      for (int k = 0; k < r.base.rank; ++k) {
        const bool armature = r.base.names[k].find("armature") != std::string::npos;
        const double error = r.estimate[k] - expected[k] - (armature ? h_b : 0.0);
        INFO(label << ", seed " << seed << ", " << r.base.names[k] << ": " << r.estimate[k]
                   << " vs " << expected[k] << ", standard error " << r.standard_error[k]
                   << " (least squares' " << r.ols_standard_error[k] << ")");
        CHECK(std::abs(error) <= 4.0 * r.standard_error[k]);
        within1 += std::abs(error) <= r.standard_error[k] ? 1 : 0;
        within1_ols += std::abs(error) <= r.ols_standard_error[k] ? 1 : 0;
        ++total;
      }
    }
    return std::pair{static_cast<double>(within1) / total,
                     static_cast<double>(within1_ols) / total};
  };
  SECTION("noise on the torque: the least-squares model itself") {
    const auto [fraction, ols] = run(
        true,
        [](identify::Trajectory& t, std::mt19937_64& rng) {
          std::normal_distribution<double> normal(0.0, 0.05);  // N m
          for (Eigen::Index i = 0; i < t.force.size(); ++i) t.force.data()[i] += normal(rng);
        },
        "torque");
    INFO("within one standard error: " << fraction << " (least squares' " << ols << ")");
    CHECK(fraction > 0.55);
    CHECK(fraction < 0.8);
  }
  SECTION("noise on qacc: errors shared by a sample's dofs (M e)") {
    const auto [fraction, ols] = run(
        true,
        [](identify::Trajectory& t, std::mt19937_64& rng) {
          std::normal_distribution<double> normal(0.0, 0.2);  // rad/s^2
          for (Eigen::Index i = 0; i < t.qacc.size(); ++i) t.qacc.data()[i] += normal(rng);
        },
        "qacc");
    INFO("within one standard error: " << fraction << " (least squares' " << ols << ")");
    CHECK(fraction > 0.55);
    CHECK(fraction < 0.8);
  }
  SECTION("noise on qvel, qacc differenced: errors correlated between neighbouring samples") {
    // each qvel error enters two differences with opposite signs: the differenced errors
    // telescope, and the textbook sigma^2 (W^T W)^-1 overstates the estimate's spread about
    // threefold (every estimate within one of its standard errors); the clustered sandwich not
    const auto [fraction, ols] = run(
        false,
        [](identify::Trajectory& t, std::mt19937_64& rng) {
          std::normal_distribution<double> normal(0.0, 2e-4);  // rad/s
          const Eigen::Index N = t.time.size();
          Eigen::MatrixXd e(t.qvel.rows(), N + 1);  // the dropped last row has its error too
          for (Eigen::Index i = 0; i < e.size(); ++i) e.data()[i] = normal(rng);
          for (Eigen::Index k = 0; k < N; ++k) {
            const double dt = k + 1 < N ? t.time[k + 1] - t.time[k] : t.time[k] - t.time[k - 1];
            t.qvel.col(k) += e.col(k);
            t.qacc.col(k) += (e.col(k + 1) - e.col(k)) / dt;
          }
        },
        "differenced");
    INFO("within one standard error: " << fraction << " (least squares' " << ols << ")");
    CHECK(fraction > 0.55);
    CHECK(fraction < 0.8);
    CHECK(ols > 0.9);
  }
}

TEST_CASE("identify: bad trajectories get clear errors", "[identify]") {
  const Model prior = mjcf::load_file(model_path("models/arm2.xml"));
  const std::string csv = temp_path("bad.csv");
  const auto write = [&](const std::string& text) { std::ofstream(csv) << text; };
  const auto error_of = [&]() -> std::string {
    try {
      identify::identify(prior, identify::read_csv(prior, csv));
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  write("time,qpos[shoulder],qvel[shoulder]\n0,0,0\n");
  CHECK_THAT(error_of(), Catch::Contains("no column 'qpos[elbow]'"));
  write(
      "time,qpos[shoulder],qpos[elbow],qvel[shoulder],qvel[elbow],qacc[shoulder],qacc[elbow],"
      "actuator_force[shoulder],actuator_force[elbow]\n0,0,0,0,0,0,0,0,nan\n");
  CHECK_THAT(error_of(), Catch::Contains(":2: column 'actuator_force[elbow]'"));
  write(
      "time,qpos[shoulder],qpos[elbow],qvel[shoulder],qvel[elbow],qacc[shoulder],qacc[elbow],"
      "actuator_force[shoulder],actuator_force[elbow]\n0,0,0,0,0,0,0,0,0\n");
  CHECK_THAT(error_of(), Catch::Contains("too few samples"));
  write(
      "time,qpos[shoulder],qpos[elbow],qvel[shoulder],qvel[elbow],qacc[shoulder],qacc[elbow],"
      "actuator_force[shoulder],actuator_force[elbow]\n0,0,1\n");
  CHECK_THAT(error_of(), Catch::Contains(":2: 3 fields, the header has 9"));
  std::filesystem::remove(csv);
  CHECK_THAT(error_of(), Catch::Contains("cannot open"));
}

}  // namespace lever::test
