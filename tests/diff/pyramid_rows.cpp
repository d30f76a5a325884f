// A pyramidal cone's rows against MuJoCo 2.2.2, bit for bit, on real files (../shared/robots or
// $LEVER_ROBOTS_DIR): its edges n +- mu t as efc_J holds them, their velocities J qvel and
// reference accelerations, and, at MuJoCo's own qacc, the forces -D (J qacc - aref) and the joint
// forces J^T f that mj_inverse finds. MuJoCo takes the products over efc_J's rows (mju_dot's four
// running sums per row; J^T f row after row); lever's, computed as c_0 +- mu c_k from the contact
// frame's products, rounded otherwise, and D up to 1e6 carried that last bit into the forces.
// The harness's random states put the hands' fingers through their objects and each other.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>

#include <filesystem>
#include <random>
#include <string>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include "bits.hpp"
#include "robots.hpp"

namespace lever::test {

TEST_CASE("diff: pyramidal rows' products and forces at one qacc are MuJoCo's bit for bit",
          "[diff][contact][robots]") {
  REQUIRE(mj_version() == 222);
  const std::string folder = robots_dir();
  if (!robots_present(folder)) return;
  // pyramids of condim 3 between fingers and on the object (the 2F-85 and the Shadow hand), and
  // the humanoid's frictionless contacts between its limbs and its joint limits
  for (const char* name :
       {"menagerie-2022/robotiq_2f85/scene.xml", "menagerie-2022/shadow_hand/scene_right.xml",
        "mujoco-2.2.2/humanoid/humanoid.xml"}) {
    const std::string file = folder + "/" + name;
    diff::Twin twin(file, diff::Path::kLoader);
    const mjModel* m = twin.m.get();
    mjData* d = twin.d.get();
    std::mt19937_64 rng(diff::default_seed(file));
    int states = 0, pyramid_rows = 0, pushing = 0;
    int J_apart = 0, vel_apart = 0, aref_apart = 0, force_apart = 0, qfrc_apart = 0;
    for (int k = 0; k < 20; ++k) {
      const State s = random_state(twin.model, rng);
      twin.set_state(s);
      try {
        forward(twin.model, twin.data);
      } catch (const StateError&) {
        continue;  // more contacts than nconmax: lever refuses what MuJoCo drops
      }
      mj_forward(m, d);
      const int n = d->nefc, nv = m->nv;
      if (d->ncon != twin.data.ncon || n != twin.data.nefc) continue;
      ++states;
      for (int r = 0; r < n; ++r) pyramid_rows += d->efc_type[r] == mjCNSTR_CONTACT_PYRAMIDAL;
      J_apart += numbers_apart(twin.data.efc_J.data(), d->efc_J, n * nv);
      vel_apart += numbers_apart(twin.data.efc_vel.data(), d->efc_vel, n);
      aref_apart += numbers_apart(twin.data.efc_aref.data(), d->efc_aref, n);
      // the forces at MuJoCo's qacc: a function of it alone
      for (int i = 0; i < nv; ++i) twin.data.qacc[i] = d->qacc[i];
      inverse(twin.model, twin.data);
      mj_inverse(m, d);
      for (int r = 0; r < n; ++r) pushing += d->efc_force[r] != 0;
      force_apart += numbers_apart(twin.data.efc_force.data(), d->efc_force, n);
      qfrc_apart += numbers_apart(twin.data.qfrc_constraint.data(), d->qfrc_constraint, nv);
    }
    INFO(name << ": " << states << " states, " << pyramid_rows << " pyramid rows, " << pushing
              << " pushing; numbers apart: efc_J " << J_apart << ", efc_vel " << vel_apart
              << ", efc_aref " << aref_apart << ", efc_force " << force_apart
              << ", qfrc_constraint " << qfrc_apart);
    CHECK(pushing > 20);
    CHECK(J_apart == 0);
    CHECK(vel_apart == 0);
    CHECK(aref_apart == 0);
    CHECK(force_apart == 0);
    CHECK(qfrc_apart == 0);
  }
}

}  // namespace lever::test
