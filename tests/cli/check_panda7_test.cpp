// `lever check` on the 7-DOF servo arm (lesson 5.2): sections (7) singular poses and (8) stability
// of the step, every figure recomputed here independently of check/: the Jacobian's SVD by Eigen
// at the printed pose, the step's spectral radius from this test's own finite-difference
// linearisation, and simulations with the reported armature. Also the servo wording of sections
// (1), (3) and (6), and `--key` on every command that takes a start state.
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <lever/harness/models.hpp>
#include "json_reader.hpp"
#include "run_lever.hpp"
#include "spectra.hpp"

namespace lever::test {

namespace {

Eigen::VectorXd vec(const json::Value& v) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
  for (size_t i = 0; i < v.size(); ++i) out[static_cast<Eigen::Index>(i)] = v[i].number;
  return out;
}

const json::Value& panda_report() {
  static const json::Value report = [] {
    const Run run = run_lever("check --json " + quoted(model_path("models/panda7.xml")));
    REQUIRE((run.status == 0 || run.status == 1));
    return json::parse(run.out);
  }();
  return report;
}

// The site's 6 x nv Jacobian at q, by the engine's kinematics.
Eigen::MatrixXd jacobian(const Model& model, const Eigen::VectorXd& q, int site) {
  Data data(model);
  data.qpos = q;
  forward(model, data);
  Eigen::MatrixXd jacp(3, model.nv), jacr(3, model.nv), J(6, model.nv);
  jac_site(model, data, site, jacp, jacr);
  J << jacp, jacr;
  return J;
}

// This test's own linearisation of the step: central differences with a different step size.
double radius(const Model& model, const Eigen::VectorXd& qpos, const Eigen::VectorXd& qvel,
              const Eigen::VectorXd& ctrl) {
  const int n = model.nq + model.nv;
  const double eps = 1e-7;
  Eigen::MatrixXd A(n, n);
  Data d(model);
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd plus(n), minus(n);
    for (const double sign : {1.0, -1.0}) {
      reset(model, d);
      d.qpos = qpos;
      d.qvel = qvel;
      d.ctrl = ctrl;
      (i < model.nq ? d.qpos[i] : d.qvel[i - model.nq]) += sign * eps;
      step(model, d);
      (sign > 0 ? plus : minus) << d.qpos, d.qvel;
    }
    A.col(i) = (plus - minus) / (2 * eps);
  }
  return lever::test::spectral_radius(A);
}

Model with(const Model& model, Integrator integrator, double timestep, double armature = -1) {
  Model m = model;
  m.opt.integrator = integrator;
  m.opt.timestep = timestep;
  if (armature >= 0) {
    for (double& a : m.dof_armature) a = armature;
    set_const(m);
  }
  return m;
}

// Steps from home: true when the run settles (no engine warning, |qvel| below 1e-3 over the
// last tenth); an unstable step either blows up or, with the forces clamped, keeps oscillating.
bool settles(const Model& model, int steps) {
  Data d(model);
  reset_keyframe(model, d, "home");
  double tail = 0.0;
  for (int k = 0; k < steps; ++k) {
    step(model, d);
    for (const WarningStat& w : d.warning) {
      if (w.number > 0) return false;
    }
    if (k >= steps - steps / 10) tail = std::max(tail, d.qvel.cwiseAbs().maxCoeff());
  }
  return tail < 1e-3;
}

}  // namespace

