// The recursive Newton-Euler algorithm summed as MuJoCo 2.2.2's mj_rne sums it: on the real files
// (MuJoCo's samples, the Menagerie of 2022) and lever's own models, at random states, lever's
// qfrc_bias and its inverse dynamics at a random acceleration (rnea(), whose armature term is
// added to MuJoCo's as mj_inverse adds it) are mj_rne's to the last bit. The bodies' velocities
// and accelerations (a segment's or a body's dof terms summed before they join, as mj_comVel and
// mju_mulDofVec sum them), their net forces (I a + v x* I v as mju_mulInertVec and
// mju_crossForce sum them) and each dof's projection (mju_dot's order of six terms) make it so:
// with Eigen's dot and Newton and Euler's shorter net force, 28440 of these 43340 entries of
// qfrc_bias differed in their last bits (5.6e-4 of the bound at worst). Both engines run only
// their kinematics and the recursion (no collision), so the files cost their loading.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/dynamics.hpp>
#include <lever/kinematics.hpp>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include <lever/harness/tolerance.hpp>

namespace lever::test {

namespace {

constexpr int kBiasStates = 20;

// Entries of one quantity compared over a file's states: how many differ at all, and the worst
// difference as a fraction of the bound (1e-12 of the quantity's magnitude in that state), which
// the report prints.
struct BitTally {
  long compared = 0, differing = 0;
  double worst = 0.0;

  void add(const double* ours, const double* theirs, int n) {
    const double size = magnitude(theirs, n);
    for (int i = 0; i < n; ++i) {
      ++compared;
      differing += ours[i] != theirs[i];
      worst = std::max(worst, excess(ours[i], theirs[i], size));
    }
  }
};

// Both engines' RNEA on `states` random states of the file (MuJoCo's compiled parameters copied
// into lever, so that only the arithmetic can differ): bias forces, and inverse dynamics at a
// random acceleration.
void tally_rnea(const std::string& file, int states, BitTally& bias, BitTally& inverse) {
  diff::Twin twin(file, diff::Path::kEngine);
  const mjModel* m = twin.m.get();
  mjData* d = twin.d.get();
  const int nv = m->nv;
  std::mt19937_64 rng(diff::default_seed(file));
  std::vector<mjtNum> theirs(nv);
  Eigen::VectorXd ours(nv);
  for (int k = 0; k < states; ++k) {
    twin.set_state(random_state(twin.model, rng));
    const Eigen::VectorXd qacc = random_qacc(twin.model, rng);
    kinematics(twin.model, twin.data);
    mj_kinematics(m, d);
    mj_comPos(m, d);
    mj_comVel(m, d);

    lever::bias(twin.model, twin.data);
    mj_rne(m, d, 0, theirs.data());
    bias.add(twin.data.qfrc_bias.data(), theirs.data(), nv);

    for (int i = 0; i < nv; ++i) d->qacc[i] = qacc[i];
    mj_rne(m, d, 1, theirs.data());
    rnea(twin.model, twin.data, qacc, ours);
    // rnea() adds the armature's torque, which mj_rne leaves to mj_inverse
    for (int i = 0; i < nv; ++i) theirs[i] += m->dof_armature[i] * qacc[i];
    inverse.add(ours.data(), theirs.data(), nv);
  }
}

}  // namespace

TEST_CASE("diff: RNEA's bias forces and inverse dynamics are mj_rne's to the bit on real files",
          "[diff][robots][rnea]") {
  REQUIRE(mj_version() == 222);
  std::vector<std::string> files;
  const std::string robots = robots_dir();
  for (const char* name :
       {"menagerie-2022/agility_cassie/scene.xml", "menagerie-2022/anybotics_anymal_c/anymal_c.xml",
        "menagerie-2022/unitree_a1/a1.xml", "menagerie-2022/franka_emika_panda/panda.xml",
        "menagerie-2022/shadow_hand/right_hand.xml", "menagerie-2022/robotiq_2f85/2f85.xml",
        "mujoco-2.2.2/humanoid/humanoid.xml", "mujoco-2.2.2/humanoid/22_humanoids.xml",
        "mujoco-2.2.2/humanoid100/humanoid100.xml", "mujoco-2.2.2/composite/rope.xml",
        "mujoco-2.2.2/composite/loop.xml", "mujoco-2.2.2/composite/grid2pin.xml",
        "mujoco-2.2.2/flag/flag.xml", "mujoco-2.2.2/slider_crank/slider_crank.xml"}) {
    const std::string file = robots + "/" + name;
    if (std::filesystem::exists(file)) files.push_back(file);
  }
  if (files.empty()) WARN("no real model files at " << robots << ": only lever's own models");
  for (const std::string& file : all_model_files()) files.push_back(file);

  BitTally all_bias, all_inverse;
  for (const std::string& file : files) {
    INFO(file);
    BitTally bias, inverse;
    tally_rnea(file, kBiasStates, bias, inverse);
    INFO("qfrc_bias: " << bias.differing << " of " << bias.compared << " entries differ, worst "
                       << bias.worst << " of the bound; inverse dynamics: " << inverse.differing
                       << " of " << inverse.compared << ", worst " << inverse.worst);
    CHECK(bias.differing == 0);
    CHECK(inverse.differing == 0);
    all_bias.compared += bias.compared;
    all_bias.differing += bias.differing;
    all_bias.worst = std::max(all_bias.worst, bias.worst);
    all_inverse.compared += inverse.compared;
    all_inverse.differing += inverse.differing;
    all_inverse.worst = std::max(all_inverse.worst, inverse.worst);
  }
  WARN(files.size() << " files, " << kBiasStates << " random states each: qfrc_bias "
                    << all_bias.differing << " of " << all_bias.compared
                    << " entries differ from mj_rne's, worst " << all_bias.worst
                    << " of the bound; inverse dynamics " << all_inverse.differing << " of "
                    << all_inverse.compared << ", worst " << all_inverse.worst);
}

}  // namespace lever::test

