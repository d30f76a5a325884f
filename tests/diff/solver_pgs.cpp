// MuJoCo's projected Gauss-Seidel solver (<option solver="PGS">, engine/src/constraint/pgs.cpp)
// against MuJoCo 2.2.2's mj_solPGS, both computed here, both engines' warm start off but in the
// warm-start case. PGS after a fixed number of sweeps is not the minimizer, so the iterates
// themselves are compared: at tolerance 0 both run every sweep, and lever's sweeps follow
// MuJoCo's order and arithmetic, so efc_force, efc_state, qacc and solver_iter after N sweeps
// agree within 1e-12, on random states and on lockstep runs with every integrator; at MuJoCo's
// default tolerance the sweeps stop at the same count; and warm-started from the last solve's
// qacc_warmstart, a few sweeps give MuJoCo's forces along a run.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/report.hpp>
#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "diff_checks.hpp"
#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include <lever/harness/tolerance.hpp>

namespace lever::test {

namespace {

struct PgsScene {
  const char* file;
  Cone cone;
};

// Every kind of row: contacts of both cones (the gripper's fingers and box, a box on a plane),
// joint limits, friction loss, equality constraints.
const PgsScene kPgsScenes[] = {
    {"models/gripper.xml", Cone::kPyramidal},
    {"models/gripper.xml", Cone::kElliptic},
    {"models/box_drop.xml", Cone::kPyramidal},
    {"models/box_drop.xml", Cone::kElliptic},
    {"tests/models/joints_limits.xml", Cone::kPyramidal},
    {"tests/models/constraints/friction_loss.xml", Cone::kPyramidal},
    {"tests/models/constraints/equality.xml", Cone::kPyramidal},
};

std::string pgs_scene_name(const PgsScene& scene) {
  return std::string(scene.file) + (scene.cone == Cone::kElliptic ? " (elliptic)" : "");
}

// Both engines on PGS with the given stopping rule, their warm starts off.
void use_pgs_on_both(diff::Twin& twin, Cone cone, double tolerance, int iterations) {
  twin.set_cone(cone, 1.0);
  twin.restart_mujoco_solver = false;  // a restart would be another PGS run from zero forces
  twin.model.opt.solver = Solver::kPGS;
  twin.model.opt.tolerance = tolerance;
  twin.model.opt.iterations = iterations;
  twin.m->opt.solver = mjSOL_PGS;
  twin.m->opt.tolerance = tolerance;
  twin.m->opt.iterations = iterations;
  twin.m->opt.disableflags |= mjDSBL_WARMSTART;
  twin.model.opt.disableflags |= kDisableWarmstart;
}

// MuJoCo's ctrl: test::smooth_control at MuJoCo's time.
void pgs_smooth_control(diff::Twin& twin) {
  Eigen::Map<Eigen::VectorXd> ctrl(twin.d->ctrl, twin.model.nu);
  smooth_control(twin.model, twin.d->time, ctrl);
}

// The worst |lever - mujoco| / (1e-12 max(1, |mujoco|)) of efc_force and qacc at the twin's
// current forward, and whether efc_state and solver_iter are the same.
struct PgsGap {
  double worst = 0;
  bool same_states = true, same_count = true;
  std::string first_difference;  // the first state or value that differs, for the message
};

void add_pgs_gap(const diff::Twin& twin, const mjData* d, PgsGap& gap) {
  REQUIRE(twin.data.nefc == d->nefc);
  for (int r = 0; r < d->nefc; ++r) {
    const double ratio =
        std::abs(twin.data.efc_force[r] - d->efc_force[r]) / allowed(d->efc_force[r]);
    const bool same_state = static_cast<int>(twin.data.efc_state[r]) == d->efc_state[r];
    if ((ratio > 1 || !same_state) && gap.first_difference.empty()) {
      gap.first_difference = "row " + std::to_string(r) + " (type " +
                             std::to_string(d->efc_type[r]) + "): force " +
                             std::to_string(twin.data.efc_force[r]) + " state " +
                             std::to_string(static_cast<int>(twin.data.efc_state[r])) +
                             " vs MuJoCo's " + std::to_string(d->efc_force[r]) + " state " +
                             std::to_string(d->efc_state[r]);
    }
    gap.worst = std::max(gap.worst, ratio);
    gap.same_states = gap.same_states && same_state;
  }
  for (int i = 0; i < twin.model.nv; ++i) {
    const double ratio = std::abs(twin.data.qacc[i] - d->qacc[i]) / allowed(d->qacc[i]);
    if (ratio > 1 && gap.first_difference.empty()) {
      gap.first_difference = "qacc " + std::to_string(i) + ": " +
                             std::to_string(twin.data.qacc[i]) + " vs MuJoCo's " +
                             std::to_string(d->qacc[i]);
    }
    gap.worst = std::max(gap.worst, ratio);
  }
  gap.same_count = gap.same_count && twin.data.solver_iter == d->solver_iter;
}

// MuJoCo's constraint solve (mj_fwdConstraint: efc_b, then its PGS) run again on lever's inputs,
// qacc_smooth and efc_aref (each engine computes them its own way, equal to 1e-12 but not to
// the bit), from the warm start the forward began with: what is left between the two is the
// sweeps' own arithmetic.
void mujoco_pgs_on_lever_inputs(diff::Twin& twin, const std::vector<double>& warmstart) {
  mjData* d = twin.d.get();
  std::copy(warmstart.begin(), warmstart.end(), d->qacc_warmstart);
  for (int i = 0; i < twin.model.nv; ++i) d->qacc_smooth[i] = twin.data.qacc_smooth[i];
  for (int r = 0; r < d->nefc; ++r) d->efc_aref[r] = twin.data.efc_aref[r];
  mj_fwdConstraint(twin.m.get(), d);
}

// A state's comparison: lever's forward against MuJoCo's (`whole`), and against MuJoCo's PGS run
// again on lever's inputs (`sweeps`); `inputs`: MuJoCo's forward against that rerun, how much
// the inputs' last bits move MuJoCo's own answer.
struct PgsComparison {
  PgsGap whole, sweeps, inputs;
  int rows = 0;
};

void compare_pgs_state(diff::Twin& twin, PgsComparison& c) {
  const std::vector<double> warmstart(twin.d->qacc_warmstart,
                                      twin.d->qacc_warmstart + twin.model.nv);
  forward(twin.model, twin.data);
  mj_forward(twin.m.get(), twin.d.get());
  add_pgs_gap(twin, twin.d.get(), c.whole);
  c.rows += twin.d->nefc;
  test::MjDataPtr rerun = test::mujoco_data(twin.m.get());
  mj_copyData(rerun.get(), twin.m.get(), twin.d.get());
  std::swap(twin.d, rerun);
  mujoco_pgs_on_lever_inputs(twin, warmstart);
  add_pgs_gap(twin, twin.d.get(), c.sweeps);
  // MuJoCo against itself: its forward (now `rerun`) as if it were lever's
  PgsGap& self = c.inputs;
  for (int i = 0; i < twin.model.nv; ++i) {
    self.worst = std::max(self.worst, std::abs(rerun->qacc[i] - twin.d->qacc[i]) /
                                          allowed(twin.d->qacc[i]));
  }
  for (int r = 0; r < twin.d->nefc; ++r) {
    self.worst = std::max(self.worst, std::abs(rerun->efc_force[r] - twin.d->efc_force[r]) /
                                          allowed(twin.d->efc_force[r]));
  }
  std::swap(twin.d, rerun);
}

}  // namespace

TEST_CASE("diff: PGS's iterates after N sweeps at tolerance 0 are MuJoCo's",
          "[diff][contact][pgs]") {
  REQUIRE(mj_version() == 222);
  for (const PgsScene& scene : kPgsScenes) {
    for (const int sweeps : {1, 7, 40}) {
      const std::string name = pgs_scene_name(scene) + ", " + std::to_string(sweeps) + " sweeps";
      diff::Twin twin(model_path(scene.file), diff::Path::kEngine);
      use_pgs_on_both(twin, scene.cone, 0.0, sweeps);
      std::mt19937_64 rng(seed_for(scene.file));
      PgsComparison c;
      // random states, then the states of a run from the start state (contacts that rest)
      for (int k = 0; k < 8; ++k) {
        State s = random_state(twin.model, rng);
        if (k % 2 == 0) s.qvel.setZero();
        twin.set_state(s);
        compare_pgs_state(twin, c);
      }
      twin.reset();
      for (int k = 0; k < 150; ++k) {
        pgs_smooth_control(twin);
        twin.follow_mujoco();
        if (k % 10 == 0) compare_pgs_state(twin, c);
        mj_step(twin.m.get(), twin.d.get());
      }
      INFO(name << ": on the same inputs within " << c.sweeps.worst << " x 1e-12; "
                << c.sweeps.first_difference << "; whole forward within " << c.whole.worst
                << " x 1e-12 (" << c.whole.first_difference << "), MuJoCo from itself on "
                << "lever's inputs " << c.inputs.worst << " x 1e-12");
      CHECK(c.rows > 0);
      CHECK(c.sweeps.worst <= 1.0);
      CHECK(c.sweeps.same_states);
      CHECK(c.sweeps.same_count);
      CHECK(c.whole.same_count);
      // the whole forward: within the bound, or, where N sweeps carry the inputs' last bits
      // further (stiff equality rows), within MuJoCo's own move on lever's inputs
      CHECK(c.whole.worst <= std::max(1.0, 2 * c.inputs.worst));
      WARN(name << ": same inputs " << c.sweeps.worst << ", whole forward " << c.whole.worst
                << ", MuJoCo on lever's inputs " << c.inputs.worst << " (x 1e-12)");
    }
  }
}


TEST_CASE("diff: PGS at MuJoCo's default tolerance stops after MuJoCo's sweeps",
          "[diff][contact][pgs]") {
  REQUIRE(mj_version() == 222);
  for (const PgsScene& scene : kPgsScenes) {
    const std::string name = pgs_scene_name(scene);
    diff::Twin twin(model_path(scene.file), diff::Path::kEngine);
    use_pgs_on_both(twin, scene.cone, 1e-8, 100);
    twin.reset();
    PgsComparison c;
    int constrained = 0, sweeps = 0;
    for (int k = 0; k < 200; ++k) {
      pgs_smooth_control(twin);
      twin.follow_mujoco();
      compare_pgs_state(twin, c);
      constrained += twin.d->nefc > 0;
      sweeps += twin.d->solver_iter;
      mj_step(twin.m.get(), twin.d.get());
    }
    INFO(name << ": " << constrained << " steps with rows, " << sweeps << " MuJoCo sweeps; on "
              << "the same inputs within " << c.sweeps.worst << " x 1e-12 ("
              << c.sweeps.first_difference << "), whole forward " << c.whole.worst
              << ", MuJoCo on lever's inputs " << c.inputs.worst);
    CHECK(constrained > 0);
    CHECK(c.sweeps.same_count);
    CHECK(c.whole.same_count);
    CHECK(c.sweeps.worst <= 1.0);
    // as above: the bound, or MuJoCo's own move on lever's inputs (their last bits) where the
    // sweeps it stops after carry those bits further
    CHECK(c.whole.worst <= std::max(1.0, 2 * c.inputs.worst));
    WARN(name << ", tolerance 1e-8: " << constrained << " steps with rows, " << sweeps
              << " sweeps; same inputs " << c.sweeps.worst << ", whole forward "
              << c.whole.worst << ", MuJoCo on lever's inputs " << c.inputs.worst
              << " (x 1e-12)");
  }
}

TEST_CASE("diff: PGS in lockstep with MuJoCo, every integrator", "[diff][contact][pgs]") {
  REQUIRE(mj_version() == 222);
  for (const PgsScene& scene : {kPgsScenes[0], kPgsScenes[1], kPgsScenes[5], kPgsScenes[6]}) {
    for (const Integrator integrator : kEveryIntegrator) {
      const std::string name = pgs_scene_name(scene) + ", " + integrator_name(integrator);
      diff::Twin twin(model_path(scene.file), diff::Path::kEngine);
      use_pgs_on_both(twin, scene.cone, 1e-8, 100);
      const diff::Report report = diff::lockstep(twin, integrator, 0.2, diff::Control::kSmooth);
      double worst = 0;
      for (const diff::Extreme& e : report.quantities()) {
        INFO(name << ": " << e.quantity << " [" << e.element << "] step " << e.state << ": lever "
                  << e.lever << " vs mujoco " << e.mujoco << ", " << e.max_ratio << " of 1e-12");
        CHECK(e.max_ratio <= 1.0);
        worst = std::max(worst, e.max_ratio);
      }
      WARN(name << " lockstep: within " << worst << " x 1e-12");
    }
  }
}

TEST_CASE("diff: PGS warm-started from the last solve's acceleration gives MuJoCo's forces",
          "[diff][contact][pgs]") {
  REQUIRE(mj_version() == 222);
  // where the forces at qacc_warmstart cost more than zero forces (the elliptic gripper, friction
  // loss and the equality rows at 4 sweeps) both engines start from zero; the pyramidal gripper
  // keeps its warm start on most steps
  double moved_most = 0;
  for (const PgsScene& scene : {kPgsScenes[0], kPgsScenes[1], kPgsScenes[5], kPgsScenes[6]}) {
    const std::string name = pgs_scene_name(scene);
    diff::Twin twin(model_path(scene.file), diff::Path::kEngine);
    // a few sweeps at tolerance 0: far from the minimizer, so where they start shows
    use_pgs_on_both(twin, scene.cone, 0.0, 4);
    twin.model.opt.disableflags &= ~kDisableWarmstart;
    twin.m->opt.disableflags &= ~mjDSBL_WARMSTART;
    Model cold = twin.model;  // the same solve from zero forces
    cold.opt.disableflags |= kDisableWarmstart;
    Data cold_data(cold);
    twin.reset();
    PgsComparison c;
    double moved = 0;  // how far the warm start moved lever's forces from a cold start's
    for (int k = 0; k < 100; ++k) {
      pgs_smooth_control(twin);
      twin.follow_mujoco();  // MuJoCo's qacc_warmstart too
      cold_data.time = twin.data.time;
      cold_data.qpos = twin.data.qpos;
      cold_data.qvel = twin.data.qvel;
      cold_data.ctrl = twin.data.ctrl;
      cold_data.act = twin.data.act;
      cold_data.qfrc_applied = twin.data.qfrc_applied;
      compare_pgs_state(twin, c);
      forward(cold, cold_data);
      REQUIRE(cold_data.nefc == twin.data.nefc);
      for (int r = 0; r < twin.data.nefc; ++r) {
        moved = std::max(moved, std::abs(cold_data.efc_force[r] - twin.data.efc_force[r]) /
                                    allowed(twin.d->efc_force[r]));
      }
      mj_step(twin.m.get(), twin.d.get());
    }
    INFO(name << ": on the same inputs within " << c.sweeps.worst << " x 1e-12 ("
              << c.sweeps.first_difference << "), whole forward " << c.whole.worst << " ("
              << c.whole.first_difference << "), MuJoCo on lever's inputs " << c.inputs.worst
              << "; the warm start moved the forces " << moved << " x 1e-12");
    CHECK(c.rows > 0);
    moved_most = std::max(moved_most, moved);
    CHECK(c.sweeps.worst <= 1.0);
    CHECK(c.sweeps.same_states);
    CHECK(c.sweeps.same_count);
    CHECK(c.whole.same_count);
    CHECK(c.whole.worst <= std::max(1.0, 2 * c.inputs.worst));
    WARN(name << ", warm-started, 4 sweeps: same inputs " << c.sweeps.worst << ", whole forward "
              << c.whole.worst << ", MuJoCo on lever's inputs " << c.inputs.worst
              << ", moved from a cold start " << moved << " (x 1e-12)");
  }
  CHECK(moved_most > 1e3);  // the warm start mattered
}

}  // namespace lever::test
