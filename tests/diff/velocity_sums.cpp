// Sums over the dofs that lever shares with MuJoCo 2.2.2, bit for bit: each adds its products in
// MuJoCo's order (engine/src/basics/sums.hpp), as a sum's last bit depends on it.
//  - ten_velocity = ten_J qvel: mju_dot's four running sums where MuJoCo holds ten_J dense, its
//    stored entries in order where sparse (mju_dotSparse; option jacobian="sparse", or "auto"
//    from 60 dofs on);
//  - actuator_velocity = actuator_moment qvel: mju_dot's sums in both layouts (a dense row);
//  - the kinetic energy qvel' M qvel / 2: M qvel as mj_mulM walks its sparse M (a dof's
//    diagonal product, then its ancestors' couplings, each also added to the ancestor's row),
//    then mju_dot's sums.
// Checked on random states of tests/models/constraints/tendons.xml (fixed tendons over six dofs),
// spatial_tendons.xml, the Shadow hand of Menagerie 2022 (fixed tendons coupling its fingers'
// joints), and humanoid100 of MuJoCo's samples (../shared/robots or $LEVER_ROBOTS_DIR).
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>

#include <random>
#include <string>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include "bits.hpp"
#include "robots.hpp"

namespace lever::test {

namespace {

struct VelocitiesApart {
  int states = 0, tendon = 0, actuator = 0;
};

// ten_velocity and actuator_velocity, lever's against MuJoCo's, over `count` random states.
VelocitiesApart compare_velocities(diff::Twin& twin, int count) {
  std::mt19937_64 rng(diff::default_seed(twin.file()));
  VelocitiesApart apart;
  for (int k = 0; k < count; ++k) {
    twin.set_state(random_state(twin.model, rng));
    try {
      forward(twin.model, twin.data);
    } catch (const StateError&) {
      continue;
    }
    mj_forward(twin.m.get(), twin.d.get());
    ++apart.states;
    apart.tendon +=
        numbers_apart(twin.data.ten_velocity.data(), twin.d->ten_velocity, twin.m->ntendon);
    apart.actuator +=
        numbers_apart(twin.data.actuator_velocity.data(), twin.d->actuator_velocity, twin.m->nu);
  }
  INFO(twin.file() << ": " << apart.states << " states; apart: ten_velocity " << apart.tendon
                   << ", actuator_velocity " << apart.actuator);
  CHECK(apart.states == count);
  CHECK(apart.tendon == 0);
  CHECK(apart.actuator == 0);
  return apart;
}

}  // namespace

TEST_CASE("diff: tendon and actuator velocities are MuJoCo's sums, bit for bit",
          "[diff][tendons]") {
  REQUIRE(mj_version() == 222);
  std::vector<std::string> files = {model_path("tests/models/constraints/tendons.xml"),
                                    model_path("tests/models/constraints/spatial_tendons.xml")};
  const std::string hand = robots_dir() + "/menagerie-2022/shadow_hand/right_hand.xml";
  if (robots_present(hand)) files.push_back(hand);
  for (const std::string& file : files) {
    diff::Twin twin(file, diff::Path::kLoader);
    REQUIRE(twin.m->ntendon > 0);
    REQUIRE(twin.m->nv < 60);  // dense by size
    compare_velocities(twin, 50);
    // option jacobian="sparse": ten_J's rows summed in order, actuator_moment's still dense
    twin.m->opt.jacobian = mjJAC_SPARSE;
    twin.model.opt.jacobian = JacobianLayout::kSparse;
    compare_velocities(twin, 20);
  }
}

TEST_CASE("diff: the kinetic energy of a large humanoid is MuJoCo's sum, bit for bit",
          "[diff][robots]") {
  REQUIRE(mj_version() == 222);
  const std::string file = robots_dir() + "/mujoco-2.2.2/humanoid100/humanoid100.xml";
  if (!robots_present(file)) return;
  diff::Twin twin(file, diff::Path::kLoader);
  twin.m->opt.enableflags |= mjENBL_ENERGY;  // mj_energyVel computes nothing without it
  std::mt19937_64 rng(diff::default_seed(twin.file()));
  int states = 0, apart = 0;
  for (int k = 0; k < 10; ++k) {
    twin.set_state(random_state(twin.model, rng));
    try {
      forward(twin.model, twin.data);
    } catch (const StateError&) {
      continue;
    }
    compute_energy(twin.model, twin.data);
    mj_forward(twin.m.get(), twin.d.get());
    mj_energyPos(twin.m.get(), twin.d.get());
    mj_energyVel(twin.m.get(), twin.d.get());
    REQUIRE(twin.d->energy[1] > 0);
    ++states;
    apart += numbers_apart(twin.data.energy.data(), twin.d->energy, 2);
  }
  INFO(states << " states, " << apart << " energies apart");
  CHECK(states == 10);
  CHECK(apart == 0);
}

}  // namespace lever::test