TEST_CASE("check panda7 (7): singular values, manipulability and aligned axes recomputed",
          "[check][panda7]") {
  const Model model = mjcf::load_file(model_path("models/panda7.xml"));
  const json::Value& site = panda_report()["singular_poses"]["sites"][0];
  CHECK(site["site"].string == "ee");
  CHECK(site["rows"].number == 6);
  CHECK(site["rank"].number == 6);
  const int ee = model.site("ee");
  const double tol = panda_report()["singular_poses"]["parallel_tolerance"].number;
  REQUIRE(site["states"].size() == 2);  // qpos0 and home
  CHECK(site["states"][1]["where"].string == "keyframe home");
  CHECK((vec(site["states"][1]["qpos"]) - model.key_qpos.row(0).transpose()).norm() == 0.0);
  REQUIRE(site["worst"].size() >= 1);
  for (const json::Value* list : {&site["states"], &site["worst"]}) {
    for (const json::Value& at : list->array) {
      INFO(at["where"].string);
      const Eigen::VectorXd q = vec(at["qpos"]);
      const Eigen::MatrixXd J = jacobian(model, q, ee);
      const Eigen::VectorXd sigma = lever::test::singular_values_jacobi(J);
      const Eigen::VectorXd printed = vec(at["sigma"]);
      REQUIRE(printed.size() == 6);
      // a singular value at or below 1e-9 sigma_1 does not count (it is the Jacobian's rounding
      // at a singular pose): printed as exactly 0, the others as computed
      const bool singular = sigma[5] <= 1e-9 * sigma[0];
      for (int i = 0; i < 6; ++i) {
        if (sigma[i] <= 1e-9 * sigma[0])
          CHECK(printed[i] == 0.0);
        else
          CHECK(std::abs(printed[i] - sigma[i]) <= 1e-12 * sigma[0]);
      }
      // the product of this test's singular values; sqrt(det(J J^T)) where it is well conditioned
      // (near a singular pose the determinant is rounding noise of order eps sigma_1^12)
      if (singular) {
        CHECK(at["manipulability"].number == 0.0);
        CHECK(at["condition"].kind == json::Value::Kind::kNull);  // infinite: JSON has no number
      } else {
        CHECK(std::abs(at["manipulability"].number - sigma.prod()) <=
              1e-9 * sigma.prod() + 1e-15 * std::pow(sigma[0], 6));
      }
      if (sigma[5] > 1e-3) {
        const double manip = std::sqrt((J * J.transpose()).determinant());
        CHECK(at["manipulability"].number == Approx(manip).epsilon(1e-9));
      }
      if (sigma[5] > 1e-9)
        CHECK(at["condition"].number == Approx(sigma[0] / sigma[5]).epsilon(1e-9));
      // aligned joints: every pair whose world axes are parallel within the tolerance, no other
      Data d(model);
      d.qpos = q;
      forward(model, d);
      size_t pairs = 0;
      for (int i = 0; i < model.njnt; ++i) {
        for (int j = i + 1; j < model.njnt; ++j) {
          const double angle =
              std::atan2(d.xaxis[i].cross(d.xaxis[j]).norm(), std::abs(d.xaxis[i].dot(d.xaxis[j])));
          if (angle > tol) continue;
          ++pairs;
          bool listed = false;
          for (const json::Value& a : at["aligned"].array) {
            listed = listed || (a["joints"][0].string == model.jnt_name[i] &&
                                a["joints"][1].string == model.jnt_name[j]);
          }
          CHECK(listed);
        }
      }
      CHECK(at["aligned"].size() == pairs);
    }
  }
  // the search found a pose at least as singular as any of this test's own random poses
  std::mt19937_64 rng(12345);
  double sampled = INFINITY;
  for (int k = 0; k < 2000; ++k) {
    Eigen::VectorXd q(model.nq);
    for (int j = 0; j < model.njnt; ++j) {
      std::uniform_real_distribution<double> u(model.jnt_range[j][0], model.jnt_range[j][1]);
      q[j] = u(rng);
    }
    sampled = std::min(sampled, lever::test::singular_values_jacobi(jacobian(model, q, ee))[5]);
  }
  const double worst = vec(site["worst"][0]["sigma"])[5];
  CHECK(worst <= sampled);
  CHECK(worst < 1e-3);  // the Panda has singular poses inside its ranges (aligned axes)
}

