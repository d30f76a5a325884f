// Elliptic friction cones against MuJoCo 2.2.2: the contact scenes and the lesson's
// models switched to <option cone="elliptic"> on both sides (MuJoCo's compiled model copied into
// lever), MuJoCo run to convergence (tolerance 0, 1000 iterations; its answer is then the
// problem's unique minimizer, the one lever's Newton solver converges to).
//   random states: the contacts and the rows (efc_J, pos, margin, R, D, K, B, imp, aref) within
//     1e-12; qacc, efc_force, qfrc_constraint and one Euler and one implicit step within the
//     solver bound; efc_state (zones) exactly; inverse() at the forward's qacc gives back its
//     forces and zones. MuJoCo's solver is restarted from its own answer until that stops
//     changing (Twin::restart_mujoco_solver): with elliptic cones its cost comparisons can stop
//     it short of the minimizer, ~1e-9 relative, at a state where lever's gradient is ~1e-12;
//   lockstep runs: lever started from MuJoCo's state at every step, Euler, RK4 and implicit.
// The states must reach all three zones of the cones, or the test has not tested them.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/compare.hpp>
#include <lever/diff/report.hpp>
#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include <lever/harness/tolerance.hpp>

#include "diff_checks.hpp"
#include "sampling.hpp"

namespace lever::test {

namespace {

struct Variant {
  std::string file;
  double impratio;
};

const std::vector<Variant>& variants() {
  static const std::vector<Variant> list = {
      {"models/box_drop.xml", 1.0},
      {"models/gripper.xml", 1.0},
      {"tests/diff/contact_scenes/free_objects.xml", 1.0},
      {"tests/diff/contact_scenes/arm_and_objects.xml", 1.0},
      {"tests/diff/contact_scenes/free_objects.xml", 5.0},  // friction rows stiffer than normal
  };
  return list;
}

std::string label(const Variant& v) {
  return v.file + " (elliptic, impratio " + std::to_string(v.impratio) + ")";
}

// Every quantity within its bound; the worst of those the solver decides, in units of 1e-12.
double check_report(const diff::Report& report, const std::string& name) {
  double worst_solver = 0;
  for (const diff::Extreme& e : report.quantities()) {
    INFO(name << ": " << e.quantity << " [" << e.element << "] state " << e.state << ": lever "
              << e.lever << " vs mujoco " << e.mujoco << ", " << e.max_ratio << " of 1e-12");
    if (diff::decided_by_solver(e.quantity)) worst_solver = std::max(worst_solver, e.max_ratio);
    CHECK(e.max_ratio <= e.bound);
  }
  return worst_solver;
}

}  // namespace

TEST_CASE("diff: elliptic cones agree with MuJoCo at random states (engine path)",
          "[diff][contact][elliptic]") {
  REQUIRE(mj_version() == 222);
  int zones[5] = {0, 0, 0, 0, 0};  // contacts seen in each state (satisfied, active, -, -, cone)
  for (const Variant& v : variants()) {
    const std::string name = label(v);
    diff::Twin twin(model_path(v.file), diff::Path::kEngine);
    twin.set_cone(Cone::kElliptic, v.impratio);
    twin.restart_mujoco_solver = true;
    std::mt19937_64 rng(seed_for(v.file));
    diff::Report report;
    report.set_solver_bound(diff::kContactSolverBound);
    int with_cones = 0;
    for (int k = 0; k < 200; ++k) {
      State s = random_state(twin.model, rng);
      if (k % 4 == 0) s.qvel.setZero();  // a quarter at rest, where contacts are steady
      diff::compare_forward(twin, s, k, report);
      bool cone = false;
      for (int i = 0; i < twin.data.ncon; ++i) {
        const Contact& con = twin.data.contact[i];
        if (con.efc_address < 0 || con.dim == 1) continue;
        REQUIRE(twin.data.efc_type[con.efc_address] == ConstraintType::kContactElliptic);
        ++zones[static_cast<int>(twin.data.efc_state[con.efc_address])];
        cone = true;
      }
      with_cones += cone;
      // inverse() at the forward's qacc finds the forward's forces and zones again (against
      // MuJoCo it would compare D (J qacc - aref) with D ~ 1e5: the rows' last bits, magnified)
      const Eigen::VectorXd force = twin.data.efc_force.head(twin.data.nefc);
      const std::vector<ConstraintState> state(twin.data.efc_state.begin(),
                                               twin.data.efc_state.begin() + twin.data.nefc);
      const Eigen::VectorXd aref = twin.data.efc_aref.head(twin.data.nefc);
      // from the state as given: forward() normalized qpos's quaternions in place (as
      // mj_kinematics does), and normalizing a unit quaternion again (MuJoCo's mju_normalize4
      // scales by 1 / |q| whatever |q| is) moves its last bits, and with them the rows'
      twin.data.qpos = s.qpos;
      inverse(twin.model, twin.data);
      CHECK((twin.data.efc_aref.head(twin.data.nefc) - aref).lpNorm<Eigen::Infinity>() == 0.0);
      CHECK((twin.data.efc_force.head(twin.data.nefc) - force).lpNorm<Eigen::Infinity>() <=
            1e-12 * std::max(1.0, force.lpNorm<Eigen::Infinity>()));
      CHECK(std::equal(state.begin(), state.end(), twin.data.efc_state.begin()));
      // one step: RK4's is left to the lockstep runs below (CI time), where each of MuJoCo's
      // four stages is converged as the first one is (diff::mujoco_rk4_step)
      for (const Integrator integrator : {Integrator::kEuler, Integrator::kImplicit}) {
        diff::compare_step(twin, s, integrator, k, report);
      }
    }
    INFO(name << ": " << with_cones << " of 200 states with elliptic rows");
    CHECK(with_cones > 20);
    const double worst = check_report(report, name);
    WARN(name << ": the solver's outputs within " << worst << " x 1e-12 of MuJoCo's");
  }
  INFO("cones satisfied " << zones[0] << ", all rows active " << zones[1] << ", on the surface "
                          << zones[4]);
  CHECK(zones[0] > 0);
  CHECK(zones[1] > 0);
  CHECK(zones[4] > 0);
}

TEST_CASE("diff: elliptic cones, lockstep runs equal MuJoCo step by step", "[diff][elliptic]") {
  REQUIRE(mj_version() == 222);
  for (const char* file : {"models/box_drop.xml", "models/gripper.xml",
                           "tests/diff/contact_scenes/free_objects.xml"}) {
    for (const Integrator integrator : kEveryIntegrator) {
      const std::string name = std::string(file) + ", " + integrator_name(integrator);
      diff::Twin twin(model_path(file), diff::Path::kEngine);
      twin.set_cone(Cone::kElliptic, 1.0);
      const diff::Report report =
          diff::lockstep(twin, integrator, run_seconds(2.0), diff::Control::kSmooth, nullptr);
      const double worst = check_report(report, name);
      WARN(name << ": the solver's outputs within " << worst << " x 1e-12 of MuJoCo's");
    }
  }
}

}  // namespace lever::test

