// `lever check` section (8): the timestep and armature searches find the boundaries they claim.
// Every boundary a search reports (the value printed, and every other change of stability it
// lists) is checked here with this test's own criterion: the spectral radius of this test's own
// finite-difference linearisation of the step (another difference step than the check's), against
// max(1, exp(h growth)) (1 + slack), the growth rate from this test's own continuous
// linearisation (or, for the pendulum, its closed form). Just below a boundary the step is on one
// side, just above on the other. A search that finds stability changing more than once must say
// so, and a finer scan of this test's own finds the same changes.
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <lever/harness/models.hpp>
#include "json_reader.hpp"
#include "run_lever.hpp"
#include "spectra.hpp"

namespace lever::test {

namespace {

// Just below and just above a boundary, relative. A relative 1e-4 moves the spectral radius by
// about 1e-4 of itself, far beyond the ~1e-9 by which two difference linearisations differ.
constexpr double kStep = 1e-4;

struct Start {
  Eigen::VectorXd qpos, qvel, ctrl;
};

Eigen::VectorXd vec(const json::Value& v) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
  for (size_t i = 0; i < v.size(); ++i) out[static_cast<Eigen::Index>(i)] = v[i].number;
  return out;
}

Model with(const Model& model, Integrator integrator, double timestep,
           const Eigen::VectorXd& armature = {}) {
  Model m = model;
  m.opt.integrator = integrator;
  m.opt.timestep = timestep;
  if (armature.size() > 0) {
    for (int i = 0; i < m.nv; ++i) m.dof_armature[i] = armature[i];
    set_const(m);
  }
  return m;
}

// This test's linearisation of the step (central differences, step 1e-7) and its spectral radius.
double radius(const Model& model, const Start& s) {
  const int n = model.nq + model.nv;
  const double eps = 1e-7;
  Eigen::MatrixXd A(n, n);
  Data d(model);
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd plus(n), minus(n);
    for (const double sign : {1.0, -1.0}) {
      reset(model, d);
      d.qpos = s.qpos;
      d.qvel = s.qvel;
      d.ctrl = s.ctrl;
      (i < model.nq ? d.qpos[i] : d.qvel[i - model.nq]) += sign * eps;
      step(model, d);
      Eigen::VectorXd& x = sign > 0 ? plus : minus;
      x.head(model.nq) = d.qpos;
      x.tail(model.nv) = d.qvel;
    }
    A.col(i) = (plus - minus) / (2 * eps);
  }
  return lever::test::spectral_radius(A);
}

// This test's continuous linearisation [[0, I], [dqacc/dq, dqacc/dqvel]] (central differences of
// forward, step 1e-7): its largest real part.
double growth(const Model& model, const Start& s) {
  const int nv = model.nv;
  const double eps = 1e-7;
  Eigen::MatrixXd Ac = Eigen::MatrixXd::Zero(2 * nv, 2 * nv);
  Ac.topRightCorner(nv, nv).setIdentity();
  Data d(model);
  for (int i = 0; i < 2 * nv; ++i) {
    Eigen::VectorXd qacc[2];
    for (int side = 0; side < 2; ++side) {
      reset(model, d);
      d.qpos = s.qpos;
      d.qvel = s.qvel;
      d.ctrl = s.ctrl;
      (i < nv ? d.qpos[i] : d.qvel[i - nv]) += side == 0 ? eps : -eps;
      forward(model, d);
      qacc[side] = d.qacc;
    }
    Ac.block(nv, i, nv, 1) = (qacc[0] - qacc[1]) / (2 * eps);
  }
  return lever::test::largest_real_part(Ac);
}

// The check's criterion, evaluated here: a step is stable when it grows no mode faster than the
// dynamics do.
using Growth = std::function<double(const Model&)>;
bool stable(const Model& m, const Start& s, double slack, const Growth& rate) {
  return radius(m, s) <= std::max(1.0, std::exp(m.opt.timestep * rate(m))) * (1 + slack);
}

// Every change a search lists, as this test finds it: its stable side stable, and stability on
// either side of it as the search says (starting from the search's first point, each change flips
// it).
void check_changes(const json::Value& scan, const std::function<bool(double)>& ok) {
  bool before = scan["stable_first"].boolean;
  for (const json::Value& c : scan["changes"].array) {
    const double x = c.number;
    INFO("change at " << x << (before ? ", stable below" : ", stable above"));
    CHECK(ok(x));                           // the stable side given is stable
    CHECK(ok(x * (1 - kStep)) == before);   // just below
    CHECK(ok(x * (1 + kStep)) == !before);  // just above
    before = !before;
  }
}

