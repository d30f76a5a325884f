// Lesson 5.1's run: arm2 from rest, zero torque, 60 s. lever and MuJoCo each run on their own
// (no resynchronisation), and still agree to the bound at every step; the arm ends resting on its
// shoulder stop, slightly past it, with the same limit force and the same depth as MuJoCo's.
#include <catch2/catch.hpp>
#include <cmath>
#include <lever/diff/runs.hpp>

#include <lever/harness/models.hpp>
#include "diff_checks.hpp"

namespace lever::test {

namespace {

constexpr double kLessonSeconds = 60.0;

// How far past its lower stop a joint is, in mrad, as the lesson prints it: 1000 (lo - q).
double mrad_past_lower_stop(double lower, double q) { return 1000 * (lower - q); }

// The value the lesson's readout shows (3 decimals), as an integer count of micro-radians.
long readout(double mrad) { return std::lround(mrad * 1000); }

}  // namespace

TEST_CASE("diff: lesson 5.1, arm2 falls onto its shoulder stop and rests there as in MuJoCo",
          "[diff][lesson]") {
  REQUIRE(mj_version() == 222);
  const std::string file = model_path("models/arm2.xml");
  for (const diff::Path path : paths_to_compare()) {
    const std::string where = context(file, path, 0) + " (no randomness)";
    INFO(where);
    diff::Twin twin(file, path);
    const diff::FreeRun run = diff::free_run(twin, kLessonSeconds, diff::Control::kZero);

    // qpos and qvel at every one of the 30000 steps; qacc and the limit force are reported by the
    // free-run test instead (section 19.3: the impacts amplify last-bit differences in them)
    check_within_bound(run.lever_vs_mujoco, {"qpos", "qvel"});

    // the end: one row, the shoulder's lower stop, in both
    const int shoulder = twin.model.joint("shoulder");
    REQUIRE(shoulder >= 0);
    REQUIRE(twin.d->nefc == 1);
    REQUIRE(twin.data.nefc == 1);
    CHECK(twin.d->efc_id[0] == shoulder);
    CHECK(twin.data.efc_id[0] == shoulder);
    CHECK(twin.data.efc_sign[0] > 0);
    for (int i = 0; i < twin.model.nv; ++i) {
      INFO(
          describe("qfrc_constraint", i, twin.data.qfrc_constraint[i], twin.d->qfrc_constraint[i]));
      CHECK(agrees(twin.data.qfrc_constraint[i], twin.d->qfrc_constraint[i]));
    }

    // resting past the stop by the same depth, to the lesson's three decimals
    const int q = twin.model.jnt_qposadr[shoulder];
    const double ours = mrad_past_lower_stop(twin.model.jnt_range[shoulder][0], twin.data.qpos[q]);
    const double theirs = mrad_past_lower_stop(twin.m->jnt_range[2 * shoulder], twin.d->qpos[q]);
    INFO("past the shoulder stop: lever " << ours << " mrad, MuJoCo " << theirs << " mrad");
    CHECK(theirs > 0);
    CHECK(readout(ours) == readout(theirs));
  }
}

}  // namespace lever::test