namespace lever::test {

// A legged model with elliptic cones, in lockstep (lever started from MuJoCo's state each step):
// MuJoCo's Newton solver, even at tolerance 0, can stop short of the minimizer with elliptic
// cones (here 7e-8 relative in qacc at step 1352, 2.7 s in, measured with mj_forward alone), and
// a free run carries that on from step to step. Restarted from its own answer
// (Twin::restart_mujoco_solver, on by default for elliptic cones, mj_step's forward warm-started
// from the converged answer) it reaches the minimizer lever's exact solve finds.
TEST_CASE("diff: elliptic cones, a legged model in lockstep for 3 s", "[diff][elliptic]") {
  REQUIRE(mj_version() == 222);
  diff::Twin twin(model_path("tests/diff/contact_scenes/legged_elliptic.xml"), diff::Path::kEngine);
  REQUIRE(twin.restart_mujoco_solver);  // on by default: contacts and elliptic cones
  diff::RunStats stats;
  const diff::Report report =
      diff::lockstep(twin, Integrator::kEuler, 3.0, diff::Control::kSmooth, &stats);
  CHECK(stats.constrained_steps > 1400);  // the feet are on the floor
  const double worst = check_report(report, "legged_elliptic.xml, Euler lockstep");
  WARN("legged_elliptic.xml, Euler lockstep 3 s: the solver's outputs within " << worst
                                                                               << " x 1e-12");
}

}  // namespace lever::test
