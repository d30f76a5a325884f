// What forward() and step() do with states that cannot give finite results (MuJoCo 2.2.2's
// mj_checkPos / mj_checkVel / mj_checkAcc for step; a recorded warning for forward).
#include <catch2/catch.hpp>

#include <lever/lever.hpp>
#include <lever/mjcf.hpp>

#include <cmath>
#include <limits>

#include <lever/harness/models.hpp>

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

int count(const lever::Data& data, lever::Warning w) {
  return data.warning[static_cast<int>(w)].number;
}

// A state away from qpos0, so that a reset is visible.
void move(lever::Data& data) {
  data.qpos << 0.6, -1.2;
  data.qvel << 0.3, -0.2;
  data.ctrl << 5, -2;
  data.time = 1.5;
}

}  // namespace

TEST_CASE("step resets a NaN or huge qpos to qpos0 and records it, as mj_step", "[bad-state]") {
  const lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  for (const double bad : {kNaN, 2e10, -std::numeric_limits<double>::infinity()}) {
    lever::Data data(model);
    move(data);
    data.qpos[1] = bad;
    lever::step(model, data);
    CHECK(count(data, lever::Warning::kBadQpos) == 1);
    CHECK(data.warning[static_cast<int>(lever::Warning::kBadQpos)].lastinfo == 1);
    // reset, then one ordinary step from rest at qpos0 with zero control
    CHECK(data.time == model.opt.timestep);
    CHECK(data.ctrl.isZero());
    CHECK(data.qpos.allFinite());
    CHECK(data.qacc.allFinite());
    CHECK(!lever::warning_text(data).empty());
  }
}

TEST_CASE("step resets a bad qvel, and a state whose acceleration blows up", "[bad-state]") {
  const lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  lever::Data data(model);
  move(data);
  data.qvel[0] = kNaN;
  lever::step(model, data);
  CHECK(count(data, lever::Warning::kBadQvel) == 1);
  CHECK(data.qvel.allFinite());

  // a velocity below 1e10 whose centrifugal acceleration is beyond it (the elbow bent, so that
  // the elbow's spin pulls on the shoulder)
  lever::Data fast(model);
  fast.qpos << 0.0, 0.5;
  fast.qvel << 0.0, 5e9;
  lever::step(model, fast);
  CHECK(count(fast, lever::Warning::kBadQacc) == 1);
  CHECK(fast.qacc.allFinite());
  CHECK(fast.qpos.allFinite());
  CHECK(fast.qvel.allFinite());
}

TEST_CASE("a NaN control zeroes every motor for that evaluation and is recorded", "[bad-state]") {
  const lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  lever::Data data(model);
  data.ctrl << kNaN, 5.0;
  lever::forward(model, data);
  CHECK(count(data, lever::Warning::kBadCtrl) == 1);
  CHECK(data.actuator_force.isZero());
  CHECK(data.qfrc_actuator.isZero());
  CHECK(data.qacc.allFinite());
  CHECK(std::isnan(data.ctrl[0]));  // the request is left as it was asked for
}

TEST_CASE("forward evaluates a bad state as given but never silently", "[bad-state]") {
  const lever::Model model = lever::mjcf::load_file(lever::test::model_path("models/arm2.xml"));
  lever::Data data(model);
  data.qpos[0] = kNaN;
  lever::forward(model, data);
  CHECK(std::isnan(data.qpos[0]));  // forward does not change the state
  CHECK(count(data, lever::Warning::kBadQpos) == 1);
  CHECK(lever::warning_count(data) >= 1);

  lever::Data applied(model);
  applied.qfrc_applied[1] = 1e11;
  lever::forward(model, applied);
  CHECK(count(applied, lever::Warning::kBadQfrcApplied) == 1);

  lever::Data fine(model);
  lever::forward(model, fine);
  CHECK(lever::warning_count(fine) == 0);
  CHECK(lever::warning_text(fine).empty());
}