TEST_CASE("check panda7 (8): spectral radii, timesteps and armature recomputed",
          "[check][panda7]") {
  const Model model = mjcf::load_file(model_path("models/panda7.xml"));
  const json::Value& st = panda_report()["step_stability"];
  CHECK(st["integrator"].string == "implicit");
  REQUIRE(st["states"].size() == 1);
  const json::Value& home = st["states"][0];
  CHECK(home["where"].string == "keyframe home");
  Data d(model);
  reset_keyframe(model, d, "home");
  const Eigen::VectorXd qpos = d.qpos, qvel = d.qvel, ctrl = d.ctrl;
  CHECK((vec(home["ctrl"]) - ctrl).norm() == 0.0);
  const double h = model.opt.timestep;

  const double rho_model = radius(model, qpos, qvel, ctrl);
  const double rho_euler = radius(with(model, Integrator::kEuler, h), qpos, qvel, ctrl);
  // two central-difference linearisations with different steps (1e-7 here, lever check's own):
  // each carries rounding of order 1e-16 |x| / eps ~ 1e-9 in A's entries and truncation of order
  // eps^2; a spectral radius agrees to far better than 1e-5, which still tells 0.98 from 1
  CHECK(home["rho_model"].number == Approx(rho_model).epsilon(1e-5));
  CHECK(home["rho_euler"].number == Approx(rho_euler).epsilon(1e-5));
  // the lesson's point: the servos are stable under implicit and not under explicit Euler
  CHECK(rho_model < 1.0);
  CHECK(home["stable_model"].boolean);
  CHECK(rho_euler > 1.5);
  CHECK_FALSE(home["stable_euler"].boolean);
  CHECK(home["growth"].number < 0);  // the held arm itself is damped

  // the largest stable timesteps: stable just below, unstable just above (rho against 1 + slack)
  const double slack = st["slack"].number;
  for (const auto& [key, integrator] : {std::pair{"max_timestep_model", Integrator::kImplicit},
                                        std::pair{"max_timestep_euler", Integrator::kEuler}}) {
    INFO(key);
    const double dt = home[key].number;
    REQUIRE(std::isfinite(dt));
    CHECK(radius(with(model, integrator, 0.99 * dt), qpos, qvel, ctrl) <= 1 + slack);
    CHECK(radius(with(model, integrator, 1.01 * dt), qpos, qvel, ctrl) > 1 + slack);
  }
  CHECK(home["max_timestep_euler"].number < h);

  // the smallest armature for Euler: stable with it (rho), unstable with less; simulations agree
  const double a = home["armature_all"].number;
  REQUIRE(std::isfinite(a));
  CHECK(radius(with(model, Integrator::kEuler, h, 1.01 * a), qpos, qvel, ctrl) <= 1 + slack);
  CHECK(radius(with(model, Integrator::kEuler, h, 0.99 * a), qpos, qvel, ctrl) > 1 + slack);
  const double margin = st["margin"].number;
  CHECK(settles(with(model, Integrator::kEuler, h, margin * a), 1000));
  CHECK_FALSE(settles(with(model, Integrator::kEuler, h), 1000));
  CHECK(settles(model, 1000));
  const json::Value& runs = home["runs"];
  REQUIRE(runs.size() >= 3);
  CHECK(runs[0]["integrator"].string == "implicit");
  CHECK(runs[0]["settled"].boolean);
  CHECK(runs[1]["integrator"].string == "Euler");
  CHECK_FALSE(runs[1]["settled"].boolean);
  CHECK(runs[2]["settled"].boolean);
}

