// Cassie's achilles rods (MuJoCo Menagerie 2022's agility_cassie, its scene.xml): a rod's ball joint
// turns it about its own axis with the rod's axial inertia, 3.754e-6 kg m^2 (the file's Ixx; the
// centre of mass lies on that axis), and M's entry for that dof is what is left when CRBA's terms
// in world coordinates, some 1e4 times larger, cancel. The cancellation magnifies each last bit of
// those terms: MuJoCo started 1e-15 away from itself moves the factor's pivot (qLDiagInv) by more
// than the 1e-12 bound. lever sums every term as MuJoCo does (the subtree centres of mass, each
// body's inertia about them, CRBA's products and sums), so its entry and pivot are MuJoCo's
// within the bound at every state (the states `lever diff` draws for the file; summed in
// another order, the pivots were 1.27 times the bound apart at state 176).
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
#include "robots.hpp"

namespace lever::test {

TEST_CASE("diff: Cassie's achilles rods' axial entry of M and its pivot are MuJoCo's",
          "[diff][robots][cancellation]") {
  REQUIRE(mj_version() == 222);
  const std::string file = robots_dir() + "/menagerie-2022/agility_cassie/scene.xml";
  if (!robots_present(file)) return;
  diff::Twin twin(file, diff::Path::kEngine);
  const mjModel* m = twin.m.get();
  const double axial = 3.754e-6;  // the rods' <inertial fullinertia> Ixx
  const int rod_dofs[2] = {m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, "left-achilles-rod")],
                           m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, "right-achilles-rod")]};
  std::mt19937_64 rng(diff::default_seed(file));
  // differences relative to MuJoCo's value: the pivots' against the 1e-12 bound
  double lever_error = 0, mujoco_error = 0, entry_apart = 0, pivot_apart = 0, mujoco_nudged = 0;
  MjDataPtr nudged = mujoco_data(m);
  for (int k = 0; k < 200; ++k) {
    const State s = random_state(twin.model, rng);
    random_qacc(twin.model, rng);  // drawn as random_states draws it, to keep the same states
    twin.set_state(s);
    forward(twin.model, twin.data);
    mj_forward(m, twin.d.get());
    diff::set_mujoco_state(m, nudged.get(), s);
    for (int i = 0; i < m->nq; ++i) nudged->qpos[i] += (rng() & 1) ? 1e-15 : -1e-15;
    mj_forward(m, nudged.get());
    for (const int dof : rod_dofs) {
      const double ours = twin.data.M(dof, dof), theirs = twin.d->qM[m->dof_Madr[dof]];
      lever_error = std::max(lever_error, std::abs(ours - axial) / axial);
      mujoco_error = std::max(mujoco_error, std::abs(theirs - axial) / axial);
      entry_apart = std::max(entry_apart, std::abs(ours - theirs) / theirs);
      const double pivot = twin.d->qLDiagInv[dof];
      pivot_apart = std::max(pivot_apart, std::abs(twin.data.qLDiagInv[dof] - pivot) / pivot);
      mujoco_nudged = std::max(mujoco_nudged, std::abs(nudged->qLDiagInv[dof] - pivot) / pivot);
    }
  }
  INFO("the rods' axial entry of M against 3.754e-6: lever " << lever_error << ", MuJoCo "
       << mujoco_error << "; lever's entry from MuJoCo's " << entry_apart << ", the pivots 1/D "
       << pivot_apart << "; MuJoCo from qpos +-1e-15 from itself " << mujoco_nudged
       << " (relative)");
  CHECK(lever_error <= 1e-12);  // both near the exact value, to the rounding of the
  CHECK(mujoco_error <= 1e-12);  // cancellation
  CHECK(mujoco_nudged > 1e-12);  // the cancellation magnifies a last bit beyond the bound ...
  CHECK(entry_apart <= 1e-12);   // ... and lever's arithmetic is MuJoCo's: within it
  CHECK(pivot_apart <= 1e-12);
  WARN("Cassie's achilles rods, 200 random states: M's axial entry within "
       << lever_error << " (lever) and " << mujoco_error << " (MuJoCo) of 3.754e-6; lever's "
       << entry_apart << " from MuJoCo's, qLDiagInv " << pivot_apart
       << " apart; MuJoCo against itself from qpos +-1e-15: " << mujoco_nudged);
}

}  // namespace lever::test
