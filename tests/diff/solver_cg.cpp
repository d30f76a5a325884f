// MuJoCo's conjugate-gradient solver (<option solver="CG">, engine/src/constraint/cg.cpp) against
// MuJoCo 2.2.2's mj_solCG, both computed here:
//   at tolerance 0 (lever solves exactly, as for Newton), on the contact scenes with pyramidal
//     and elliptic cones at random states: every forward output within the solver's bound of
//     MuJoCo's CG (1000 iterations, restarted from its own answer as the harness restarts
//     Newton). On tests/diff/contact_scenes/free_objects.xml MuJoCo's CG stalls short of the
//     minimizer even restarted (1e-8 pyramidal, 3e-7 elliptic, relative in qacc): left out;
//   at MuJoCo's default tolerance (1e-8) and iterations (100), a lockstep run (lever started
//     from MuJoCo's state each step; MuJoCo's warm start off, as lever's CG never warm-starts): the
//     same iteration counts (solver_iter), and lever's answer as near the minimizer as MuJoCo's.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/compare.hpp>
#include <lever/diff/report.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>

namespace lever::test {

namespace {

struct CgScene {
  const char* file;
  Cone cone;
};

const char* cg_cone_label(Cone cone) { return cone == Cone::kElliptic ? "elliptic" : "pyramidal"; }

// Both engines on CG with the given stopping rule.
void use_cg_on_both(diff::Twin& twin, Cone cone, double tolerance, int iterations) {
  twin.set_cone(cone, 1.0);
  twin.restart_mujoco_solver = tolerance == 0;
  twin.model.opt.solver = Solver::kCG;
  twin.model.opt.tolerance = tolerance;
  twin.model.opt.iterations = iterations;
  twin.m->opt.solver = mjSOL_CG;
  twin.m->opt.tolerance = tolerance;
  twin.m->opt.iterations = iterations;
}

// max |a - b| / max(1, max |b|) over n numbers.
double cg_relative_gap(const double* a, const double* b, int n) {
  double gap = 0, scale = 1;
  for (int i = 0; i < n; ++i) {
    gap = std::max(gap, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(b[i]));
  }
  return gap / scale;
}

}  // namespace

TEST_CASE("diff: CG at tolerance 0 agrees with MuJoCo's CG run to the minimizer",
          "[diff][contact][cg]") {
  REQUIRE(mj_version() == 222);
  const CgScene scenes[] = {
      {"models/box_drop.xml", Cone::kPyramidal},
      {"models/box_drop.xml", Cone::kElliptic},
      {"tests/diff/contact_scenes/arm_and_objects.xml", Cone::kPyramidal},
      {"tests/diff/contact_scenes/arm_and_objects.xml", Cone::kElliptic},
  };
  for (const CgScene& scene : scenes) {
    const std::string name = std::string(scene.file) + " (" + cg_cone_label(scene.cone) + ")";
    diff::Twin twin(model_path(scene.file), diff::Path::kEngine);
    use_cg_on_both(twin, scene.cone, 0.0, 1000);
    std::mt19937_64 rng(seed_for(scene.file));
    diff::Report report;
    report.set_solver_bound(diff::kContactSolverBound);
    int with_rows = 0;
    for (int k = 0; k < 12; ++k) {
      State s = random_state(twin.model, rng);
      if (k % 3 == 0) s.qvel.setZero();
      diff::compare_forward(twin, s, k, report);
      with_rows += twin.data.nefc > 0 && twin.d->solver_iter > 0;
    }
    CHECK(with_rows > 4);
    double worst = 0;
    for (const diff::Extreme& e : report.quantities()) {
      INFO(name << ": " << e.quantity << " [" << e.element << "] state " << e.state << ": lever "
                << e.lever << " vs mujoco " << e.mujoco << ", " << e.max_ratio << " of 1e-12");
      CHECK(e.max_ratio <= e.bound);
      if (diff::decided_by_solver(e.quantity)) worst = std::max(worst, e.max_ratio);
    }
    WARN(name << ", CG at tolerance 0: within " << worst << " x 1e-12 of MuJoCo's CG");
  }
}

TEST_CASE("diff: CG at MuJoCo's default tolerance tracks MuJoCo's CG step by step",
          "[diff][contact][cg]") {
  REQUIRE(mj_version() == 222);
  for (const CgScene& scene :
       {CgScene{"tests/diff/contact_scenes/free_objects.xml", Cone::kPyramidal},
        CgScene{"tests/diff/contact_scenes/free_objects.xml", Cone::kElliptic},
        CgScene{"tests/diff/contact_scenes/arm_and_objects.xml", Cone::kPyramidal}}) {
    const std::string name = std::string(scene.file) + " (" + cg_cone_label(scene.cone) + ")";
    diff::Twin twin(model_path(scene.file), diff::Path::kEngine);
    use_cg_on_both(twin, scene.cone, 1e-8, 100);
    twin.m->opt.disableflags |= mjDSBL_WARMSTART;
    Model exact_model = twin.model;  // the minimizer: lever's exact solve
    exact_model.opt.tolerance = 0;
    Data exact(exact_model);
    const mjModel* m = twin.m.get();
    mjData* d = twin.d.get();
    twin.reset();
    int constrained = 0, same_count = 0, iterations = 0;
    double worst_gap = 0, worst_mujoco = 0, worst_lever = 0;
    for (int step = 0; step < 300; ++step) {
      twin.follow_mujoco();
      forward(twin.model, twin.data);
      mj_forward(m, d);
      if (d->nefc > 0) {
        ++constrained;
        iterations += d->solver_iter;
        same_count += twin.data.solver_iter == d->solver_iter;
        exact.time = twin.data.time;
        exact.qpos = twin.data.qpos;
        exact.qvel = twin.data.qvel;
        exact.ctrl = twin.data.ctrl;
        exact.qfrc_applied = twin.data.qfrc_applied;
        forward(exact_model, exact);
        // lever's CG stops as near the minimizer as MuJoCo's (each CG's distance from it is
        // what the tolerance leaves, set by the rounding of each product along the way)
        const double mujoco_off = cg_relative_gap(d->qacc, exact.qacc.data(), m->nv);
        const double lever_off = cg_relative_gap(twin.data.qacc.data(), exact.qacc.data(), m->nv);
        INFO(name << " step " << step << ": " << d->solver_iter << " MuJoCo iterations, "
                  << twin.data.solver_iter << " lever's; from the minimizer MuJoCo "
                  << mujoco_off << ", lever " << lever_off);
        CHECK(lever_off <= 10 * mujoco_off + diff::kContactSolverBound * 1e-12);
        worst_gap =
            std::max(worst_gap, cg_relative_gap(twin.data.qacc.data(), d->qacc, m->nv));
        worst_mujoco = std::max(worst_mujoco, mujoco_off);
        worst_lever = std::max(worst_lever, lever_off);
      }
      mj_step(m, d);
    }
    WARN(name << ", CG at tolerance 1e-8, 100 iterations, lockstep " << constrained
              << " steps with rows (" << iterations << " MuJoCo iterations): " << same_count
              << " with the same iteration count; qacc from MuJoCo's " << worst_gap
              << ", from the minimizer MuJoCo " << worst_mujoco << ", lever " << worst_lever);
    CHECK(constrained > 100);
    CHECK(same_count >= constrained * 95 / 100);
  }
}

}  // namespace lever::test