// This test's own scan, four times finer than the check's (40 points a decade, plus 0 when
// `with_zero`): how often stability changes along it.
int changes_along(const std::function<bool(double)>& ok, double from, double to, bool with_zero) {
  const int intervals = static_cast<int>(std::ceil(40 * std::log10(to / from)));
  bool previous = with_zero ? ok(0.0) : ok(from);
  int changes = 0;
  for (int k = with_zero ? 0 : 1; k <= intervals; ++k) {
    const bool now = ok(from * std::pow(to / from, static_cast<double>(k) / intervals));
    if (now != previous) ++changes;
    previous = now;
  }
  return changes;
}

// An inverted pendulum, upright at qpos0 under strong gravity, braked by a velocity actuator:
// under explicit Euler its stability changes more than once along the timestep and along the
// armature (the criterion lets a step grow as fast as the falling pendulum does, exp(h growth),
// which outgrows the brake's instability at large steps and small inertia).
std::string pendulum(double gravity, double kv) {
  return temporary_file("lever-check-inverted-pendulum.xml", R"(<mujoco model="inverted">
  <option timestep="0.05" integrator="Euler" gravity="0 0 -)" + std::to_string(gravity) +
                                                                 R"("/>
  <worldbody>
    <body name="pole">
      <joint name="hinge" type="hinge" axis="0 1 0"/>
      <inertial pos="0 0 0.1" mass="1" diaginertia="0.001 0.001 0.001"/>
    </body>
  </worldbody>
  <actuator>
    <velocity name="brake" joint="hinge" kv=")" + std::to_string(kv) +
                                                                 R"(" ctrlrange="-1 1"/>
  </actuator>
</mujoco>
)");
}

}  // namespace

TEST_CASE("check (8): the pendulum's searches list every change of stability, each verified",
          "[check][stability]") {
  // two pendulums: stability changes twice along the armature for the first, three times for the
  // second (stable only in a window and then from some armature on)
  for (const auto& [gravity, kv, armature_changes] :
       {std::tuple{300.0, 0.3, 2}, {1000.0, 1.0, 3}}) {
    const std::string file = pendulum(gravity, kv);
    const Model model = mjcf::load_file(file);
    const Run text = run_lever("check " + quoted(file));
    const Run run = run_lever("check --json " + quoted(file));
    REQUIRE((run.status == 0 || run.status == 1));  // 1: the model's own step is unstable
    const json::Value report = json::parse(run.out);
    const json::Value& st = report["step_stability"];
    const json::Value& at = st["states"][0];
    const double slack = st["slack"].number, h = model.opt.timestep;
    const Start s{model.qpos0, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1)};
    // the growth rate in closed form: I' theta'' = m g l theta - kv theta', with I' the inertia
    // about the hinge plus the armature (m l^2 + I_yy + a)
    const double g = gravity, brake = kv;  // (a lambda may not capture a structured binding)
    const Growth rate = [&](const Model& m) {
      const double inertia = 1.0 * 0.1 * 0.1 + 0.001 + m.dof_armature[0];
      const double K = 1.0 * g * 0.1 / inertia, C = brake / inertia;
      return 0.5 * (-C + std::sqrt(C * C + 4 * K));
    };
    // the check reports the growth rate from a numerical eigenvalue at a boundary bisected to a
    // relative 1e-9; the closed form here is exact, so 1e-6 is the bisection and eigen-solver
    // rounding, not a term that differs
    CHECK(at["growth"].number == Approx(rate(model)).epsilon(1e-6));

    INFO("gravity " << gravity << ", kv " << kv);
    const auto at_timestep = [&](double dt) {
      return stable(with(model, Integrator::kEuler, dt), s, slack, rate);
    };
    const json::Value& dt_scan = at["timestep_scan_model"];
    REQUIRE(dt_scan["changes"].size() == 2);  // stable, unstable, then stable again
    CHECK(dt_scan["stable_first"].boolean);
    check_changes(dt_scan, at_timestep);
    CHECK(changes_along(at_timestep, dt_scan["from"].number, dt_scan["to"].number, false) == 2);
    // the timestep reported: the first change, below which every timestep is stable
    CHECK(at["max_timestep_model"].number == dt_scan["changes"][0].number);

    const auto at_armature = [&](double a) {
      return stable(with(model, Integrator::kEuler, h, Eigen::VectorXd::Constant(1, a)), s, slack,
                    rate);
    };
    const json::Value& arm_scan = at["armature_scan_all"];
    REQUIRE(arm_scan["changes"].size() == static_cast<size_t>(armature_changes));
    check_changes(arm_scan, at_armature);
    CHECK(changes_along(at_armature, arm_scan["from"].number, arm_scan["to"].number, true) ==
          armature_changes);
    // the armature reported: the last change, above which every armature is stable
    const double a = at["armature_all"].number;
    CHECK(a == arm_scan["changes"][static_cast<size_t>(armature_changes - 1)].number);
    CHECK(at_armature(a));
    CHECK_FALSE(at_armature(a * (1 - kStep)));
    CHECK(at_armature(10 * a));

    // the text says that stability changed more than once, and which boundary it reports
    INFO(text.out);
    CHECK(text.out.find("stability changes more than once in:") != std::string::npos);
    CHECK(text.out.find("Euler timestep: 2 changes, stable on [") != std::string::npos);
    CHECK(text.out.find("Euler armature on every joint: " + std::to_string(armature_changes) +
                        " changes") != std::string::npos);
    CHECK(text.out.find("reported: the largest timestep below which every one is stable") !=
          std::string::npos);
    CHECK(text.out.find("reported: the smallest armature above which every one is stable") !=
          std::string::npos);
    std::filesystem::remove(file);
  }
}

