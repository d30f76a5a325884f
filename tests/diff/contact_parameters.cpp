// The soft parameters of the constraint rows against MuJoCo 2.2.2, bit for bit: a contact's
// friction, solref, solimp and mu, each row's impedance, K, B, R, D and diagApprox, and the
// model constants they are made of (body_invweight0, dof_invweight0, tendon_invweight0). They are
// arithmetic, not a solver's answer, so nothing but the order of operations can part them; and D,
// up to 1e6 on a cone's rows, carries its last bit into the forces. Two terms did: the mean of
// the bodies' J M^-1 J^T diagonals summed per dof as mju_dot sums (four running sums), not in
// order (an ulp in body_invweight0 of a third of the Unitree A1's bodies, hence in every R and D
// of their contacts and in mu = friction sqrt(R_1 / R_0)), and solimp's sigmoid through libm's
// pow as MuJoCo calls it: pow(x, 2) is not always x * x.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include "robots.hpp"

namespace lever::test {

namespace {

// Counts the numbers compared and those whose bits differ, naming the first that does.
struct BitTally {
  long compared = 0, apart = 0;
  std::string first;
  void add(const std::string& what, double ours, double theirs) {
    ++compared;
    if (std::memcmp(&ours, &theirs, sizeof(double)) == 0) return;
    if (apart++ == 0) {
      char numbers[96];
      std::snprintf(numbers, sizeof numbers, ": lever %.17g vs MuJoCo %.17g", ours, theirs);
      first = what + numbers;
    }
  }
};

void tally_model_constants(const Model& model, const mjModel* m, BitTally& tally) {
  for (int b = 0; b < m->nbody; ++b) {
    for (int k = 0; k < 2; ++k) {
      tally.add("body_invweight0 of body " + std::to_string(b), model.body_invweight0[b][k],
                m->body_invweight0[2 * b + k]);
    }
  }
  for (int i = 0; i < m->nv; ++i) {
    tally.add("dof_invweight0 " + std::to_string(i), model.dof_invweight0[i], m->dof_invweight0[i]);
  }
  for (int t = 0; t < m->ntendon; ++t) {
    tally.add("tendon_invweight0 " + std::to_string(t), model.tendon_invweight0[t],
              m->tendon_invweight0[t]);
  }
}

// The rows' parameters at the state both hold (lever after forward, MuJoCo after
// mj_fwdPosition), and the contacts'.
void tally_rows(const Data& data, const mjData* d, int state, BitTally& tally) {
  const std::string at = "state " + std::to_string(state) + ", ";
  for (int i = 0; i < d->ncon; ++i) {
    const Contact& ours = data.contact[i];
    const mjContact& theirs = d->contact[i];
    const std::string contact = at + "contact " + std::to_string(i) + " ";
    for (int k = 0; k < 5; ++k)
      tally.add(contact + "friction", ours.friction[k], theirs.friction[k]);
    for (int k = 0; k < 2; ++k) tally.add(contact + "solref", ours.solref[k], theirs.solref[k]);
    for (int k = 0; k < 5; ++k) tally.add(contact + "solimp", ours.solimp[k], theirs.solimp[k]);
    tally.add(contact + "includemargin", ours.includemargin, theirs.includemargin);
    tally.add(contact + "mu", ours.mu, theirs.mu);
  }
  for (int r = 0; r < d->nefc; ++r) {
    const std::string row = at + "row " + std::to_string(r) + " ";
    tally.add(row + "efc_imp", data.efc_imp[r], d->efc_KBIP[4 * r + 2]);
    tally.add(row + "efc_K", data.efc_K[r], d->efc_KBIP[4 * r]);
    tally.add(row + "efc_B", data.efc_B[r], d->efc_KBIP[4 * r + 1]);
    tally.add(row + "efc_R", data.efc_R[r], d->efc_R[r]);
    tally.add(row + "efc_D", data.efc_D[r], d->efc_D[r]);
    tally.add(row + "efc_diagApprox", data.efc_diagApprox[r], d->efc_diagApprox[r]);
  }
}

}  // namespace

TEST_CASE("diff: contact parameters and the rows' R and D are MuJoCo's bit for bit on real files",
          "[diff][contact][robots]") {
  REQUIRE(mj_version() == 222);
  const std::string folder = robots_dir();
  if (!robots_present(folder)) return;
  // elliptic cones on a floor (A1: 160 of 1696 contacts' mu an ulp apart at 50 states before),
  // pyramidal ones between a hand's links and on its object, frictionless capsules and joint
  // limits on the humanoid's own limbs
  for (const char* name :
       {"menagerie-2022/unitree_a1/scene.xml", "menagerie-2022/shadow_hand/scene_right.xml",
        "mujoco-2.2.2/humanoid/humanoid.xml"}) {
    const std::string file = folder + "/" + name;
    diff::Twin twin(file, diff::Path::kLoader);
    const mjModel* m = twin.m.get();
    mjData* d = twin.d.get();
    BitTally constants, rows;
    tally_model_constants(twin.model, m, constants);
    std::mt19937_64 rng(diff::default_seed(file));
    int states = 0, contacts = 0;
    for (int k = 0; k < 20; ++k) {
      const State s = random_state(twin.model, rng);
      twin.set_state(s);
      try {
        forward(twin.model, twin.data);
      } catch (const StateError&) {
        continue;  // more contacts than nconmax: lever refuses what MuJoCo drops
      }
      mj_fwdPosition(m, d);
      if (d->ncon != twin.data.ncon || d->nefc != twin.data.nefc) continue;
      ++states;
      contacts += d->ncon;
      tally_rows(twin.data, d, k, rows);
    }
    INFO(name << ": model constants " << constants.apart << " of " << constants.compared
              << " apart, first " << constants.first);
    CHECK(constants.apart == 0);
    INFO(name << ": " << states << " states, " << contacts << " contacts, " << rows.apart << " of "
              << rows.compared << " numbers apart, first " << rows.first);
    CHECK(contacts > 20);
    CHECK(rows.apart == 0);
  }
}

TEST_CASE("diff: solimp's sigmoid is MuJoCo's bit for bit", "[diff][constraints]") {
  // Three hinges, each past its lower limit by up to twice its solimp width, with the default
  // power 2 at midpoint 0.5 (pow(x, 2) against x * x), a cubic at 0.3 and a power 1.5 at 0.7
  // (the powers of the midpoint).
  REQUIRE(mj_version() == 222);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "lever_solimp_sigmoid.xml";
  std::ofstream(file) << R"(<mujoco>
  <compiler angle="radian"/>
  <option gravity="0 0 0"/>
  <worldbody>
    <body><joint name="a" range="-1 1" limited="true" solimplimit="0.1 0.99 0.01 0.5 2"/>
      <geom size="0.1" mass="1" contype="0" conaffinity="0"/></body>
    <body><joint name="b" range="-1 1" limited="true" solimplimit="0.2 0.9 0.02 0.3 3"/>
      <geom size="0.1" mass="2" contype="0" conaffinity="0"/></body>
    <body><joint name="c" range="-1 1" limited="true" solimplimit="0.5 0.95 0.01 0.7 1.5"
                 margin="0.003"/>
      <geom size="0.1" mass="3" contype="0" conaffinity="0"/></body>
  </worldbody>
</mujoco>)";
  diff::Twin twin(file.string(), diff::Path::kLoader);
  const mjModel* m = twin.m.get();
  mjData* d = twin.d.get();
  const double width[3] = {0.01, 0.02, 0.01};
  std::mt19937_64 rng(seed_for("solimp sigmoid"));
  std::uniform_real_distribution<double> past(-2.0, 0.0);
  BitTally rows;
  int on_the_slope = 0;  // rows whose impedance is strictly between d0 and dmax
  for (int k = 0; k < 300; ++k) {
    State s = random_state(twin.model, rng);
    for (int j = 0; j < 3; ++j) s.qpos[j] = -1 + past(rng) * width[j];
    twin.set_state(s);
    forward(twin.model, twin.data);
    mj_fwdPosition(m, d);
    REQUIRE(d->nefc == 3);
    REQUIRE(twin.data.nefc == 3);
    tally_rows(twin.data, d, k, rows);
    for (int r = 0; r < 3; ++r) {
      const int j = d->efc_id[r];
      on_the_slope += m->jnt_solimp[5 * j] < d->efc_KBIP[4 * r + 2] &&
                      d->efc_KBIP[4 * r + 2] < m->jnt_solimp[5 * j + 1];
    }
  }
  std::filesystem::remove(file);
  INFO(rows.apart << " of " << rows.compared << " apart, first " << rows.first << "; "
                  << on_the_slope << " of 900 rows on the sigmoid's slope");
  CHECK(on_the_slope > 300);
  CHECK(rows.apart == 0);
}

}  // namespace lever::test
