// The step's derivatives through connect and weld constraints (their rows move with the bodies'
// poses: the anchors' separation and the orientation error, the Jacobian at the moving anchors,
// the impedance at the error's norm), under Euler, RK4 and implicit, against centred differences
// of lever's own step (eps 1e-6) and of MuJoCo 2.2.2's mj_step at tolerance 0 (eps 1e-6 and 1e-5;
// step_differences.hpp), within 1e-6 of the matrix's scale, computed both ways here: on
// tests/models/constraints/equality.xml (a four-bar closed by a connect, a ball pendulum pinned to
// the world, a free lid welded to a free base, a base welded to the world with relpose and
// torquescale, joint couplings), on Menagerie 2022's Agility Cassie (four connects closing the
// legs' linkages, ball joints, a free pelvis) and its Robotiq 2F-85 (two connects, a joint
// coupling, a tendon actuator).
#include <catch2/catch.hpp>
#include <lever/diff/twin.hpp>

#include <lever/derivatives.hpp>
#include <lever/lever.hpp>

#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <string>

#include <lever/harness/models.hpp>
#include "step_checks.hpp"
#include "robots.hpp"

namespace lever::test::equality_derivatives {

namespace {

using namespace lever::test::step_differences;

struct BodyRows {
  int connect_rows = 0, weld_rows = 0;
  bool curved = false;  // a connect's or weld's error within its solimp width (imp below dmax)
};

BodyRows body_rows(const Model& model, const State& s) {
  Data data(model);
  apply(s, data);
  forward(model, data);
  BodyRows rows;
  for (int r = 0; r < data.nefc; ++r) {
    if (data.efc_type[r] != ConstraintType::kEquality) continue;
    const int e = data.efc_id[r];
    if (model.eq_type[e] == EqualityType::kConnect) ++rows.connect_rows;
    if (model.eq_type[e] == EqualityType::kWeld) ++rows.weld_rows;
    rows.curved = rows.curved || data.efc_imp[r] < model.eq_solimp[e][1];
  }
  return rows;
}

// qpos0 moved along every tangent direction by a deterministic amount, velocities, then `steps`
// Euler steps of lever: the constraints pull the bodies back towards consistent poses, so the
// state has errors of the size the simulation has, and velocities.
State moved_and_settled(const Model& model, double move, int steps, const Eigen::VectorXd& ctrl) {
  State s = state_of(model);
  Eigen::VectorXd dq(model.nv);
  for (int i = 0; i < model.nv; ++i) dq[i] = move * ((i * 7 % 5) - 2) / 2.0;
  integrate_pos(model, s.qpos, dq, 1.0);
  for (int i = 0; i < model.nv; ++i) s.qvel[i] = 0.3 * ((i * 3 % 7) - 3) / 3.0;
  s.ctrl = ctrl;
  return settle(model, s, steps);
}

void run_equality_case(const std::string& file, const std::string& name, double move, int steps,
                       const Eigen::VectorXd& ctrl, int connect_rows, int weld_rows,
                       std::initializer_list<Integrator> integrators) {
  diff::Twin twin(file, diff::Path::kEngine);
  converge(twin);
  for (const Integrator integrator : integrators) {
    twin.set_integrator(integrator);
    const State s = moved_and_settled(twin.model, move, steps, ctrl);
    const BodyRows rows = body_rows(twin.model, s);
    CHECK(rows.connect_rows == connect_rows);
    CHECK(rows.weld_rows == weld_rows);
    INFO(name);
    const double worst = check_step_derivatives(twin, s, rows.curved);
    INFO(name << ", " << integrator_name(integrator) << ": worst " << worst << " of the bound"
              << (rows.curved ? " (curved impedance)" : ""));
    CHECK(worst <= 1);
  }
}

}  // namespace

TEST_CASE("derivatives through connect and weld: equality.xml",
          "[derivatives][mujoco][equality]") {
  const std::string file = model_path("tests/models/constraints/equality.xml");
  Eigen::VectorXd ctrl(2);
  ctrl << 0.5, -0.3;
  run_equality_case(file, "equality.xml", 0.02, 20, ctrl, 6, 12,
                    {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit});
}

TEST_CASE("derivatives through connect: Menagerie's Cassie and Robotiq 2F-85",
          "[derivatives][mujoco][equality][robots]") {
  const std::string folder = robots_dir();
  if (!robots_present(folder)) return;
  // Cassie under Euler only: MuJoCo's mj_step at tolerance 0 runs its Newton solver's 100
  // iterations on 32 dofs (about 10 ms a step here), and the integrators' own terms are the
  // other two models'
  run_equality_case(folder + "/menagerie-2022/agility_cassie/cassie.xml", "Cassie", 0.01, 20,
                    Eigen::VectorXd::Constant(10, 0.5), 12, 0, {Integrator::kEuler});
  Eigen::VectorXd grip(1);
  grip << 120;
  run_equality_case(folder + "/menagerie-2022/robotiq_2f85/2f85.xml", "2F-85", 0.0, 100, grip, 6,
                    0, {Integrator::kEuler, Integrator::kRK4, Integrator::kImplicit});
}

}  // namespace lever::test::equality_derivatives
