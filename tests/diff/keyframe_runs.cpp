// Runs from a keyframe, as lesson 5.2 starts its 7-DOF arm at `home`. lever's reset_keyframe and
// MuJoCo's mj_resetDataKeyframe give the same state, for every keyframe of every model. From the
// first keyframe, with its servo targets held, 60 steps under each integrator:
//  * in lockstep (both start every step from MuJoCo's state): every one-step transition within
//    the bound, under Euler, RK4 and implicit alike;
//  * free (each engine on its own): within the bound where the step is stable. Where it is not
//    (panda7's stiff servos at 2 ms under Euler and RK4, as `lever check` section 8 shows), any
//    last-bit difference grows by the spectral radius each step, in MuJoCo against itself too;
//    there lever is held to MuJoCo's own sensitivity (a run started 1e-15 away), as the free-run
//    test does.
#include <catch2/catch.hpp>
#include <lever/diff/runs.hpp>
#include <lever/forward.hpp>

#include <lever/harness/models.hpp>
#include <lever/harness/tolerance.hpp>
#include "diff_checks.hpp"

namespace lever::test {

namespace {

constexpr int kSteps = 60;
constexpr double kNudge = 1e-15;

// whether MuJoCo itself, started 1e-15 away, leaves the bound: the step then amplifies last-bit
// differences, and no independent implementation can hold the bound along the run
bool mujoco_is_sensitive(const diff::FreeRun& run) {
  const diff::Extreme* noise = run.nudged_vs_mujoco.find("qvel");
  return noise && noise->max_abs_diff > allowed(noise->max_abs_mujoco);
}

}  // namespace

TEST_CASE("diff: reset to a keyframe gives MuJoCo's state", "[diff][keyframe]") {
  REQUIRE(mj_version() == 222);
  int keyframes = 0;
  for (const std::string& file : all_model_files()) {
    diff::Twin twin(file, diff::Path::kLoader);
    REQUIRE(twin.model.nkey == twin.m->nkey);
    for (int key = 0; key < twin.model.nkey; ++key) {
      INFO(file << ", keyframe '" << twin.model.key_name[key] << "'");
      reset_keyframe(twin.model, twin.data, key);
      mj_resetDataKeyframe(twin.m.get(), twin.d.get(), key);
      diff::Report start;
      const diff::Labeler none = [](int i) { return std::to_string(i); };
      start.compare("qpos", 0, twin.data.qpos.data(), twin.d->qpos, twin.model.nq, none);
      start.compare("qvel", 0, twin.data.qvel.data(), twin.d->qvel, twin.model.nv, none);
      start.compare("ctrl", 0, twin.data.ctrl.data(), twin.d->ctrl, twin.model.nu, none);
      start.compare("time", 0, twin.data.time, twin.d->time);
      for (const diff::Extreme& e : start.quantities()) CHECK(e.max_abs_diff == 0.0);
      ++keyframes;
    }
  }
  CHECK(keyframes > 0);  // models/panda7.xml has `home`: without it this test would be vacuous
}

TEST_CASE("diff: 60 steps from the first keyframe agree under Euler, RK4 and implicit",
          "[diff][keyframe]") {
  REQUIRE(mj_version() == 222);
  for (const std::string& file : all_model_files()) {
    for (const diff::Path path : paths_to_compare()) {
      diff::Twin twin(file, path);
      if (twin.model.nkey == 0) continue;
      const double seconds = kSteps * twin.model.opt.timestep;
      const Integrator own = twin.model.opt.integrator;
      for (const Integrator integrator : kEveryIntegrator) {
        INFO(context(file, path, 0)
             << ", from " << twin.start_name() << ", " << integrator_name(integrator));
        check_within_bound(diff::lockstep(twin, integrator, seconds, diff::Control::kKeep));
        twin.set_integrator(integrator);
        const diff::FreeRun run = diff::free_run(twin, seconds, diff::Control::kKeep, kNudge);
        if (!mujoco_is_sensitive(run)) {
          check_within_bound(run.lever_vs_mujoco, {"qpos", "qvel", "actuator_force"});
        } else {
          check_near_noise_floor(run, {"qpos", "qvel", "actuator_force"});
        }
        twin.set_integrator(own);
      }
      // the model's own integrator must be one whose free run holds the bound: a lesson's
      // model that MuJoCo itself cannot reproduce from its keyframe would be a bad model
      twin.set_integrator(own);
      const diff::FreeRun run = diff::free_run(twin, seconds, diff::Control::kKeep, kNudge);
      INFO(context(file, path, 0) << ", its own integrator " << integrator_name(own));
      CHECK_FALSE(mujoco_is_sensitive(run));
      check_within_bound(run.lever_vs_mujoco, {"qpos", "qvel", "actuator_force"});
    }
  }
}

}  // namespace lever::test
