// lever::contact_force against MuJoCo 2.2.2's mj_contactForce: the same contact scenes
// at random states, MuJoCo's solver run to convergence, each contact's force in its frame; with
// pyramidal cones (two rows per tangent) and elliptic ones (one row per component).
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/contact_force.hpp>
#include <lever/diff/twin.hpp>
#include <lever/error.hpp>
#include <lever/lever.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>

namespace lever::test {

namespace {

void compare_contact_forces(const std::string& name, Cone cone, int states) {
  diff::Twin twin(model_path(name), diff::Path::kEngine);
  twin.m->opt.tolerance = 0;  // MuJoCo's answer made unique, as tests/diff/contact_dynamics
  twin.m->opt.iterations = 1000;
  if (cone == Cone::kElliptic) {
    twin.set_cone(Cone::kElliptic, 1.0);
    twin.restart_mujoco_solver = true;  // as tests/diff/contact_elliptic
  }
  std::mt19937_64 rng(seed_for(name) + 1);
  int with_force = 0, with_friction = 0;
  double worst = 0;
  for (int k = 0; k < states; ++k) {
    State s = random_state(twin.model, rng);
    if (k % 2 == 0) s.qvel.setZero();
    twin.set_state(s);
    forward(twin.model, twin.data);
    twin.mujoco_forward();
    REQUIRE(twin.data.ncon == twin.d->ncon);
    for (int i = 0; i < twin.data.ncon; ++i) {
      const Eigen::Matrix<double, 6, 1> ours = contact_force(twin.model, twin.data, i);
      mjtNum theirs[6];
      mj_contactForce(twin.m.get(), twin.d.get(), i, theirs);
      with_force += theirs[0] > 0;
      with_friction += theirs[1] != 0;
      for (int c = 0; c < 6; ++c) {
        // the solver decides efc_force: the same 1e-10 relative bound as its rows
        const double scale = std::max(1.0, std::abs(theirs[c]));
        INFO(name << " state " << k << " contact " << i << " component " << c << ": lever "
                  << ours[c] << " vs mujoco " << theirs[c]);
        CHECK(std::abs(ours[c] - theirs[c]) <= 1e-10 * scale);
        worst = std::max(worst, std::abs(ours[c] - theirs[c]) / scale);
      }
    }
  }
  INFO(name << ": " << with_force << " contacts pushing, " << with_friction << " with friction");
  CHECK(with_force > 10);
  CHECK(with_friction > 10);
  WARN(name << (cone == Cone::kElliptic ? " (elliptic)" : "") << ": contact_force within "
            << worst << " of mj_contactForce (relative)");
}

}  // namespace

TEST_CASE("diff: contact_force agrees with mj_contactForce", "[diff][contact]") {
  REQUIRE(mj_version() == 222);
  for (const std::string name : {"models/box_drop.xml", "models/gripper.xml",
                                 "tests/diff/contact_scenes/free_objects.xml"}) {
    compare_contact_forces(name, Cone::kPyramidal, 100);
  }
}

// an elliptic cone's contact has dim rows, fewer than a pyramid's 2 (dim - 1) once dim is 3 or
// more: the last contact's rows end exactly at nefc
TEST_CASE("diff: contact_force agrees with mj_contactForce, elliptic cones",
          "[diff][contact][elliptic]") {
  REQUIRE(mj_version() == 222);
  for (const std::string name : {"models/box_drop.xml", "tests/diff/contact_scenes/free_objects.xml"}) {
    compare_contact_forces(name, Cone::kElliptic, 50);
  }
}

TEST_CASE("contact_force refuses a contact that does not exist", "[diff][contact]") {
  diff::Twin twin(model_path("models/box_drop.xml"), diff::Path::kLoader);
  forward(twin.model, twin.data);
  CHECK_THROWS_AS(contact_force(twin.model, twin.data, -1), StateError);
  CHECK_THROWS_AS(contact_force(twin.model, twin.data, twin.data.ncon), StateError);
}

}  // namespace lever::test
