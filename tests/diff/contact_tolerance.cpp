// What MuJoCo's solver options do to its own answer, measured for docs/contact.md:
//   build/tests/diff/test_diff_collision "[tolerance]" -s
// On the contact scenes, pyramidal and elliptic, at 200 random states each: MuJoCo 2.2.2 with its
// defaults (tolerance 1e-8, 100 iterations) against MuJoCo run to convergence (tolerance 0, 1000
// iterations, restarted from its own answer while that changes it), qacc and efc_force relative to
// max(1, |value|). And, for pyramidal models, lever's Newton solver (constraint/newton.cpp) against its exact
// LCP (constraint/rows.cpp), both against MuJoCo converged: why the LCP stays.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>

#include "constraint/constraint_room.hpp"

namespace lever::test {

namespace {

std::string sci(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1e", x);
  return text;
}

double relative(const double* a, const double* b, int n) {
  double diff = 0, scale = 1;
  for (int i = 0; i < n; ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  return diff / scale;
}

}  // namespace

TEST_CASE("diff: how far MuJoCo's default tolerance moves its answer", "[diff][tolerance]") {
  REQUIRE(mj_version() == 222);
  std::printf(
      "| model | cone | states with contact rows | qacc, tolerance 1e-8 | efc_force, "
      "tolerance 1e-8 | qacc, lever Newton vs active sets | qacc, Newton vs MuJoCo | qacc, "
      "active sets vs MuJoCo | qacc, pivoting vs MuJoCo "
      "|\n|---|---|---|---|---|---|---|---|---|\n");
  for (const char* file :
       {"models/box_drop.xml", "models/gripper.xml", "tests/diff/contact_scenes/free_objects.xml",
        "tests/diff/contact_scenes/arm_and_objects.xml"}) {
    for (const Cone cone : {Cone::kPyramidal, Cone::kElliptic}) {
      diff::Twin twin(model_path(file), diff::Path::kEngine);
      twin.set_cone(cone, 1.0);
      twin.restart_mujoco_solver = true;
      const int nv = twin.model.nv;
      std::mt19937_64 rng(seed_for(file));
      double loose_qacc = 0, loose_force = 0, newton_lcp = 0, newton_mj = 0, lcp_mj = 0;
      double pivoting_mj = 0;
      int with_rows = 0;
      for (int k = 0; k < 200; ++k) {
        State s = random_state(twin.model, rng);
        if (k % 4 == 0) s.qvel.setZero();
        // MuJoCo converged (the Twin's settings)
        twin.set_state(s);
        twin.mujoco_forward();
        const int nefc = twin.d->nefc;
        if (nefc == 0) continue;
        ++with_rows;
        const std::vector<double> qacc(twin.d->qacc, twin.d->qacc + nv);
        const std::vector<double> force(twin.d->efc_force, twin.d->efc_force + nefc);
        // MuJoCo with its defaults, from the same cleared warm start
        const double tolerance = twin.m->opt.tolerance;
        const int iterations = twin.m->opt.iterations;
        twin.m->opt.tolerance = 1e-8;
        twin.m->opt.iterations = 100;
        twin.set_state(s);
        mj_forward(twin.m.get(), twin.d.get());
        twin.m->opt.tolerance = tolerance;
        twin.m->opt.iterations = iterations;
        REQUIRE(twin.d->nefc == nefc);
        loose_qacc = std::max(loose_qacc, relative(twin.d->qacc, qacc.data(), nv));
        loose_force = std::max(loose_force, relative(twin.d->efc_force, force.data(), nefc));
        // lever: its solver for this cone; for a pyramid (solved by active sets), also the
        // Newton solver and the principal pivoting (the active sets' fallback)
        forward(twin.model, twin.data);
        if (cone == Cone::kPyramidal) {
          const Eigen::VectorXd lcp = twin.data.qacc;
          solve_constraint_newton(twin.model, twin.data);
          newton_lcp = std::max(newton_lcp, relative(twin.data.qacc.data(), lcp.data(), nv));
          newton_mj = std::max(newton_mj, relative(twin.data.qacc.data(), qacc.data(), nv));
          lcp_mj = std::max(lcp_mj, relative(lcp.data(), qacc.data(), nv));
          solve_constraint_pivoting(twin.model, twin.data);
          pivoting_mj = std::max(pivoting_mj, relative(twin.data.qacc.data(), qacc.data(), nv));
        }
      }
      CHECK(with_rows > 20);
      const bool pyramid = cone == Cone::kPyramidal;
      std::printf("| %s | %s | %d | %.1e | %.1e | %s | %s | %s | %s |\n", file,
                  pyramid ? "pyramidal" : "elliptic", with_rows, loose_qacc, loose_force,
                  pyramid ? sci(newton_lcp).c_str() : "", pyramid ? sci(newton_mj).c_str() : "",
                  pyramid ? sci(lcp_mj).c_str() : "", pyramid ? sci(pivoting_mj).c_str() : "");
      if (pyramid) {
        // each of lever's solvers reaches MuJoCo's converged answer
        CHECK(newton_mj <= 1e-10);
        CHECK(lcp_mj <= 1e-10);
        CHECK(pivoting_mj <= 1e-10);
      }
    }
  }
}

}  // namespace lever::test
