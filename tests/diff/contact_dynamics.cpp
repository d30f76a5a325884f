// Contact dynamics against MuJoCo 2.2.2: models/box_drop.xml, models/gripper.xml and
// tests/diff/contact_scenes/free_objects.xml with
// MuJoCo's compiled model copied into lever (the engine path: the loader's contact attributes are
// tested in tests/mjcf), at random states: the contacts, the constraint rows (efc_J, pos, margin,
// R, D, aref, diagApprox) within the 1e-12 bound; qacc, qfrc_constraint and efc_force, which
// MuJoCo finds iteratively, against MuJoCo run with tolerance 0 and 1000 iterations (its answer is
// then the problem's unique minimizer) within 1e-10 relative, the worst reported against 1e-12.
// Then one step of each integrator from the same states.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/compare.hpp>
#include <lever/diff/report.hpp>
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

namespace lever::test {

namespace {

// MuJoCo's answer made unique: its Newton solver run to convergence.
void converge_mujoco(diff::Twin& twin) {
  twin.m->opt.tolerance = 0;
  twin.m->opt.iterations = 1000;
}

// A state of a scene: the free bodies dropped into it or resting on what is below them, the
// servo targets anywhere in their ranges.
State scene_state(const Model& model, std::mt19937_64& rng, int k) {
  State s = random_state(model, rng);
  // a quarter of the states at rest, where contacts are steady
  if (k % 4 == 0) s.qvel.setZero();
  return s;
}

}  // namespace

TEST_CASE("diff: contact scenes agree with MuJoCo at random states (engine path)",
          "[diff][contact]") {
  REQUIRE(mj_version() == 222);
  for (const std::string name : {"models/box_drop.xml", "models/gripper.xml",
                                 "tests/diff/contact_scenes/free_objects.xml"}) {
    diff::Twin twin(model_path(name), diff::Path::kEngine);
    converge_mujoco(twin);
    std::mt19937_64 rng(seed_for(name));
    diff::Report report;
    report.set_solver_bound(diff::kContactSolverBound);
    int with_contacts = 0;
    for (int k = 0; k < 200; ++k) {
      const State s = scene_state(twin.model, rng, k);
      diff::compare_forward(twin, s, k, report);
      with_contacts += twin.data.ncon > 0 && twin.data.nefc > 0;
      for (const Integrator integrator : kEveryIntegrator) {
        diff::compare_step(twin, s, integrator, k, report);
      }
    }
    INFO(name << ": " << with_contacts << " of 200 states with contact rows");
    CHECK(with_contacts > 20);
    double worst_solver = 0;
    for (const diff::Extreme& e : report.quantities()) {
      INFO(name << ": " << e.quantity << " [" << e.element << "] state " << e.state << ": lever "
                << e.lever << " vs mujoco " << e.mujoco << ", " << e.max_ratio << " of 1e-12");
      if (diff::decided_by_solver(e.quantity)) worst_solver = std::max(worst_solver, e.max_ratio);
      CHECK(e.max_ratio <= e.bound);  // 1e-10 relative where the solver decides, else 1e-12
    }
    WARN(name << ": the solver's outputs within " << worst_solver * 1e-12
              << " of MuJoCo's (relative to max(1, |value|))");
  }
}

}  // namespace lever::test
