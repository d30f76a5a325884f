// Trajectories in lockstep: 10 s (a quarter under the sanitizers) from the model's first keyframe
// (else from rest) under a smooth control that sweeps every motor's whole range (so the joints hit
// their stops). At every step
// lever starts from MuJoCo's own state, and one lever step must equal one MuJoCo step: qpos and
// qvel after it, qacc and qfrc_constraint of its forward pass.
#include <catch2/catch.hpp>
#include <lever/diff/runs.hpp>

#include <lever/harness/models.hpp>
#include "diff_checks.hpp"
#include "sampling.hpp"

namespace lever::test {

namespace {

constexpr double kTrajectorySeconds = run_seconds(10.0);

void lockstep_every_model(Integrator integrator) {
  REQUIRE(mj_version() == 222);
  for (const std::string& file : all_model_files()) {
    for (const diff::Path path : paths_to_compare()) {
      const std::string where =
          context(file, path, 0) + " (no randomness), " + integrator_name(integrator);
      INFO(where);
      diff::Twin twin(file, path);
      diff::RunStats stats;
      const diff::Report report =
          diff::lockstep(twin, integrator, kTrajectorySeconds, diff::Control::kSmooth, &stats);
      check_within_bound(report);
      INFO(stats.constrained_steps << " of " << stats.steps << " steps with limit rows");
      if (has_limits(twin.model)) CHECK(stats.constrained_steps > 0);
    }
  }
}

}  // namespace

TEST_CASE("diff: lockstep trajectories, one Euler step equals one MuJoCo step",
          "[diff][lockstep]") {
  lockstep_every_model(Integrator::kEuler);
}

TEST_CASE("diff: lockstep trajectories, one RK4 step equals one MuJoCo step", "[diff][lockstep]") {
  lockstep_every_model(Integrator::kRK4);
}

TEST_CASE("diff: lockstep trajectories, one implicit step equals one MuJoCo step",
          "[diff][lockstep]") {
  lockstep_every_model(Integrator::kImplicit);
}

}  // namespace lever::test