TEST_CASE("check panda7: servos in sections (1), (3) and (6)", "[check][panda7]") {
  const Model model = mjcf::load_file(model_path("models/panda7.xml"));
  const Run text = run_lever("check " + quoted(model_path("models/panda7.xml")));
  INFO(text.out);
  CHECK(text.out.find("  servo actuator1 (joint joint1): force = kp (ctrl - length) - kv velocity, "
                      "kp 4500 kv 450") != std::string::npos);
  CHECK(text.out.find("(7) singular poses") != std::string::npos);
  CHECK(text.out.find("(8) stability of the step") != std::string::npos);
  const json::Value& report = panda_report();
  // the budget's limit of a servo is gear x forcerange (ctrl is a target position, not a torque)
  for (int j = 0; j < model.njnt; ++j) {
    const json::Value& b = report["torque_budget"]["joints"][static_cast<size_t>(j)];
    INFO(b["joint"].string);
    CHECK(b["servo"].boolean);
    const int a = j;  // actuator j drives joint j
    const double kp = model.actuator_gainprm[a][0];
    if (b["loaded"].boolean) {
      const double tau = std::abs(b["worst_gravity_torque"].number);
      const double limit = b["worst_gravity_torque"].number < 0 ? -model.actuator_forcerange[a][0]
                                                                : model.actuator_forcerange[a][1];
      CHECK(b["motor_limit"].number == limit);
      CHECK(b["ratio"].number == Approx(limit / tau).epsilon(1e-15));
      CHECK(b["servo_offset"].number == Approx(tau / kp).epsilon(1e-15));
    }
  }
  // (6): the target is ctrl clamped to ctrlrange; the force, kp (target - q) - kv qd clamped to
  // forcerange, recomputed here at qpos0 and rest
  const json::Value& c = report["clamping"];
  for (int a = 0; a < model.nu; ++a) {
    const double ctrl = c["ctrl"][static_cast<size_t>(a)].number;
    const auto& r = model.actuator_ctrlrange[a];
    const double target = std::clamp(ctrl, r[0], r[1]);
    CHECK(c["target"][static_cast<size_t>(a)].number == target);
    const double q = model.qpos0[a];
    const double kp = model.actuator_gainprm[a][0];
    const double force = kp * target - kp * q;
    // the engine sums kp target + (-kp) length in another order: |kp q| reaches ~7e3 N m, so
    // the two roundings differ by ~1e-12; 1e-9 N m is that with room, and far below any term
    CHECK(c["force_before_forcerange"][static_cast<size_t>(a)].number ==
          Approx(force).margin(1e-9));
    const auto& f = model.actuator_forcerange[a];
    CHECK(c["actuator_force"][static_cast<size_t>(a)].number ==
          Approx(std::clamp(force, f[0], f[1])).margin(1e-9));
  }
}

TEST_CASE("docs/lesson-5.2.md's block is what lever check prints for panda7", "[check][panda7]") {
  std::ifstream in(model_path("docs/lesson-5.2.md"));
  std::stringstream doc;
  doc << in.rdbuf();
  const std::string text = doc.str();
  const size_t open = text.find("```text\n");
  REQUIRE(open != std::string::npos);
  const size_t start = open + 8, end = text.find("```", start);
  const std::string block = text.substr(start, end - start);
  const Run run = run_lever("check " + quoted(model_path("models/panda7.xml")));
  const size_t from = run.out.find("(7) singular poses");
  REQUIRE(from != std::string::npos);
  CHECK(block == run.out.substr(from));
}

TEST_CASE("check --svg writes the torque budget, the singular poses and the step's stability",
          "[check][panda7]") {
  const std::string svg =
      (std::filesystem::temp_directory_path() / "lever-check-panda7.svg").string();
  const Run run =
      run_lever("check --svg " + quoted(svg) + " " + quoted(model_path("models/panda7.xml")));
  CHECK((run.status == 0 || run.status == 1));
  const std::string stem = svg.substr(0, svg.size() - 4);
  for (const std::string& file :
       {svg, stem + "-singular-poses.svg", stem + "-step-stability.svg"}) {
    INFO(file);
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    CHECK(text.str().find("<svg") != std::string::npos);
    CHECK(text.str().find("panda7") != std::string::npos);
    std::filesystem::remove(file);
  }
}

