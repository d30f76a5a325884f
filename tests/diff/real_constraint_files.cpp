// Real robot files that use joint friction loss (MuJoCo Menagerie 2022's ANYmal B and C and
// Unitree A1, from ../shared/robots beside the repository, or the folder $LEVER_ROBOTS_DIR names)
// against MuJoCo 2.2.2: random states and a lockstep run, both paths. Their feet and shins are
// meshes and cylinders that collide with each other, pairs lever's collision stage does not
// compute yet, so contacts are disabled on both sides (<flag contact="disable">): what is
// compared is the legs' friction-loss rows, their joint limits and the rest of the dynamics. A
// missing folder skips the test with a warning (the files are not part of the repository).
#include <catch2/catch.hpp>
#include <lever/diff/runs.hpp>

#include <cstdlib>
#include <filesystem>

#include <lever/harness/from_mujoco.hpp>
#include <lever/harness/models.hpp>
#include <lever/mjcf.hpp>
#include "diff_checks.hpp"
#include "sampling.hpp"
#include "robots.hpp"

namespace lever::test {

namespace {

int friction_rows(const Data& data) {
  int n = 0;
  for (int r = 0; r < data.nefc; ++r) n += data.efc_type[r] == ConstraintType::kFrictionDof;
  return n;
}

// A twin of the file with contacts disabled on both sides.
void disable_contacts(diff::Twin& twin) {
  twin.m->opt.disableflags |= mjDSBL_CONTACT;
  twin.model.opt.disableflags |= kDisableContact;
  set_const(twin.model);
  twin.data = Data(twin.model);
}

}  // namespace

TEST_CASE("diff: Cassie's closed leg chains (equality connects) agree with MuJoCo",
          "[diff][constraints][robots]") {
  // Random states, both paths (lever's loader reads the motors' and sensors' `user` data);
  // inverse dynamics at the forward qacc to 1e-12 of the cancelled forces
  REQUIRE(mj_version() == 222);
  const std::string file = robots_dir() + "/menagerie-2022/agility_cassie/cassie.xml";
  if (!robots_present(file)) return;
  for (const diff::Path path : paths_to_compare()) {
    const std::uint64_t seed = diff::default_seed(file);
    INFO(context(file, path, seed));
    diff::Twin twin(file, path);
    disable_contacts(twin);
    const diff::Report report = diff::random_states(twin, samples(50), seed);
    check_within_bound(report, all_but_inverse_at_forward(report));
    inverse_at_forward_agrees(twin, samples(50), seed);
    twin.reset();
    forward(twin.model, twin.data);
    CHECK(twin.data.ne == 12);  // four connects
  }
}

TEST_CASE("diff: Cassie's user data is MuJoCo's", "[diff][robots][user]") {
  REQUIRE(mj_version() == 222);
  const std::string file = robots_dir() + "/menagerie-2022/agility_cassie/cassie.xml";
  if (!robots_present(file)) return;
  const Model model = mjcf::load_file(file);
  const MjModelPtr m = mujoco_load(file);
  REQUIRE(model.nuser_actuator == m->nuser_actuator);
  REQUIRE(model.nuser_sensor == m->nuser_sensor);
  REQUIRE(model.nuser_actuator == 1);  // the motors' `user`: one number each
  for (int i = 0; i < model.actuator_user.size(); ++i) {
    CHECK(model.actuator_user.data()[i] == m->actuator_user[i]);
  }
  for (int i = 0; i < model.sensor_user.size(); ++i) {
    CHECK(model.sensor_user.data()[i] == m->sensor_user[i]);
  }
  CHECK(model.actuator_user(0, 0) == 2900);
}

TEST_CASE("diff: Cassie runs 1 s from its keyframe within MuJoCo's own sensitivity",
          "[diff][constraints][robots]") {
  // free fall from `home` with the connects holding the legs' closed chains; each engine on its
  // own, held to MuJoCo against itself started 1e-15 away
  REQUIRE(mj_version() == 222);
  const std::string file = robots_dir() + "/menagerie-2022/agility_cassie/cassie.xml";
  if (!robots_present(file)) return;
  diff::Twin twin(file, diff::Path::kLoader);
  disable_contacts(twin);
  REQUIRE(twin.start_name() == "keyframe 'home'");
  const diff::FreeRun run = diff::free_run(twin, 1.0, diff::Control::kZero, 1e-15);
  check_near_noise_floor(run, {"qpos", "qvel"});
}

TEST_CASE("diff: real files with friction loss agree with MuJoCo", "[diff][constraints][robots]") {
  REQUIRE(mj_version() == 222);
  const std::string folder = robots_dir();
  if (!robots_present(folder)) return;
  for (const char* name :
       {"menagerie-2022/anybotics_anymal_b/anymal_b.xml",
        "menagerie-2022/anybotics_anymal_c/anymal_c.xml", "menagerie-2022/unitree_a1/a1.xml"}) {
    const std::string file = folder + "/" + name;
    for (const diff::Path path : paths_to_compare()) {
      const std::uint64_t seed = diff::default_seed(file);
      INFO(context(file, path, seed));
      diff::Twin twin(file, path);
      disable_contacts(twin);
      const diff::Report report = diff::random_states(twin, samples(50), seed);
      check_within_bound(report);
      const diff::Report run =
          diff::lockstep(twin, Integrator::kEuler, 0.2, diff::Control::kSmooth);
      check_within_bound(run);
      // every dof of the legs has friction loss: the rows were there to compare
      twin.reset();
      forward(twin.model, twin.data);
      CHECK(friction_rows(twin.data) == 12);
    }
  }
}

}  // namespace lever::test