TEST_CASE("check (8) panda7: each timestep and armature reported is a boundary, verified here",
          "[check][stability][panda7]") {
  const Model model = mjcf::load_file(model_path("models/panda7.xml"));
  const Run run = run_lever("check --json " + quoted(model_path("models/panda7.xml")));
  REQUIRE((run.status == 0 || run.status == 1));
  const json::Value report = json::parse(run.out);
  const json::Value& st = report["step_stability"];
  const json::Value& at = st["states"][0];
  Data data(model);
  reset_keyframe(model, data, "home");
  const Start s{data.qpos, data.qvel, data.ctrl};
  const double slack = st["slack"].number, h = model.opt.timestep;
  const Growth rate = [&](const Model& m) { return growth(m, s); };

  // timesteps: one change each along the whole search (a single boundary), and that boundary
  for (const auto& [name, integrator] :
       {std::pair{std::string("model"), model.opt.integrator}, {"euler", Integrator::kEuler}}) {
    INFO(name);
    const Integrator chosen = integrator;  // (a lambda may not capture a structured binding)
    const auto ok = [&](double dt) { return stable(with(model, chosen, dt), s, slack, rate); };
    const json::Value& scan = at["timestep_scan_" + name];
    REQUIRE(scan["changes"].size() == 1);
    check_changes(scan, ok);
    const double dt = at["max_timestep_" + name].number;
    CHECK(dt == scan["changes"][0].number);
    CHECK(ok(dt * (1 - kStep)));
    CHECK_FALSE(ok(dt * (1 + kStep)));
  }

  // armatures: the same on every joint, per joint with the others heavy, the common floor
  const auto euler = [&](const Eigen::VectorXd& armature) {
    return stable(with(model, Integrator::kEuler, h, armature), s, slack, rate);
  };
  const double all = at["armature_all"].number;
  REQUIRE(std::isfinite(all));
  REQUIRE(all > 0);
  const auto uniform = [&](double a) { return euler(Eigen::VectorXd::Constant(model.nv, a)); };
  check_changes(at["armature_scan_all"], uniform);
  CHECK(uniform(all));
  CHECK_FALSE(uniform(all * (1 - kStep)));
  const Eigen::VectorXd each = vec(at["armature_each"]);
  const double ample = st["ample"].number;
  for (int j = 0; j < model.njnt; ++j) {
    INFO("joint " << model.jnt_name[j] << ", others at " << ample << " x " << all);
    const auto own = [&](double a) {
      Eigen::VectorXd arm = Eigen::VectorXd::Constant(model.nv, ample * all);
      arm[model.jnt_dofadr[j]] = a;
      return euler(arm);
    };
    check_changes(at["armature_scan_each"][static_cast<size_t>(j)], own);
    CHECK(own(each[j]));
    if (each[j] > 0) CHECK_FALSE(own(each[j] * (1 - kStep)));
  }
  const double floor = at["armature_floor"].number;
  const auto floored = [&](double t) {
    Eigen::VectorXd arm = Eigen::VectorXd::Constant(model.nv, t);
    for (int j = 0; j < model.njnt; ++j) arm[model.jnt_dofadr[j]] = std::max(each[j], t);
    return euler(arm);
  };
  check_changes(at["armature_scan_floor"], floored);
  CHECK(floored(floor));
  CHECK_FALSE(floored(floor * (1 - kStep)));
}

}  // namespace lever::test