TEST_CASE("key option: forward, simulate, derivatives and check start from a keyframe",
          "[check][key]") {
  const std::string panda = quoted(model_path("models/panda7.xml"));
  const Model model = mjcf::load_file(model_path("models/panda7.xml"));
  const Run fwd = run_lever("forward --key home --json " + panda);
  REQUIRE(fwd.status == 0);
  const json::Value out = json::parse(fwd.out);
  CHECK((vec(out["qpos"]) - model.key_qpos.row(0).transpose()).norm() == 0.0);
  CHECK((vec(out["ctrl"]) - model.key_ctrl.row(0).transpose()).norm() == 0.0);
  // --qpos overrides the keyframe's qpos, and keeps its ctrl
  const Run over = run_lever("forward --key home --qpos 0,0,0,-1,0,1,0 --json " + panda);
  REQUIRE(over.status == 0);
  CHECK(json::parse(over.out)["qpos"][3].number == -1.0);
  CHECK((vec(json::parse(over.out)["ctrl"]) - model.key_ctrl.row(0).transpose()).norm() == 0.0);

  const Run sim = run_lever("simulate --key home --steps 2 --json " + panda);
  REQUIRE(sim.status == 0);
  const json::Value first = json::parse(sim.out.substr(0, sim.out.find('\n')));
  CHECK((vec(first["qpos"]) - model.key_qpos.row(0).transpose()).norm() == 0.0);
  CHECK((vec(first["ctrl"]) - model.key_ctrl.row(0).transpose()).norm() == 0.0);

  const Run chk = run_lever("check --key home --json " + panda);
  CHECK((chk.status == 0 || chk.status == 1));
  CHECK(json::parse(chk.out)["step_stability"]["states"][0]["where"].string == "keyframe home");

  for (const char* command : {"forward", "simulate", "derivatives", "check"}) {
    INFO(command);
    const Run bad = run_lever(std::string(command) + " --key nosuch " + panda, true);
    CHECK(bad.status == 2);
    CHECK(bad.out.find("nosuch") != std::string::npos);
    CHECK(bad.out.find("'home'") != std::string::npos);  // the error lists the keyframes
  }
  const Run none = run_lever("forward --key home " + quoted(model_path("models/arm2.xml")), true);
  CHECK(none.status == 2);
  CHECK(none.out.find("no named keyframes") != std::string::npos);
}

TEST_CASE("check arm2: sections (7) and (8) for a planar 2-joint arm", "[check]") {
  const Model model = mjcf::load_file(model_path("models/arm2.xml"));
  const Run run = run_lever("check --json " + quoted(model_path("models/arm2.xml")));
  const json::Value report = json::parse(run.out);
  const json::Value& site = report["singular_poses"]["sites"][0];
  CHECK(site["rows"].number == 3);  // fewer than 6 joints: the position is the task
  CHECK(site["rank"].number == 2);
  // the most singular pose of a two-link arm: the elbow straight or folded, sigma_2 = 0
  const Eigen::VectorXd q = vec(site["worst"][0]["qpos"]);
  Data d(model);
  d.qpos = q;
  forward(model, d);
  Eigen::MatrixXd jacp(3, model.nv), jacr(3, model.nv);
  jac_site(model, d, model.site("ee"), jacp, jacr);
  const Eigen::VectorXd sigma = lever::test::singular_values_jacobi(jacp);
  CHECK(std::abs(vec(site["worst"][0]["sigma"])[1] - sigma[1]) <= 1e-12);
  // singular up to the search's resolution: its golden sections stop near 1e-8 rad in q, where
  // the vanishing singular value is ~1e-9 of the others and sin(q2) ~1e-8
  CHECK(sigma[1] < 1e-9);
  CHECK(std::abs(std::sin(q[1])) < 1e-6);
  const json::Value& st = report["step_stability"]["states"][0];
  CHECK(st["where"].string == "qpos0");
  // as at home: two finite-difference linearisations with different steps
  CHECK(st["rho_model"].number == Approx(radius(model, model.qpos0, Eigen::VectorXd::Zero(model.nv),
                                                Eigen::VectorXd::Zero(model.nu)))
                                      .epsilon(1e-5));
}

}  // namespace lever::test