namespace lever::test {

// The derivatives hold the converged solution's active set: with CG at tolerance 0 (the exact
// solve) they are Newton's, bit for bit; a CG stopped by a tolerance is refused by name.
TEST_CASE("derivatives of CG and PGS models: Newton's at tolerance 0, refused above it", "[cg]") {
  Model newton_model = mjcf::load_file(model_path("models/box_drop.xml"));
  Model cg_model = newton_model;
  cg_model.opt.solver = Solver::kCG;
  cg_model.opt.tolerance = 0;
  Data newton(newton_model), cg(cg_model);
  if (newton_model.nkey > 0) {
    reset_keyframe(newton_model, newton, 0);
    reset_keyframe(cg_model, cg, 0);
  }
  for (int k = 0; k < 150; ++k) step(newton_model, newton);  // the box resting on the floor
  cg.qpos = newton.qpos;
  cg.qvel = newton.qvel;
  Derivatives dn(newton_model), dc(cg_model);
  forward_derivatives(newton_model, newton, dn);
  forward_derivatives(cg_model, cg, dc);
  REQUIRE(newton.nefc > 0);
  CHECK(dc.dqacc_dq == dn.dqacc_dq);
  CHECK(dc.dqacc_dv == dn.dqacc_dv);
  cg_model.opt.tolerance = 1e-8;
  CHECK_THROWS_WITH(forward_derivatives(cg_model, cg, dc),
                    Catch::Contains("opt.solver is CG with tolerance"));
  CHECK_THROWS_WITH(step_derivatives(cg_model, cg, dc),
                    Catch::Contains("opt.solver is CG with tolerance"));
  cg_model.opt.solver = Solver::kPGS;  // PGS stopped by its tolerance: the same refusal
  CHECK_THROWS_WITH(step_derivatives(cg_model, cg, dc),
                    Catch::Contains("opt.solver is PGS with tolerance"));
}

}  // namespace lever::test
