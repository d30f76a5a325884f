// Free runs: lever and MuJoCo each running on its own for 10 s from rest, under the smooth
// control that drives every joint into its stops. This is a report, not a 1e-12 assertion: lever
// is an independent implementation, and the stiff limit impacts amplify any last-bit difference
// (section 19.3 of the MuJoCo note measured 1e-11 in qacc for MuJoCo against itself with the warm
// start switched off). The yardstick is MuJoCo's own sensitivity: the same MuJoCo run with its
// initial qpos nudged by 1e-15.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <lever/diff/runs.hpp>

#include <lever/harness/models.hpp>
#include "diff_checks.hpp"
#include "sampling.hpp"

namespace lever::test {

namespace {

constexpr double kFreeRunSeconds = run_seconds(10.0);
constexpr double kNudge = 1e-15;
// lever may diverge from MuJoCo up to this many times MuJoCo's divergence from itself (plus the
// bound): generous on purpose, since a chaotic stretch can amplify one difference more than the
// other; a wrong term in the dynamics would show up as O(1) differences, far beyond it.
constexpr double kGenerosity = 100.0;

}  // namespace

TEST_CASE("diff: free runs stay at the dynamics' own noise floor", "[diff][free-run]") {
  REQUIRE(mj_version() == 222);
  std::printf("%-22s %-7s %-16s %16s %24s\n", "model", "path", "quantity", "lever vs MuJoCo",
              "MuJoCo vs nudged MuJoCo");
  for (const std::string& file : all_model_files()) {
    for (const diff::Path path : paths_to_compare()) {
      const std::string where = context(file, path, 0) + " (no randomness)";
      INFO(where);
      diff::Twin twin(file, path);
      const diff::FreeRun run =
          diff::free_run(twin, kFreeRunSeconds, diff::Control::kSmooth, kNudge);
      for (const std::string& q : diff::free_run_quantities()) {
        const diff::Extreme* ours = run.lever_vs_mujoco.find(q);
        const diff::Extreme* noise = run.nudged_vs_mujoco.find(q);
        REQUIRE(ours);
        REQUIRE(noise);
        std::printf("%-22s %-7s %-16s %16.2e %24.2e\n",
                    std::filesystem::path(file).filename().c_str(), diff::path_name(path),
                    q.c_str(), ours->max_abs_diff, noise->max_abs_diff);
      }
      check_near_noise_floor(run, diff::free_run_quantities(), kGenerosity);
    }
  }
}

}  // namespace lever::test
